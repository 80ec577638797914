//! A heavy top spinning on a pivot precesses; prints the measured precession rate next to the steady-precession
//! rate of a heavy symmetric top, the slow root of I1 cos(theta) W^2 - I3 w3 W + M g l = 0.
//!
//! `cargo run --release --example spinning_top`

use tumble::scenes::spinning_top;

fn main() -> Result<(), tumble::WorldError> {
    let (mut world, _) = spinning_top()?;
    println!("plan    {}", world.plan());
    let run = world.run(5.0, 1.0 / 60.0)?;
    let azimuth = |f: usize| {
        let x = run.body_position(f, 0);
        x.y.atan2(x.x)
    };
    let mut turned = 0.0;
    for f in 1..run.frames() {
        let mut d = azimuth(f) - azimuth(f - 1);
        d -= (d / std::f64::consts::TAU).round() * std::f64::consts::TAU;
        turned += d;
    }
    let rate = turned / (run.times[run.frames() - 1] - run.times[0]);
    let (a, b, c) = (0.02 * 0.3f64.cos(), 0.04 * 40.0, 1.0 * 9.81 * 0.1);
    let expected = (b - (b * b - 4.0 * a * c).sqrt()) / (2.0 * a);
    println!("precession {rate:.4} rad/s; steady precession of a heavy top {expected:.4} rad/s");
    println!("{}", run.report);
    Ok(())
}
