//! Every error path returns its error and leaves the caller's state untouched.

use tumble_integrate::problems::{Dahlquist, DampedOscillator, StiffSpring, VanDerPol};
use tumble_integrate::{
    solve, FnSystem, Integrator, Method, NewtonMode, OdeError, OdeSystem, SaveAt, Settings, SystemError,
};

const OSC: DampedOscillator = DampedOscillator { mass: 1.0, damping: 0.1, stiffness: 1.0 };

fn err_of(sys: &mut impl OdeSystem, settings: &Settings, y0: &[f64], t0: f64, t_end: f64) -> OdeError {
    let before = y0.to_vec();
    let e = solve(sys, settings, t0, y0, t_end, &SaveAt::End).expect_err("the call must fail");
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(y0), bits(&before), "solve must not write to y0");
    e
}

fn invalid_name(e: &OdeError) -> &'static str {
    match e {
        OdeError::InvalidArgument { name, .. } => name,
        other => panic!("expected InvalidArgument, got {other:?}"),
    }
}

#[test]
fn bad_arguments_name_the_argument() {
    let y0 = [1.0, 0.0];
    for dt in [0.0, -0.1, f64::NAN, f64::INFINITY] {
        let e = err_of(&mut OSC.clone(), &Settings::fixed(Method::Rk4, dt), &y0, 0.0, 1.0);
        assert_eq!(invalid_name(&e), "dt", "dt = {dt}");
    }
    let e = err_of(&mut OSC.clone(), &Settings::fixed(Method::Rk4, 0.1), &y0, 0.0, -1.0);
    assert_eq!(invalid_name(&e), "t_end");
    let e = err_of(&mut OSC.clone(), &Settings::fixed(Method::Rk4, 0.1), &[1.0, 0.0, 0.0], 0.0, 1.0);
    assert_eq!(invalid_name(&e), "y0");
    let e = err_of(&mut OSC.clone(), &Settings::fixed(Method::Rk4, 0.1), &[f64::NAN, 0.0], 0.0, 1.0);
    assert_eq!(invalid_name(&e), "y0");
    let e = err_of(&mut OSC.clone(), &Settings::fixed(Method::Rk4, 0.1), &y0, f64::NAN, 1.0);
    assert!(matches!(e, OdeError::InvalidArgument { .. }));
    let e = err_of(&mut OSC.clone(), &Settings::tolerances(Method::Dopri5, -1e-6, 1e-9), &y0, 0.0, 1.0);
    assert_eq!(invalid_name(&e), "rtol");
    let e = err_of(&mut OSC.clone(), &Settings::tolerances(Method::Dopri5, 1e-6, f64::NAN), &y0, 0.0, 1.0);
    assert_eq!(invalid_name(&e), "atol");
    let e = err_of(&mut OSC.clone(), &Settings::step_doubling(Method::Rk4, 0.0, 0.1), &y0, 0.0, 1.0);
    assert_eq!(invalid_name(&e), "tolerance");
    let e = err_of(&mut OSC.clone(), &Settings::fixed(Method::Rk4, 0.1).max_steps(0), &y0, 0.0, 1.0);
    assert_eq!(invalid_name(&e), "max_steps");
    let e = solve(&mut OSC.clone(), &Settings::fixed(Method::Rk4, 0.1), 0.0, &y0, 1.0, &SaveAt::Times(vec![0.5, 0.2]))
        .unwrap_err();
    assert_eq!(invalid_name(&e), "save_at");
    let e = solve(&mut OSC.clone(), &Settings::fixed(Method::Rk4, 0.1), 0.0, &y0, 1.0, &SaveAt::Times(vec![2.0]))
        .unwrap_err();
    assert_eq!(invalid_name(&e), "save_at");
    assert_eq!(invalid_name(&"rk5".parse::<Method>().unwrap_err()), "integrator");
}

#[test]
fn unsupported_combinations_are_refused() {
    let unsupported = |e: OdeError| assert!(matches!(e, OdeError::Unsupported { .. }), "{e:?}");
    let no_split = || FnSystem::new(1, |_, y: &[f64], dy: &mut [f64]| dy[0] = -y[0]);
    unsupported(err_of(&mut no_split(), &Settings::fixed(Method::Verlet, 0.1), &[1.0], 0.0, 1.0));
    unsupported(err_of(&mut no_split(), &Settings::tolerances(Method::Rk4, 1e-6, 1e-6), &[1.0], 0.0, 1.0));
    unsupported(err_of(&mut no_split(), &Settings::step_doubling(Method::Ab4, 1e-6, 0.1), &[1.0], 0.0, 1.0));
    unsupported(err_of(&mut no_split(), &Settings::fixed(Method::EulerVariable, 0.1), &[1.0], 0.0, 1.0));
}

/// A system whose derivative turns NaN once t passes 0.5.
fn poisoned() -> impl OdeSystem {
    FnSystem::new(1, |t, y: &[f64], dy: &mut [f64]| dy[0] = if t > 0.5 { f64::NAN } else { -y[0] })
}

