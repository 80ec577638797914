fn main() {
    let (mut w, _) = tumble::scenes::Benchmark::CubePile.build().unwrap();
    w.set_threads(1).unwrap();
    w.set_mode(tumble::Mode::Accurate(tumble::AccurateSettings { contact_tolerance: Some(1e-3), ..Default::default() })).unwrap();
    let t = std::time::Instant::now();
    w.step(1.0).unwrap();
    println!("{:.3} s\n{}", t.elapsed().as_secs_f64(), w.report());
}
