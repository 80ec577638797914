//! Step-size control: the chapter's step doubling around every one-step method, Adams-Moulton with Milne's
//! estimate, the reports' counters, and the sparse Jacobian path.

use crate::common;
use common::final_state;
use tumble_integrate::problems::DampedOscillator;
use tumble_integrate::*;

const OSC: DampedOscillator = DampedOscillator { mass: 1.0, damping: 0.3, stiffness: 4.0 };

fn osc_error(settings: &Settings) -> (f64, Report) {
    let (x, v) = OSC.exact(5.0, 1.0, 0.0);
    let sol = final_state(&mut OSC.clone(), settings, &[1.0, 0.0], 5.0).unwrap();
    let e = ((sol.final_state[0] - x).powi(2) + (sol.final_state[1] - v).powi(2)).sqrt();
    (e, sol.report)
}

/// Step doubling works around every one-step method and its accuracy follows the tolerance: a 1e4-fold tighter
/// per-step tolerance gives at least a 10-fold smaller global error (order n gives (1e4)^(n/(n+1)) in theory,
/// at least 1e2 for n = 1). Each run reports rejected steps and an error estimate.
#[test]
fn step_doubling_around_every_one_step_method() {
    for method in Method::ALL.into_iter().filter(|m| m.is_one_step()) {
        let (loose, r1) = osc_error(&Settings::step_doubling(method, 1e-5, 0.1));
        let (tight, r2) = osc_error(&Settings::step_doubling(method, 1e-9, 0.1));
        assert!(tight * 10.0 < loose, "{method}: error {loose:e} at 1e-5, {tight:e} at 1e-9");
        assert!(r2.steps > r1.steps, "{method}");
        assert!(r1.error_estimate.is_some());
    }
}

/// The chapter's rule h_new = h (e_max/e)^(1/(n+1)) makes the measured doubling differences e hover at e_max:
/// for RK4 the global error after many steps is of the order of (steps x e_max / (2^4 - 1)), never far above.
#[test]
fn step_doubling_error_tracks_tolerance() {
    let tol = 1e-8;
    let (err, report) = osc_error(&Settings::step_doubling(Method::Rk4, tol, 0.1));
    let bound = report.steps as f64 * tol;
    assert!(err < bound, "global error {err:e} exceeds steps x e_max = {bound:e}");
    let estimate = report.error_estimate.unwrap();
    assert!(estimate > 0.0 && estimate < bound);
}

/// Adams-Moulton PECE under Milne's estimate: the global error falls with the tolerance (h only moves by factors
/// of 2, so a 1e4-fold tolerance ratio is only promised a 10-fold error ratio), it stays below the sum of the
/// per-step tolerances (this problem contracts, so local errors add at most linearly), and the estimate is
/// reported.
#[test]
fn am4_milne_control() {
    let (loose, r1) = osc_error(&Settings::tolerances(Method::Am4, 1e-5, 1e-7));
    let (tight, r2) = osc_error(&Settings::tolerances(Method::Am4, 1e-9, 1e-11));
    assert!(tight * 10.0 < loose, "am4: {loose:e} vs {tight:e}");
    assert!(loose < r1.steps as f64 * 1e-5 && tight < r2.steps as f64 * 1e-9);
    assert!(r1.error_estimate.is_some() && r2.error_estimate.is_some());
    assert!(r2.steps > r1.steps);
}

/// Explicit methods never form a Jacobian or factor a matrix; implicit ones do.
#[test]
fn explicit_methods_build_no_jacobian() {
    for method in Method::ALL {
        let settings = match method {
            Method::EulerVariable => Settings::euler_variable(1e-6),
            m => Settings::fixed(m, 0.01),
        };
        let (_, r) = osc_error(&settings);
        if method.uses_jacobian() {
            assert!(r.jacobians > 0 && r.factorizations > 0, "{method}: {r:?}");
        } else {
            assert_eq!((r.jacobians, r.factorizations, r.linear_solves), (0, 0, 0), "{method}");
        }
    }
}

/// A chain of N masses and springs with fixed ends, y = (x_1..x_N, v_1..v_N), offered three ways: with a sparse
/// analytic Jacobian, a dense analytic one, and none (finite differences).
struct Chain {
    n: usize,
    k: f64,
    c: f64,
    jac: JacobianStructure,
    split: bool,
}

impl Chain {
    fn pattern(n: usize) -> Vec<(usize, usize)> {
        let mut p = Vec::new();
        for i in 0..n {
            p.push((i, n + i));
            for j in [i.wrapping_sub(1), i, i + 1] {
                if j < n {
                    p.push((n + i, j));
                }
            }
            p.push((n + i, n + i));
        }
        p
    }
    fn values(&self) -> Vec<f64> {
        let mut v = Vec::new();
        for i in 0..self.n {
            v.push(1.0);
            for j in [i.wrapping_sub(1), i, i + 1] {
                if j < self.n {
                    v.push(if j == i { -2.0 * self.k } else { self.k });
                }
            }
            v.push(-self.c);
        }
        v
    }
}

