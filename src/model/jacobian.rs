//! The world's Jacobian. Particles, springs between particles or fixed points, and constant loads give analytic
//! 3x3 blocks (so implicit steps cost time linear in the number of springs). Bodies and callbacks give a
//! coupling pattern instead, filled by coloured finite differences in the integrator.
//!
//! A compressed spring's exact Jacobian has a positive transverse stiffness k (l0/l - 1) (the buckling mode), which
//! can make I/h - J nearly singular and lets the chapter's single linearised implicit Euler step inject energy
//! into a stiff cloth. The definite variant clamps that term at zero and drops the damping's position derivative
//! (Choi and Ko, 2002), so every spring block is negative semidefinite and the step dissipates.

use crate::model::layout::get3;
use crate::model::{Model, ResolvedAttachment};
use nalgebra::{Matrix3, Vector3};
use tumble_contact::{SpringLaw, COINCIDENT};

impl Model {
    /// Every Jacobian entry (row, column, value) of a world without bodies or callbacks, always in the same order;
    /// with `y = None` the values are zero (for the pattern).
    pub(crate) fn analytic_entries(&self, y: Option<&[f64]>, emit: &mut impl FnMut(usize, usize, f64)) {
        let l = self.layout;
        for (i, p) in self.particles.iter().enumerate() {
            for k in 0..3 {
                emit(l.px(i) + k, l.pv(i) + k, 1.0);
                emit(l.pv(i) + k, l.px(i) + k, -p.stiffness * p.inv_mass);
                emit(l.pv(i) + k, l.pv(i) + k, -p.damping * p.inv_mass);
            }
        }
        for s in &self.springs {
            let (kb, cb) = match y {
                Some(y) => spring_blocks(&s.law, self.end_pv(y, s.a), self.end_pv(y, s.b), self.definite_springs),
                None => (Matrix3::zeros(), Matrix3::zeros()),
            };
            for (row, row_sign) in [(s.a, 1.0), (s.b, -1.0)] {
                let ResolvedAttachment::Particle(ir) = row else { continue };
                for (col, col_sign) in [(s.a, 1.0), (s.b, -1.0)] {
                    let ResolvedAttachment::Particle(ic) = col else { continue };
                    let scale = row_sign * col_sign * self.particles[ir].inv_mass;
                    for r in 0..3 {
                        for c in 0..3 {
                            emit(l.pv(ir) + r, l.px(ic) + c, scale * kb[(r, c)]);
                            emit(l.pv(ir) + r, l.pv(ic) + c, scale * cb[(r, c)]);
                        }
                    }
                }
            }
        }
    }

    /// The analytic pattern.
    pub(crate) fn analytic_pattern(&self) -> Vec<(usize, usize)> {
        let mut v = Vec::new();
        self.analytic_entries(None, &mut |r, c, _| v.push((r, c)));
        v
    }

    /// Position and velocity of a particle or fixed spring end.
    fn end_pv(&self, y: &[f64], e: ResolvedAttachment) -> (Vector3<f64>, Vector3<f64>) {
        match e {
            ResolvedAttachment::Particle(i) => (get3(y, self.layout.px(i)), get3(y, self.layout.pv(i))),
            ResolvedAttachment::Point(p) => (p, Vector3::zeros()),
            ResolvedAttachment::Body(..) => unreachable!("analytic Jacobians are for worlds without bodies"),
        }
    }

    /// Rows written and columns read by each object: a particle's force rows are its velocity rows and its state
    /// its position and velocity; a body's force rows are P and L and its state x, q, P, L.
    fn rows_cols(&self, e: ResolvedAttachment) -> (Vec<usize>, Vec<usize>) {
        let l = self.layout;
        match e {
            ResolvedAttachment::Particle(i) => {
                ((l.pv(i)..l.pv(i) + 3).collect(), (l.px(i)..l.px(i) + 3).chain(l.pv(i)..l.pv(i) + 3).collect())
            }
            ResolvedAttachment::Body(j, _) => (
                (l.bp(j)..l.bp(j) + 3).chain(l.bl(j)..l.bl(j) + 3).collect(),
                (l.bx(j)..l.bx(j) + 3)
                    .chain(l.bq(j)..l.bq(j) + 4)
                    .chain(l.bp(j)..l.bp(j) + 3)
                    .chain(l.bl(j)..l.bl(j) + 3)
                    .collect(),
            ),
            ResolvedAttachment::Point(_) => (Vec::new(), Vec::new()),
        }
    }

