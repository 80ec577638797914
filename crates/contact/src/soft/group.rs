//! A group of the soft step, solved as one: its bodies and its manifolds' rows laid out for the solver, and the
//! substep loop that reads as Box2D v3's stages (`stages.rs`): per substep, integrate velocities (the springs'
//! impulses first), warm start, a biased soft solve, integrate positions, a relax solve without bias; after the
//! substeps, restitution. Manifolds are swept colour by colour, a colour's in bundles of eight lanes (`bundle.rs`):
//! those of a colour share no moving body, so they are solved side by side with the bits of one after another; the
//! overflow colour's, which may share bodies, a lane a bundle. The colours come from the constraint graph the caller
//! keeps (`graph.rs`): nothing here sorts or colours a manifold again.

use super::bundle::{self, Arms, Bundle, FrictionBundle, Sweep, P, W};
use super::geometry;
use super::graph::OVERFLOW;
use super::joints::{JointSet, JointSweep};
use super::manifold::SoftManifold;
use super::row::Mover;
use super::settings::SoftSettings;
use super::softness::Softness;
use super::springs::SpringSet;
use super::stages::{self, Passes, Substeps};
use crate::body::BodyState;
use crate::contact::tangents;
use crate::islands::body_islands;
use nalgebra::Vector3;

/// A group: its movers (local indices) and rows, in bundles of rows of one colour (`bundle.rs`), each in two parts:
/// normal (`bundles`) and friction (`frictions`, at the same place), with the arms the gaps are measured from.
pub(crate) struct Group {
    pub movers: Vec<Mover>,
    pub bundles: Vec<Bundle>,
    pub frictions: Vec<FrictionBundle>,
    arms: Vec<Arms>,
    /// The bundles of each colour in sweep order, and whether it is the overflow colour (whose manifolds may share
    /// bodies).
    colours: Vec<(std::ops::Range<usize>, bool)>,
    /// Whether its passes sweep on until the impulses settle (an island of a large mass ratio, `converges`).
    converge: bool,
    /// Its joints, an island's set each (solved before the contacts in every stage).
    pub joints: Vec<JointSet>,
    /// Its springs (evaluated at the start of every substep).
    pub springs: SpringSet,
    /// Each mover's velocities at the step's start (`keep_push_energy`, `restitution`).
    start: Vec<(Vector3<f64>, Vector3<f64>)>,
    /// Whether a contact may bounce (one with restitution closes at the step's start).
    bounces: bool,
}

/// How much a point counts towards its manifold's friction centre by its gap (Box3D's friction centre decay, with a
/// millimetre for its speculative distance): fully while touching or within `FRICTION_FADE`, then less, down to a
/// thousandth past twice it, so that the centre moves smoothly as points come and go.
fn friction_weight(gap: f64) -> f64 {
    (2.0 - gap / FRICTION_FADE).clamp(1e-3, 1.0)
}

/// The gap over which a point's weight in its manifold's friction centre fades (m).
const FRICTION_FADE: f64 = 1e-3;

/// Mass ratio above which an island's passes sweep until the impulses settle (a heavy body on a light one needs many
/// Gauss-Seidel sweeps to pass its weight down: one or two leave it jittering at centimetres a second): an island of
/// contacts alone from `MASS_RATIO` (a bin of mixed shapes, its capsules a sixteenth of its boxes, rests without), one
/// with joints or springs from `JOINED_MASS_RATIO` (a ragdoll's limbs stretch their joints past a millimetre
/// without).
pub(crate) const MASS_RATIO: f64 = 100.0;
pub(crate) const JOINED_MASS_RATIO: f64 = 10.0;