#[test]
fn non_finite_derivative_is_an_error_not_a_nan() {
    for settings in [Settings::fixed(Method::Rk4, 0.1), Settings::tolerances(Method::Dopri5, 1e-6, 1e-9)] {
        let e = err_of(&mut poisoned(), &settings, &[1.0], 0.0, 1.0);
        assert!(matches!(e, OdeError::NonFinite { .. }), "{}: {e:?}", settings.method);
    }
}

#[test]
fn divergence_is_reported_before_overflow() {
    // Explicit Euler on the stiff spring at h = 1e-3 multiplies the amplitude by ~10 a step.
    let e = err_of(&mut StiffSpring { stiffness: 1e8 }, &Settings::fixed(Method::Euler, 1e-3), &[1.0, 0.0], 0.0, 1.0);
    match e {
        OdeError::Divergence { norm, limit, .. } => assert!(norm > limit && norm.is_finite()),
        other => panic!("expected Divergence, got {other:?}"),
    }
}

#[test]
fn step_below_minimum() {
    // Dormand-Prince on Van der Pol (eps = 1e-6) needs steps ~1e-6 in the fast transitions.
    let settings = Settings::tolerances(Method::Dopri5, 1e-6, 1e-6).min_step(1e-3);
    let e = err_of(&mut VanDerPol { eps: 1e-6 }, &settings, &[2.0, 0.0], 0.0, 2.0);
    assert!(matches!(e, OdeError::StepTooSmall { .. }), "{e:?}");
}

#[test]
fn newton_failure() {
    // One Newton iteration at h = 0.5 on Van der Pol cannot meet 1e-14.
    let settings = Settings::fixed(Method::ImplicitEuler, 0.5).newton(NewtonMode::Newton { tol: 1e-14, max_iter: 1 });
    let e = err_of(&mut VanDerPol { eps: 1e-6 }, &settings, &[2.0, 0.0], 0.0, 2.0);
    assert!(matches!(e, OdeError::NewtonFailure { .. }), "{e:?}");
    // Radau5 at a fixed h = 0.5 across Van der Pol's fast transitions: its simplified Newton does not converge.
    let e = err_of(&mut VanDerPol { eps: 1e-6 }, &Settings::fixed(Method::Radau5, 0.5), &[2.0, 0.0], 0.0, 2.0);
    assert!(matches!(e, OdeError::NewtonFailure { .. }), "{e:?}");
}

#[test]
fn singular_iteration_matrix() {
    // y' = y with h = 1: I/h - J = 0.
    let e = err_of(&mut Dahlquist { lambda: 1.0 }, &Settings::fixed(Method::ImplicitEuler, 1.0), &[1.0], 0.0, 2.0);
    assert!(matches!(e, OdeError::SingularMatrix { .. }), "{e:?}");
}

#[test]
fn too_many_steps() {
    for settings in [
        Settings::fixed(Method::Rk4, 0.01).max_steps(10),
        Settings::tolerances(Method::Dopri5, 1e-10, 1e-10).max_steps(10),
    ] {
        let e = err_of(&mut OSC.clone(), &settings, &[1.0, 0.0], 0.0, 10.0);
        assert!(matches!(e, OdeError::TooManySteps { .. }), "{e:?}");
    }
}

struct Failing;
impl OdeSystem for Failing {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), SystemError> {
        if t > 0.25 {
            return Err(SystemError::new("contact solver failed"));
        }
        dy[0] = -y[0];
        Ok(())
    }
}

#[test]
fn system_error_is_passed_on() {
    let e = err_of(&mut Failing, &Settings::fixed(Method::Rk4, 0.1), &[1.0], 0.0, 1.0);
    match e {
        OdeError::System { message, .. } => assert_eq!(message, "contact solver failed"),
        other => panic!("expected System, got {other:?}"),
    }
}

/// An integrator advanced part way and then failing is restored exactly: time, state, and it can continue.
#[test]
fn failed_advance_restores_time_and_state() {
    for settings in [
        Settings::fixed(Method::Rk4, 0.01),
        Settings::fixed(Method::Ab4, 0.01),
        Settings::tolerances(Method::Dopri5, 1e-8, 1e-8),
        Settings::tolerances(Method::Rodas4, 1e-8, 1e-8),
        Settings::tolerances(Method::Radau5, 1e-8, 1e-8),
        Settings::tolerances(Method::Dop853, 1e-8, 1e-8),
    ] {
        let mut sys = poisoned();
        let mut integ = Integrator::new(&mut sys, settings.clone(), 0.0, &[1.0]).unwrap();
        integ.advance_to(&mut sys, 0.3, &[], |_, _, _| {}).unwrap();
        let (t, y) = (integ.time(), integ.state().to_vec());
        let e = integ.advance_to(&mut sys, 1.0, &[], |_, _, _| {}).unwrap_err();
        assert!(matches!(e, OdeError::NonFinite { .. }), "{}: {e:?}", settings.method);
        assert_eq!(integ.time(), t, "{}", settings.method);
        assert_eq!(integ.state(), &y[..], "{}", settings.method);
        // It can still go on to where the system is healthy, and matches exp(-t).
        integ.advance_to(&mut sys, 0.5, &[], |_, _, _| {}).unwrap();
        assert!((integ.state()[0] - (-0.5f64).exp()).abs() < 1e-6, "{}", settings.method);
    }
}
