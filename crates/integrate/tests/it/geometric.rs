//! Geometric behaviour: velocity Verlet's energy error on the Kepler orbit stays bounded over 1e5 steps, while
//! RK4's drifts.

use tumble_integrate::problems::Kepler;
use tumble_integrate::{solve, Method, SaveAt, Settings};

/// Energy error |H(t) - H(0)| at 1000 equally spaced outputs over 1e5 steps of h = 2 pi / 1000 (100 orbits of
/// eccentricity 0.6).
fn energy_errors(method: Method) -> Vec<f64> {
    let p = Kepler::problem();
    let h = 2.0 * std::f64::consts::PI / 1000.0;
    let t_end = 1e5 * h;
    let times: Vec<f64> = (1..=1000).map(|k| k as f64 * t_end / 1000.0).collect();
    let sol = solve(&mut Kepler, &Settings::fixed(method, h), 0.0, &p.y0, t_end, &SaveAt::Times(times)).unwrap();
    assert_eq!(sol.report.steps, 100_000);
    let h0 = Kepler::energy(&p.y0);
    (0..sol.times.len()).map(|k| (Kepler::energy(sol.states.column(k).as_slice()) - h0).abs()).collect()
}

/// Verlet: the largest energy error over the last tenth of the run is no larger than 1.5 x the largest over the
/// first tenth (bounded oscillation; the factor allows for where in the orbit the samples fall). RK4: the error
/// at the end is at least 5 x the error after the first tenth (a drift that grows linearly gives 10 x).
#[test]
fn verlet_energy_bounded_rk4_energy_drifts() {
    let max = |v: &[f64]| v.iter().cloned().fold(0.0, f64::max);
    let verlet = energy_errors(Method::Verlet);
    let (first, last) = (max(&verlet[..100]), max(&verlet[900..]));
    assert!(last <= 1.5 * first, "verlet: first tenth {first:e}, last tenth {last:e}");

    let rk4 = energy_errors(Method::Rk4);
    let (early, end) = (rk4[99], rk4[999]);
    assert!(end >= 5.0 * early, "rk4: after a tenth {early:e}, at the end {end:e}");
    // And the drift is monotone in the large: each tenth ends with a larger error than the previous one.
    for k in 1..10 {
        assert!(rk4[100 * k + 99] > rk4[100 * k - 1], "rk4 energy error should keep growing (tenth {k})");
    }
}