impl Group {
    /// Rows for `manifolds` (the step's, taken in the order of `of_group`, indices into it), between `movers` (body
    /// indices mapped by `local`), warm-started from their impulses.
    pub fn new(
        movers: Vec<Mover>,
        bodies: &[BodyState],
        manifolds: &[&SoftManifold],
        of_group: &[usize],
        local: impl Fn(usize) -> usize,
        converge: bool,
        decays: &[f64],
    ) -> Group {
        // colour by colour; within a colour the fullest manifolds first (so that a bundle's lanes have as many points
        // as each other), then in order: a counting sort on (colour, points), the order within each kept
        let key = |m: usize| {
            let mf = manifolds[m];
            let colour = mf.colour.min(OVERFLOW) as usize;
            colour * (P + 1) + (P - mf.count)
        };
        let mut starts = vec![0usize; (OVERFLOW as usize + 1) * (P + 1) + 1];
        for &m in of_group {
            starts[key(m) + 1] += 1;
        }
        for k in 1..starts.len() {
            starts[k] += starts[k - 1];
        }
        let mut order = vec![0usize; of_group.len()];
        for &m in of_group {
            let slot = &mut starts[key(m)];
            order[*slot] = m;
            *slot += 1;
        }
        // each manifold's bundle and lane: a new bundle at each colour, when full, and for every manifold of the
        // overflow colour (which may share bodies)
        let (mut slots, mut colour, mut lanes) = (Vec::with_capacity(order.len()), u32::MAX, W);
        for &m in &order {
            let c = manifolds[m].colour.min(OVERFLOW);
            if c != colour || lanes == W || c == OVERFLOW {
                (colour, lanes) = (c, 0);
                slots.push((slots.last().map_or(0, |&(k, _): &(usize, usize)| k + 1), 0));
            } else {
                slots.push((slots.last().expect("a bundle is open").0, lanes));
            }
            lanes += 1;
        }
        // sized once: bundles are kilobytes, and a growing vector would copy them
        let count = slots.last().map_or(0, |&(k, _)| k + 1);
        let (mut bundles, mut frictions, mut arms) = bundle::rows(count);
        for (&m, &(k, l)) in order.iter().zip(&slots) {
            let (bu, fr, arm) = (&mut bundles[k], &mut frictions[k], &mut arms[k]);
            let mf = manifolds[m];
            bu.lanes = l + 1;
            let (a, b) = (local(mf.a), local(mf.b));
            let (ma, mb) = (&movers[a], &movers[b]);
            bu.a[l] = a;
            bu.b[l] = b;
            bu.manifold[l] = m;
            bu.ima[l] = ma.inv_mass;
            bu.imb[l] = mb.inv_mass;
            bu.fixed[l] = ma.inv_mass == 0.0 || mb.inv_mass == 0.0;
            bu.moves[l] = (ma.moves(), mb.moves());
            bu.count[l] = mf.count;
            bu.points = bu.points.max(mf.count);
            bu.restitution[l] = mf.restitution;
            bu.decay[l] = decays.get(m).copied().unwrap_or(1.0);
            let (xa, xb) = (bodies[mf.a].position, bodies[mf.b].position);
            // the manifold's normal (its points' mean: they share it but for a decomposed mesh's), its tangents,
            // and its friction centre: the points' mean, each weighted less as it lies farther apart than touching
            let mut normal = Vector3::zeros();
            let (mut centre_a, mut centre_b, mut weights) = (Vector3::zeros(), Vector3::zeros(), 0.0);
            for (p, c) in mf.points().iter().enumerate() {
                let (ra, rb) = (c.point - xa, c.point - xb);
                for i in 0..3 {
                    arm.ra[p][i][l] = ra[i];
                    arm.rb[p][i][l] = rb[i];
                }
                arm.gap[p][l] = c.gap;
                let row = &mut bu.rows[p];
                row.normal_axis.set_dir(l, &c.normal);
                row.gap[l] = c.gap;
                row.normal[l] = c.normal_impulse.max(0.0);
                normal += c.normal;
                let weight = friction_weight(c.gap);
                centre_a += ra * weight;
                centre_b += rb * weight;
                weights += weight;
            }
            let n = normal.normalize();
            let (centre_a, centre_b) = (centre_a / weights, centre_b / weights);
            for (p, c) in mf.points().iter().enumerate() {
                fr.lever[p][l] = (c.point - xa - centre_a).norm();
            }
            for i in 0..3 {
                arm.centre_a[i][l] = centre_a[i];
                arm.centre_b[i][l] = centre_b[i];
                fr.twist_axis.ca[i][l] = n[i];
            }
            let (t0, t1) = tangents(&n);
            let tangent = mf.tangent_impulse - n * n.dot(&mf.tangent_impulse);
            fr.axes[0].set_dir(l, &t0);
            fr.axes[1].set_dir(l, &t1);
            fr.tangent[0][l] = t0.dot(&tangent);
            fr.tangent[1][l] = t1.dot(&tangent);
            fr.twist[l] = mf.twist_impulse;
            fr.friction[l] = mf.friction;
            if mf.rolling_resistance > 0.0 || mf.torsional_resistance > 0.0 {
                // the rolling radius: along the normal from the friction centre to the farther turning centre
                let turns = |m: &Mover| m.moves() && m.inv_inertia != nalgebra::Matrix3::zeros();
                let radius = [(ma, centre_a), (mb, centre_b)]
                    .iter()
                    .filter(|(m, _)| turns(m))
                    .map(|(_, arm)| n.dot(arm).abs())
                    .fold(0.0, f64::max);
                fr.resists = true;
                fr.rolling[l] = mf.rolling_resistance * radius;
                fr.torsion[l] = mf.torsional_resistance * radius;
                for i in 0..3 {
                    fr.roll_axes[0].ca[i][l] = t0[i];
                    fr.roll_axes[1].ca[i][l] = t1[i];
                }
                fr.roll[0][l] = t0.dot(&mf.rolling_impulse);
                fr.roll[1][l] = t1.dot(&mf.rolling_impulse);
            }
        }
        geometry::build(&mut bundles, &mut frictions, &arms, &movers);
        // each bundle's colour is its first manifold's
        let mut of_bundle: Vec<u32> = Vec::with_capacity(count);
        for (&m, &(k, _)) in order.iter().zip(&slots) {
            if k == of_bundle.len() {
                of_bundle.push(manifolds[m].colour.min(OVERFLOW));
            }
        }
        let mut by_colour = Vec::new();
        let mut start = 0;
        for run in of_bundle.chunk_by(|x, y| x == y) {
            by_colour.push((start..start + run.len(), run[0] == OVERFLOW));
            start += run.len();
        }
        // each point's normal speed at the step's start (for restitution)
        for bu in &mut bundles {
            for l in 0..bu.lanes {
                let (a, b) = (&movers[bu.a[l]], &movers[bu.b[l]]);
                for p in 0..bu.count[l] {
                    let closing = bu.rows[p].normal_axis.speed_of(l, a, b);
                    bu.rows[p].closing[l] = closing;
                }
            }
        }
        let bounces = bundles.iter().any(|bu| {
            (0..bu.lanes).any(|l| bu.restitution[l] != 0.0 && (0..bu.count[l]).any(|p| bu.rows[p].closing[l] < 0.0))
        });
        let start = movers.iter().map(|m| (m.v, m.w)).collect();
        Group {
            movers,
            bundles,
            frictions,
            arms,
            colours: by_colour,
            converge,
            joints: Vec::new(),
            springs: SpringSet::empty(),
            start,
            bounces,
        }
    }

