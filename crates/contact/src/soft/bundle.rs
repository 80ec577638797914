//! Manifolds of one colour swept eight at a time. A lane holds a manifold (a body pair and its contact points, up
//! to four), solved point by point (normal, then its friction) as engines do, so that the pair's velocities are
//! gathered once for its points. Manifolds of a colour share no moving body (`graph.rs`), so solving eight of them
//! side by side gives what solving them one after another gives, bit for bit: the same arithmetic on each, lane by
//! lane, which the compiler turns into vector instructions. A bundle holds its lanes' rows as structure of arrays;
//! a sweep gathers its bodies' velocities into lanes, solves, and writes them back.
//!
//! Why eight lanes: a point's solve is a chain of dependent operations (speed, impulse, clamp, apply, friction
//! speed, circle, apply) that the processor cannot overlap with the next lane's when one bundle's instructions
//! fill its window; eight lanes give each step of the chain twice the work of four. Measured on the 1,000-cube pile
//! with a row (point) a lane (one thread, solving time a step, alternating runs): rows one by one 5.8-6.4 ms, four
//! lanes 5.9-6.4, eight 4.9-5.6, sixteen 5.7-6.3; then a manifold a lane, eight lanes: 4.2-4.7 ms against 5.1-5.5
//! (the 100-cube pile 0.34-0.42 against 0.43-0.47 ms).

pub(crate) use super::friction_bundle::FrictionBundle;
use super::row::Mover;
use super::softness::Softness;

use super::wide::{dot, wide3, Wide};
pub(crate) use super::wide::{Lanes, Vec3Lanes, W};
/// One constraint axis of each lane's row (see `Axis`).
#[derive(Clone, Debug, Default)]
pub(crate) struct AxisLanes {
    pub dir: Vec3Lanes,
    pub ca: Vec3Lanes,
    pub cb: Vec3Lanes,
    pub ia: Vec3Lanes,
    pub ib: Vec3Lanes,
    pub mass: Lanes,
}

impl AxisLanes {
    /// Sets lane `l`'s direction (the rest comes from `build`).
    pub fn set_dir(&mut self, l: usize, dir: &nalgebra::Vector3<f64>) {
        for i in 0..3 {
            self.dir[i][l] = dir[i];
        }
    }

    /// The direction of lane `l`.
    pub fn dir_of(&self, l: usize) -> nalgebra::Vector3<f64> {
        nalgebra::Vector3::new(self.dir[0][l], self.dir[1][l], self.dir[2][l])
    }

    /// The relative velocity along lane `l`'s axis of B's point against A's (as `Axis::speed`).
    pub fn speed_of(&self, l: usize, a: &Mover, b: &Mover) -> f64 {
        let d = b.v - a.v;
        let linear = self.dir[0][l] * d[0] + self.dir[1][l] * d[1] + self.dir[2][l] * d[2];
        let turn_b = self.cb[0][l] * b.w[0] + self.cb[1][l] * b.w[1] + self.cb[2][l] * b.w[2];
        let turn_a = self.ca[0][l] * a.w[0] + self.ca[1][l] * a.w[1] + self.ca[2][l] * a.w[2];
        linear + turn_b - turn_a
    }

    /// Applies an impulse of `p` along lane `l`'s axis: +p on B, -p on A (as `Axis::apply`).
    pub fn apply_of(&self, l: usize, a: &mut Mover, b: &mut Mover, p: f64) {
        for i in 0..3 {
            a.v[i] -= self.dir[i][l] * (p * a.inv_mass);
            a.w[i] -= self.ia[i][l] * p;
            b.v[i] += self.dir[i][l] * (p * b.inv_mass);
            b.w[i] += self.ib[i][l] * p;
        }
    }

    /// The relative speed of every lane from gathered velocities.
    #[inline(always)]
    fn speed(&self, v: &Gathered) -> Wide {
        let d = [v.vb[0] - v.va[0], v.vb[1] - v.va[1], v.vb[2] - v.va[2]];
        dot(&wide3(&self.dir), &d) + dot(&wide3(&self.cb), &v.wb) - dot(&wide3(&self.ca), &v.wa)
    }

    /// Applies each lane's impulse `p` to gathered velocities.
    #[inline(always)]
    fn apply(&self, p: Wide, v: &mut Gathered) {
        let (pa, pb) = (p * v.ima, p * v.imb);
        for i in 0..3 {
            let dir = Wide(self.dir[i]);
            v.va[i] = v.va[i] - dir * pa;
            v.wa[i] = v.wa[i] - Wide(self.ia[i]) * p;
            v.vb[i] = v.vb[i] + dir * pb;
            v.wb[i] = v.wb[i] + Wide(self.ib[i]) * p;
        }
    }
}

