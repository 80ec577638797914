//! A 16 x 16 cloth pinned at two corners falls and swings under gravity; prints the plan and the run report.
//!
//! `cargo run --release --example cloth`

use tumble::scenes::Cloth;

fn main() -> Result<(), tumble::WorldError> {
    let (mut world, _) = Cloth::default().build()?;
    println!("plan    {}", world.plan());
    let run = world.run(3.0, 1.0 / 60.0)?;
    let last = run.frames() - 1;
    println!("energy  {:.6} J -> {:.6} J", run.energy(0), run.energy(last));
    println!("{}", run.report);
    Ok(())
}