    /// Gives its rows' room back for the next group this thread sets up.
    pub fn give_back(self) {
        bundle::give_back((self.bundles, self.frictions, self.arms));
    }

    /// The substeps of a step of h on up to `threads` workers (one stage list, `stages.rs`): the same bits on any
    /// number.
    pub fn solve(&mut self, h: f64, s: &SoftSettings, threads: usize) {
        let n = s.substeps.max(1);
        let hs = h / n as f64;
        let hertz = s.contact_hertz.min(0.25 / hs);
        let soft = Softness::new(hertz, s.damping_ratio, hs);
        let stiff = Softness::new(2.0 * hertz, s.damping_ratio, hs);
        let rigid = Softness::new(s.joint_hertz.min(0.5 / hs), s.joint_damping_ratio, hs);
        let biased = Sweep { hs, soft: Some((&soft, &stiff)), max_push: s.max_push_out, friction: false };
        let passes = Passes {
            iterations: s.iterations.max(1),
            biased,
            relax: Sweep { soft: None, friction: true, ..biased },
            biased_joints: JointSweep { hs, rigid: Some(rigid) },
            relax_joints: JointSweep { hs, rigid: None },
        };
        let group = Substeps {
            movers: &mut self.movers,
            bundles: &mut self.bundles,
            frictions: &mut self.frictions,
            arms: &self.arms,
            colours: &self.colours,
            joints: &mut self.joints,
            springs: &mut self.springs,
            converge: self.converge,
        };
        stages::substeps(group, n, hs, passes, threads);
        self.keep_push_energy();
        self.restitution(s.bounce_threshold);
    }

