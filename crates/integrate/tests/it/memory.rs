//! An integration's memory (`Integrator::memory` / `set_memory`): given to a fresh integrator of the same system
//! and settings it continues bit for bit, for every method and step control; a memory that does not fit is
//! refused by name and leaves the integrator unchanged.

use tumble_integrate::faer::MatMut;
use tumble_integrate::*;

/// Two Duffing oscillators coupled by a spring, damped: y = (x0, x1, v0, v1),
/// a_i = -k x_i - c x_i^3 - d v_i + s (x_j - x_i). Nonlinear (the Jacobian changes along the path), stiff enough with k = 400 that the implicit
/// methods reuse and refactor; dense or sparse analytic Jacobian.
#[derive(Clone)]
struct Duffing {
    sparse: bool,
}

const K: f64 = 400.0;
const C: f64 = 30.0;
const D: f64 = 0.4;
const S: f64 = 50.0;
const PATTERN: [(usize, usize); 8] = [(0, 2), (1, 3), (2, 0), (2, 1), (2, 2), (3, 0), (3, 1), (3, 3)];

impl Duffing {
    fn accel(y: &[f64], dp: &mut [f64]) {
        for i in 0..2 {
            let (x, xo, v) = (y[i], y[1 - i], y[2 + i]);
            dp[i] = -K * x - C * x * x * x - D * v + S * (xo - x);
        }
    }

    fn entries(y: &[f64]) -> [f64; 8] {
        let diag = |x: f64| -K - 3.0 * C * x * x - S;
        [1.0, 1.0, diag(y[0]), S, -D, S, diag(y[1]), -D]
    }
}

impl OdeSystem for Duffing {
    fn dim(&self) -> usize {
        4
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), SystemError> {
        dy[0] = y[2];
        dy[1] = y[3];
        Duffing::accel(y, &mut dy[2..]);
        Ok(())
    }
    fn jacobian_structure(&self) -> JacobianStructure {
        if self.sparse {
            JacobianStructure::Sparse(PATTERN.to_vec())
        } else {
            JacobianStructure::Dense
        }
    }
    fn dense_jacobian(&mut self, _t: f64, y: &[f64], mut jac: MatMut<'_, f64>) -> Result<(), SystemError> {
        for (&(i, j), v) in PATTERN.iter().zip(Duffing::entries(y)) {
            jac[(i, j)] = v;
        }
        Ok(())
    }
    fn sparse_jacobian(&mut self, _t: f64, y: &[f64], values: &mut [f64]) -> Result<(), SystemError> {
        values.copy_from_slice(&Duffing::entries(y));
        Ok(())
    }
    fn is_autonomous(&self) -> bool {
        true
    }
    fn split(&self) -> Option<Split> {
        Some(Split { positions: 2, force_depends_on_velocity: true, kinematic_identity: true })
    }
    fn position_rate(&mut self, _t: f64, y: &[f64], dq: &mut [f64]) -> Result<(), SystemError> {
        dq.copy_from_slice(&y[2..]);
        Ok(())
    }
    fn velocity_rate(&mut self, _t: f64, y: &[f64], dp: &mut [f64]) -> Result<(), SystemError> {
        Duffing::accel(y, dp);
        Ok(())
    }
}

const Y0: [f64; 4] = [0.8, -0.3, 0.0, 1.0];
const SAVES: [f64; 3] = [0.61, 0.9, 1.17];

/// Every method under every control it accepts, on the dense and the sparse system; implicit Euler also with
/// Newton and with the iterative linear solver.
fn cases() -> Vec<(Settings, bool)> {
    let mut out = Vec::new();
    for method in Method::ALL {
        let mut settings = vec![
            Settings::fixed(method, 2e-3),
            Settings::tolerances(method, 1e-6, 1e-8),
            Settings::step_doubling(method, 1e-4, 1e-2),
        ];
        if method == Method::ImplicitEuler {
            let newton = NewtonMode::Newton { tol: 1e-10, max_iter: 8 };
            settings.push(Settings::fixed(method, 2e-3).newton(newton));
            settings.push(Settings::step_doubling(method, 1e-4, 1e-2).newton(newton));
            let krylov = LinearSolver::Iterative { rtol: 1e-12, max_iter: 50 };
            settings.push(Settings::fixed(method, 2e-3).linear_solver(krylov));
        }
        for s in settings {
            for sparse in [false, true] {
                if s.validate(&Duffing { sparse }).is_ok() {
                    out.push((s.clone(), sparse));
                }
            }
        }
    }
    out.push((Settings::euler_variable(1e-4), false));
    out
}

