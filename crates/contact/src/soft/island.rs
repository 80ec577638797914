//! One island of the soft step: its bodies and contact rows laid out for the solver, and the substep loop that reads
//! as Box2D v3's stages: per substep, integrate velocities, warm start, a biased soft solve, integrate positions, a
//! relax solve without bias; after the substeps, restitution. Rows are solved in contact order (Gauss-Seidel), so
//! the answer is fixed by the input alone.

use super::softness::Softness;
use super::{SoftImpulse, SoftSettings};
use crate::body::BodyState;
use crate::contact::Contact;
use nalgebra::{Matrix3, UnitQuaternion, Vector3};

/// A body as the substeps move it.
#[derive(Clone, Debug)]
pub(crate) struct Mover {
    pub inv_mass: f64,
    pub inv_inertia: Matrix3<f64>,
    pub v: Vector3<f64>,
    pub w: Vector3<f64>,
    /// Velocity change per second from the applied forces (F / m, I^-1 (tau - w x I w) at the step's start).
    pub accel: Vector3<f64>,
    pub angular_accel: Vector3<f64>,
    /// Displacement of the centre of mass since the step's start.
    pub dp: Vector3<f64>,
    /// Rotation since the step's start.
    pub dq: UnitQuaternion<f64>,
}

impl Mover {
    pub fn new(b: &BodyState) -> Mover {
        let dynamic = b.is_dynamic();
        let w = b.angular_velocity;
        Mover {
            inv_mass: b.inv_mass,
            inv_inertia: b.inv_inertia,
            v: b.velocity,
            w,
            accel: if dynamic { b.force * b.inv_mass } else { Vector3::zeros() },
            angular_accel: if dynamic {
                b.inv_inertia * (b.torque - w.cross(&(b.inertia * w)))
            } else {
                Vector3::zeros()
            },
            dp: Vector3::zeros(),
            dq: UnitQuaternion::identity(),
        }
    }

    /// Free motion over h in `substeps` (no contact): the same sequence the islands' bodies follow.
    pub fn free(&mut self, h: f64, substeps: usize) {
        let hs = h / substeps.max(1) as f64;
        for _ in 0..substeps.max(1) {
            self.integrate_velocity(hs);
            self.integrate_position(hs);
        }
    }

    fn integrate_velocity(&mut self, h: f64) {
        self.v += self.accel * h;
        self.w += self.angular_accel * h;
    }

    fn integrate_position(&mut self, h: f64) {
        self.dp += self.v * h;
        if self.w != Vector3::zeros() {
            self.dq = UnitQuaternion::from_scaled_axis(self.w * h) * self.dq;
        }
    }

    /// How far the material point at arm r (from the centre, at the step's start) has moved.
    fn moved(&self, r: &Vector3<f64>) -> Vector3<f64> {
        self.dp + (self.dq * r - r)
    }

    fn apply(&mut self, impulse: &Vector3<f64>, r: &Vector3<f64>) {
        self.v += impulse * self.inv_mass;
        self.w += self.inv_inertia * r.cross(impulse);
    }
}

/// One contact point as a solver row.
#[derive(Clone, Debug)]
pub(crate) struct Row {
    a: usize,
    b: usize,
    ra: Vector3<f64>,
    rb: Vector3<f64>,
    n: Vector3<f64>,
    t: [Vector3<f64>; 2],
    normal_mass: f64,
    tangent_mass: [f64; 2],
    friction: f64,
    restitution: f64,
    /// Gap at the step's start (negative: penetration).
    gap: f64,
    /// Relative normal velocity at the step's start (for restitution).
    closing: f64,
    /// Against a static or kinematic body (stiffer softness).
    fixed: bool,
    pub normal: f64,
    pub tangent: [f64; 2],
    pub max_normal: f64,
    /// Normal impulse applied over the step so far (each substep's accumulated impulse, plus restitution's).
    pub step_normal: f64,
}

impl Row {
    /// The friction impulse as a world vector.
    pub fn tangent_vector(&self) -> Vector3<f64> {
        self.t[0] * self.tangent[0] + self.t[1] * self.tangent[1]
    }
}

/// Two unit vectors completing n to a right-handed basis (a fixed choice, so the rows are a function of n).
fn tangents(n: &Vector3<f64>) -> [Vector3<f64>; 2] {
    let seed = if n.x.abs() < 0.57 { Vector3::x() } else { Vector3::y() };
    let t1 = n.cross(&seed).normalize();
    [t1, n.cross(&t1)]
}