    /// How far the step's end is from the exact contact conditions (m/s), the largest over the rows of: the
    /// approach speed of a contact that touches (gap <= 0), the separating speed of one that pushes while apart,
    /// and the slip of one whose friction is inside its Coulomb bound (sticking).
    pub fn residual(&self) -> f64 {
        let worst = bundle::residual(&self.bundles, &self.frictions, &self.movers);
        self.joints.iter().fold(worst, |w, j| w.max(j.residual(&self.movers)))
    }

    /// Newton's restitution for contacts that closed faster than the threshold and pushed: the normal velocity is
    /// raised to -e times the closing one (the impulse only grows). Newton's law at several points at once, or with
    /// friction on a turning body (Kane's paradox: a spinning mesh hitting the floor came off with 25 J more than it
    /// brought), can put energy in: the bounce is then scaled back, as a whole, to the largest share of it that keeps
    /// the group's energy (`keep_energy`).
    fn restitution(&mut self, threshold: f64) {
        if !self.bounces {
            return;
        }
        let before: Vec<(Vector3<f64>, Vector3<f64>)> = self.movers.iter().map(|m| (m.v, m.w)).collect();
        let mut applied = Vec::new();
        for (k, bu) in self.bundles.iter_mut().enumerate() {
            for l in (0..bu.lanes).filter(|&l| bu.restitution[l] != 0.0) {
                for p in 0..bu.count[l] {
                    let row = &mut bu.rows[p];
                    if row.closing[l] > -threshold || row.max_normal[l] == 0.0 {
                        continue;
                    }
                    let (a, b) = pair(&mut self.movers, bu.a[l], bu.b[l]);
                    let n = &row.normal_axis;
                    let impulse = -n.mass[l] * (n.speed_of(l, a, b) + bu.restitution[l] * row.closing[l]);
                    let total = (row.normal[l] + impulse).max(0.0);
                    let delta = total - row.normal[l];
                    row.normal[l] = total;
                    row.step[l] += delta;
                    row.weighed[l] += delta;
                    if delta != 0.0 {
                        n.apply_of(l, a, b, delta);
                        applied.push((k, l, p, delta));
                    }
                }
            }
        }
        if !applied.is_empty() {
            self.keep_energy(&before, &applied);
        }
    }

    /// Scales the bounce just applied (the movers' velocities from `before`, the impulses `applied`: bundle, lane,
    /// point, impulse) by the largest share s in [0, 1] whose kinetic energy keeps the group's mechanical energy at
    /// most its start's, or at most what it was before the bounce if the soft contacts' push-out had already raised
    /// it (`share_within`).
    fn keep_energy(&mut self, before: &[(Vector3<f64>, Vector3<f64>)], applied: &[(usize, usize, usize, f64)]) {
        let path = &paths_from(&self.movers, &self.start, before, |_| 0, 1)[0];
        let Some(s) = path.share_within(path.start.max(path.from) + path.rounding) else { return };
        scale_from(&mut self.movers, before, |_| (s, 1.0));
        for &(k, l, p, delta) in applied {
            let row = &mut self.bundles[k].rows[p];
            row.normal[l] -= (1.0 - s) * delta;
            row.step[l] -= (1.0 - s) * delta;
            row.weighed[l] -= (1.0 - s) * delta;
        }
    }

