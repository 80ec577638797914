//! A 12 x 12 cloth of particles falls over a ball and drapes onto the floor (fast mode); prints the lowest and
//! highest particle over time and the run report.
//!
//! `cargo run --release --example cloth_drape`

use tumble::scenes::ClothDrape;

fn main() -> Result<(), tumble::WorldError> {
    let (mut world, ps) = ClothDrape::default().build()?;
    println!("plan    {}", world.plan());
    let run = world.run(3.0, 0.25)?;
    for f in 0..run.frames() {
        let z: Vec<f64> = (0..ps.len()).map(|i| run.particle_position(f, i).z).collect();
        let (lo, hi) = (z.iter().cloned().fold(f64::MAX, f64::min), z.iter().cloned().fold(f64::MIN, f64::max));
        println!("t {:.2} s  particles between z = {lo:.3} and {hi:.3} m", run.times[f]);
    }
    println!("{}", run.report);
    Ok(())
}
