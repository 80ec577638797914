//! A box thrown spinning onto the floor comes to rest (fast mode); prints its energy every half second and the
//! run report.
//!
//! `cargo run --release --example tumbling_box`

fn main() -> Result<(), tumble::WorldError> {
    let (mut world, b) = tumble::scenes::tumbling_box()?;
    println!("plan    {}", world.plan());
    let run = world.run(4.0, 0.5)?;
    for f in 0..run.frames() {
        println!("t {:.1} s  energy {:9.3} J  height {:.4} m", run.times[f], run.energy(f), run.body_position(f, 1).z);
    }
    let body = world.body(b)?;
    println!("at rest: |v| = {:.2e} m/s, |w| = {:.2e} rad/s", body.velocity().norm(), body.angular_velocity().norm());
    println!("{}", run.report);
    Ok(())
}