    /// Each island whose soft contacts put energy in over the substeps has its motion scaled back to keep its
    /// mechanical energy at most the start's: first its velocity change over the step, to the largest share that
    /// keeps it (a 4.6 kg ball landing on a 57 g piece, 4.7 cm deep, left 80 J richer: the relaxing sweeps do not
    /// take all of the push back at a mass ratio of 80); then, where the contacts lifted it by more than its kinetic
    /// energy along that way can pay for, its velocities as a whole, so that a lift pays for itself out of its own
    /// motion (a cylinder wobbling on its rim, lifted a little at every step, crept up 6e-4 J of 1.04 J in 0.3 s).
    /// A lift its motion cannot pay for stays (a body pushed out of an overlap from rest: at most the weights times
    /// the depth). Not in a group with joints or springs, whose energy the movers do not hold, nor in an island a
    /// moving kinematic body pushes.
    fn keep_push_energy(&mut self) {
        if !self.joints.is_empty() || !self.springs.is_empty() {
            return;
        }
        let links = self.bundles.iter().flat_map(|bu| (0..bu.lanes).map(move |l| (bu.a[l], bu.b[l])));
        let movers = &self.movers;
        let (island, count) = body_islands(movers.len(), |m| movers[m].moves(), links);
        // an island a moving kinematic body pushes is driven: the energy it is given is not the contacts'
        let mut driven = vec![false; count];
        for bu in &self.bundles {
            for l in 0..bu.lanes {
                let (a, b) = (&movers[bu.a[l]], &movers[bu.b[l]]);
                for (pusher, pushed) in [(a, bu.b[l]), (b, bu.a[l])] {
                    let moving = pusher.v != Vector3::zeros() || pusher.w != Vector3::zeros();
                    if !pusher.moves() && moving && island[pushed] != usize::MAX {
                        driven[island[pushed]] = true;
                    }
                }
            }
        }
        let scales: Vec<(f64, f64)> = paths_from(movers, &self.start, &self.start, |m| island[m], count)
            .iter()
            .zip(&driven)
            .map(|(path, &driven)| {
                if driven {
                    return (1.0, 1.0);
                }
                let target = path.start + path.rounding;
                let share = path.share_within(target).unwrap_or(1.0);
                let kinetic = path.at(share);
                let whole = if kinetic > target && kinetic > 0.0 { (target.max(0.0) / kinetic).sqrt() } else { 1.0 };
                (share, whole)
            })
            .collect();
        if scales.iter().any(|&s| s != (1.0, 1.0)) {
            let at = |m: usize| if island[m] == usize::MAX { (1.0, 1.0) } else { scales[island[m]] };
            scale_from(&mut self.movers, &self.start, at);
        }
    }
}

/// The kinetic energy of each of `count` sets of `movers` (`set` of each moving one) on the way from the velocities
/// `from` to the movers' own (`start`: their velocities at the step's start): K(s) = from + s (b + s c), with the
/// start's kinetic energy plus the applied forces' work over the step's displacement (rotational energy at the
/// step's start inertia, as the end's is kept: `semi_implicit::turned_momentum`).
fn paths_from(
    movers: &[Mover],
    start: &[(Vector3<f64>, Vector3<f64>)],
    from: &[(Vector3<f64>, Vector3<f64>)],
    set: impl Fn(usize) -> usize,
    count: usize,
) -> Vec<EnergyPath> {
    let mut paths = vec![EnergyPath::default(); count];
    let mut worked = vec![0.0; count];
    for (k, ((m, &(v0, w0)), &(vr, wr))) in movers.iter().zip(start).zip(from).enumerate() {
        if !m.moves() {
            continue;
        }
        let path = &mut paths[set(k)];
        let mass = if m.inv_mass > 0.0 { 1.0 / m.inv_mass } else { 0.0 };
        let inertia = m.inv_inertia.try_inverse().unwrap_or_else(nalgebra::Matrix3::zeros);
        let (dv, dw) = (m.v - vr, m.w - wr);
        path.start += 0.5 * (mass * v0.norm_squared() + w0.dot(&(inertia * w0)));
        path.from += 0.5 * (mass * vr.norm_squared() + wr.dot(&(inertia * wr)));
        path.b += mass * vr.dot(&dv) + wr.dot(&(inertia * dw));
        path.c += 0.5 * (mass * dv.norm_squared() + dw.dot(&(inertia * dw)));
        worked[set(k)] += m.force_work();
    }
    for (path, work) in paths.iter_mut().zip(worked) {
        (path.start, path.rounding) = (path.start + work, 1e-12 * (path.start + work.abs()));
    }
    paths
}

