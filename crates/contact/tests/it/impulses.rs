//! Collision impulses against closed forms: equal spheres exchanging velocities (e = 1) or moving on together
//! (e = 0), momentum conserved and kinetic energy never gained, the spin an off-centre hit gives, the particle form,
//! and simultaneous impulses along a row of touching balls.
#![cfg(feature = "clarabel")]

use crate::common;

use nalgebra::{Matrix3, Point3, Unit, Vector3};
use tumble_contact::{
    collision_impulses, impulse_magnitude, reflect, velocities_after, BodyState, BodyVelocity, Contact, SolverSettings,
};

fn ball(mass: f64, radius: f64, x: f64, v: Vector3<f64>) -> BodyState {
    let i = 0.4 * mass * radius * radius;
    BodyState { velocity: v, ..BodyState::rigid(mass, Matrix3::from_diagonal_element(i), Point3::new(x, 0.0, 0.0)) }
}

fn momentum(bodies: &[BodyState], v: &[BodyVelocity]) -> Vector3<f64> {
    bodies.iter().zip(v).map(|(b, v)| v.linear / b.inv_mass).sum()
}

fn energy(bodies: &[BodyState], v: &[BodyVelocity]) -> f64 {
    bodies
        .iter()
        .zip(v)
        .map(|(b, v)| 0.5 * v.linear.norm_squared() / b.inv_mass + 0.5 * v.angular.dot(&(b.inertia * v.angular)))
        .sum()
}

fn before(bodies: &[BodyState]) -> Vec<BodyVelocity> {
    bodies.iter().map(|b| BodyVelocity { linear: b.velocity, angular: b.angular_velocity }).collect()
}

/// Applies the chapter's single-contact impulse.
fn chapter(bodies: &[BodyState], c: &Contact) -> Vec<BodyVelocity> {
    let j = impulse_magnitude(bodies, c).unwrap();
    velocities_after(bodies, std::slice::from_ref(c), &[c.normal.into_inner() * j])
}

#[test]
fn equal_spheres_exchange_velocities_when_elastic_and_move_together_when_plastic() {
    let v = Vector3::new(3.0, 0.0, 0.0);
    let bodies = [ball(2.0, 0.5, -0.5, v), ball(2.0, 0.5, 0.5, Vector3::zeros())];
    let hit = Contact::new(0, 1, Point3::origin(), Vector3::x_axis());
    for solve in [true, false] {
        let after = |e: f64| -> Vec<BodyVelocity> {
            let c = hit.with_restitution(e);
            if solve {
                collision_impulses(&bodies, &[c], &SolverSettings::default()).unwrap().velocities
            } else {
                chapter(&bodies, &c)
            }
        };
        // 1e-9: the QP is solved to 1e-10 relative; the formula is exact to rounding.
        let elastic = after(1.0);
        assert!((elastic[0].linear).norm() < 1e-9 && (elastic[1].linear - v).norm() < 1e-9, "{elastic:?}");
        let plastic = after(0.0);
        assert!((plastic[0].linear - v / 2.0).norm() < 1e-9 && (plastic[1].linear - v / 2.0).norm() < 1e-9);
        // head-on through the centres: no spin
        assert!(elastic.iter().chain(&plastic).all(|b| b.angular.norm() < 1e-12));
    }
}

