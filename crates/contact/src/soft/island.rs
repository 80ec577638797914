//! One island of the soft step: its bodies and contact rows laid out for the solver, and the substep loop that reads
//! as Box2D v3's stages: per substep, integrate velocities (the springs' impulses first, `springs.rs`), warm start, a
//! biased soft solve, integrate positions, a relax solve without bias; after the substeps, restitution. Rows are
//! solved Gauss-Seidel in an order fixed by the input alone: a body pair's points together as a manifold, manifolds
//! colour by colour (`colour.rs`), those of a colour sharing no moving body, so that they are swept eight at a time
//! (`bundle.rs`) with the bits of one at a time.

use super::bundle::{self, Arms, Bundle, FrictionBundle, Sweep, P, W};
use super::colour::{colours, COLOURS};
use super::geometry;
use super::joints::{JointSet, JointSweep};
use super::row::{Mover, RowInfo};
use super::softness::Softness;
use super::springs::SpringSet;
use super::stages::{self, Passes, Substeps};
use super::{SoftImpulse, SoftSettings};
use crate::body::BodyState;
use crate::contact::tangents;
use crate::contact::Contact;

/// The island: its movers (local indices) and rows, in bundles of rows of one colour (`bundle.rs`), each in three
/// parts: normal (`bundles`), friction (`frictions`, at the same place) and the rest (`infos`, a row each in sweep
/// order).
pub(crate) struct Island {
    pub movers: Vec<Mover>,
    pub bundles: Vec<Bundle>,
    pub frictions: Vec<FrictionBundle>,
    arms: Vec<Arms>,
    pub infos: Vec<RowInfo>,
    /// The bundles of each colour in sweep order, and whether it is the last colour (`COLOURS`, whose manifolds may
    /// share bodies).
    colours: Vec<(std::ops::Range<usize>, bool)>,
    /// Whether its passes sweep on until the impulses settle (an island of a large mass ratio, `converges`).
    converge: bool,
    /// Its joints (solved before the contacts in every stage).
    pub joints: JointSet,
    /// Its springs (evaluated at the start of every substep).
    pub springs: SpringSet,
}

/// Mass ratio above which an island's passes sweep until the impulses settle (a heavy body on a light one needs many
/// Gauss-Seidel sweeps to pass its weight down: one or two leave it jittering at centimetres a second).
const MASS_RATIO: f64 = 10.0;

/// Whether the bodies of an island (their inverse masses) need sweeps until its impulses settle: a largest over
/// smallest mass of its moving bodies above `MASS_RATIO`.
pub(crate) fn converges(inverse_masses: impl Iterator<Item = f64>) -> bool {
    let masses = inverse_masses.filter(|&m| m > 0.0).map(|m| 1.0 / m);
    let (lo, hi) = masses.fold((f64::INFINITY, 0.0f64), |(lo, hi), m| (lo.min(m), hi.max(m)));
    lo > 0.0 && hi / lo > MASS_RATIO
}

