//! Resting-contact forces against closed forms: a box on a plane, stacks of up to 50 boxes (also with masses
//! 1 : 1e3 : 1e6), the velocity-product terms of the normal acceleration (a particle sliding along a turning
//! paddle needs the Coriolis force), and complementarity on random resting configurations checked by recomputing
//! the accelerations from the forces.
#![cfg(feature = "clarabel")]

use crate::common;

use nalgebra::{Matrix3, Point3, Unit, Vector3};
use tumble_contact::{contact_wrenches, resting_forces, BodyState, Contact, NormalMotion, SolverSettings};

const G: f64 = 9.81;

fn cuboid(mass: f64, h: Vector3<f64>, centre: Point3<f64>) -> BodyState {
    let i = Matrix3::from_diagonal(&Vector3::new(h.y * h.y + h.z * h.z, h.x * h.x + h.z * h.z, h.x * h.x + h.y * h.y))
        * (mass / 3.0);
    BodyState { force: Vector3::new(0.0, 0.0, -mass * G), ..BodyState::rigid(mass, i, centre) }
}

/// Four contacts at the corners of the (a, b) rectangle at height z, from body `below` to body `above`.
fn corners(below: usize, above: usize, a: f64, b: f64, z: f64) -> Vec<Contact> {
    [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
        .iter()
        .map(|(sx, sy)| {
            Contact::new(below, above, Point3::new(sx * a, sy * b, z), Vector3::z_axis())
                .with_normal_motion(NormalMotion::WithA)
        })
        .collect()
}

/// A stack on a static ground (body 0): box j (1-based from the bottom) has mass masses[j - 1].
fn stack(masses: &[f64]) -> (Vec<BodyState>, Vec<Contact>) {
    let h = Vector3::new(0.5, 0.4, 0.3);
    let mut bodies = vec![BodyState::fixed(Point3::origin())];
    let mut contacts = Vec::new();
    for (j, &m) in masses.iter().enumerate() {
        bodies.push(cuboid(m, h, Point3::new(0.0, 0.0, h.z * (2 * j + 1) as f64)));
        contacts.extend(corners(j, j + 1, h.x, h.y, 2.0 * h.z * j as f64));
    }
    (bodies, contacts)
}

/// The total force through each interface, bottom first.
fn interface_loads(forces: &[f64], n: usize) -> Vec<f64> {
    (0..n).map(|j| forces[4 * j..4 * j + 4].iter().sum()).collect()
}

#[test]
fn box_on_a_plane_rests_on_four_equal_corner_forces() {
    let (bodies, contacts) = stack(&[3.0]);
    let out = resting_forces(&bodies, &contacts, &SolverSettings::default()).unwrap();
    let w = 3.0 * G;
    // Together they carry m g (fixed by the equations: 1e-9 relative, the solver's accuracy). The four corners are
    // redundant (three would do): the equations leave the split open and the interior point ends near the centre of
    // the solution set, the symmetric split, to about 1e-8 relative: 1e-6.
    assert!((out.forces.iter().sum::<f64>() - w).abs() < 1e-9 * w);
    for f in &out.forces {
        assert!((f - w / 4.0).abs() < 1e-6 * w, "{:?}", out.forces);
    }
    assert!(out.accelerations.iter().all(|a| a.abs() < 1e-9 * G));
}

#[test]
fn stacks_of_up_to_50_boxes_carry_the_weight_above_each_interface() {
    for n in [2, 5, 20, 50] {
        let (bodies, contacts) = stack(&vec![1.5; n]);
        let out = resting_forces(&bodies, &contacts, &SolverSettings::default()).unwrap();
        for (j, load) in interface_loads(&out.forces, n).iter().enumerate() {
            let want = (n - j) as f64 * 1.5 * G; // the k-th interface from the top carries k m g
            assert!((load - want).abs() < 1e-6 * want, "n = {n}, interface {j}: {load} vs {want}");
        }
        assert!(out.residual < 1e-6);
    }
}

#[test]
fn stacks_with_masses_in_ratio_1_to_1e3_to_1e6_are_still_right_to_1e_6() {
    for masses in [[1.0, 1e3, 1e6], [1e6, 1e3, 1.0], [1e3, 1.0, 1e6]] {
        let masses: Vec<f64> = masses.iter().cycle().take(9).copied().collect();
        let (bodies, contacts) = stack(&masses);
        let out = resting_forces(&bodies, &contacts, &SolverSettings::default()).unwrap();
        for (j, load) in interface_loads(&out.forces, masses.len()).iter().enumerate() {
            let want: f64 = masses[j..].iter().sum::<f64>() * G;
            assert!((load - want).abs() < 1e-6 * want, "{masses:?}, interface {j}: {load} vs {want}");
        }
    }
}

#[test]
fn a_particle_sliding_along_a_turning_paddle_needs_the_coriolis_force() {
    // A paddle (kinematic: infinite mass) turns at w about z; a particle slides outward along it at s' and is pushed
    // by it: the push must supply the Coriolis acceleration 2 w s', so f = 2 m w s' (the centripetal part is along
    // the paddle). This is all velocity-product terms: b = n . (p_B'' - p_A'') + 2 n' . (p_B' - p_A') = -2 w s'.
    let (m, w, s, s_dot, theta): (f64, f64, f64, f64, f64) = (0.7, 3.0, 1.2, 0.8, 0.4);
    let (e_r, e_t) = (Vector3::new(theta.cos(), theta.sin(), 0.0), Vector3::new(-theta.sin(), theta.cos(), 0.0));
    let p = Point3::from(e_r * s);
    let particle = BodyState::particle(m, p, e_r * s_dot + e_t * (w * s));
    let paddle = BodyState { angular_velocity: Vector3::new(0.0, 0.0, w), ..BodyState::fixed(Point3::origin()) };
    // The paddle is behind the particle: the normal from the particle (A) to the paddle (B) is -e_t, a face of B.
    let c = Contact::new(0, 1, p, Unit::new_normalize(-e_t)).with_normal_motion(NormalMotion::WithB);
    let out = resting_forces(&[particle, paddle], &[c], &SolverSettings::default()).unwrap();
    let want = 2.0 * m * w * s_dot;
    assert!((out.forces[0] - want).abs() < 1e-9 * want, "{} vs {want}", out.forces[0]);
}

#[test]
fn random_resting_configurations_are_complementary() {
    // Random boxes on a ground and on each other, spinning and pushed; forces from the QP, then accelerations
    // recomputed from the bodies' equations of motion with the contact wrenches (not through A): f >= 0, a >= 0,
    // f . a = 0 within the stated tolerance.
    let mut rnd = common::uniform(3);
    let settings = SolverSettings::default();
    let mut separating = 0;
    for case in 0..200 {
        let n = 1 + (rnd() * 6.0) as usize;
        let mut bodies = vec![BodyState::fixed(Point3::origin())];
        let mut contacts = Vec::new();
        for j in 0..n {
            let h = Vector3::new(0.2 + rnd(), 0.2 + rnd(), 0.1 + rnd());
            let mut b = cuboid(0.1 + 5.0 * rnd(), h, Point3::new(rnd() - 0.5, rnd() - 0.5, 0.5 + j as f64));
            b.velocity = Vector3::new(rnd() - 0.5, rnd() - 0.5, 0.0);
            b.angular_velocity = Vector3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 2.0;
            b.force += Vector3::new(rnd() - 0.5, rnd() - 0.5, 20.0 * (rnd() - 0.5));
            b.torque = Vector3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5);
            bodies.push(b);
            let below = if j == 0 { 0 } else { (rnd() * (j + 1) as f64) as usize };
            for _ in 0..(1 + (rnd() * 4.0) as usize) {
                let normal = Unit::new_normalize(Vector3::new(0.3 * (rnd() - 0.5), 0.3 * (rnd() - 0.5), 1.0));
                let point = Point3::new(rnd() - 0.5, rnd() - 0.5, j as f64);
                let motion = if rnd() < 0.5 { NormalMotion::WithA } else { NormalMotion::WithB };
                contacts.push(Contact::new(below, j + 1, point, normal).with_normal_motion(motion));
            }
        }
        let out = resting_forces(&bodies, &contacts, &settings).unwrap();
        // accelerations from the equations of motion
        let wrenches = contact_wrenches(&bodies, &contacts, &out.forces);
        let accel = |k: usize, p: &Point3<f64>| {
            let b = &bodies[k];
            let mut with = *b;
            with.force += wrenches[k].0;
            with.torque += wrenches[k].1;
            with.free_point_acceleration(p)
        };
        // forces here are newtons on bodies of 0.1 to 5 kg: a 1 N floor for the scale
        let f_scale = out.forces.iter().fold(0.0f64, |m, f| m.max(*f)).max(1.0);
        for (i, c) in contacts.iter().enumerate() {
            let vel = bodies[c.b].point_velocity(&c.point) - bodies[c.a].point_velocity(&c.point);
            let nd = match c.normal_motion {
                NormalMotion::WithA => bodies[c.a].angular_velocity.cross(&c.normal),
                _ => bodies[c.b].angular_velocity.cross(&c.normal),
            };
            let a = c.normal.dot(&(accel(c.b, &c.point) - accel(c.a, &c.point))) + 2.0 * nd.dot(&vel);
            // against the solver's own accelerations, to rounding of forces of order f_scale
            assert!(
                (a - out.accelerations[i]).abs() < 1e-8 * (1.0 + f_scale),
                "case {case} contact {i}: {a} vs {}",
                out.accelerations[i]
            );
            let a_scale = 1.0 + out.accelerations.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            // the stated tolerance: SolverSettings::complementarity_tolerance (1e-6), relative to the scales
            assert!(out.forces[i] >= 0.0 && a >= -1e-6 * a_scale, "case {case} contact {i}: f {} a {a}", out.forces[i]);
            assert!(
                (out.forces[i] * a).abs() <= 1e-6 * f_scale * a_scale,
                "case {case} contact {i}: f a = {}",
                out.forces[i] * a
            );
            separating += (out.forces[i] == 0.0 || out.forces[i] < 1e-9 * f_scale) as usize;
        }
        assert!(out.residual <= settings.complementarity_tolerance);
    }
    // Both kinds of contact must appear for the test to mean anything.
    assert!(separating > 100, "only {separating} contacts had no force");
}

