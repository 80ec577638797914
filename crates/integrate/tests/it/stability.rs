//! Stability on y' = lambda y with lambda = -1e6: explicit methods decay just below their real-axis limit of
//! h|lambda| and grow just above it; implicit Euler and Rodas4 decay at any step.

use tumble_integrate::problems::Dahlquist;
use tumble_integrate::{solve, Method, SaveAt, Settings};

const LAMBDA: f64 = -1e6;

/// |y| after `steps` fixed steps of h = z / |lambda| from y = 1.
fn magnitude_after(method: Method, z: f64, steps: usize) -> f64 {
    let h = z / LAMBDA.abs();
    let sol = solve(
        &mut Dahlquist { lambda: LAMBDA },
        &Settings::fixed(method, h),
        0.0,
        &[1.0],
        h * steps as f64,
        &SaveAt::End,
    )
    .unwrap_or_else(|e| panic!("{method} at h|lambda| = {z}: {e}"));
    sol.final_state[0].abs()
}

/// Limits on the negative real axis: Euler 2, midpoint 2, RK4 2.7853, AB4 0.3, AM4 PECE 1.2848 (computed from
/// the amplification polynomials). 1% inside, the amplification factor is at most 0.993 a step; 1% outside, at
/// least 1.0067; 5000 steps turn that into a factor < 1e-14 or > 1e14, so the thresholds 1e-6 and 1e6 leave
/// eight orders of margin either way.
#[test]
fn explicit_methods_decay_below_their_limit_and_grow_above() {
    for (method, limit) in [
        (Method::Euler, 2.0),
        (Method::Midpoint, 2.0),
        (Method::Rk4, 2.785293563405293),
        (Method::Ab4, 0.3),
        (Method::Am4, 1.284816263106901),
    ] {
        let below = magnitude_after(method, 0.99 * limit, 5000);
        let above = magnitude_after(method, 1.01 * limit, 5000);
        assert!(below < 1e-6, "{method}: |y| = {below:e} just below its limit");
        assert!(above > 1e6, "{method}: |y| = {above:e} just above its limit");
    }
}

/// Implicit Euler (R(z) = 1/(1-z)) and the L-stable Rodas4 and Radau5 (R(-inf) = 0) decay at h = 1 and h = 1e6, i.e.
/// h|lambda| = 1e6 and 1e12, far beyond any explicit limit. One step must already shrink |y| below 1e-5
/// (implicit Euler's factor is 1/(1 + h|lambda|) <= 1e-6), and ten steps keep it shrinking.
#[test]
fn implicit_methods_decay_at_huge_steps() {
    for method in [Method::ImplicitEuler, Method::Rodas4, Method::Radau5] {
        for h in [1.0, 1e6] {
            let one =
                solve(&mut Dahlquist { lambda: LAMBDA }, &Settings::fixed(method, h), 0.0, &[1.0], h, &SaveAt::End)
                    .unwrap();
            let ten = solve(
                &mut Dahlquist { lambda: LAMBDA },
                &Settings::fixed(method, h),
                0.0,
                &[1.0],
                10.0 * h,
                &SaveAt::End,
            )
            .unwrap();
            let (y1, y10) = (one.final_state[0].abs(), ten.final_state[0].abs());
            assert!(y1 < 1e-5, "{method} h = {h}: |y1| = {y1:e}");
            assert!(y10 <= y1, "{method} h = {h}: |y10| = {y10:e} > |y1| = {y1:e}");
        }
    }
}

/// The stiff spring (eigenvalues +-1e4 i): explicit Euler's factor is |1 + i h w| > 1 for every h, so it diverges
/// at any step, while RK4 is stable up to h w = 2.83 (the imaginary-axis limit 2 sqrt 2).
#[test]
fn stiff_spring_euler_always_unstable_rk4_stable_below_limit() {
    use tumble_integrate::problems::StiffSpring;
    let spring = || StiffSpring { stiffness: 1e8 };
    let energy = |y: &[f64]| 0.5 * y[1] * y[1] + 0.5 * 1e8 * y[0] * y[0];
    let e0 = energy(&[1.0, 0.0]);
    for h in [1e-5, 1e-6] {
        let sol =
            solve(&mut spring(), &Settings::fixed(Method::Euler, h), 0.0, &[1.0, 0.0], 0.1, &SaveAt::End).unwrap();
        // 0.1/h steps, each multiplying the energy by 1 + (h w)^2.
        let growth = energy(sol.final_state.as_slice()) / e0;
        let expected = (1.0 + (h * 1e4f64).powi(2)).powf(0.1 / h);
        assert!((growth / expected - 1.0).abs() < 1e-6, "h = {h}: growth {growth:e}, expected {expected:e}");
        assert!(growth > 1.0);
    }
    // 250 steps: RK4's energy factor per step is |R(i h w)|^2, 0.866 at h w = 2.8 and 1.171 at 2.86.
    let stable =
        solve(&mut spring(), &Settings::fixed(Method::Rk4, 2.8e-4), 0.0, &[1.0, 0.0], 0.07, &SaveAt::End).unwrap();
    assert!(energy(stable.final_state.as_slice()) < 0.9 * e0, "RK4 at h w = 2.8 must lose energy");
    let unstable =
        solve(&mut spring(), &Settings::fixed(Method::Rk4, 2.86e-4), 0.0, &[1.0, 0.0], 0.0715, &SaveAt::End).unwrap();
    assert!(energy(unstable.final_state.as_slice()) > 2.0 * e0, "RK4 at h w = 2.86 must gain energy");
}
