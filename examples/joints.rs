//! The jointed scenes, each run and measured: a pendulum's period against the elliptic integral, a hanging chain's
//! stretch, how much of Newton's cradle's momentum reaches the last ball, a door driven open to its limit by its
//! motor, and a ragdoll pushed down a flight of stairs.
//!
//! `cargo run --release --example joints`

use std::time::Instant;
use tumble::scenes::joints;

fn main() -> Result<(), tumble::WorldError> {
    // the pendulum: period from two crossings of the vertical (frames of 1 ms, linear interpolation)
    let (mut w, _) = joints::pendulum(1.0, 0.05)?;
    println!("pendulum     plan {}", w.plan());
    let clock = Instant::now();
    let run = w.run(4.0, 1e-3)?;
    let x: Vec<f64> = (0..run.frames()).map(|k| run.body_position(k, 0).x).collect();
    let mut crossings = Vec::new();
    for k in 1..x.len() {
        if x[k - 1] > 0.0 && x[k] <= 0.0 {
            crossings.push(run.times[k - 1] + x[k - 1] / (x[k - 1] - x[k]) * (run.times[k] - run.times[k - 1]));
        }
    }
    let exact = 4.0 * (1.0f64 / 9.81).sqrt() * 1.854_074_677_301_372;
    let period = crossings[1] - crossings[0];
    println!(
        "             period {period:.12} s, exact {exact:.12} s, relative error {:.1e}; rod error {:.1e} m; {:.2} s",
        (period - exact) / exact,
        w.report().joint_error,
        clock.elapsed().as_secs_f64()
    );

    // the chain: 20 links and a 10 kg weight, 5 s at dt 1/60
    let (mut w, links) = joints::chain(20)?;
    let clock = Instant::now();
    w.step(5.0)?;
    let end = w.body(*links.last().expect("a weight")).expect("live").position();
    println!(
        "chain        stretch {:.1e} m, largest joint error {:.1e} m, {:.3} ms a step",
        (2.5 - end.z) - 2.1,
        w.report().joint_error,
        clock.elapsed().as_secs_f64() * 1e3 / 300.0
    );

    // Newton's cradle: the first ball's speed at impact against the fastest the others reach in the first 0.5 s
    // (the first ball strikes at 0.36 s; the last swings out until about 0.7 s)
    let (mut w, balls) = joints::newtons_cradle(5, 0.5)?;
    let (mut impact, mut last, mut others) = (0.0f64, 0.0f64, 0.0f64);
    for _ in 0..120 {
        w.step(1.0 / 240.0)?;
        let v: Vec<f64> = balls.iter().map(|&b| w.body(b).expect("live").velocity().x).collect();
        impact = impact.max(v[0]);
        last = last.max(v[v.len() - 1]);
        others = others.max(v[1..v.len() - 1].iter().fold(0.0f64, |m, x| m.max(x.abs())));
    }
    println!(
        "cradle       first ball hits at {impact:.3} m/s; the last leaves at up to {last:.3} m/s ({:.0}%), the middle \
         ones move at up to {others:.3} m/s",
        100.0 * last / impact
    );

    // the door: its motor turns it at 1 rad/s until the limit at 1.5 rad
    let (mut w, door) = joints::door()?;
    for k in 1..=6 {
        w.step(0.5)?;
        let d = w.body(door).expect("live");
        println!(
            "door   {:.1} s angle {:.4} rad, turning at {:.4} rad/s",
            0.5 * k as f64,
            d.orientation().scaled_axis().z,
            d.angular_velocity().z
        );
    }

    // the ragdoll down the stairs
    let (mut w, parts) = joints::ragdoll()?;
    let clock = Instant::now();
    w.step(3.0)?;
    let torso = w.body(parts[0]).expect("live").position();
    let r = w.report();
    println!(
        "ragdoll      torso at ({:.2}, {:.2}, {:.2}) m after 3 s; largest joint error {:.1e} m, {:.1e} rad; {:.2} ms a step",
        torso.x,
        torso.y,
        torso.z,
        r.joint_error,
        r.joint_angle_error,
        clock.elapsed().as_secs_f64() * 1e3 / 180.0
    );
    Ok(())
}