/// Contact points of a manifold solved in one lane (parry's manifolds are reduced to four).
pub(crate) const P: usize = 4;

/// One contact point of each lane's manifold: its normal row.
#[derive(Clone, Debug, Default)]
pub(crate) struct PointLanes {
    pub normal_axis: AxisLanes,
    /// The gap where the substeps have moved the bodies (negative: penetration).
    pub gap: Lanes,
    /// Accumulated normal impulse of the current substep, and the largest it has been.
    pub normal: Lanes,
    pub max_normal: Lanes,
    /// Normal speed at the step's start (for restitution), and the normal impulse over the step so far (each
    /// substep's accumulated impulse, plus restitution's).
    pub closing: Lanes,
    pub step: Lanes,
    /// The normal impulse over the step so far with each substep's weighed by the lane's `decay` once a later
    /// substep (`SoftStep::manifold_impulses`).
    pub weighed: Lanes,
}

/// A bundle: up to W manifolds of one colour (a lane each: a body pair and up to P contact points), their normal
/// rows; what every sweep reads and writes. A lane's points past its count are empty (zero axes, never pushing).
#[derive(Clone, Debug, Default)]
pub(crate) struct Bundle {
    /// Lanes used (the rest are empty and never written back).
    pub lanes: usize,
    /// Points of its fullest lane.
    pub points: usize,
    /// Points of each lane, and its manifold (an index into the step's).
    pub count: [usize; W],
    pub manifold: [usize; W],
    pub a: [usize; W],
    pub b: [usize; W],
    /// Inverse masses of the two bodies.
    pub ima: Lanes,
    pub imb: Lanes,
    /// Against a static or kinematic body (stiffer softness).
    pub fixed: [bool; W],
    /// Whether each lane's bodies A and B move (can take an impulse).
    pub moves: [(bool, bool); W],
    /// Each lane's coefficient of restitution.
    pub restitution: Lanes,
    /// Each lane's weight on its impulses a substep later (its window's decay, `SoftLinks::manifold_windows`; 1 for
    /// a plain sum).
    pub decay: Lanes,
    pub rows: [PointLanes; P],
}

/// Where a bundle's points sit on their bodies, for the gaps as the bodies move: the arms from the centres and the
/// gaps at the step's start; and the friction centre's arms.
#[derive(Clone, Debug, Default)]
pub(crate) struct Arms {
    pub ra: [Vec3Lanes; P],
    pub rb: [Vec3Lanes; P],
    pub gap: [Lanes; P],
    pub centre_a: Vec3Lanes,
    pub centre_b: Vec3Lanes,
}

/// A bundle's bodies' velocities gathered into lanes.
struct Gathered {
    va: [Wide; 3],
    wa: [Wide; 3],
    vb: [Wide; 3],
    wb: [Wide; 3],
    ima: Wide,
    imb: Wide,
}

impl Gathered {
    /// SAFETY: as `MoverPtr::get` for the bundle's bodies.
    #[inline(always)]
    unsafe fn new(bundle: &Bundle, movers: MoverPtr) -> Gathered {
        let mut g = Gathered {
            va: [Wide::default(); 3],
            wa: [Wide::default(); 3],
            vb: [Wide::default(); 3],
            wb: [Wide::default(); 3],
            ima: Wide(bundle.ima),
            imb: Wide(bundle.imb),
        };
        for l in 0..bundle.lanes {
            let (a, b) = (movers.get(bundle.a[l]), movers.get(bundle.b[l]));
            for i in 0..3 {
                g.va[i].0[l] = a.v[i];
                g.wa[i].0[l] = a.w[i];
                g.vb[i].0[l] = b.v[i];
                g.wb[i].0[l] = b.w[i];
            }
        }
        g
    }

    /// Writes the used lanes' moving bodies back (an impulse changes nothing on a static or kinematic body, which
    /// several lanes, and threads, may share). SAFETY: as `MoverPtr::set` for the bundle's moving bodies.
    #[inline(always)]
    unsafe fn scatter(&self, bundle: &Bundle, movers: MoverPtr) {
        let lane = |x: &[Wide; 3], l: usize| [x[0].0[l], x[1].0[l], x[2].0[l]];
        for l in 0..bundle.lanes {
            if bundle.moves[l].0 {
                movers.set(bundle.a[l], lane(&self.va, l), lane(&self.wa, l));
            }
            if bundle.moves[l].1 {
                movers.set(bundle.b[l], lane(&self.vb, l), lane(&self.wb, l));
            }
        }
    }
}