impl OdeSystem for Chain {
    fn dim(&self) -> usize {
        2 * self.n
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), SystemError> {
        let n = self.n;
        for i in 0..n {
            let left = if i > 0 { y[i - 1] } else { 0.0 };
            let right = if i + 1 < n { y[i + 1] } else { 0.0 };
            dy[i] = y[n + i];
            dy[n + i] = self.k * (left - 2.0 * y[i] + right) - self.c * y[n + i];
        }
        Ok(())
    }
    fn jacobian_structure(&self) -> JacobianStructure {
        self.jac.clone()
    }
    fn sparse_jacobian(&mut self, _t: f64, _y: &[f64], values: &mut [f64]) -> Result<(), SystemError> {
        values.copy_from_slice(&self.values());
        Ok(())
    }
    fn dense_jacobian(&mut self, _t: f64, _y: &[f64], mut jac: faer::MatMut<'_, f64>) -> Result<(), SystemError> {
        for (&(i, j), v) in Chain::pattern(self.n).iter().zip(self.values()) {
            jac[(i, j)] += v;
        }
        Ok(())
    }
    fn is_autonomous(&self) -> bool {
        true
    }
    fn split(&self) -> Option<Split> {
        self.split.then_some(Split { positions: self.n, force_depends_on_velocity: true, kinematic_identity: true })
    }
    fn position_rate(&mut self, _t: f64, y: &[f64], dq: &mut [f64]) -> Result<(), SystemError> {
        dq.copy_from_slice(&y[self.n..]);
        Ok(())
    }
    fn velocity_rate(&mut self, t: f64, y: &[f64], dp: &mut [f64]) -> Result<(), SystemError> {
        let mut dy = vec![0.0; 2 * self.n];
        self.rhs(t, y, &mut dy)?;
        dp.copy_from_slice(&dy[self.n..]);
        Ok(())
    }
}

/// The velocity-only form of the linearised implicit Euler step (used when dq/dt = p and the Jacobian is sparse)
/// is the same step as the full one: trajectories agree to round-off (1e-12 relative). BiCGSTAB at rtol = 1e-12
/// agrees to 1e-9 (its residual tolerance, amplified by the condition number of ~1e3 over 100 steps).
#[test]
fn velocity_form_of_implicit_euler_is_the_same_step() {
    let n = 40;
    let y0: Vec<f64> =
        (0..2 * n).map(|i| if i < n { (i as f64 * 0.3).sin() } else { 0.1 * (i as f64).cos() }).collect();
    let run = |split: bool, solver: LinearSolver| {
        let mut chain = Chain { n, k: 1e4, c: 0.5, jac: JacobianStructure::Sparse(Chain::pattern(n)), split };
        final_state(&mut chain, &Settings::fixed(Method::ImplicitEuler, 0.01).linear_solver(solver), &y0, 1.0).unwrap()
    };
    let full = run(false, LinearSolver::Direct);
    let reduced = run(true, LinearSolver::Direct);
    let iterative = run(true, LinearSolver::Iterative { rtol: 1e-12, max_iter: 500 });
    let scale = full.final_state.amax();
    assert!((&reduced.final_state - &full.final_state).amax() < 1e-12 * scale);
    assert!((&iterative.final_state - &full.final_state).amax() < 1e-9 * scale);
    assert!(iterative.report.krylov_iterations > 0 && iterative.report.factorizations == 0);
    assert_eq!(full.report.krylov_iterations, 0);
}

/// Sparse LU, dense LU (faer: the chain's 80 unknowns are past the small-matrix kernel, and Radau5's complex
/// pair becomes a 160 x 160 real system) and finite differences give the same implicit Euler, Rodas4 and Radau5
/// trajectories: to 1e-12 between the analytic ones (same matrix, different factorization order; Radau5 may take a
/// different number of Newton iterations, so 1e-9 for it), 1e-5 against finite differences
/// (forward differences of entries of size 2e4 carry ~1e-8 relative round-off, and the linearised implicit
/// Euler step passes that on to the state: 1.5e-6 was measured after 100 steps).
#[test]
fn sparse_dense_and_finite_difference_jacobians_agree() {
    let n = 40;
    let y0: Vec<f64> = (0..2 * n).map(|i| if i < n { (i as f64 * 0.3).sin() } else { 0.0 }).collect();
    for settings in [Settings::fixed(Method::ImplicitEuler, 0.01), Settings::tolerances(Method::Rodas4, 1e-8, 1e-10)] {
        let run = |jac: JacobianStructure| {
            let mut chain = Chain { n, k: 1e4, c: 0.5, jac, split: false };
            final_state(&mut chain, &settings, &y0, 1.0).unwrap()
        };
        let sparse = run(JacobianStructure::Sparse(Chain::pattern(n)));
        let dense = run(JacobianStructure::Dense);
        let fd = run(JacobianStructure::FiniteDifference);
        let colored = run(JacobianStructure::SparseFiniteDifference(Chain::pattern(n)));
        let scale = dense.final_state.amax();
        assert!((&sparse.final_state - &dense.final_state).amax() < 1e-12 * scale.max(1.0), "{}", settings.method);
        assert!((&fd.final_state - &dense.final_state).amax() < 1e-5 * scale.max(1.0), "{}", settings.method);
        assert!((&colored.final_state - &dense.final_state).amax() < 1e-5 * scale.max(1.0), "{}", settings.method);
        assert!(fd.report.rhs_evals > dense.report.rhs_evals + 2 * n, "{}: FD costs evaluations", settings.method);
    }
}

