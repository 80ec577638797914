//! Orders of convergence measured as slopes of log error against log h, against closed forms.

use crate::common;
use common::{final_state, loglog_slope};
use tumble_integrate::problems::DampedOscillator;
use tumble_integrate::{solve, Method, SaveAt, Settings};

const OSC: DampedOscillator = DampedOscillator { mass: 1.0, damping: 0.3, stiffness: 4.0 };
const T_END: f64 = 5.0;

fn oscillator_error(settings: &Settings) -> f64 {
    let (x, v) = OSC.exact(T_END, 1.0, 0.0);
    let sol = final_state(&mut OSC.clone(), settings, &[1.0, 0.0], T_END).unwrap();
    ((sol.final_state[0] - x).powi(2) + (sol.final_state[1] - v).powi(2)).sqrt()
}

/// Every fixed-step method, over a halving sequence of steps chosen so that errors stay well above round-off
/// (1e-13) and in the asymptotic range. The slope must be within 0.25 of the order (the tolerance).
#[test]
fn fixed_step_orders_match_theory() {
    let cases: [(Method, &[f64]); 12] = [
        (Method::Euler, &[0.01, 0.005, 0.0025, 0.00125]),
        (Method::Midpoint, &[0.02, 0.01, 0.005, 0.0025]),
        (Method::Rk4, &[0.05, 0.025, 0.0125, 0.00625]),
        (Method::Ab4, &[0.02, 0.01, 0.005, 0.0025]),
        (Method::Am4, &[0.04, 0.02, 0.01, 0.005]),
        (Method::ImplicitEuler, &[0.01, 0.005, 0.0025, 0.00125]),
        (Method::Dopri5, &[0.1, 0.05, 0.025, 0.0125]),
        (Method::SymplecticEuler, &[0.01, 0.005, 0.0025, 0.00125]),
        (Method::Verlet, &[0.02, 0.01, 0.005, 0.0025]),
        (Method::Rodas4, &[0.05, 0.025, 0.0125, 0.00625]),
        (Method::Radau5, &[0.2, 0.1, 0.05, 0.025]),
        (Method::Dop853, &[0.5, 0.4, 0.3, 0.2]),
    ];
    for (method, steps) in cases {
        let errors: Vec<f64> = steps.iter().map(|&h| oscillator_error(&Settings::fixed(method, h))).collect();
        let slope = loglog_slope(steps, &errors);
        let order = method.order() as f64;
        assert!(
            (slope - order).abs() <= 0.25,
            "{method}: measured order {slope:.3}, theory {order} (errors {errors:?})"
        );
    }
}

/// Implicit Euler with full Newton converges at order 1 too, and on this linear problem agrees with the
/// linearised step to round-off (Newton converges in one correction; tolerance 1e-12 absolute).
#[test]
fn implicit_euler_newton_matches_linearised_on_linear_problem() {
    let h = 0.01;
    let lin = oscillator_error(&Settings::fixed(Method::ImplicitEuler, h));
    let newton = Settings::fixed(Method::ImplicitEuler, h)
        .newton(tumble_integrate::NewtonMode::Newton { tol: 1e-10, max_iter: 8 });
    let sol_lin =
        final_state(&mut OSC.clone(), &Settings::fixed(Method::ImplicitEuler, h), &[1.0, 0.0], T_END).unwrap();
    let sol_new = final_state(&mut OSC.clone(), &newton, &[1.0, 0.0], T_END).unwrap();
    assert!((sol_lin.final_state - sol_new.final_state).norm() < 1e-12);
    assert!(lin > 0.0);
    assert!(sol_new.report.newton_iterations >= sol_new.report.steps);
}

/// The chapter's variable-step Euler takes h = sqrt(2 eps/||f'||), so its global error, O(h), falls as
/// sqrt(eps): slope 0.5 in log eps (within 0.1: the step formula is only asymptotically exact).
#[test]
fn euler_variable_error_falls_as_sqrt_of_tolerance() {
    let eps = [1e-5, 1e-6, 1e-7, 1e-8];
    let errors: Vec<f64> = eps.iter().map(|&e| oscillator_error(&Settings::euler_variable(e))).collect();
    let slope = loglog_slope(&eps, &errors);
    assert!((slope - 0.5).abs() < 0.1, "slope {slope}, errors {errors:?}");
}

/// Dense output: Dormand-Prince's interpolant is 4th order, Rodas4's and Radau5's (the collocation polynomial)
/// 3rd order. Interpolated states at 101 times
/// must be as accurate as the tolerance allows: within 100 x atol of the closed form (the interpolant's error is
/// of the size of the local error, which the controller keeps near the tolerance).
#[test]
fn dense_output_matches_closed_form() {
    let times: Vec<f64> = (0..=100).map(|k| k as f64 * T_END / 100.0).collect();
    for method in [Method::Dopri5, Method::Rodas4, Method::Radau5] {
        let atol = 1e-9;
        let settings = Settings::tolerances(method, 1e-9, atol);
        let sol = solve(&mut OSC.clone(), &settings, 0.0, &[1.0, 0.0], T_END, &SaveAt::Times(times.clone())).unwrap();
        let stepped = solve(
            &mut OSC.clone(),
            &settings.clone().dense_output(false),
            0.0,
            &[1.0, 0.0],
            T_END,
            &SaveAt::Times(times.clone()),
        )
        .unwrap();
        assert!(
            sol.report.steps < stepped.report.steps,
            "{method}: the outputs should be interpolated, not stepped to"
        );
        for (k, &t) in times.iter().enumerate() {
            let (x, v) = OSC.exact(t, 1.0, 0.0);
            let e = (sol.states[(0, k)] - x).abs().max((sol.states[(1, k)] - v).abs());
            assert!(e < 100.0 * atol, "{method} at t = {t}: error {e:e}");
        }
    }
}

/// Fixed-step outputs: each output interval is divided into equal steps, so a fixed-step method lands exactly on
/// every output time and returns the state there (checked against RK4 run to each time separately).
#[test]
fn fixed_step_outputs_are_exact_step_stops() {
    let settings = Settings::fixed(Method::Rk4, 0.01);
    let times = vec![0.0, 0.37, 1.0, 2.5];
    let sol = solve(&mut OSC.clone(), &settings, 0.0, &[1.0, 0.0], 2.5, &SaveAt::Times(times.clone())).unwrap();
    for (k, &t) in times.iter().enumerate() {
        let (x, _) = OSC.exact(t, 1.0, 0.0);
        assert!((sol.states[(0, k)] - x).abs() < 1e-8, "t = {t}");
    }
}