/// The island's bodies as sweeps reach them: by index through a pointer, so that threads sweeping different
/// bundles of one colour can share them (`stages.rs`): such bundles touch different moving bodies, and bodies that
/// do not move are read, never written.
#[derive(Clone, Copy)]
pub(crate) struct MoverPtr(*mut Mover, usize);

// SAFETY: see the type: the threads that share it reach disjoint moving bodies between barriers.
unsafe impl Send for MoverPtr {}
unsafe impl Sync for MoverPtr {}

impl MoverPtr {
    pub fn from_raw(movers: *mut Mover, len: usize) -> MoverPtr {
        MoverPtr(movers, len)
    }

    /// Body `i`. SAFETY: no thread writes it meanwhile.
    #[inline(always)]
    unsafe fn get(&self, i: usize) -> &Mover {
        assert!(i < self.1, "a body of the island");
        &*self.0.add(i)
    }

    /// Body `i`'s velocities set. SAFETY: no other thread reaches it meanwhile.
    #[inline(always)]
    unsafe fn set(&self, i: usize, v: [f64; 3], w: [f64; 3]) {
        assert!(i < self.1, "a body of the island");
        let m = self.0.add(i);
        (*m).v = v.into();
        (*m).w = w.into();
    }
}

/// How a sweep treats the normal rows: with the soft bias (contact and static-contact softness) or rigid.
#[derive(Clone, Copy)]
pub(crate) struct Sweep<'a> {
    pub hs: f64,
    pub soft: Option<(&'a Softness, &'a Softness)>,
    pub max_push: f64,
    pub friction: bool,
}

/// Tests set this to take the portable path on a processor that has AVX2 (whose bits must be the same).
#[cfg(test)]
pub(crate) static PORTABLE: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Whether to take the AVX2 build of the sweeps (four f64 lanes a register; the portable build has two, and the
/// same bits): where the processor has it and the environment variable `TUMBLE_PORTABLE` is not set (tools that
/// run the program on a processor of their own, as valgrind does, may not know every AVX2 instruction).
#[cfg(target_arch = "x86_64")]
pub(crate) fn avx2() -> bool {
    static AVX2: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    #[cfg(test)]
    if PORTABLE.load(std::sync::atomic::Ordering::Relaxed) {
        return false;
    }
    *AVX2.get_or_init(|| std::is_x86_feature_detected!("avx2") && std::env::var_os("TUMBLE_PORTABLE").is_none())
}

/// One sweep over the bundles in order: normal rows with the soft bias or rigid, then friction (Coulomb's circle)
/// if asked, through shared bodies; returns the largest change of a normal impulse.
/// SAFETY: no other thread reaches the bundles' moving bodies meanwhile, nor writes
/// their other bodies.
pub(crate) unsafe fn sweep_shared(
    bundles: &mut [Bundle],
    frictions: &mut [FrictionBundle],
    movers: MoverPtr,
    s: Sweep,
) -> f64 {
    #[cfg(target_arch = "x86_64")]
    if avx2() {
        // the processor has AVX2 (checked just above)
        return sweep_avx2(bundles, frictions, movers, s);
    }
    sweep_lanes(bundles, frictions, movers, s)
}

/// `sweep_lanes` compiled for AVX2. No fused multiply-add: the bits are those of the portable build.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn sweep_avx2(bundles: &mut [Bundle], frictions: &mut [FrictionBundle], movers: MoverPtr, s: Sweep) -> f64 {
    sweep_lanes(bundles, frictions, movers, s)
}

