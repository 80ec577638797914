//! A group's substeps as one list of stages run by one scheduler, on one worker or many (Box2D v3's way): every
//! worker runs the same list, each stage on its share (a colour's bundles, a range of bodies or of bundles, a range
//! of the islands' joint sets, or all of it on worker 0 for the springs), and waits for the others at a barrier
//! before the next. A colour's manifolds share no moving body and bodies that do not move are never written
//! (`bundle.rs`), so the workers never write the same memory, and each bundle's arithmetic is the one-worker
//! arithmetic in the same colour order: the answer is the same bit for bit on any number of workers. The workers
//! are the kept pool's (`threads.rs`); on one, the barriers are a counter.
//!
//! Per substep: springs, velocities, joints' rows and warm start, the contacts' warm start colour by colour, the
//! biased passes, positions, joints' rows and the gaps, the relaxing passes, the step's impulses summed. A pass is
//! `iterations` sweeps (joints, then the contacts colour by colour); a group of a large mass ratio sweeps on until
//! its impulses settle, every worker taking the same decision from the largest change of each.

use super::bundle::{self, Arms, Bundle, FrictionBundle, MoverPtr, Sweep};
use super::geometry;
use super::joints::{JointSet, JointSweep};
use super::row::Mover;
use super::springs::SpringSet;
use std::ops::Range;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
/// A barrier that spins (the waits are microseconds), yielding the core after a while so that more threads than
/// cores still progress. A thread that panics poisons it (`Poison`), and the others then panic instead of waiting
/// for it forever.
pub(crate) struct SpinBarrier {
    threads: usize,
    arrived: AtomicUsize,
    generation: AtomicUsize,
    poisoned: AtomicBool,
}

/// Poisons the barrier if its thread unwinds while it is held.
pub(crate) struct Poison<'a>(pub &'a SpinBarrier);

impl Drop for Poison<'_> {
    fn drop(&mut self) {
        if std::thread::panicking() {
            self.0.poisoned.store(true, Ordering::Release);
        }
    }
}

impl SpinBarrier {
    pub fn new(threads: usize) -> SpinBarrier {
        SpinBarrier {
            threads,
            arrived: AtomicUsize::new(0),
            generation: AtomicUsize::new(0),
            poisoned: AtomicBool::new(false),
        }
    }

    /// Returns once every thread has called it (the writes of each before its call are seen by all after).
    pub fn wait(&self) {
        if self.threads == 1 {
            // alone: nobody to wait for (a few atomics a stage add up over a step's islands)
            return;
        }
        let generation = self.generation.load(Ordering::Acquire);
        if self.arrived.fetch_add(1, Ordering::AcqRel) + 1 == self.threads {
            self.arrived.store(0, Ordering::Relaxed);
            self.generation.fetch_add(1, Ordering::Release);
            return;
        }
        let mut spins = 0u32;
        while self.generation.load(Ordering::Acquire) == generation {
            if self.poisoned.load(Ordering::Acquire) {
                panic!("another thread of the island's solve panicked");
            }
            if spins < 4096 {
                std::hint::spin_loop();
                spins += 1;
            } else {
                std::thread::yield_now();
            }
        }
    }
}

/// Thread t's share of `range` split among `threads` (contiguous, in order).
fn share(range: &Range<usize>, t: usize, threads: usize) -> Range<usize> {
    let n = range.len();
    range.start + n * t / threads..range.start + n * (t + 1) / threads
}

/// Thread t's share of a colour's bundles: all of the last colour's (whose manifolds may share bodies) to thread 0.
fn colour_share(range: &Range<usize>, last: bool, t: usize, threads: usize) -> Range<usize> {
    match (last, t) {
        (true, 0) => range.clone(),
        (true, _) => 0..0,
        (false, _) => share(range, t, threads),
    }
}

/// A slice's elements as several threads reach them: disjoint ranges each, never the same element at once.
#[derive(Clone, Copy)]
struct Shared<T>(*mut T, usize);

// SAFETY: the pointer is only turned into disjoint ranges (`range`), one thread each between barriers.
unsafe impl<T: Send> Send for Shared<T> {}
unsafe impl<T: Send> Sync for Shared<T> {}

impl<T> Shared<T> {
    fn new(items: &mut [T]) -> Shared<T> {
        Shared(items.as_mut_ptr(), items.len())
    }

    /// All elements, to read. SAFETY: no thread writes any of them until the next barrier.
    unsafe fn all(&self) -> &[T] {
        std::slice::from_raw_parts(self.0, self.1)
    }

