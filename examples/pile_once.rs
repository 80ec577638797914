//! One run of the 20-cube pile at a contact tolerance given on the command line (default: the defaults), for
//! profiling: `cargo run --release --example pile_once -- 1e-3`
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