    /// A superset of the Jacobian's nonzeros for coloured finite differences: every object's force rows against
    /// its own state, the kinematic rows against what they read, and every spring's ends against each other.
    pub(crate) fn coupling_pattern(&self) -> Vec<(usize, usize)> {
        let l = self.layout;
        let mut v = Vec::new();
        let mut block = |rows: &[usize], cols: &[usize]| {
            for &r in rows {
                v.extend(cols.iter().map(|&c| (r, c)));
            }
        };
        for i in 0..l.particles {
            for k in 0..3 {
                block(&[l.px(i) + k], &[l.pv(i) + k]);
            }
            let (rows, cols) = self.rows_cols(ResolvedAttachment::Particle(i));
            block(&rows, &cols);
        }
        for j in 0..l.bodies {
            let (rows, cols) = self.rows_cols(ResolvedAttachment::Body(j, Vector3::zeros()));
            block(&rows, &cols);
            let x_rows: Vec<usize> = (l.bx(j)..l.bx(j) + 3).collect();
            block(&x_rows, &(l.bp(j)..l.bp(j) + 3).collect::<Vec<_>>());
            let q_rows: Vec<usize> = (l.bq(j)..l.bq(j) + 4).collect();
            block(&q_rows, &(l.bq(j)..l.bq(j) + 4).chain(l.bl(j)..l.bl(j) + 3).collect::<Vec<_>>());
        }
        for s in &self.springs {
            let (ra, ca) = self.rows_cols(s.a);
            let (rb, cb) = self.rows_cols(s.b);
            let rows: Vec<usize> = ra.into_iter().chain(rb).collect();
            let cols: Vec<usize> = ca.into_iter().chain(cb).collect();
            block(&rows, &cols);
        }
        v
    }
}

/// dF_a/dd and dF_a/dv_rel for the law's F_a = -(k (l - l0) + c (n . v_rel)) n, d = x_a - x_b, l = |d|, n = d / l; with
/// `definite`, the semidefinite approximation described at the top of this file.
fn spring_blocks(
    law: &SpringLaw,
    (pa, va): (Vector3<f64>, Vector3<f64>),
    (pb, vb): (Vector3<f64>, Vector3<f64>),
    definite: bool,
) -> (Matrix3<f64>, Matrix3<f64>) {
    let (k, c, l0) = (law.stiffness, law.damping, law.rest_length);
    let d = pa - pb;
    let len = d.norm();
    if len <= COINCIDENT {
        return (-k * Matrix3::identity(), Matrix3::zeros());
    }
    let n = d / len;
    let nn = n * n.transpose();
    let across = Matrix3::identity() - nn;
    if definite {
        return (-k * (nn + (1.0 - l0 / len).max(0.0) * across), -c * nn);
    }
    let v = va - vb;
    let stiff = -k * (nn + (1.0 - l0 / len) * across);
    let damp = -c / len * (n * (across * v).transpose() + n.dot(&v) * across);
    (stiff + damp, -c * nn)
}

#[cfg(test)]
mod tests {
    use crate::scenes::Cloth;
    use nalgebra::DMatrix;

    /// The exact analytic Jacobian of a damped, pinned, moving and partly compressed cloth agrees with central
    /// differences of the right-hand side to 1e-6 relative (differences with step 1e-6 carry ~1e-6 relative error
    /// on entries of size k/m = 4e3 ... 4e5); the definite one differs, and only where springs are compressed.
    #[test]
    fn analytic_jacobian_matches_central_differences() {
        let (mut w, ps) =
            Cloth { n: 4, size: 1.0, mass: 0.16, stiffness: 500.0, damping: 0.3, pin_stiffness: 5e3 }.build().unwrap();
        for (k, p) in ps.iter().enumerate() {
            let x = w.particle(*p).unwrap().position();
            let jiggle =
                nalgebra::Vector3::new((k as f64 * 1.3).sin(), (k as f64 * 0.7).cos(), (k as f64 * 2.1).sin()) * 0.05;
            w.set_particle_state(*p, x + jiggle, jiggle * 10.0).unwrap();
        }
        let compiled = w.compile();
        let mut model = compiled.model;
        let y = compiled_y(&w);
        let n = model.layout.dim();
        let mut exact = DMatrix::zeros(n, n);
        model.definite_springs = false;
        model.analytic_entries(Some(&y), &mut |r, c, v| exact[(r, c)] += v);
        let mut fd = DMatrix::zeros(n, n);
        let (mut fp, mut fm) = (vec![0.0; n], vec![0.0; n]);
        for c in 0..n {
            let mut yp = y.clone();
            let mut ym = y.clone();
            yp[c] += 1e-6;
            ym[c] -= 1e-6;
            model.rates(&mut Default::default(), 0.0, &yp, &mut fp, true).unwrap();
            model.rates(&mut Default::default(), 0.0, &ym, &mut fm, true).unwrap();
            for r in 0..n {
                fd[(r, c)] = (fp[r] - fm[r]) / 2e-6;
            }
        }
        let scale = exact.amax();
        assert!((&exact - &fd).amax() < 1e-6 * scale, "max difference {:e} of {scale:e}", (&exact - &fd).amax());
        model.definite_springs = true;
        let mut definite = DMatrix::zeros(n, n);
        model.analytic_entries(Some(&y), &mut |r, c, v| definite[(r, c)] += v);
        assert!((&definite - &exact).amax() > 1e-3 * scale, "the definite variant should differ on this state");
    }

    fn compiled_y(w: &crate::World) -> Vec<f64> {
        let c = w.compile();
        c.handles.pack(w.particles_arena(), w.bodies_arena())
    }
}