/// Coloured finite differences cost a number of evaluations per Jacobian set by the pattern's shape, not by the
/// size: the chain's columns touch at most three neighbouring rows blocks, so 40 and 400 masses need the same
/// number of colours, while dense differences need one evaluation per unknown.
#[test]
fn colored_finite_differences_cost_does_not_grow_with_size() {
    let per_jacobian = |n: usize, jac: JacobianStructure| {
        let mut chain = Chain { n, k: 1e4, c: 0.5, jac, split: false };
        let y0: Vec<f64> = (0..2 * n).map(|i| if i < n { (i as f64 * 0.3).sin() } else { 0.0 }).collect();
        let r = final_state(&mut chain, &Settings::fixed(Method::ImplicitEuler, 0.01), &y0, 0.1).unwrap().report;
        // Implicit Euler (linearised) evaluates f once a step besides the Jacobian.
        (r.rhs_evals - r.steps) / r.jacobians
    };
    let small = per_jacobian(40, JacobianStructure::SparseFiniteDifference(Chain::pattern(40)));
    let large = per_jacobian(400, JacobianStructure::SparseFiniteDifference(Chain::pattern(400)));
    assert_eq!(small, large);
    assert!(small <= 10, "{small} colours for a chain");
    assert_eq!(per_jacobian(40, JacobianStructure::FiniteDifference), 80);
}

/// A sparse pattern entry outside the matrix is refused when the integrator is built.
#[test]
fn sparse_pattern_out_of_range_is_refused() {
    let mut chain = Chain { n: 3, k: 1.0, c: 0.0, jac: JacobianStructure::Sparse(vec![(0, 7)]), split: false };
    let e = final_state(&mut chain, &Settings::fixed(Method::ImplicitEuler, 0.1), &[0.0; 6], 1.0).unwrap_err();
    assert!(matches!(e, OdeError::InvalidArgument { name: "jacobian pattern", .. }), "{e:?}");
}

/// Rotation on the unit circle, y' = (-y2, y1), with a projection back onto |y| = 1 after every step: explicit
/// Euler alone spirals outwards (|y| grows by sqrt(1 + h^2) a step); with the projection the norm is 1 to
/// round-off, and the system saw one projection per accepted step.
#[test]
fn projection_after_every_accepted_step() {
    struct Circle {
        projections: usize,
        project: bool,
    }
    impl OdeSystem for Circle {
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), SystemError> {
            dy[0] = -y[1];
            dy[1] = y[0];
            Ok(())
        }
        fn project(&mut self, _t: f64, y: &mut [f64]) -> bool {
            if !self.project {
                return false;
            }
            self.projections += 1;
            let r = (y[0] * y[0] + y[1] * y[1]).sqrt();
            y.iter_mut().for_each(|v| *v /= r);
            true
        }
    }
    let settings = Settings::fixed(Method::Euler, 0.01);
    let mut free = Circle { projections: 0, project: false };
    let drift = final_state(&mut free, &settings, &[1.0, 0.0], 10.0).unwrap().final_state.norm();
    assert!((drift - (1.0f64 + 1e-4).powf(500.0)).abs() < 1e-9, "unprojected norm {drift}");
    let mut held = Circle { projections: 0, project: true };
    let sol = final_state(&mut held, &settings, &[1.0, 0.0], 10.0).unwrap();
    assert!((sol.final_state.norm() - 1.0).abs() < 1e-15);
    assert_eq!(held.projections, sol.report.steps);
}

/// Pausing with `advance_until` does not change the integration: ten pauses give bit for bit the outputs, final
/// state and step count of one `advance_to` (dense output fills the outputs between steps either way).
#[test]
fn pausing_does_not_change_the_integration() {
    let times: Vec<f64> = (0..=100).map(|k| k as f64 * 0.05).collect();
    let settings = Settings::tolerances(Method::Dopri5, 1e-8, 1e-10);
    let mut sys = OSC;
    let mut whole = Integrator::new(&mut sys, settings.clone(), 0.0, &[1.0, 0.0]).unwrap();
    let mut a = Vec::new();
    whole.advance_to(&mut sys, 5.0, &times, |_, t, y| a.push((t, y.to_vec()))).unwrap();
    let mut paused = Integrator::new(&mut sys, settings, 0.0, &[1.0, 0.0]).unwrap();
    let (mut b, mut done) = (Vec::new(), 0);
    while done < times.len() {
        let pause = times[(done + 10).min(times.len()) - 1];
        done += paused.advance_until(&mut sys, 5.0, pause, &times[done..], |_, t, y| b.push((t, y.to_vec()))).unwrap();
    }
    assert_eq!(a, b);
    assert_eq!(whole.state(), paused.state());
    assert_eq!(whole.time(), 5.0);
    assert_eq!(whole.report().steps, paused.report().steps);
}
