//! One island of the soft step: its bodies and contact rows laid out for the solver, and the substep loop that reads
//! as Box2D v3's stages: per substep, integrate velocities, warm start, a biased soft solve, integrate positions, a
//! relax solve without bias; after the substeps, restitution. Rows are solved Gauss-Seidel in an order fixed by
//! the input alone (`colour.rs`): grouped so that consecutive rows seldom share a moving body, which lets the
//! processor overlap their solves instead of waiting on each body's last update.

use super::row::{Axis, FrictionRow, Mover, Row, RowInfo, Still};
use super::softness::Softness;
use super::{SoftImpulse, SoftSettings};
use crate::body::BodyState;
use crate::contact::tangents;
use crate::contact::Contact;

/// The island: its movers (local indices) and rows, each row in three parts (normal, friction, the rest) at the
/// same place of three lists.
pub(crate) struct Island {
    pub movers: Vec<Mover>,
    pub rows: Vec<Row>,
    pub frictions: Vec<FrictionRow>,
    pub infos: Vec<RowInfo>,
    /// Whether its passes sweep on until the impulses settle (an island of a large mass ratio, `converges`).
    converge: bool,
}

/// Mass ratio above which an island's passes sweep until the impulses settle (a heavy body on a light one needs many
/// Gauss-Seidel sweeps to pass its weight down: one or two leave it jittering at centimetres a second).
const MASS_RATIO: f64 = 10.0;
/// Most sweeps of one pass of such an island.
const MAX_SWEEPS: usize = 64;
/// A pass has converged when no impulse changed by more than this fraction of the largest.
const SETTLED: f64 = 1e-4;

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
        let order = super::colour::colour_order(&pairs, &movers);
        let (mut rows, mut frictions, mut infos) =
            (Vec::with_capacity(order.len()), Vec::with_capacity(order.len()), Vec::with_capacity(order.len()));
        for index in order {
            let (c, w) = (contacts[index], &warm[index]);
            let (a, b) = pairs[index];
            let (ma, mb) = (&movers[a], &movers[b]);
            let n = c.normal.into_inner();
            let ra = c.point - bodies[c.a].position;
            let rb = c.point - bodies[c.b].position;
            let (t0, t1) = tangents(&n);
            let normal_axis = Axis::new(ma, mb, &ra, &rb, n);
            let tangent = w.tangent - n * n.dot(&w.tangent);
            infos.push(RowInfo {
                index,
                ra,
                rb,
                restitution: c.restitution,
                gap: c.distance,
                closing: normal_axis.speed(ma, mb),
                step_normal: 0.0,
            });
            frictions.push(FrictionRow {
                axes: [Axis::new(ma, mb, &ra, &rb, t0), Axis::new(ma, mb, &ra, &rb, t1)],
                tangent: [t0.dot(&tangent), t1.dot(&tangent)],
                friction: c.friction,
            });
            rows.push(Row {
                a,
                b,
                normal_axis,
                current_gap: c.distance,
                fixed: ma.inv_mass == 0.0 || mb.inv_mass == 0.0,
                still: Still::of(ma, mb),
                normal: w.normal.max(0.0),
                max_normal: 0.0,
            });
        }
        Island { movers, rows, frictions, infos, converge }
    }

    /// The substeps of a step of h.
    pub fn solve(&mut self, h: f64, s: &SoftSettings) {
        let n = s.substeps.max(1);
        let hs = h / n as f64;
        let hertz = s.contact_hertz.min(0.25 / hs);
        let soft = Softness::new(hertz, s.damping_ratio, hs);
        let stiff = Softness::new(2.0 * hertz, s.damping_ratio, hs);
        for _ in 0..n {
            for m in &mut self.movers {
                m.integrate_velocity(hs);
            }
            self.warm_start();
            self.pass(s.iterations, |island| island.solve_rows(hs, Some((&soft, &stiff)), s.max_push_out, false));
            for m in &mut self.movers {
                m.integrate_position(hs);
            }
            self.update_gaps();
            self.pass(s.iterations, |island| island.solve_rows(hs, None, s.max_push_out, true));
            for (info, r) in self.infos.iter_mut().zip(&self.rows) {
                info.step_normal += r.normal;
            }
        }
        self.restitution(s.bounce_threshold);
    }

    /// How far the step's end is from the exact contact conditions (m/s), the largest over the rows of: the
    /// approach speed of a contact that touches (gap <= 0), the separating speed of one that pushes while apart,
    /// and the slip of one whose friction is inside its Coulomb bound (sticking).
    pub fn residual(&self) -> f64 {
        let mut worst = 0.0f64;
        for (r, f) in self.rows.iter().zip(&self.frictions) {
            let (a, b) = (&self.movers[r.a], &self.movers[r.b]);
            let vn = r.normal_axis.speed(a, b);
            if r.current_gap <= 0.0 {
                worst = worst.max(-vn);
            } else if r.normal > 0.0 {
                worst = worst.max(vn);
            }
            let friction = (f.tangent[0] * f.tangent[0] + f.tangent[1] * f.tangent[1]).sqrt();
            if f.friction > 0.0 && r.normal > 0.0 && friction < f.friction * r.normal * (1.0 - 1e-9) {
                let [t0, t1] = &f.axes;
                worst = worst.max(t0.speed(a, b).hypot(t1.speed(a, b)));
            }
        }
        worst
    }

    /// The rows' gaps where the bodies now are (positions move once a substep, so both passes use these).
    fn update_gaps(&mut self) {
        for (r, info) in self.rows.iter_mut().zip(&self.infos) {
            let (a, b) = (&self.movers[r.a], &self.movers[r.b]);
            r.current_gap = info.gap + r.normal_axis.dir.dot(&(b.moved(&info.rb) - a.moved(&info.ra)));
        }
    }

    /// `iterations` sweeps; for an island of a large mass ratio, on until they settle (at most `MAX_SWEEPS`).
    fn pass(&mut self, iterations: usize, mut sweep: impl FnMut(&mut Island) -> f64) {
        let extra = if self.converge { MAX_SWEEPS } else { 0 };
        for k in 0..iterations.max(1) + extra {
            let change = sweep(self);
            if extra > 0 && k + 1 >= iterations.max(1) {
                let largest = self.rows.iter().fold(0.0f64, |m, r| m.max(r.normal));
                if change <= SETTLED * largest {
                    break;
                }
            }
        }
    }

    fn warm_start(&mut self) {
        for (r, f) in self.rows.iter().zip(&self.frictions) {
            let (a, b) = pair(&mut self.movers, r.a, r.b);
            r.normal_axis.apply_on(a, b, r.normal, r.still);
            f.axes[0].apply_on(a, b, f.tangent[0], r.still);
            f.axes[1].apply_on(a, b, f.tangent[1], r.still);
        }
    }

    /// One sweep over the rows: normal rows with the soft bias (`soft`: contact and static-contact softness) or
    /// rigid without it; friction (Coulomb's circle) in the pass without bias. Returns the largest change of a
    /// normal impulse.
    fn solve_rows(&mut self, hs: f64, soft: Option<(&Softness, &Softness)>, max_push: f64, friction: bool) -> f64 {
        let mut change = 0.0f64;
        for (k, r) in self.rows.iter_mut().enumerate() {
            let (a, b) = pair(&mut self.movers, r.a, r.b);
            let n = &r.normal_axis;
            let gap = r.current_gap;
            let (bias, mass_scale, impulse_scale) = if gap > 0.0 {
                // speculative: close the gap in the substep and no more
                (gap / hs, 1.0, 0.0)
            } else if let Some((contact, fixed)) = soft {
                let sf = if r.fixed { fixed } else { contact };
                ((sf.bias_rate * gap).max(-max_push), sf.mass_scale, sf.impulse_scale)
            } else {
                (0.0, 1.0, 0.0)
            };
            let still = r.still;
            let vn = n.speed_on(a, b, still);
            let impulse = -n.mass * mass_scale * (vn + bias) - impulse_scale * r.normal;
            let total = (r.normal + impulse).max(0.0);
            let delta = total - r.normal;
            change = change.max(delta.abs());
            r.normal = total;
            r.max_normal = r.max_normal.max(total);
            if delta != 0.0 {
                n.apply_on(a, b, delta, still);
            }
            if !friction {
                continue;
            }
            let f = &mut self.frictions[k];
            if f.friction > 0.0 {
                let [t0, t1] = &f.axes;
                let old = f.tangent;
                let mut new =
                    [old[0] - t0.mass * t0.speed_on(a, b, still), old[1] - t1.mass * t1.speed_on(a, b, still)];
                let limit = f.friction * r.normal;
                let size = (new[0] * new[0] + new[1] * new[1]).sqrt();
                if size > limit {
                    let scale = if size > 0.0 { limit / size } else { 0.0 };
                    new = [new[0] * scale, new[1] * scale];
                }
                f.tangent = new;
                t0.apply_on(a, b, new[0] - old[0], still);
                t1.apply_on(a, b, new[1] - old[1], still);
            }
        }
        change
    }

    /// Newton's restitution for contacts that closed faster than the threshold and pushed: the normal velocity is
    /// raised to -e times the closing one (the impulse only grows).
    fn restitution(&mut self, threshold: f64) {
        for (r, info) in self.rows.iter_mut().zip(&mut self.infos) {
            if info.restitution == 0.0 || info.closing > -threshold || r.max_normal == 0.0 {
                continue;
            }
            let (a, b) = pair(&mut self.movers, r.a, r.b);
            let n = &r.normal_axis;
            let impulse = -n.mass * (n.speed(a, b) + info.restitution * info.closing);
            let total = (r.normal + impulse).max(0.0);
            let delta = total - r.normal;
            r.normal = total;
            info.step_normal += delta;
            if delta != 0.0 {
                n.apply(a, b, delta);
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