#[test]
fn position_correction_lifts_a_sunken_box_out_by_the_least_motion() {
    // A box sunk 1 mm into the ground at its four corners comes up by exactly 1 mm without turning; a box sunk at
    // one corner only also turns (the least mass-weighted motion), and afterwards no corner is below the ground.
    use tumble_contact::position_correction;
    let (bodies, contacts) = stack(&[2.0]);
    let sunk: Vec<Contact> = contacts.iter().map(|c| c.with_distance(-1e-3)).collect();
    let d = position_correction(&bodies, &sunk, &SolverSettings::default()).unwrap().moves;
    // 1e-9 m: the interior point's 1e-12 gap on a problem whose redundant corners leave its solution set flat (3e-11
    // seen)
    assert!((d[1].linear - Vector3::new(0.0, 0.0, 1e-3)).norm() < 1e-9 && d[1].angular.norm() < 1e-9, "{:?}", d[1]);
    let mut one = contacts.clone();
    one[0].distance = -1e-3;
    let d = position_correction(&bodies, &one, &SolverSettings::default()).unwrap().moves;
    for c in &one {
        let r = c.point - bodies[1].position;
        let lift = c.normal.dot(&(d[1].linear + d[1].angular.cross(&r)));
        // to first order in the small rotation: d + lift >= 0, and = 0 at the sunken corner
        assert!(c.distance + lift > -1e-9, "{c:?}: lift {lift}");
    }
    let lift0 = one[0].normal.dot(&(d[1].linear + d[1].angular.cross(&(one[0].point - bodies[1].position))));
    assert!((one[0].distance + lift0).abs() < 1e-9);
    assert!(d[1].angular.norm() > 0.0);
}
