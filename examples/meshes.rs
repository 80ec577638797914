//! The mesh scenes, each mesh built in code: a ball dropped into a cup (and onto the cup's hull), a ring tossed onto
//! a peg, a chair of one mesh on its legs, a rolling torus (accurate mode), and the 50-mesh pile (fast mode). Prints
//! where things end, the convex pieces and the wall time.
//!
//! `cargo run --release --example meshes`

use nalgebra::Vector3;
use std::time::Instant;
use tumble::scenes::meshes::{ball_in_cup, chair, mesh_pile, ring_on_peg, torus_roll};
use tumble::{BodyHandle, Mode, World, WorldError};

fn run(name: &str, (mut w, body): (World, BodyHandle), seconds: f64) -> Result<(), WorldError> {
    let clock = Instant::now();
    w.step(seconds)?;
    let b = w.body(body).expect("the scene's body");
    let tilt = (b.orientation() * Vector3::z()).z.clamp(-1.0, 1.0).acos().to_degrees();
    let p = b.position();
    println!(
        "{name:<24} after {seconds} s: at ({:+.4}, {:+.4}, {:.4}) m, tilted {tilt:6.2} deg; {:>3} pieces, {:.3} s",
        p.x,
        p.y,
        p.z,
        w.report().mesh_pieces,
        clock.elapsed().as_secs_f64()
    );
    Ok(())
}

fn main() -> Result<(), WorldError> {
    let accurate = Mode::default;
    let (w, _, ball) = ball_in_cup(accurate(), false)?;
    run("ball in the cup", (w, ball), 3.0)?;
    let (w, _, ball) = ball_in_cup(accurate(), true)?;
    run("ball on the cup's hull", (w, ball), 3.0)?;
    let (w, _, ring) = ring_on_peg(accurate())?;
    run("ring on the peg", (w, ring), 3.0)?;
    run("chair", chair(accurate())?, 2.0)?;
    run("torus rolling", torus_roll(accurate())?, 2.0)?;
    let (w, bodies) = mesh_pile(Mode::fast(1.0 / 240.0), 50, false)?;
    run("50-mesh pile (fast)", (w, bodies[0]), 3.0)?;
    Ok(())
}
