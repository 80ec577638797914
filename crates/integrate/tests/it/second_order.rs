//! The second-order form x'' = a(t, x, v) through the `FirstOrder` adapter: every method accepts it, and the
//! symplectic ones use its (x, v) split.

use tumble_integrate::{solve, FirstOrder, Method, SaveAt, SecondOrderSystem, Settings, SystemError};

/// The pendulum x'' = -sin x: energy E = v^2/2 - cos x is conserved.
struct Pendulum;

impl SecondOrderSystem for Pendulum {
    fn dof(&self) -> usize {
        1
    }
    fn acceleration(&mut self, _t: f64, x: &[f64], _v: &[f64], a: &mut [f64]) -> Result<(), SystemError> {
        a[0] = -x[0].sin();
        Ok(())
    }
    fn depends_on_velocity(&self) -> bool {
        false
    }
    fn is_autonomous(&self) -> bool {
        true
    }
}

fn energy(y: &[f64]) -> f64 {
    0.5 * y[1] * y[1] - y[0].cos()
}

/// A large swing (2 rad) for 100 time units. Dormand-Prince at rtol = 1e-10 keeps the energy to 1e-8 (3.4e-9
/// measured). Verlet at h = 0.01 keeps it to 1e-4 (2.7e-5 measured): its error is O(h^2) = 1e-4 times a constant
/// below 1 and does not drift. Radau5 at rtol = 1e-10 aims at its internal tolerance 0.1 rtol^(2/3) = 2.2e-8 per
/// step (RADAU5's tolerance transform), so 1e-7 (1.5e-8 measured).
#[test]
fn pendulum_energy_through_first_order_adapter() {
    let y0 = [2.0, 0.0];
    let e0 = energy(&y0);
    for (settings, tol) in [
        (Settings::tolerances(Method::Dopri5, 1e-10, 1e-10), 1e-8),
        (Settings::fixed(Method::Verlet, 0.01), 1e-4),
        (Settings::tolerances(Method::Radau5, 1e-10, 1e-10), 1e-7),
    ] {
        let sol = solve(&mut FirstOrder(Pendulum), &settings, 0.0, &y0, 100.0, &SaveAt::Every(1.0)).unwrap();
        for k in 0..sol.times.len() {
            let e = energy(sol.states.column(k).as_slice());
            assert!((e - e0).abs() < tol, "{} at t = {}: energy error {:e}", settings.method, sol.times[k], e - e0);
        }
    }
}

/// The adapter's rhs is (v, a(t, x, v)), so RK4 on it and RK4 on a hand-written first-order pendulum agree to
/// the last bit.
#[test]
fn first_order_adapter_is_the_chapter_reduction() {
    let settings = Settings::fixed(Method::Rk4, 0.01);
    let a = solve(&mut FirstOrder(Pendulum), &settings, 0.0, &[1.0, 0.5], 3.0, &SaveAt::End).unwrap();
    let mut manual = tumble_integrate::FnSystem::new(2, |_, y: &[f64], dy: &mut [f64]| {
        dy[0] = y[1];
        dy[1] = -y[0].sin();
    });
    let b = solve(&mut manual, &settings, 0.0, &[1.0, 0.5], 3.0, &SaveAt::End).unwrap();
    assert_eq!(a.final_state, b.final_state);
}