/// Each mover's velocities a share s of the way from `from` to its own, then times a factor: (s, factor) = `at` of
/// the mover.
fn scale_from(movers: &mut [Mover], from: &[(Vector3<f64>, Vector3<f64>)], at: impl Fn(usize) -> (f64, f64)) {
    for (k, (m, &(vr, wr))) in movers.iter_mut().zip(from).enumerate() {
        let (s, factor) = at(k);
        m.v = vr + (m.v - vr) * s;
        m.w = wr + (m.w - wr) * s;
        if factor != 1.0 {
            (m.v, m.w) = (m.v * factor, m.w * factor);
        }
    }
}

/// A group's kinetic energy along a path of velocities, K(s) = from + s (b + s c), and the energy its step started
/// with (kinetic plus the forces' work), and the rounding allowed on it.
#[derive(Clone, Default)]
struct EnergyPath {
    from: f64,
    b: f64,
    c: f64,
    start: f64,
    rounding: f64,
}

impl EnergyPath {
    /// The kinetic energy a share s of the way.
    fn at(&self, s: f64) -> f64 {
        self.from + s * (self.b + s * self.c)
    }

    /// The largest share s in [0, 1] whose kinetic energy is at most `target` (the root of a quadratic), or None
    /// when the whole way (s = 1) keeps it.
    fn share_within(&self, target: f64) -> Option<f64> {
        let at_end = self.at(1.0);
        if at_end <= target || self.c <= 0.0 {
            return None;
        }
        let disc = (self.b * self.b + 4.0 * self.c * (target - self.from)).max(0.0);
        Some(((-self.b + disc.sqrt()) / (2.0 * self.c)).clamp(0.0, 1.0))
    }
}

/// The two movers of a row, mutably (a != b: a contact joins two bodies).
#[inline]
fn pair(movers: &mut [Mover], a: usize, b: usize) -> (&mut Mover, &mut Mover) {
    if a < b {
        let (lo, hi) = movers.split_at_mut(b);
        (&mut lo[a], &mut hi[0])
    } else {
        let (lo, hi) = movers.split_at_mut(a);
        (&mut hi[0], &mut lo[b])
    }
}

#[cfg(test)]
mod energy_path_tests {
    use super::EnergyPath;

    #[test]
    fn the_share_kept_is_the_root_of_the_kinetic_energys_quadratic() {
        // K(s) = 1 + s (2 + s 3): K(1) = 6
        let path = EnergyPath { from: 1.0, b: 2.0, c: 3.0, start: 0.0, rounding: 0.0 };
        assert_eq!(path.share_within(6.0), None);
        assert_eq!(path.share_within(7.0), None);
        // K(s) = 2.5 at s = 1/3 (3 s^2 + 2 s - 1.5 = 0 -> s = (-2 + sqrt(4 + 18)) / 6)
        let s = path.share_within(2.5).unwrap();
        assert!((path.at(s) - 2.5).abs() < 1e-15, "{s}");
        // below what s = 0 gives: the least energy on the way, clamped to [0, 1]
        assert_eq!(path.share_within(0.5), Some(0.0));
        // nothing changes along the way (c = 0): nothing to scale
        assert_eq!(EnergyPath { c: 0.0, ..path }.share_within(0.5), None);
    }
}