#[inline(always)]
unsafe fn sweep_lanes(bundles: &mut [Bundle], frictions: &mut [FrictionBundle], movers: MoverPtr, s: Sweep) -> f64 {
    let mut change = Wide::default();
    let (zero, one) = (Wide::splat(0.0), Wide::splat(1.0));
    for (bu, fr) in bundles.iter_mut().zip(frictions.iter_mut()) {
        let mut v = Gathered::new(bu, movers);
        // the softness of each lane: stiffer against static and kinematic bodies
        let (soft_rate, soft_mass, soft_impulse) = match s.soft {
            Some((contact, fixed)) => {
                let pick =
                    |f: fn(&Softness) -> f64| Wide::select(bu.fixed, Wide::splat(f(fixed)), Wide::splat(f(contact)));
                (Some(pick(|x| x.bias_rate)), pick(|x| x.mass_scale), pick(|x| x.impulse_scale))
            }
            None => (None, one, zero),
        };
        let (mut total, mut twist_limit) = (zero, zero);
        for (row, lever) in bu.rows[..bu.points].iter_mut().zip(&fr.lever) {
            let vn = row.normal_axis.speed(&v);
            let (gap, normal) = (Wide(row.gap), Wide(row.normal));
            // speculative (a gap): close it in the substep and no more; touching: the soft bias, or rigid
            let open = gap.gt(zero);
            let bias = match soft_rate {
                Some(rate) => (rate * gap).max(Wide::splat(-s.max_push)),
                None => zero,
            };
            let bias = Wide::select(open, gap / Wide::splat(s.hs), bias);
            let mass_scale = Wide::select(open, one, soft_mass);
            let impulse_scale = Wide::select(open, zero, soft_impulse);
            let impulse = Wide(row.normal_axis.mass).neg() * mass_scale * (vn + bias) - impulse_scale * normal;
            let new = (normal + impulse).max(zero);
            let delta = new - normal;
            change = change.max(delta.abs());
            row.normal = new.0;
            row.max_normal = Wide(row.max_normal).max(new).0;
            row.normal_axis.apply(delta, &mut v);
            total = total + new;
            twist_limit = twist_limit + Wide(*lever) * new;
        }
        if s.friction {
            let friction = Wide(fr.friction);
            // the twist about the normal, then the two tangents through the centre
            let tw = &fr.twist_axis;
            let old = Wide(fr.twist);
            let limit =
                if fr.resists { friction * twist_limit + Wide(fr.torsion) * total } else { friction * twist_limit };
            let new = (old - Wide(tw.mass) * tw.speed(&v)).max(limit.neg()).min(limit);
            fr.twist = new.0;
            tw.apply(new - old, &mut v);
            if fr.resists {
                // rolling resistance: the relative turn across the normal, within its disc
                let [r0, r1] = &fr.roll_axes;
                let (s0, s1) = (r0.speed(&v), r1.speed(&v));
                let old = [Wide(fr.roll[0]), Wide(fr.roll[1])];
                let [m00, m01, m11] = fr.roll_block.map(Wide);
                let new = [old[0] - (m00 * s0 + m01 * s1), old[1] - (m01 * s0 + m11 * s1)];
                let limit = Wide(fr.rolling) * total;
                let size = (new[0] * new[0] + new[1] * new[1]).sqrt();
                let scale = Wide::select(size.gt(limit), Wide::select(size.gt(zero), limit / size, zero), one);
                let new = [new[0] * scale, new[1] * scale];
                fr.roll = [new[0].0, new[1].0];
                r0.apply(new[0] - old[0], &mut v);
                r1.apply(new[1] - old[1], &mut v);
            }
            let [t0, t1] = &fr.axes;
            let (s0, s1) = (t0.speed(&v), t1.speed(&v));
            let old = [Wide(fr.tangent[0]), Wide(fr.tangent[1])];
            let [m00, m01, m11] = fr.block.map(Wide);
            let new = [old[0] - (m00 * s0 + m01 * s1), old[1] - (m01 * s0 + m11 * s1)];
            let limit = friction * total;
            let size = (new[0] * new[0] + new[1] * new[1]).sqrt();
            // inside the circle: as is (times one); outside: back onto it
            let scale = Wide::select(size.gt(limit), Wide::select(size.gt(zero), limit / size, zero), one);
            let new = [new[0] * scale, new[1] * scale];
            fr.tangent = [new[0].0, new[1].0];
            t0.apply(new[0] - old[0], &mut v);
            t1.apply(new[1] - old[1], &mut v);
        }
        v.scatter(bu, movers);
    }
    change.0.iter().fold(0.0f64, |m, c| m.max(*c))
}

/// How far the bundles' rows are from the exact contact conditions (m/s), the largest of: the approach speed of a
/// point that touches (gap <= 0), the separating speed of one that pushes while apart, and the slip at the centre
/// of a manifold whose friction is inside its Coulomb bound (sticking).
pub(crate) fn residual(bundles: &[Bundle], frictions: &[FrictionBundle], movers: &[Mover]) -> f64 {
    // read only: the pointer is never written through
    let movers = MoverPtr::from_raw(movers.as_ptr().cast_mut(), movers.len());
    let zero = Wide::splat(0.0);
    let mut worst = zero;
    for (bu, fr) in bundles.iter().zip(frictions) {
        // SAFETY: nothing writes the bodies meanwhile
        let v = unsafe { Gathered::new(bu, movers) };
        let mut total = zero;
        for row in &bu.rows[..bu.points] {
            let vn = row.normal_axis.speed(&v);
            let (gap, normal) = (Wide(row.gap), Wide(row.normal));
            let apart = Wide::select(normal.gt(zero), vn, zero);
            worst = worst.max(Wide::select(gap.gt(zero), apart, vn.neg()));
            total = total + normal;
        }
        let [t0, t1] = &fr.axes;
        let (f0, f1) = (Wide(fr.tangent[0]), Wide(fr.tangent[1]));
        let (friction, size) = (Wide(fr.friction), (f0 * f0 + f1 * f1).sqrt());
        let bound = friction * total * Wide::splat(1.0 - 1e-9);
        let sticks: [bool; W] =
            std::array::from_fn(|l| friction.0[l] > 0.0 && total.0[l] > 0.0 && size.0[l] < bound.0[l]);
        let (s0, s1) = (t0.speed(&v), t1.speed(&v));
        worst = worst.max(Wide::select(sticks, (s0 * s0 + s1 * s1).sqrt(), zero));
    }
    worst.0.iter().fold(0.0f64, |m, c| m.max(*c))
}

