//! Solving independent groups (islands) on several threads, with answers in group order whatever the thread count.

use crate::error::ContactError;

/// The machine's cores, asked once (the standard library reads the cgroup files on every call: a few per cent of a
/// fast step's time when asked every step).
pub(crate) fn cores() -> usize {
    static CORES: std::sync::OnceLock<usize> = std::sync::OnceLock::new();
    *CORES.get_or_init(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}

/// Islands are independent (no body in two), so their programs are solved on up to as many threads as the machine
/// has cores, each taking the largest remaining island first; a step of fewer than `least` contacts or one island
/// stays on the calling thread (threads are started for each step: below that, starting them costs more than they
/// save). Results come back in island order, so the answer does not depend on the thread count.
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
    let mut slots: Vec<Option<Result<T, ContactError>>> = (0..groups.len()).map(|_| None).collect();
    let done: Vec<Vec<(usize, Result<T, ContactError>)>> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                scope.spawn(|| {
                    let mut mine = Vec::new();
                    loop {
                        let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                        let Some(&g) = order.get(k) else { break };
                        mine.push((g, solve(&groups[g])));
                    }
                    mine
                })
            })
            .collect();
        workers.into_iter().map(|w| w.join().expect("an island solve does not panic")).collect()
    });
    for (g, r) in done.into_iter().flatten() {
        slots[g] = Some(r);
    }
    slots.into_iter().map(|r| r.expect("every island was solved")).collect()
}
