//! The workers that solve on several threads: a pool per thread count, started once per process and kept (rayon),
//! run as `workers` of one job each, the calling thread being worker 0; and independent groups (islands) solved
//! on them, with answers in group order whatever the thread count.

use crate::error::ContactError;
use std::sync::{Arc, Mutex, OnceLock};

/// The machine's cores, asked once (the standard library reads the cgroup files on every call: a few per cent of a
/// fast step's time when asked every step).
pub fn cores() -> usize {
    static CORES: OnceLock<usize> = OnceLock::new();
    *CORES.get_or_init(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}

/// The kept pools, by their number of threads.
type Pools = Mutex<Vec<(usize, Arc<rayon::ThreadPool>)>>;

/// The pool of `helpers` threads (kept for the process: threads are started once, not every step), or none if it
/// cannot be started (then the caller works alone).
fn pool(helpers: usize) -> Option<Arc<rayon::ThreadPool>> {
    static POOLS: OnceLock<Pools> = OnceLock::new();
    let pools = POOLS.get_or_init(|| Mutex::new(Vec::new()));
    let mut pools = pools.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, p)) = pools.iter().find(|(n, _)| *n == helpers) {
        return Some(p.clone());
    }
    let built = rayon::ThreadPoolBuilder::new()
        .num_threads(helpers)
        .thread_name(|k| format!("tumble-solver-{k}"))
        .build()
        .ok()?;
    let built = Arc::new(built);
    pools.push((helpers, built.clone()));
    Some(built)
}

/// Workers for one job each, at once: worker 0 the calling thread, the others the kept pool's.
pub struct Workers {
    pool: Option<Arc<rayon::ThreadPool>>,
    /// How many run (1 if no pool could be started).
    pub count: usize,
}

impl Workers {
    /// Up to `threads` workers (at least one).
    pub fn new(threads: usize) -> Workers {
        match (threads > 1).then(|| pool(threads - 1)).flatten() {
            Some(pool) => Workers { pool: Some(pool), count: threads },
            None => Workers { pool: None, count: 1 },
        }
    }

    /// Runs `job(t)` for every worker t in 0..count at once (each on its own thread, so that the jobs may wait for
    /// each other at a barrier).
    pub fn run(&self, job: impl Fn(usize) + Sync) {
        match &self.pool {
            None => job(0),
            Some(pool) => pool.in_place_scope(|scope| {
                scope.spawn_broadcast(|_, ctx| job(ctx.index() + 1));
                job(0);
            }),
        }
    }
}

/// Islands are independent (no body in two), so their programs are solved on up to as many threads as the machine
/// has cores, each taking the largest remaining island first; a step of fewer than `least` contacts or one island
/// stays on the calling thread (below that, sharing out the work costs more than it saves). Results come back in
/// island order, so the answer does not depend on the thread count.
/// Groups of any kind, `size` giving the work of one (the largest start first).
pub(crate) fn in_parallel_by<G: Sync, T: Send>(
    groups: &[G],
    size: impl Fn(&G) -> usize + Sync,
    (contacts, least): (usize, usize),
    threads: usize,
    solve: impl Fn(&G) -> Result<T, ContactError> + Sync,
) -> Vec<Result<T, ContactError>> {
    let threads = if threads == 0 { cores() } else { threads }.min(groups.len());
    if threads < 2 || contacts < least {
        return groups.iter().map(&solve).collect();
    }
    let mut order: Vec<usize> = (0..groups.len()).collect();
    order.sort_by_key(|&g| std::cmp::Reverse(size(&groups[g])));
    let next = std::sync::atomic::AtomicUsize::new(0);
    let workers = Workers::new(threads);
    type Solved<T> = Mutex<Vec<(usize, Result<T, ContactError>)>>;
    let done: Vec<Solved<T>> = (0..workers.count).map(|_| Mutex::new(Vec::new())).collect();
    workers.run(|t| {
        let mut mine = Vec::new();
        loop {
            let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            let Some(&g) = order.get(k) else { break };
            mine.push((g, solve(&groups[g])));
        }
        *done[t].lock().unwrap_or_else(|e| e.into_inner()) = mine;
    });
    let mut slots: Vec<Option<Result<T, ContactError>>> = (0..groups.len()).map(|_| None).collect();
    for (g, r) in done.into_iter().flat_map(|d| d.into_inner().unwrap_or_else(|e| e.into_inner())) {
        slots[g] = Some(r);
    }
    slots.into_iter().map(|r| r.expect("every island was solved")).collect()
}