/// Applies every lane's carried impulses (each point's normal, then the twist and the two tangents), bundle by
/// bundle, through shared bodies.
/// SAFETY: as `sweep_shared`.
pub(crate) unsafe fn warm_start_shared(bundles: &[Bundle], frictions: &[FrictionBundle], movers: MoverPtr) {
    #[cfg(target_arch = "x86_64")]
    if avx2() {
        return warm_start_avx2(bundles, frictions, movers);
    }
    warm_start_lanes(bundles, frictions, movers)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn warm_start_avx2(bundles: &[Bundle], frictions: &[FrictionBundle], movers: MoverPtr) {
    warm_start_lanes(bundles, frictions, movers)
}

#[inline(always)]
unsafe fn warm_start_lanes(bundles: &[Bundle], frictions: &[FrictionBundle], movers: MoverPtr) {
    for (bu, fr) in bundles.iter().zip(frictions) {
        let mut v = Gathered::new(bu, movers);
        for row in &bu.rows[..bu.points] {
            row.normal_axis.apply(Wide(row.normal), &mut v);
        }
        fr.twist_axis.apply(Wide(fr.twist), &mut v);
        if fr.resists {
            fr.roll_axes[0].apply(Wide(fr.roll[0]), &mut v);
            fr.roll_axes[1].apply(Wide(fr.roll[1]), &mut v);
        }
        fr.axes[0].apply(Wide(fr.tangent[0]), &mut v);
        fr.axes[1].apply(Wide(fr.tangent[1]), &mut v);
        v.scatter(bu, movers);
    }
}

/// Lane data whose all-zero bytes are its `Default` (every field an integer, a float or a bool, or arrays of them):
/// room for a step's bundles is zeroed in one pass instead of a default built and copied each (which the compiler
/// did for these kilobyte structs: 6% of a small pile's soft step).
///
/// # Safety
/// Implement only for types whose every field is an integer, a float, a bool or an array of those.
pub(crate) unsafe trait Zeroed: Default {}

// SAFETY: usize, f64 and bool fields and arrays of them, all zero in their default.
unsafe impl Zeroed for Bundle {}
// SAFETY: f64 arrays.
unsafe impl Zeroed for Arms {}

/// `n` defaults of `T` in `v` (its room reused), zeroed in place.
pub(crate) fn zeroed_in<T: Zeroed>(mut v: Vec<T>, n: usize) -> Vec<T> {
    v.clear();
    v.reserve(n);
    // SAFETY: `Zeroed` types are valid, and their default, as all-zero bytes; the room was just reserved.
    unsafe {
        std::ptr::write_bytes(v.as_mut_ptr(), 0, n);
        v.set_len(n);
    }
    v
}

/// A group's bundles, their friction and their arms.
pub(crate) type Rows = (Vec<Bundle>, Vec<FrictionBundle>, Vec<Arms>);

thread_local! {
    /// Room for the rows of the groups this thread sets up, kept from step to step: a step's rows are megabytes
    /// on a large scene, which the allocator would hand back to the system and fault in again every step.
    static ROOM: std::cell::RefCell<Vec<Rows>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Rows for `n` bundles, zeroed, in room this thread kept if it has some.
pub(crate) fn rows(n: usize) -> Rows {
    let (b, f, a) = ROOM.with(|room| room.borrow_mut().pop()).unwrap_or_default();
    (zeroed_in(b, n), zeroed_in(f, n), zeroed_in(a, n))
}

/// Gives a group's rows back to this thread's room (at most two sets are kept).
pub(crate) fn give_back(rows: Rows) {
    ROOM.with(|room| {
        let mut room = room.borrow_mut();
        if room.len() < 2 {
            room.push(rows);
        }
    });
}