/// Runs on from the integrator's time to 1.2 with three outputs: the outputs, the final state and the proposed
/// step, as bits.
fn continue_run(i: &mut Integrator<Duffing>, sparse: bool, what: &str) -> Vec<u64> {
    let mut out = Vec::new();
    i.advance_to(&mut Duffing { sparse }, 1.2, &SAVES, |_, t, y| {
        out.push(t.to_bits());
        out.extend(y.iter().map(|v| v.to_bits()));
    })
    .unwrap_or_else(|e| panic!("{what}: {e}"));
    out.extend(i.state().iter().map(|v| v.to_bits()));
    out.push(i.proposed_step().unwrap_or(0.0).to_bits());
    out
}

#[test]
fn a_memory_given_to_a_fresh_integrator_continues_bit_for_bit_for_every_method_and_control() {
    let cases = cases();
    assert!(cases.len() >= 30, "only {} cases", cases.len());
    let mut histories = 0;
    for (settings, sparse) in cases {
        let what = format!("{:?} {:?} sparse={sparse}", settings.method, settings.control);
        let mut sys = Duffing { sparse };
        let mut a = Integrator::new(&mut sys, settings.clone(), 0.0, &Y0).unwrap();
        a.advance_to(&mut sys, 0.5, &[], |_, _, _| {}).unwrap();
        let memory = a.memory();
        assert_eq!(memory.method(), settings.method.name());
        let (t, y) = (a.time(), a.state().to_vec());
        let expected = continue_run(&mut a, sparse, &what);

        let mut b = Integrator::new(&mut sys, settings.clone(), 0.0, &Y0).unwrap();
        b.set_memory(&memory).unwrap();
        assert_eq!(continue_run(&mut b, sparse, &what), expected, "{what}");

        // Without the memory (the same time and state, histories and caches dropped) a method that keeps
        // anything between steps goes another way: the memory is what carried it.
        let mut c = Integrator::new(&mut sys, settings.clone(), 0.0, &Y0).unwrap();
        c.set_state(t, &y).unwrap();
        if continue_run(&mut c, sparse, &what) != expected {
            histories += 1;
        }
    }
    assert!(histories >= 10, "only {histories} cases depend on their memory");
}

#[test]
fn a_memory_that_does_not_fit_is_refused_by_name_and_changes_nothing() {
    let mut sys = Duffing { sparse: false };
    let radau = Settings::tolerances(Method::Radau5, 1e-6, 1e-8);
    let mut a = Integrator::new(&mut sys, radau.clone(), 0.0, &Y0).unwrap();
    a.advance_to(&mut sys, 0.3, &[], |_, _, _| {}).unwrap();
    let radau_memory = a.memory();
    let mut dopri = Integrator::new(&mut sys, Settings::tolerances(Method::Dopri5, 1e-6, 1e-8), 0.0, &Y0).unwrap();
    dopri.advance_to(&mut sys, 0.3, &[], |_, _, _| {}).unwrap();
    let before = dopri.memory();
    // Another method.
    match dopri.set_memory(&radau_memory) {
        Err(OdeError::InvalidArgument { name: "memory", .. }) => {}
        other => panic!("expected the memory refused, got {other:?}"),
    }
    assert_eq!(dopri.memory(), before);
    // Another size: the same method on a system of one oscillator's dimension.
    let small = FnSystem::new(2, |_t, y: &[f64], dy: &mut [f64]| {
        dy[0] = y[1];
        dy[1] = -y[0];
    });
    let mut small_sys = small;
    let mut s = Integrator::new(&mut small_sys, radau.clone(), 0.0, &[1.0, 0.0]).unwrap();
    let small_before = s.memory();
    match s.set_memory(&radau_memory) {
        Err(OdeError::InvalidArgument { name: "memory", reason }) => {
            assert!(reason.contains("numbers"), "{reason}")
        }
        other => panic!("expected the memory refused, got {other:?}"),
    }
    assert_eq!(s.memory(), small_before);
}
