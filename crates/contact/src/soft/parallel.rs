//! One large island's substeps on several threads, graph colour by graph colour (Box2D v3's way): every thread runs
//! the same list of stages, each on its share (a colour's bundles, a range of bodies), and waits for the others at a
//! barrier before the next. A colour's manifolds share no moving body and bodies that do not move are never written
//! (`bundle.rs`), so the threads never write the same memory, and each bundle's arithmetic is the one-thread
//! arithmetic in the same colour order: the answer is the same bit for bit on any thread count.
//!
//! What it buys is small on two cores: the 1,000-cube pile (one island, 6-9 colours of about 20 bundles) solves in
//! 3.2-3.6 ms a step on two threads against 3.6-3.8 with its islands alone spread (alternating runs); a colour's
//! sweep is a few microseconds, so the barriers and the parts still on one thread (building the rows, restitution)
//! take much of the rest.

use super::bundle::{self, Arms, Bundle, FrictionBundle, MoverPtr, Sweep};
use super::geometry;
use super::row::{Mover, RowInfo};
use std::ops::Range;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

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

/// What the threads share of an island for its substeps.
pub(crate) struct Substeps<'a> {
    pub movers: &'a mut [Mover],
    pub bundles: &'a mut [Bundle],
    pub frictions: &'a mut [FrictionBundle],
    pub arms: &'a [Arms],
    pub infos: &'a mut [RowInfo],
    /// The bundles of each colour, and whether it is the last colour (whose manifolds may share bodies: one thread
    /// sweeps it).
    pub colours: &'a [(Range<usize>, bool)],
}

/// The substeps (each: integrate velocities, warm start, `biased` passes, integrate positions, the gaps, `relax`
/// passes, the step's impulses summed) on `threads` threads.
pub(crate) fn substeps(island: Substeps, n: usize, hs: f64, passes: (usize, Sweep, Sweep), threads: usize) {
    let (iterations, biased, relax) = passes;
    let barrier = SpinBarrier::new(threads);
    let movers = Shared::new(island.movers);
    let pointer = MoverPtr::from_raw(movers.0, movers.1);
    let (bundles, frictions) = (Shared::new(island.bundles), Shared::new(island.frictions));
    let infos = Shared::new(island.infos);
    let (arms, colours) = (island.arms, island.colours);
    let all_movers = 0..movers.1;
    let all_bundles = 0..bundles.1;
    let run = |t: usize| {
        let _poison = Poison(&barrier);
        // SAFETY (every block below): each stage reaches disjoint shares (`share`) of the bodies or of a colour's
        // bundles, reads bodies through `pointer` only where no thread writes them (other colours' are behind a
        // barrier; static and kinematic bodies are never written), and ends at the barrier.
        let sweep_colours = |how: Sweep| {
            for (range, last) in colours {
                let mine = colour_share(range, *last, t, threads);
                unsafe {
                    bundle::sweep_shared(bundles.range(mine.clone()), frictions.range(mine), pointer, how);
                }
                barrier.wait();
            }
        };
        for _ in 0..n {
            for m in unsafe { movers.range(share(&all_movers, t, threads)) } {
                m.integrate_velocity(hs);
            }
            barrier.wait();
            for (range, last) in colours {
                let mine = colour_share(range, *last, t, threads);
                unsafe {
                    bundle::warm_start_shared(bundles.range(mine.clone()), frictions.range(mine), pointer);
                }
                barrier.wait();
            }
            for _ in 0..iterations {
                sweep_colours(biased);
            }
            for m in unsafe { movers.range(share(&all_movers, t, threads)) } {
                m.integrate_position(hs);
            }
            barrier.wait();
            let mine = share(&all_bundles, t, threads);
            unsafe {
                let (mine_bundles, mine_arms) = (bundles.range(mine.clone()), &arms[mine]);
                geometry::update_gaps(mine_bundles, mine_arms, movers.all());
            }
            barrier.wait();
            for _ in 0..iterations {
                sweep_colours(relax);
            }
            if t == 0 {
                unsafe {
                    let infos = infos.range(0..infos.1);
                    for bu in bundles.all() {
                        for l in 0..bu.lanes {
                            for p in 0..bu.count[l] {
                                infos[bu.info[l][p]].step_normal += bu.rows[p].normal[l];
                            }
                        }
                    }
                }
            }
            barrier.wait();
        }
    };
    std::thread::scope(|scope| {
        for t in 1..threads {
            let run = &run;
            scope.spawn(move || run(t));
        }
        run(0);
    });
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