#[test]
fn momentum_is_conserved_and_energy_never_gained_for_any_restitution() {
    // Random unequal bodies hitting off-centre at random restitutions: momentum to rounding, energy never up, and
    // exactly conserved at e = 1.
    let mut rnd = common::uniform(7);
    for case in 0..500 {
        let inertia =
            |r: &mut dyn FnMut() -> f64| Matrix3::from_diagonal(&Vector3::new(0.1 + r(), 0.1 + r(), 0.1 + r()));
        let mut a = BodyState::rigid(0.5 + 3.0 * rnd(), inertia(&mut rnd), Point3::new(-1.0, 0.0, 0.0));
        let mut b = BodyState::rigid(0.5 + 3.0 * rnd(), inertia(&mut rnd), Point3::new(1.0, 0.3 * rnd(), 0.0));
        a.velocity = Vector3::new(2.0 + rnd(), rnd() - 0.5, rnd() - 0.5);
        a.angular_velocity = Vector3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5);
        b.velocity = Vector3::new(-1.0 - rnd(), rnd() - 0.5, rnd() - 0.5);
        let e = if case % 5 == 0 { 1.0 } else { rnd() };
        let point = Point3::new(0.0, rnd() - 0.5, rnd() - 0.5);
        let normal = Unit::new_normalize(Vector3::new(1.0, 0.4 * (rnd() - 0.5), 0.4 * (rnd() - 0.5)));
        let bodies = [a, b];
        let c = Contact::new(0, 1, point, normal).with_restitution(e);
        if c.relative_normal_velocity(&bodies) >= 0.0 {
            continue;
        }
        let v0 = before(&bodies);
        for after in
            [chapter(&bodies, &c), collision_impulses(&bodies, &[c], &SolverSettings::default()).unwrap().velocities]
        {
            let (p0, p1) = (momentum(&bodies, &v0), momentum(&bodies, &after));
            assert!((p1 - p0).norm() < 1e-9 * p0.norm().max(1.0), "case {case}: momentum {p0} -> {p1}");
            let (k0, k1) = (energy(&bodies, &v0), energy(&bodies, &after));
            assert!(k1 <= k0 * (1.0 + 1e-9), "case {case}: energy {k0} -> {k1} at e = {e}");
            if e == 1.0 {
                assert!((k1 - k0).abs() < 1e-8 * k0, "case {case}: elastic energy {k0} -> {k1}");
            }
            // Newton's law: the relative normal velocity reverses and scales by e.
            let vrel = |v: &[BodyVelocity]| {
                let pv = |k: usize| v[k].linear + v[k].angular.cross(&(point - bodies[k].position));
                normal.dot(&(pv(1) - pv(0)))
            };
            assert!((vrel(&after) + e * vrel(&v0)).abs() < 1e-8 * vrel(&v0).abs(), "case {case}");
        }
    }
}

#[test]
fn off_centre_hit_sets_the_spin_the_impulse_formula_gives() {
    // A particle of mass m at speed u hits a resting rod (mass M, moment of inertia I about z) at distance d from its
    // centre, square on: j = (1 + e) u / (1/m + 1/M + d^2 / I); the rod gets v = j / M and spin w = j d / I.
    let (m, big_m, i_z, d, u, e) = (0.3, 2.0, 0.4, 0.35, 5.0, 0.6);
    let particle = BodyState::particle(m, Point3::new(-1.0, d, 0.0), Vector3::new(u, 0.0, 0.0));
    let rod = BodyState::rigid(big_m, Matrix3::from_diagonal(&Vector3::new(0.05, 0.4, i_z)), Point3::origin());
    let c = Contact::new(0, 1, Point3::new(0.0, d, 0.0), Vector3::x_axis()).with_restitution(e);
    let j = (1.0 + e) * u / (1.0 / m + 1.0 / big_m + d * d / i_z);
    let bodies = [particle, rod];
    assert!((impulse_magnitude(&bodies, &c).unwrap() - j).abs() < 1e-12 * j);
    for v in [chapter(&bodies, &c), collision_impulses(&bodies, &[c], &SolverSettings::default()).unwrap().velocities] {
        assert!((v[1].linear - Vector3::new(j / big_m, 0.0, 0.0)).norm() < 1e-9);
        // r x (j x) = (0, d, 0) x (j, 0, 0) = (0, 0, -j d): the rod turns clockwise about z.
        assert!((v[1].angular - Vector3::new(0.0, 0.0, -j * d / i_z)).norm() < 1e-9, "{:?}", v[1].angular);
        assert!((v[0].linear - Vector3::new(u - j / m, 0.0, 0.0)).norm() < 1e-9);
    }
}

#[test]
fn particle_form_keeps_the_tangential_part_and_scales_the_normal_part() {
    let n = Unit::new_normalize(Vector3::new(0.0, 0.0, 1.0));
    let v = Vector3::new(1.5, -0.5, -4.0);
    assert_eq!(reflect(&v, &n, 1.0), Vector3::new(1.5, -0.5, 4.0));
    assert_eq!(reflect(&v, &n, 0.5), Vector3::new(1.5, -0.5, 2.0));
    assert_eq!(reflect(&v, &n, 0.0), Vector3::new(1.5, -0.5, 0.0));
    // and it is the impulse formula with a static body on the other side
    let bodies = [BodyState::particle(2.0, Point3::origin(), v), BodyState::fixed(Point3::new(0.0, 0.0, -1.0))];
    let c = Contact::new(0, 1, Point3::origin(), -Vector3::z_axis()).with_restitution(0.5);
    assert!((chapter(&bodies, &c)[0].linear - reflect(&v, &n, 0.5)).norm() < 1e-12);
}