    /// The elements in `r`. SAFETY: no other thread reaches them until the next barrier.
    #[allow(clippy::mut_from_ref)]
    unsafe fn range(&self, r: Range<usize>) -> &mut [T] {
        assert!(r.start <= r.end && r.end <= self.1, "a range within the slice");
        std::slice::from_raw_parts_mut(self.0.add(r.start), r.len())
    }
}

/// Most sweeps of one pass of an island that sweeps until its impulses settle.
pub(crate) const MAX_SWEEPS: usize = 64;
/// A pass has converged when no impulse changed by more than this fraction of the largest.
const SETTLED: f64 = 1e-4;

/// What the workers share of a group for its substeps.
pub(crate) struct Substeps<'a> {
    pub movers: &'a mut [Mover],
    pub bundles: &'a mut [Bundle],
    pub frictions: &'a mut [FrictionBundle],
    pub arms: &'a [Arms],
    /// The bundles of each colour, and whether it is the overflow colour (whose manifolds may share bodies: one
    /// worker sweeps it).
    pub colours: &'a [(Range<usize>, bool)],
    /// Each island's joints (swept by worker 0, island after island).
    pub joints: &'a mut [JointSet],
    pub springs: &'a mut SpringSet,
    /// Whether its passes sweep on until the impulses settle.
    pub converge: bool,
}

/// How the passes sweep: `iterations` sweeps each, biased then relaxing, for the contacts and the joints.
#[derive(Clone, Copy)]
pub(crate) struct Passes<'a> {
    pub iterations: usize,
    pub biased: Sweep<'a>,
    pub relax: Sweep<'a>,
    pub biased_joints: JointSweep,
    pub relax_joints: JointSweep,
}

/// One value that only worker 0 reaches, between barriers.
struct Serial<T>(*mut T);

// SAFETY: only worker 0 dereferences it, between barriers.
unsafe impl<T: Send> Send for Serial<T> {}
unsafe impl<T: Send> Sync for Serial<T> {}

impl<T> Serial<T> {
    /// The value. SAFETY: only worker 0 calls it, between barriers, or every worker reads while none writes.
    #[allow(clippy::mut_from_ref)]
    unsafe fn get(&self) -> &mut T {
        &mut *self.0
    }
}

