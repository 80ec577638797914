//! Twenty dominoes fall one after another (fast mode); prints when each one has fallen and the run report.
//!
//! `cargo run --release --example dominoes`

use tumble::scenes::Dominoes;

fn main() -> Result<(), tumble::WorldError> {
    let (mut world, row) = Dominoes::default().build()?;
    println!("plan    {}", world.plan());
    let run = world.run(6.0, 1.0 / 60.0)?;
    for (k, _) in row.iter().enumerate() {
        // fallen: its centre has dropped below 60% of its standing height
        let fell = (0..run.frames()).find(|&f| run.body_position(f, k + 1).z < 0.6 * 0.4).map(|f| run.times[f]);
        match fell {
            Some(t) => println!("domino {:>2} down at {t:.3} s", k + 1),
            None => println!("domino {:>2} still standing", k + 1),
        }
    }
    println!("{}", run.report);
    Ok(())
}
