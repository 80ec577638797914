//! A ball dropped from 1 m bounces with e = 0.8 (accurate mode): prints each impact time and apex height next to
//! the closed forms sqrt(2 h / g) + ... and 0.64^n, and the run report.
//!
//! `cargo run --release --example bouncing_ball`

use tumble::scenes::BouncingBall;

fn main() -> Result<(), tumble::WorldError> {
    let scene = BouncingBall::default();
    let (mut world, ball) = scene.build()?;
    println!("plan    {}", world.plan());
    let run = world.run(5.0, 1e-3)?;
    let (g, e, r) = (9.81f64, scene.restitution, scene.radius);
    let v1 = (2.0 * g * scene.height).sqrt();
    let mut exact = v1 / g;
    println!("impact   time (s)          closed form       apex after (m)   closed form");
    for (n, &t) in run.contact_events.iter().take(8).enumerate() {
        let f = ((t + 0.05) / 1e-3).round() as usize;
        let (z, vz) = (run.body_position(f, 1).z, run.body_velocity(f, 1).z);
        let apex = z - r + vz * vz / (2.0 * g);
        println!(
            "{:>6}   {t:.12}    {exact:.12}    {apex:.9}      {:.9}",
            n + 1,
            scene.height * e.powi(2 * (n as i32 + 1))
        );
        exact += 2.0 * e.powi(n as i32 + 1) * v1 / g;
    }
    let b = world.body(ball)?;
    println!(
        "at rest: z = {:.9} m, |v| = {:.2e} m/s after {} impacts",
        b.position().z,
        b.velocity().norm(),
        run.report.collisions
    );
    println!("{}", run.report);
    Ok(())
}