fn effective_mass(a: &Mover, b: &Mover, ra: &Vector3<f64>, rb: &Vector3<f64>, d: &Vector3<f64>) -> f64 {
    let (ca, cb) = (ra.cross(d), rb.cross(d));
    let k = a.inv_mass + b.inv_mass + ca.dot(&(a.inv_inertia * ca)) + cb.dot(&(b.inv_inertia * cb));
    if k > 0.0 {
        1.0 / k
    } else {
        0.0
    }
}

/// The island: its movers (local indices) and rows.
pub(crate) struct Island {
    pub movers: Vec<Mover>,
    pub rows: Vec<Row>,
    /// Largest over smallest mass of its moving bodies: above `MASS_RATIO`, sweeps go on until they converge.
    ratio: f64,
}

/// Mass ratio above which an island's passes sweep until the impulses settle (a heavy body on a light one needs many
/// Gauss-Seidel sweeps to pass its weight down: one or two leave it jittering at centimetres a second).
const MASS_RATIO: f64 = 10.0;
/// Most sweeps of one pass of such an island.
const MAX_SWEEPS: usize = 64;
/// A pass has converged when no impulse changed by more than this fraction of the largest.
const SETTLED: f64 = 1e-4;

impl Island {
    /// Rows for `contacts` between `movers` (contact body indices mapped by `local`), warm-started from `warm`.
    pub fn new(
        movers: Vec<Mover>,
        bodies: &[BodyState],
        contacts: &[&Contact],
        local: impl Fn(usize) -> usize,
        warm: &[SoftImpulse],
    ) -> Island {
        let rows = contacts
            .iter()
            .zip(warm)
            .map(|(c, w)| {
                let (a, b) = (local(c.a), local(c.b));
                let (ma, mb) = (&movers[a], &movers[b]);
                let n = c.normal.into_inner();
                let ra = c.point - bodies[c.a].position;
                let rb = c.point - bodies[c.b].position;
                let t = tangents(&n);
                let dv = (mb.v + mb.w.cross(&rb)) - (ma.v + ma.w.cross(&ra));
                let tangent = w.tangent - n * n.dot(&w.tangent);
                Row {
                    a,
                    b,
                    ra,
                    rb,
                    n,
                    t,
                    normal_mass: effective_mass(ma, mb, &ra, &rb, &n),
                    tangent_mass: [effective_mass(ma, mb, &ra, &rb, &t[0]), effective_mass(ma, mb, &ra, &rb, &t[1])],
                    friction: c.friction,
                    restitution: c.restitution,
                    gap: c.distance,
                    closing: n.dot(&dv),
                    fixed: ma.inv_mass == 0.0 || mb.inv_mass == 0.0,
                    normal: w.normal.max(0.0),
                    tangent: [t[0].dot(&tangent), t[1].dot(&tangent)],
                    max_normal: 0.0,
                    step_normal: 0.0,
                }
            })
            .collect();
        let masses = movers.iter().filter(|m| m.inv_mass > 0.0).map(|m| 1.0 / m.inv_mass);
        let (lo, hi) = masses.fold((f64::INFINITY, 0.0f64), |(lo, hi), m| (lo.min(m), hi.max(m)));
        Island { movers, rows, ratio: if lo > 0.0 { hi / lo } else { 1.0 } }
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
            self.pass(s.iterations, |island| island.solve_rows(hs, None, s.max_push_out, true));
            for r in &mut self.rows {
                r.step_normal += r.normal;
            }
        }
        self.restitution(s.bounce_threshold);
    }

    /// `iterations` sweeps; for an island of a large mass ratio, on until they settle (at most `MAX_SWEEPS`).
    fn pass(&mut self, iterations: usize, mut sweep: impl FnMut(&mut Island) -> f64) {
        let extra = if self.ratio > MASS_RATIO { MAX_SWEEPS } else { 0 };
        for k in 0..iterations.max(1) + extra {
            let change = sweep(self);
            if k + 1 >= iterations.max(1) {
                let largest = self.rows.iter().fold(0.0f64, |m, r| m.max(r.normal));
                if change <= SETTLED * largest {
                    break;
                }
            }
        }
    }

    fn warm_start(&mut self) {
        for r in &self.rows {
            let p = r.n * r.normal + r.t[0] * r.tangent[0] + r.t[1] * r.tangent[1];
            if p != Vector3::zeros() {
                self.movers[r.a].apply(&-p, &r.ra);
                self.movers[r.b].apply(&p, &r.rb);
            }
        }
    }

    /// Relative velocity of B's point against A's for row r.
    fn relative(&self, r: &Row) -> Vector3<f64> {
        let (a, b) = (&self.movers[r.a], &self.movers[r.b]);
        (b.v + b.w.cross(&r.rb)) - (a.v + a.w.cross(&r.ra))
    }

    fn push(&mut self, k: usize, p: Vector3<f64>) {
        let (a, b, ra, rb) = (self.rows[k].a, self.rows[k].b, self.rows[k].ra, self.rows[k].rb);
        self.movers[a].apply(&-p, &ra);
        self.movers[b].apply(&p, &rb);
    }

    /// One sweep over the rows: normal rows with the soft bias (`soft`: contact and static-contact softness) or
    /// rigid without it; friction (Coulomb's circle) in the pass without bias.
    /// Returns the largest change of a normal impulse.
    fn solve_rows(&mut self, hs: f64, soft: Option<(&Softness, &Softness)>, max_push: f64, friction: bool) -> f64 {
        let mut change = 0.0f64;
        for k in 0..self.rows.len() {
            let r = &self.rows[k];
            let (a, b) = (&self.movers[r.a], &self.movers[r.b]);
            let gap = r.gap + r.n.dot(&(b.moved(&r.rb) - a.moved(&r.ra)));
            let (bias, mass_scale, impulse_scale) = if gap > 0.0 {
                // speculative: close the gap in the substep and no more
                (gap / hs, 1.0, 0.0)
            } else if let Some((contact, fixed)) = soft {
                let sf = if r.fixed { fixed } else { contact };
                ((sf.bias_rate * gap).max(-max_push), sf.mass_scale, sf.impulse_scale)
            } else {
                (0.0, 1.0, 0.0)
            };
            let vn = r.n.dot(&self.relative(r));
            let impulse = -r.normal_mass * mass_scale * (vn + bias) - impulse_scale * r.normal;
            let total = (r.normal + impulse).max(0.0);
            let delta = total - r.normal;
            change = change.max(delta.abs());
            let n = r.n;
            self.rows[k].normal = total;
            self.rows[k].max_normal = self.rows[k].max_normal.max(total);
            if delta != 0.0 {
                self.push(k, n * delta);
            }
            if friction && self.rows[k].friction > 0.0 {
                self.solve_friction(k);
            }
        }
        change
    }

    fn solve_friction(&mut self, k: usize) {
        let r = &self.rows[k];
        let dv = self.relative(r);
        let old = r.tangent;
        let mut new = [old[0] - r.tangent_mass[0] * r.t[0].dot(&dv), old[1] - r.tangent_mass[1] * r.t[1].dot(&dv)];
        let limit = r.friction * r.normal;
        let size = (new[0] * new[0] + new[1] * new[1]).sqrt();
        if size > limit {
            let scale = if size > 0.0 { limit / size } else { 0.0 };
            new = [new[0] * scale, new[1] * scale];
        }
        let p = r.t[0] * (new[0] - old[0]) + r.t[1] * (new[1] - old[1]);
        self.rows[k].tangent = new;
        if p != Vector3::zeros() {
            self.push(k, p);
        }
    }

    /// Newton's restitution for contacts that closed faster than the threshold and pushed: the normal velocity is
    /// raised to -e times the closing one (the impulse only grows).
    fn restitution(&mut self, threshold: f64) {
        for k in 0..self.rows.len() {
            let r = &self.rows[k];
            if r.restitution == 0.0 || r.closing > -threshold || r.max_normal == 0.0 {
                continue;
            }
            let vn = r.n.dot(&self.relative(r));
            let impulse = -r.normal_mass * (vn + r.restitution * r.closing);
            let total = (r.normal + impulse).max(0.0);
            let delta = total - r.normal;
            let n = r.n;
            self.rows[k].normal = total;
            self.rows[k].step_normal += delta;
            if delta != 0.0 {
                self.push(k, n * delta);
            }
        }
    }
}
