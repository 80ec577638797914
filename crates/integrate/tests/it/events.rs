//! Events inside steps: a falling point crossing the floor, found by bisection on the step's dense output (or on
//! fresh steps for a method without one), cuts the step there and the advance returns with the event.

use tumble_integrate::{FnSystem, Integrator, Method, Settings};

fn fall() -> FnSystem<impl FnMut(f64, &[f64], &mut [f64])> {
    // y = (height, vertical velocity), g = 9.81
    FnSystem::new(2, |_t, y: &[f64], dy: &mut [f64]| {
        dy[0] = y[1];
        dy[1] = -9.81;
    })
}

#[test]
fn a_fall_is_cut_where_it_crosses_the_floor() {
    let exact = (2.0f64 / 9.81).sqrt();
    for settings in [Settings::tolerances(Method::Dopri5, 1e-10, 1e-12), Settings::fixed(Method::Rk4, 0.1)] {
        let mut sys = fall();
        let mut integ = Integrator::new(&mut sys, settings.clone(), 0.0, &[1.0, 0.0]).unwrap();
        let mut saved = Vec::new();
        let out = integ
            .advance_with_events(
                &mut sys,
                2.0,
                2.0,
                &[0.1, 0.2, 0.3, 1.5],
                |_, t, y| saved.push((t, y[0])),
                |step| {
                    if step.y1()[0] >= 0.0 {
                        return Ok(None);
                    }
                    // bisection on the state within the step, to 1e-12 s
                    let (mut lo, mut hi) = (step.t0(), step.t1());
                    while hi - lo > 1e-12 {
                        let mid = 0.5 * (lo + hi);
                        if step.state_at(mid)?[0] < 0.0 {
                            hi = mid
                        } else {
                            lo = mid
                        }
                    }
                    Ok(Some(lo))
                },
            )
            .unwrap();
        let tc = out.event.expect("the floor is crossed");
        // The fall is a parabola, which RK4 and Dormand-Prince's interpolant reproduce to rounding: tc to the
        // bisection's 1e-12 plus rounding.
        assert!((tc - exact).abs() < 1e-11, "{}: {tc} vs {exact}", settings.method.name());
        assert_eq!(integ.time(), tc);
        assert!(integ.state()[0].abs() < 1e-10, "height at the event: {}", integ.state()[0]);
        // outputs before the event were delivered (0.1 .. 0.3 s), the one after it was not
        assert_eq!(out.delivered, 3);
        for (t, y) in &saved {
            assert!((y - (1.0 - 0.5 * 9.81 * t * t)).abs() < 1e-9, "output at {t}: {y}");
        }
    }
}
