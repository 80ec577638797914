//! A ten-layer pyramid of 55 cubes stands for 10 s (fast mode); prints how far any cube moved and the report.
//!
//! `cargo run --release --example pyramid`

use tumble::scenes::Pyramid;

fn main() -> Result<(), tumble::WorldError> {
    let (mut world, cubes) = Pyramid::default().build()?;
    println!("plan    {}", world.plan());
    let start: Vec<_> = cubes.iter().map(|&c| world.body(c).map(|b| b.position())).collect::<Result<_, _>>()?;
    let run = world.run(10.0, 0.5)?;
    let moved = cubes
        .iter()
        .zip(&start)
        .map(|(&c, s)| world.body(c).map(|b| (b.position() - s).norm()))
        .collect::<Result<Vec<_>, _>>()?;
    println!("{} cubes; the farthest moved {:.2e} m", cubes.len(), moved.iter().fold(0.0f64, |m, d| m.max(*d)));
    println!("{}", run.report);
    Ok(())
}
