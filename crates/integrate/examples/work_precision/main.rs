//! Error against run time for every applicable method on the reference problems.
//!
//! ```text
//! cargo run --release -p tumble-integrate --example work_precision -- --out DIR
//!     [--problem NAME]...   only these problems (default: all eight)
//!     [--peer CSV]...       overlay another tool's runs (same columns), e.g. benches/peers/scipy_work_precision.py's
//!     [--budget SECONDS]    timing budget per point (default 0.05): repeats until spent, keeps the fastest
//! ```
//!
//! Writes `DIR/work_precision.csv` (problem,method,param,error,seconds,rhs_evals,steps,rejected) and
//! `DIR/<problem>.png` (error against seconds, log-log, one curve per method). With peers it also prints, and
//! writes to `DIR/comparison.md`, the time of our best method and of the peer's best method at equal error.

mod plot;

use std::io::Write;
use std::path::PathBuf;
use std::time::{Duration, Instant};
use tumble_integrate::problems;
use tumble_integrate::work_precision::{best_time_at, sweep_problem, PrecisionRun, CSV_HEADER};

struct Args {
    out: PathBuf,
    problems: Vec<String>,
    peers: Vec<PathBuf>,
    budget: f64,
}

fn parse_args() -> Result<Args, String> {
    let mut args = Args { out: PathBuf::new(), problems: vec![], peers: vec![], budget: 0.05 };
    let mut it = std::env::args().skip(1);
    let mut out = None;
    while let Some(a) = it.next() {
        let mut value = || it.next().ok_or(format!("{a} needs a value"));
        match a.as_str() {
            "--out" => out = Some(PathBuf::from(value()?)),
            "--problem" => args.problems.push(value()?),
            "--peer" => args.peers.push(PathBuf::from(value()?)),
            "--budget" => args.budget = value()?.parse().map_err(|e| format!("--budget: {e}"))?,
            "-h" | "--help" => return Err(String::new()),
            other => return Err(format!("unknown argument {other}")),
        }
    }
    args.out = out.ok_or("--out DIR is required")?;
    let known: Vec<&str> = problems::all().iter().map(|p| p.name).collect();
    if let Some(bad) = args.problems.iter().find(|p| !known.contains(&p.as_str())) {
        return Err(format!("unknown problem {bad}; known: {}", known.join(", ")));
    }
    Ok(args)
}

fn read_runs(path: &PathBuf) -> Result<Vec<PrecisionRun>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(text.lines().skip(1).filter_map(PrecisionRun::parse_csv_row).collect())
}

fn main() {
    let args = match parse_args() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("{e}\nusage: work_precision --out DIR [--problem NAME]... [--peer CSV]... [--budget SECONDS]");
            std::process::exit(2);
        }
    };
    std::fs::create_dir_all(&args.out).expect("create the output directory");
    let peers: Vec<PrecisionRun> =
        args.peers.iter().flat_map(|p| read_runs(p).unwrap_or_else(|e| panic!("{e}"))).collect();
    let selected: Vec<_> = problems::all()
        .into_iter()
        .filter(|p| args.problems.is_empty() || args.problems.iter().any(|n| n == p.name))
        .collect();

    let clock = Instant::now();
    let mut all = Vec::new();
    for problem in &selected {
        eprint!("{:15}", problem.name);
        let mut skipped = 0;
        let runs = sweep_problem(problem, Duration::from_secs_f64(args.budget), |_, _, _| skipped += 1)
            .unwrap_or_else(|e| panic!("{}: reference failed: {e}", problem.name));
        eprintln!(
            "{} points ({} left out: unstable, over budget or error > 1), {:.1} s",
            runs.len(),
            skipped,
            clock.elapsed().as_secs_f64()
        );
        let peer_runs: Vec<PrecisionRun> = peers.iter().filter(|r| r.problem == problem.name).cloned().collect();
        let png = args.out.join(format!("{}.png", problem.name));
        plot::work_precision(&png, problem.name, &runs, &peer_runs)
            .unwrap_or_else(|e| panic!("plot {}: {e}", png.display()));
        all.extend(runs);
    }

    let csv = args.out.join("work_precision.csv");
    let mut f = std::fs::File::create(&csv).expect("create the CSV");
    writeln!(f, "{CSV_HEADER}").unwrap();
    for r in &all {
        writeln!(f, "{}", r.csv_row()).unwrap();
    }
    println!("wrote {} ({} points) and {} plots to {}", csv.display(), all.len(), selected.len(), args.out.display());
    if !peers.is_empty() {
        let table = comparison(&selected.iter().map(|p| p.name).collect::<Vec<_>>(), &all, &peers);
        print!("{table}");
        std::fs::write(args.out.join("comparison.md"), &table).expect("write comparison.md");
    }
}

/// For each problem and each error level 1e-3 .. 1e-10 that both sides reach: our best time, the peer's best
/// time, and their ratio.
fn comparison(problems: &[&str], ours: &[PrecisionRun], peers: &[PrecisionRun]) -> String {
    let mut s = String::from(
        "| problem | error | ours (best method) | peer (best method) | peer / ours |\n|---|---|---|---|---|\n",
    );
    for &name in problems {
        let mine: Vec<PrecisionRun> = ours.iter().filter(|r| r.problem == name).cloned().collect();
        let theirs: Vec<PrecisionRun> = peers.iter().filter(|r| r.problem == name).cloned().collect();
        for k in 3..=10 {
            let e = 10f64.powi(-k);
            if let (Some((a, am)), Some((b, bm))) = (best_time_at(&mine, e), best_time_at(&theirs, e)) {
                s += &format!("| {name} | 1e-{k} | {:.3e} s ({am}) | {:.3e} s ({bm}) | {:.0} |\n", a, b, b / a);
            }
        }
    }
    s
}