#[test]
fn simultaneous_elastic_impulses_along_a_row_of_three_balls() {
    // Ball 1 at speed v hits balls 2 and 3, which touch: with equal masses and e = 1 at both contacts the
    // simultaneous law gives impulses m v (4/3, 2/3) and velocities v (-1/3, 2/3, 2/3), which keep momentum and
    // kinetic energy.
    let v = Vector3::new(1.0, 0.0, 0.0);
    let bodies =
        [ball(1.0, 0.5, -1.0, v), ball(1.0, 0.5, 0.0, Vector3::zeros()), ball(1.0, 0.5, 1.0, Vector3::zeros())];
    let contacts = [
        Contact::new(0, 1, Point3::new(-0.5, 0.0, 0.0), Vector3::x_axis()).with_restitution(1.0),
        Contact::new(1, 2, Point3::new(0.5, 0.0, 0.0), Vector3::x_axis()).with_restitution(1.0),
    ];
    let out = collision_impulses(&bodies, &contacts, &SolverSettings::default()).unwrap();
    assert!(
        (out.magnitudes[0] - 4.0 / 3.0).abs() < 1e-9 && (out.magnitudes[1] - 2.0 / 3.0).abs() < 1e-9,
        "{:?}",
        out.magnitudes
    );
    for (k, want) in [-1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0].iter().enumerate() {
        assert!((out.velocities[k].linear.x - want).abs() < 1e-9);
    }
    assert!(out.residual < 1e-6);
}

#[test]
fn contacts_are_classified_by_relative_normal_velocity_with_a_scene_scaled_tolerance() {
    use tumble_contact::{classify, velocity_tolerance, ContactClass};
    // 1e-3 sqrt(2 g L): a thousandth of the speed of a fall through the scene.
    assert!((velocity_tolerance(1.0, 9.81) - 1e-3 * (2.0f64 * 9.81).sqrt()).abs() < 1e-15);
    assert!((velocity_tolerance(100.0, 9.81) / velocity_tolerance(1.0, 9.81) - 10.0).abs() < 1e-12);
    assert_eq!(velocity_tolerance(0.0, 0.0), 1e-9);
    let tol = velocity_tolerance(1.0, 9.81);
    let ground = BodyState::fixed(Point3::origin());
    let at = |vz: f64| [ground, BodyState::particle(1.0, Point3::origin(), Vector3::new(0.3, 0.0, vz))];
    let c = Contact::new(0, 1, Point3::origin(), Vector3::z_axis());
    assert_eq!(classify(&at(0.5), &c, tol), ContactClass::Separating);
    assert_eq!(classify(&at(-0.5), &c, tol), ContactClass::Colliding);
    assert_eq!(classify(&at(0.5 * tol), &c, tol), ContactClass::Resting);
    assert_eq!(classify(&at(-0.5 * tol), &c, tol), ContactClass::Resting);
}

#[test]
fn impulses_between_bodies_that_barely_move_are_solved_on_the_problems_own_scale() {
    // Regression: a box settling on the floor touched it at two corners closing at 6e-5 m/s and 1e-11 m/s; with
    // clarabel's absolute tolerances of 1e-12 on data that small the answer missed complementarity by 0.9. The
    // problem is now scaled to order one before the solve.
    let r = 0.4;
    let inertia = Matrix3::from_diagonal(&Vector3::new(0.4, 0.8, 1.04));
    let mut b = BodyState::rigid(24.0, inertia, Point3::new(-2.0, 0.0, 0.1));
    b.velocity = Vector3::new(0.0, 0.0, -0.0047);
    b.angular_velocity = Vector3::new(-3e-4, -0.0157, 0.0);
    let bodies = [b, BodyState::fixed(Point3::origin())];
    let down = Unit::new_normalize(Vector3::new(0.0, 0.0, -1.0));
    let contacts = [
        Contact::new(0, 1, Point3::new(-2.0 + r * 0.75, 0.2, 0.0), down),
        Contact::new(0, 1, Point3::new(-2.0 + r * 0.745, -0.2, 0.0), down),
    ];
    let out = collision_impulses(&bodies, &contacts, &SolverSettings::default()).unwrap();
    assert!(out.relative_velocities.iter().all(|v| *v > -1e-12), "{:?}", out.relative_velocities);
    assert!(out.residual < 1e-6);
}
