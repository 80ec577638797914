//! Published references: the stiff test set by Rodas4 and the non-stiff problems by Dormand-Prince, each to at
//! least 6 significant digits.

use tumble_integrate::problems::{self, LotkaVolterra};
use tumble_integrate::{solve, Method, SaveAt, Settings};

/// 6 significant digits: every component within a relative 5e-7 of the reference.
const SIX_DIGITS: f64 = 5e-7;

fn run(name: &str, settings: &Settings) -> (f64, tumble_integrate::Report) {
    let p = problems::by_name(name).unwrap();
    let reference = p.reference.clone().unwrap();
    let sol = solve(&mut p.system(), settings, p.t0, &p.y0, p.t_end, &SaveAt::End).unwrap();
    (p.error(sol.final_state.as_slice(), &reference), sol.report)
}

/// Van der Pol (eps = 1e-6), ROBER to t = 1e11, HIRES and OREGO: Rodas4 and Radau5 at rtol = 1e-8. ROBER's
/// y2 ~ 8e-14 and y1 ~ 2e-8 need an absolute tolerance far below them (1e-18); the others take atol = 1e-10.
#[test]
fn stiff_methods_reproduce_the_stiff_test_set() {
    for method in [Method::Rodas4, Method::Radau5] {
        for (name, atol) in [("van-der-pol", 1e-10), ("rober", 1e-18), ("hires", 1e-10), ("orego", 1e-10)] {
            let (err, report) = run(name, &Settings::tolerances(method, 1e-8, atol));
            assert!(err < SIX_DIGITS, "{method} on {name}: componentwise relative error {err:e}");
            assert!(report.jacobians > 0 && report.factorizations > 0, "{name}: {report:?}");
        }
    }
}

/// Radau5 keeps its Jacobian while Newton converges fast: on Van der Pol it evaluates fewer Jacobians than it
/// takes steps (Rodas4 needs one per step).
#[test]
fn radau5_reuses_jacobians() {
    let (_, radau) = run("van-der-pol", &Settings::tolerances(Method::Radau5, 1e-8, 1e-10));
    assert!(radau.jacobians < radau.steps, "{radau:?}");
}

/// Arenstorf and Kepler close after one period, and the stiff spring has a closed form: Dormand-Prince 5 and 8
/// at rtol = atol = 1e-11 (the Arenstorf orbit passes close to the moon and amplifies errors ~1e4-fold).
#[test]
fn dormand_prince_reproduces_the_nonstiff_references() {
    for method in [Method::Dopri5, Method::Dop853] {
        for name in ["arenstorf", "kepler", "stiff-spring"] {
            let (err, _) = run(name, &Settings::tolerances(method, 1e-11, 1e-11));
            assert!(err < SIX_DIGITS, "{method} on {name}: relative error {err:e}");
        }
    }
}

/// Lotka-Volterra has no closed form but an invariant, V = d u1 - c ln u1 + b u2 - a ln u2. Dormand-Prince at
/// rtol = 1e-10 keeps it to 1e-8 relative over t in [0, 10] (the drift is of the order of the tolerance times the
/// number of steps), and agrees with RK4 at h = 1e-4 (global error ~1e-13) to 6 digits.
#[test]
fn dopri5_lotka_volterra_invariant_and_agreement() {
    let p = problems::by_name("lotka-volterra").unwrap();
    let lv = LotkaVolterra { p: [1.5, 1.0, 3.0, 1.0] };
    let [a, b, c, d] = lv.p;
    let v = |u: &[f64]| d * u[0] - c * u[0].ln() + b * u[1] - a * u[1].ln();
    let sol = solve(
        &mut lv.clone(),
        &Settings::tolerances(Method::Dopri5, 1e-10, 1e-10),
        0.0,
        &p.y0,
        p.t_end,
        &SaveAt::Every(0.5),
    )
    .unwrap();
    let v0 = v(&p.y0);
    for k in 0..sol.times.len() {
        let vk = v(sol.states.column(k).as_slice());
        assert!(((vk - v0) / v0).abs() < 1e-8, "t = {}: invariant drifted by {:e}", sol.times[k], (vk - v0) / v0);
    }
    let rk4 = solve(&mut lv.clone(), &Settings::fixed(Method::Rk4, 1e-4), 0.0, &p.y0, p.t_end, &SaveAt::End).unwrap();
    let err = p.error(sol.final_state.as_slice(), rk4.final_state.as_slice());
    assert!(err < SIX_DIGITS, "dopri5 vs rk4: {err:e}");
}