/// The substeps of `hs` (`n` of them) on up to `threads` workers.
pub(crate) fn substeps(island: Substeps, n: usize, hs: f64, passes: Passes, threads: usize) {
    let workers = crate::threads::Workers::new(threads);
    let threads = workers.count;
    let barrier = SpinBarrier::new(threads);
    let movers = Shared::new(island.movers);
    let pointer = MoverPtr::from_raw(movers.0, movers.1);
    let (bundles, frictions) = (Shared::new(island.bundles), Shared::new(island.frictions));
    let (arms, colours, converge) = (island.arms, island.colours, island.converge);
    let (has_joints, has_springs) = (!island.joints.is_empty(), !island.springs.is_empty());
    let all_joints = 0..island.joints.len();
    let joints = Shared::new(island.joints);
    let springs = Serial(island.springs as *mut SpringSet);
    let changes: Vec<AtomicU64> = (0..threads).map(|_| AtomicU64::new(0)).collect();
    let all_movers = 0..movers.1;
    let all_bundles = 0..bundles.1;
    // the stages of a sweep: one a colour on several workers; on one, a single stage over all the bundles (the
    // colours are consecutive runs of them: the same arithmetic in the same order, without a call a colour)
    let whole = [(all_bundles.clone(), true)];
    let colour_stages: &[(Range<usize>, bool)] = if threads == 1 { &whole } else { colours };
    let run = |t: usize| {
        let _poison = Poison(&barrier);
        // SAFETY (every block below): each stage reaches disjoint shares (`share`) of the bodies or of a colour's
        // bundles, or worker 0 reaches all of it, reads bodies through `pointer` only where no worker writes them
        // (other colours' are behind a barrier; static and kinematic bodies are never written), and ends at the
        // barrier.
        let pass = |how: Sweep, joint_how: JointSweep| {
            let extra = if converge { MAX_SWEEPS } else { 0 };
            for k in 0..passes.iterations + extra {
                let mut change = 0.0f64;
                if has_joints {
                    if t == 0 {
                        for set in unsafe { joints.range(all_joints.clone()) } {
                            change = change.max(set.sweep(unsafe { movers.range(all_movers.clone()) }, joint_how));
                        }
                    }
                    barrier.wait();
                }
                for (range, last) in colour_stages {
                    let mine = colour_share(range, *last, t, threads);
                    let swept = unsafe {
                        bundle::sweep_shared(bundles.range(mine.clone()), frictions.range(mine), pointer, how)
                    };
                    change = change.max(swept);
                    barrier.wait();
                }
                if extra > 0 && k + 1 >= passes.iterations {
                    changes[t].store(change.to_bits(), Ordering::Relaxed);
                    barrier.wait();
                    let change = changes[..threads]
                        .iter()
                        .map(|c| f64::from_bits(c.load(Ordering::Relaxed)))
                        .fold(0.0, f64::max);
                    let contacts = unsafe { bundles.all() }
                        .iter()
                        .flat_map(|bu| bu.rows.iter().flat_map(|r| r.normal))
                        .fold(0.0f64, f64::max);
                    let largest = unsafe { joints.all() }.iter().fold(contacts, |m, set| m.max(set.largest()));
                    // every worker has read before any writes again
                    barrier.wait();
                    if change <= SETTLED * largest {
                        break;
                    }
                }
            }
        };
        for _ in 0..n {
            if has_springs {
                if t == 0 {
                    unsafe { springs.get().apply(movers.range(all_movers.clone()), hs) };
                }
                barrier.wait();
            }
            for m in unsafe { movers.range(share(&all_movers, t, threads)) } {
                m.integrate_velocity(hs);
            }
            barrier.wait();
            if has_joints {
                if t == 0 {
                    for set in unsafe { joints.range(all_joints.clone()) } {
                        unsafe {
                            set.prepare(movers.all());
                            set.warm_start(movers.range(all_movers.clone()));
                        }
                    }
                }
                barrier.wait();
            }
            for (range, last) in colour_stages {
                let mine = colour_share(range, *last, t, threads);
                unsafe {
                    bundle::warm_start_shared(bundles.range(mine.clone()), frictions.range(mine), pointer);
                }
                barrier.wait();
            }
            pass(passes.biased, passes.biased_joints);
            for m in unsafe { movers.range(share(&all_movers, t, threads)) } {
                m.integrate_position(hs);
            }
            barrier.wait();
            if has_joints && t == 0 {
                for set in unsafe { joints.range(all_joints.clone()) } {
                    set.prepare(unsafe { movers.all() });
                }
            }
            let mine = share(&all_bundles, t, threads);
            unsafe {
                let (mine_bundles, mine_arms) = (bundles.range(mine.clone()), &arms[mine]);
                geometry::update_gaps(mine_bundles, mine_arms, movers.all());
            }
            barrier.wait();
            pass(passes.relax, passes.relax_joints);
            if has_joints && t == 0 {
                for set in unsafe { joints.range(all_joints.clone()) } {
                    set.end_substep();
                }
            }
            let mine = share(&all_bundles, t, threads);
            let (mine_bundles, mine_frictions) = unsafe { (bundles.range(mine.clone()), frictions.range(mine)) };
            for (bu, fr) in mine_bundles.iter_mut().zip(mine_frictions) {
                for row in &mut bu.rows[..bu.points] {
                    row.step = std::array::from_fn(|l| row.step[l] + row.normal[l]);
                    row.weighed = std::array::from_fn(|l| row.weighed[l] * bu.decay[l] + row.normal[l]);
                }
                fr.end_substep(&bu.decay);
            }
            barrier.wait();
        }
    };
    workers.run(run);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_thread_that_panics_does_not_leave_the_others_waiting() {
        // Two threads share a barrier; one panics before reaching it. The other must not wait forever: it panics
        // too, and the scope hands the panic to the caller.
        let barrier = SpinBarrier::new(2);
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            std::thread::scope(|scope| {
                scope.spawn(|| {
                    let _poison = Poison(&barrier);
                    panic!("a failing share");
                });
                let _poison = Poison(&barrier);
                barrier.wait();
            })
        }));
        assert!(outcome.is_err());
        // and a barrier that no thread poisons lets its threads through, stage after stage
        let barrier = SpinBarrier::new(3);
        let passed = AtomicUsize::new(0);
        std::thread::scope(|scope| {
            for _ in 0..3 {
                scope.spawn(|| {
                    for _ in 0..100 {
                        barrier.wait();
                    }
                    passed.fetch_add(1, Ordering::Relaxed);
                });
            }
        });
        assert_eq!(passed.load(Ordering::Relaxed), 3);
    }
}
