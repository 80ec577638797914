//! One run of an accurate-mode benchmark scene (`pile`, the default, `dominoes` or `slide`) at a contact tolerance
//! given on the command line (anything else: the defaults) over its span or a given one, printing the wall time and
//! the report, for profiling: `cargo run --release --example pile_once -- 1e-3 pile 3.0`
use tumble::scenes::Benchmark;
use tumble::{AccurateSettings, Mode};
fn main() {
    let arg = std::env::args().nth(1);
    let which = std::env::args().nth(2).unwrap_or("pile".into());
    let scene = match which.as_str() {
        "dominoes" => Benchmark::DominoRow,
        "slide" => Benchmark::Slide,
        _ => Benchmark::CubePile,
    };
    let (mut w, _) = scene.build().unwrap();
    w.set_threads(1).unwrap();
    if let Some(t) = arg.and_then(|a| a.parse::<f64>().ok()) {
        w.set_mode(Mode::Accurate(AccurateSettings { contact_tolerance: Some(t), ..AccurateSettings::default() }))
            .unwrap();
    }
    let clock = std::time::Instant::now();
    let span = std::env::args().nth(3).and_then(|a| a.parse::<f64>().ok()).unwrap_or(scene.span());
    let run = w.run(span, 1.0 / 60.0).unwrap();
    println!("{:.3} s\n{}", clock.elapsed().as_secs_f64(), run.report);
}