impl Island {
    /// Rows for `contacts` between `movers` (contact body indices mapped by `local`), warm-started from `warm`.
    pub fn new(
        movers: Vec<Mover>,
        bodies: &[BodyState],
        contacts: &[&Contact],
        local: impl Fn(usize) -> usize,
        warm: &[SoftImpulse],
        converge: bool,
    ) -> Island {
        let pairs: Vec<(usize, usize)> = contacts.iter().map(|c| (local(c.a), local(c.b))).collect();
        // manifolds: a body pair's contacts, P at most, in the order of their first contacts
        let mut by_pair: Vec<(usize, usize, usize)> = pairs.iter().zip(0..).map(|(&(a, b), k)| (a, b, k)).collect();
        by_pair.sort_unstable();
        let mut manifolds: Vec<&[(usize, usize, usize)]> =
            by_pair.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)).flat_map(|run| run.chunks(P)).collect();
        manifolds.sort_unstable_by_key(|m| m[0].2);
        let manifold_pairs: Vec<(usize, usize)> = manifolds.iter().map(|m| (m[0].0, m[0].1)).collect();
        // colour by colour; within a colour, the fullest manifolds first (so that a bundle's lanes have as many
        // points as each other), then in order
        let mut order: Vec<(u32, usize)> = colours(&manifold_pairs, &movers).into_iter().zip(0..).collect();
        order.sort_unstable_by_key(|&(colour, m)| (colour, P - manifolds[m].len(), m));
        let mut infos = Vec::with_capacity(contacts.len());
        // each manifold's bundle and lane: a new bundle at each colour, when full, and for every manifold of the
        // last colour (which may share bodies)
        let (mut slots, mut colour, mut lanes) = (Vec::with_capacity(order.len()), u32::MAX, W);
        for &(m_colour, _) in &order {
            if m_colour != colour || lanes == W || m_colour == COLOURS {
                (colour, lanes) = (m_colour, 0);
                slots.push((slots.last().map_or(0, |&(k, _): &(usize, usize)| k + 1), 0));
            } else {
                slots.push((slots.last().expect("a bundle is open").0, lanes));
            }
            lanes += 1;
        }
        // sized once: bundles are kilobytes, and a growing vector would copy them
        let count = slots.last().map_or(0, |&(k, _)| k + 1);
        let (mut bundles, mut frictions, mut arms): (Vec<Bundle>, Vec<FrictionBundle>, Vec<Arms>) =
            (bundle::zeroed(count), bundle::zeroed(count), bundle::zeroed(count));
        for (&(_, m), &(k, l)) in order.iter().zip(&slots) {
            let (bu, fr, arm) = (&mut bundles[k], &mut frictions[k], &mut arms[k]);
            bu.lanes = l + 1;
            let (a, b) = manifold_pairs[m];
            let (ma, mb) = (&movers[a], &movers[b]);
            bu.a[l] = a;
            bu.b[l] = b;
            bu.ima[l] = ma.inv_mass;
            bu.imb[l] = mb.inv_mass;
            bu.fixed[l] = ma.inv_mass == 0.0 || mb.inv_mass == 0.0;
            bu.moves[l] = (ma.moves(), mb.moves());
            bu.count[l] = manifolds[m].len();
            bu.points = bu.points.max(manifolds[m].len());
            for (p, &(_, _, index)) in manifolds[m].iter().enumerate() {
                let (c, w) = (contacts[index], &warm[index]);
                let n = c.normal.into_inner();
                let ra = c.point - bodies[c.a].position;
                let rb = c.point - bodies[c.b].position;
                let (t0, t1) = tangents(&n);
                let tangent = w.tangent - n * n.dot(&w.tangent);
                bu.info[l][p] = infos.len();
                for i in 0..3 {
                    arm.ra[p][i][l] = ra[i];
                    arm.rb[p][i][l] = rb[i];
                }
                arm.gap[p][l] = c.distance;
                infos.push(RowInfo { index, restitution: c.restitution, closing: 0.0, step_normal: 0.0 });
                let f = &mut fr.points[p];
                f.axes[0].set_dir(l, &t0);
                f.axes[1].set_dir(l, &t1);
                f.tangent[0][l] = t0.dot(&tangent);
                f.tangent[1][l] = t1.dot(&tangent);
                f.friction[l] = c.friction;
                let row = &mut bu.rows[p];
                row.normal_axis.set_dir(l, &n);
                row.gap[l] = c.distance;
                row.normal[l] = w.normal.max(0.0);
            }
        }
        geometry::build(&mut bundles, &mut frictions, &arms, &movers);
        // each bundle's colour is its first manifold's
        let mut of_bundle: Vec<u32> = Vec::with_capacity(count);
        for (&(c, _), &(k, _)) in order.iter().zip(&slots) {
            if k == of_bundle.len() {
                of_bundle.push(c);
            }
        }
        let mut by_colour = Vec::new();
        let mut start = 0;
        for run in of_bundle.chunk_by(|x, y| x == y) {
            by_colour.push((start..start + run.len(), run[0] == COLOURS));
            start += run.len();
        }
        // each point's normal speed at the step's start (for restitution)
        for bu in &bundles {
            for l in 0..bu.lanes {
                let (a, b) = (&movers[bu.a[l]], &movers[bu.b[l]]);
                for p in 0..bu.count[l] {
                    infos[bu.info[l][p]].closing = bu.rows[p].normal_axis.speed_of(l, a, b);
                }
            }
        }
        Island {
            movers,
            bundles,
            frictions,
            arms,
            infos,
            colours: by_colour,
            converge,
            joints: JointSet::empty(),
            springs: SpringSet::empty(),
        }
    }

    /// Each used point of the bundles: (bundle, lane, point).
    fn points(&self) -> impl Iterator<Item = (usize, usize, usize)> + '_ {
        self.bundles
            .iter()
            .enumerate()
            .flat_map(|(k, bu)| (0..bu.lanes).flat_map(move |l| (0..bu.count[l]).map(move |p| (k, l, p))))
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
        let island = Substeps {
            movers: &mut self.movers,
            bundles: &mut self.bundles,
            frictions: &mut self.frictions,
            arms: &self.arms,
            infos: &mut self.infos,
            colours: &self.colours,
            joints: &mut self.joints,
            springs: &mut self.springs,
            converge: self.converge,
        };
        stages::substeps(island, n, hs, passes, threads);
        self.restitution(s.bounce_threshold);
    }

    /// How far the step's end is from the exact contact conditions (m/s), the largest over the rows of: the
    /// approach speed of a contact that touches (gap <= 0), the separating speed of one that pushes while apart,
    /// and the slip of one whose friction is inside its Coulomb bound (sticking).
    pub fn residual(&self) -> f64 {
        let mut worst = 0.0f64;
        for (k, l, p) in self.points() {
            let (bu, f) = (&self.bundles[k], &self.frictions[k].points[p]);
            let row = &bu.rows[p];
            let (a, b) = (&self.movers[bu.a[l]], &self.movers[bu.b[l]]);
            let vn = row.normal_axis.speed_of(l, a, b);
            let normal = row.normal[l];
            if row.gap[l] <= 0.0 {
                worst = worst.max(-vn);
            } else if normal > 0.0 {
                worst = worst.max(vn);
            }
            let (f0, f1) = (f.tangent[0][l], f.tangent[1][l]);
            let friction = (f0 * f0 + f1 * f1).sqrt();
            if f.friction[l] > 0.0 && normal > 0.0 && friction < f.friction[l] * normal * (1.0 - 1e-9) {
                worst = worst.max(f.axes[0].speed_of(l, a, b).hypot(f.axes[1].speed_of(l, a, b)));
            }
        }
        worst.max(self.joints.residual(&self.movers))
    }

    /// Newton's restitution for contacts that closed faster than the threshold and pushed: the normal velocity is
    /// raised to -e times the closing one (the impulse only grows).
    fn restitution(&mut self, threshold: f64) {
        for bu in &mut self.bundles {
            for l in 0..bu.lanes {
                for p in 0..bu.count[l] {
                    let info = &mut self.infos[bu.info[l][p]];
                    let row = &mut bu.rows[p];
                    if info.restitution == 0.0 || info.closing > -threshold || row.max_normal[l] == 0.0 {
                        continue;
                    }
                    let (a, b) = pair(&mut self.movers, bu.a[l], bu.b[l]);
                    let n = &row.normal_axis;
                    let impulse = -n.mass[l] * (n.speed_of(l, a, b) + info.restitution * info.closing);
                    let total = (row.normal[l] + impulse).max(0.0);
                    let delta = total - row.normal[l];
                    row.normal[l] = total;
                    info.step_normal += delta;
                    if delta != 0.0 {
                        n.apply_of(l, a, b, delta);
                    }
                }
            }
        }
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
