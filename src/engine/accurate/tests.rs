//! Unit tests of accurate mode's stages, each on its own small inputs with the number it must give: the equations of
//! motion with the joints' and resting contacts' forces and held components, the joints' projection, the impact
//! stage, collision times and passes through, drift correction, one convex step, the extrapolation of the touching
//! phase, the free actors, the memory's checks and an integration saved and given back.

use super::contact_stages::ContactStages;
use super::detect::detect;
#[cfg(feature = "clarabel")] // (the tests of the chapter's QPs)
use super::impact::impact;
use super::integration::Integration;
use super::joint_forces::{project_joints, JOINT_DRIFT};
use super::system::AccurateSystem;
use super::AccurateEngine;
use crate::engine::semi_implicit::Form;
use crate::engine::state_error::state_difference;
use crate::mode::{AccurateSettings, Mode};
use crate::model::layout::{get3, set3};
use crate::{JointBuilder, Material, ParticleBuilder, RigidBodyBuilder, Shape, World};
use nalgebra::{UnitQuaternion, Vector3};
use std::collections::BTreeMap;
use std::sync::Arc;
use tumble_integrate::{Integrator, OdeSystem, Settings};

const G: f64 = 9.81;

/// Accurate mode's engine of world `w` as it is (its own scene and settings).
fn engine(w: &World) -> AccurateEngine {
    let compiled = w.compile();
    let collider_set = w.collider_set(&compiled);
    let y = compiled.handles.pack(&w.particles, &w.bodies);
    let settings = w.settings.clone().divergence_limit(1e12);
    let Mode::Accurate(accurate) = w.mode else { panic!("an accurate world") };
    AccurateEngine::new(compiled, collider_set, settings, accurate, w.gravity.norm(), 1, 0.0, y).unwrap()
}

/// The contact stages' context, the equations of motion and the main integrator of an engine with contact stages.
fn parts(e: &mut AccurateEngine) -> (ContactStages<'_>, &mut AccurateSystem, &mut Integrator<AccurateSystem>) {
    let AccurateEngine { core, system, contacts, memory, .. } = e;
    let (integration, contact) = (memory.integration.as_mut().unwrap(), memory.contact.as_mut().unwrap());
    let stages = contacts.as_mut().unwrap().stages(
        contact,
        &mut memory.broken,
        &mut memory.load_averages,
        &mut core.report,
        1,
        1e12,
    );
    (stages, system, integration.live_mut())
}

/// The right-hand side of `system` at `y`.
fn rates(system: &mut AccurateSystem, y: &[f64]) -> Vec<f64> {
    let mut dy = vec![0.0; y.len()];
    system.rhs(0.0, y, &mut dy).unwrap();
    dy
}

/// A 2 kg ball of radius 0.1 m hung at rest from the world by a ball joint 0.5 m above its centre.
fn hanging() -> World {
    let mut w = World::new();
    let ball = RigidBodyBuilder::from_shape_with_mass(Shape::sphere(0.1).unwrap(), 2.0);
    let b = w.add_body(ball.position(Vector3::new(0.0, 0.0, 1.0))).unwrap();
    w.add_joint(
        JointBuilder::ball(None, Some(b)).anchor_a(Vector3::new(0.0, 0.0, 1.5)).anchor_b(Vector3::new(0.0, 0.0, 0.5)),
    )
    .unwrap();
    w
}

#[test]
fn the_joint_carries_a_hanging_body_so_its_momenta_do_not_change() {
    let mut e = engine(&hanging());
    let y = e.memory.state().to_vec();
    let dy = rates(&mut e.system, &y);
    let l = e.system.model.layout;
    // gravity m g, and the joint's force against it (1e-12 of m g: the row solve's rounding)
    assert!(get3(&dy, l.bp(0)).norm() < 1e-12 * 2.0 * G, "dP/dt = {}", get3(&dy, l.bp(0)));
    assert!(get3(&dy, l.bl(0)).norm() < 1e-12 * 2.0 * G * 0.5, "dL/dt = {}", get3(&dy, l.bl(0)));
    // without the joint it falls at g
    e.system.model.joints.clear();
    let dy = rates(&mut e.system, &y);
    assert_eq!(get3(&dy, l.bp(0)), Vector3::new(0.0, 0.0, -2.0 * G));
}

#[test]
fn held_components_have_zero_rates() {
    let mut w = World::new();
    w.add_particle(ParticleBuilder::new(1.0).velocity(Vector3::new(1.0, 2.0, 3.0))).unwrap();
    let mut e = engine(&w);
    let y = e.memory.state().to_vec();
    e.system.held_components = (0..6).collect();
    assert_eq!(rates(&mut e.system, &y), vec![0.0; 6]);
    e.system.held_components.clear();
    assert_eq!(rates(&mut e.system, &y), vec![1.0, 2.0, 3.0, 0.0, 0.0, -G]);
}

#[test]
fn the_projection_puts_a_displaced_pendulum_back_on_its_joint() {
    let e = engine(&hanging());
    let mut y = e.memory.state().to_vec();
    let l = e.system.model.layout;
    // moved 1 mm aside and given a speed along the rod (both off the joint)
    set3(&mut y, l.bx(0), &Vector3::new(1e-3, 0.0, 1.0));
    set3(&mut y, l.bp(0), &Vector3::new(0.0, 0.0, 0.3));
    assert!(project_joints(&e.system.model, &mut y, JOINT_DRIFT));
    let (_, (position, angle)) = e.system.model.joint_errors(&y);
    // Gauss-Newton in the mass metric to the drift tolerance (1e-12 m)
    assert!(position <= JOINT_DRIFT && angle <= JOINT_DRIFT, "{position} m, {angle} rad");
    // and no row moves the anchors apart any more: every row's speed is removed (to the same tolerance)
    let model = &e.system.model;
    let (rows, ends) = model.all_rows(&y, false);
    for (j, r) in rows {
        let (a, b) = &ends[j];
        assert!(r.speed(&a.v, &a.w, &b.v, &b.w).abs() <= JOINT_DRIFT, "a row's speed after the projection");
    }
}

/// A 0.2 m cube of 4 kg resting on a ground, with its friction, restitution and the accurate-mode settings.
fn resting_cube(material: Material, accurate: AccurateSettings) -> World {
    let mut w = World::new();
    w.set_mode(Mode::Accurate(accurate)).unwrap();
    w.add_ground(0.0, material).unwrap();
    let cube = Shape::cuboid(Vector3::repeat(0.1)).unwrap();
    let body = RigidBodyBuilder::from_shape(cube, 500.0)
        .position(Vector3::new(0.0, 0.0, 0.1))
        .restitution(material.restitution)
        .friction(material.friction);
    w.add_body(body).unwrap();
    w
}

#[cfg(feature = "clarabel")] // the chapter's QPs
#[test]
fn resting_forces_carry_a_resting_cubes_weight_inside_the_equations_of_motion() {
    // the chapter's resting contact: at the impact stage the four corners rest; the QP's forces cancel gravity
    let frictionless = Material::new(0.0, 0.0);
    let accurate = AccurateSettings { persistent: crate::mode::Persistent::RestingForces, ..Default::default() };
    let mut e = engine(&resting_cube(frictionless, accurate));
    let (mut stages, system, integrator) = parts(&mut e);
    impact(&mut stages, system, integrator).unwrap();
    let y = integrator.state().to_vec();
    assert_eq!(stages.memory.resting.as_ref().map(|r| r.contacts.len()), Some(4));
    system.resting = stages.memory.resting.take();
    let dy = rates(system, &y);
    let l = system.model.layout;
    // to the QP's tolerance: 1e-9 of m g
    assert!(get3(&dy, l.bp(0)).norm() < 1e-9 * 4.0 * G, "dP/dt = {}", get3(&dy, l.bp(0)));
    assert!(system.resting_solves >= 1);
}

#[cfg(feature = "clarabel")] // the chapter's QPs
#[test]
fn the_impact_stage_bounces_a_frictionless_ball_at_its_restitution_and_starts_touching_with_friction() {
    for (friction, touching) in [(0.0, false), (0.5, true)] {
        let material = Material::new(0.5, friction);
        let mut w = World::new();
        w.add_ground(0.0, material).unwrap();
        let ball = RigidBodyBuilder::from_shape(Shape::sphere(0.1).unwrap(), 1000.0)
            .position(Vector3::new(0.0, 0.0, 0.1))
            .velocity(Vector3::new(0.0, 0.0, -2.0))
            .restitution(0.5)
            .friction(friction);
        w.add_body(ball).unwrap();
        let mut e = engine(&w);
        let (mut stages, system, integrator) = parts(&mut e);
        impact(&mut stages, system, integrator).unwrap();
        assert_eq!(stages.memory.touching.is_some(), touching, "friction {friction}");
        if !touching {
            // Newton's law: it leaves at e times its closing speed, to the rounding
            let l = system.model.layout;
            let m = system.model.bodies[0].mass;
            let v = get3(integrator.state(), l.bp(0)) / m;
            assert!((v.z - 1.0).abs() < 1e-12 && v.x == 0.0 && v.y == 0.0, "{v}");
            assert_eq!(stages.report.collisions, 1);
        }
    }
}

#[test]
fn a_collision_is_located_by_bisection_to_the_time_tolerance() {
    // a frictionless ball of radius 0.1 m dropped from rest at 1 m: it reaches the ground at sqrt(2 (0.9) / g)
    let mut w = World::new();
    w.set_integrator(Settings::tolerances(tumble_integrate::Method::Dopri5, 1e-12, 1e-12)).unwrap();
    w.add_ground(0.0, Material::new(0.5, 0.0)).unwrap();
    let ball = RigidBodyBuilder::from_shape(Shape::sphere(0.1).unwrap(), 1000.0).position(Vector3::new(0.0, 0.0, 1.0));
    w.add_body(ball.friction(0.0)).unwrap();
    let mut e = engine(&w);
    let (mut stages, system, integrator) = parts(&mut e);
    let adv =
        integrator.advance_with_events(system, 1.0, 1.0, &[], |_, _, _| {}, |step| detect(&mut stages, step)).unwrap();
    let t = adv.event.expect("the ball meets the ground");
    let exact = (2.0 * 0.9 / G).sqrt();
    // the time tolerance (1e-10 s) and the contact distance over the speed (1e-7 m at 4.2 m/s: 2.4e-8 s): the
    // located time is the last before the ball sinks into the ground, within that of the exact one
    assert!(t <= exact + 1e-10 && exact - t < 3e-8, "{t} s, exact {exact} s");
    assert!(stages.report.bisection_steps > 0);
}

#[test]
fn a_fast_ball_through_a_thin_wall_within_one_step_is_caught() {
    // no gravity; a 1 cm ball at 20 m/s toward a wall 2 mm thick 0.5 m away, integrated by RK4 in steps of 0.1 s
    // (2 m a step: apart from the wall at both ends of the step): the search finds the first touch at
    // (0.5 - 0.001 - 0.01) / 20 s
    let mut w = World::new();
    w.set_gravity(Vector3::zeros()).unwrap();
    w.set_integrator(Settings::fixed(tumble_integrate::Method::Rk4, 0.1)).unwrap();
    let wall = RigidBodyBuilder::fixed(Some(Shape::cuboid(Vector3::new(0.001, 1.0, 1.0)).unwrap()));
    w.add_body(wall.position(Vector3::new(0.5, 0.0, 0.0))).unwrap();
    let ball =
        RigidBodyBuilder::from_shape(Shape::sphere(0.01).unwrap(), 1000.0).velocity(Vector3::new(20.0, 0.0, 0.0));
    w.add_body(ball).unwrap();
    let mut e = engine(&w);
    let (mut stages, system, integrator) = parts(&mut e);
    let adv =
        integrator.advance_with_events(system, 1.0, 1.0, &[], |_, _, _| {}, |step| detect(&mut stages, step)).unwrap();
    let t = adv.event.expect("the pass through is caught");
    let exact = (0.5 - 0.001 - 0.01) / 20.0;
    // the search's tolerance: the contact distance over the closing speed bound (1.1 x 20 m/s each way): 2.3e-9 s
    assert!((t - exact).abs() < 1e-8 && t <= exact, "{t} s, exact {exact} s");
}

#[cfg(feature = "clarabel")] // the chapter's QPs
#[test]
fn drift_correction_lifts_a_sunk_cube_to_zero_gap() {
    let frictionless = Material::new(0.0, 0.0);
    let accurate = AccurateSettings { persistent: crate::mode::Persistent::RestingForces, ..Default::default() };
    let mut w = resting_cube(frictionless, accurate);
    let (h, b) = w.bodies().nth(1).map(|(h, b)| (h, b.clone())).unwrap();
    w.set_body_state(h, Vector3::new(0.0, 0.0, 0.099), b.orientation(), Vector3::zeros(), Vector3::zeros()).unwrap();
    let mut e = engine(&w);
    let (mut stages, system, integrator) = parts(&mut e);
    // the impact stage finds the corners 1 mm deep, past the contact distance: it lifts the cube out
    impact(&mut stages, system, integrator).unwrap();
    let z = get3(integrator.state(), system.model.layout.bx(0)).z;
    // to the position LCP's tolerance: 1e-9 m
    assert!((z - 0.1).abs() < 1e-9, "{z}");
}

#[test]
fn a_convex_step_carries_a_resting_cubes_weight_and_slows_a_sliding_one_at_mu_g() {
    let h = 1e-3;
    for (v0, what) in [(0.0, "resting"), (2.0, "sliding")] {
        let mut w = resting_cube(Material::new(0.0, 0.5), AccurateSettings::default());
        let (b, body) = w.bodies().nth(1).map(|(h, b)| (h, b.clone())).unwrap();
        w.set_body_state(b, body.position(), body.orientation(), Vector3::new(v0, 0.0, 0.0), Vector3::zeros()).unwrap();
        let mut e = engine(&w);
        let (mut stages, system, integrator) = parts(&mut e);
        let y = integrator.state().to_vec();
        let statics = Arc::clone(&stages.collider_set.static_poses);
        let states = super::convex_step::actors_with_forces(system, &statics, 0.0, &y).unwrap();
        let found =
            super::convex_step::every_contact_in_reach(&mut stages, &system.model, &states, &y, 0.0, h).unwrap().0;
        assert_eq!(found.len(), 4);
        // the lagged friction bound from the weight shared by the corners
        let lagged: BTreeMap<_, _> = found.iter().map(|f| (f.key, 4.0 * G / 4.0)).collect();
        let warm = BTreeMap::new();
        let step =
            super::convex_step::convex_step(&mut stages, &system.model, &states, &found, (&lagged, &warm), 0.0, &y, h)
                .unwrap()
                .expect("the solver answers");
        let total: f64 = step.forces.values().sum();
        // the normal forces carry m g to clarabel's tolerance (1e-4 of tol / h as a velocity, over h: 1e-6 relative)
        assert!((total - 4.0 * G).abs() < 1e-6 * 4.0 * G, "{what}: {total} N");
        let l = system.model.layout;
        let v = get3(&step.y, l.bp(0)).x / 4.0;
        let expected = if v0 > 0.0 { v0 - 0.5 * G * h } else { 0.0 };
        assert!((v - expected).abs() < 1e-8, "{what}: {v} m/s, Coulomb gives {expected}");
    }
}

#[test]
fn the_touching_phase_extrapolates_two_halves_against_the_whole_step() {
    let mut w = World::new();
    w.add_particle(ParticleBuilder::new(1.0)).unwrap();
    w.add_body(RigidBodyBuilder::from_shape(Shape::sphere(0.1).unwrap(), 1000.0)).unwrap();
    let e = engine(&w);
    let model = &e.system.model;
    let l = model.layout;
    let (mut halves, mut whole) = (vec![0.0; l.dim()], vec![0.0; l.dim()]);
    set3(&mut halves, l.px(0), &Vector3::new(1.0, 2.0, 3.0));
    set3(&mut whole, l.px(0), &Vector3::new(0.5, 2.0, 4.0));
    let (qa, qb) =
        (UnitQuaternion::from_euler_angles(0.1, 0.0, 0.0), UnitQuaternion::from_euler_angles(0.05, 0.0, 0.0));
    crate::model::layout::set_quat(&mut halves, l.bq(0), &qa);
    crate::model::layout::set_quat(&mut whole, l.bq(0), &qb);
    super::step_estimate::extrapolate(model, &mut halves, &whole);
    // 2 y_half - y_whole
    assert_eq!(get3(&halves, l.px(0)), Vector3::new(1.5, 2.0, 2.0));
    // the rotation extrapolated: 0.15 rad about x to third order in the angles (the blend of the quaternions is
    // off by 3.1e-5 rad here), and a unit quaternion
    let q = UnitQuaternion::from_quaternion(crate::model::layout::get_quat(&halves, l.bq(0)));
    assert!((q.angle() - 0.15).abs() < 1e-4, "{}", q.angle());
    assert!((crate::model::layout::get_quat(&halves, l.bq(0)).norm() - 1.0).abs() < 1e-15);
}

#[test]
fn the_free_actors_are_those_in_no_contact_and_joined_to_none_by_a_spring() {
    // particles 0, 1, 2: 0 touches something; 1 hangs from 0 on a spring; 2 is on its own
    let mut w = World::new();
    w.add_ground(0.0, Material::default()).unwrap();
    let ps: Vec<_> = (0..3)
        .map(|k| {
            w.add_particle(ParticleBuilder::new(1.0).radius(0.05).position(Vector3::new(k as f64, 0.0, 0.05))).unwrap()
        })
        .collect();
    w.add_spring(crate::SpringBuilder::new(crate::Attachment::Particle(ps[0]), crate::Attachment::Particle(ps[1])))
        .unwrap();
    let e = engine(&w);
    let model = &e.system.model;
    let contact = tumble_contact::Contact::new(0, 3, nalgebra::Point3::origin(), Vector3::z_axis());
    let found = crate::engine::found_contact::FoundContact {
        contact,
        key: crate::engine::found_contact::ContactKey { colliders: (0, 3), features: (0, 0) },
        point_a: nalgebra::Point3::origin(),
        point_b: nalgebra::Point3::origin(),
    };
    let involved = super::free_flight::involved(model, &[&[found]]);
    assert_eq!(involved, vec![true, true, false]);
    // the free actor's components are copied, the others kept
    let (from, mut to) = (vec![1.0; 18], vec![0.0; 18]);
    super::free_flight::copy_free(model, &involved, &from, &mut to);
    let l = model.layout;
    assert_eq!(get3(&to, l.px(2)), Vector3::repeat(1.0));
    assert_eq!(get3(&to, l.pv(2)), Vector3::repeat(1.0));
    assert_eq!(get3(&to, l.px(0)), Vector3::zeros());
}

#[test]
fn two_states_differ_by_their_largest_position_turn_or_velocity_over_the_step() {
    let mut w = World::new();
    w.add_particle(ParticleBuilder::new(2.0)).unwrap();
    let e = engine(&w);
    let (a, mut b) = (vec![0.0; 6], vec![0.0; 6]);
    b[1] = 3e-4; // a position 0.3 mm off
    assert_eq!(state_difference(&e.system.model, None, (&a, &b), Form::Momenta, 0.01), 3e-4);
    b[4] = 0.1; // and a velocity 0.1 m/s off: over a step of 0.01 s, 1 mm
    assert_eq!(state_difference(&e.system.model, None, (&a, &b), Form::Momenta, 0.01), 1e-3);
    assert_eq!(
        state_difference(&e.system.model, Some(&[false]), (&a, &b), Form::Momenta, 0.01),
        0.0,
        "an actor left out"
    );
}

#[test]
fn a_contact_memory_that_does_not_fit_is_refused_with_the_reason() {
    let mut e = engine(&resting_cube(Material::default(), AccurateSettings::default()));
    let (collider_set, dim) = {
        let c = e.contacts.as_ref().unwrap();
        ((c.collider_set.actors(), c.collider_set.colliders.len()), e.system.model.layout.dim())
    };
    let good = e.memory.contact.clone().unwrap();
    assert!(good.check(collider_set.0, collider_set.1, dim).is_ok());
    let mut bad = good.clone();
    bad.penetration = f64::NAN;
    assert_eq!(bad.check(collider_set.0, collider_set.1, dim).unwrap_err(), "its penetration is not finite");
    let mut bad = good.clone();
    bad.scales.tolerance = -1.0;
    assert_eq!(bad.check(collider_set.0, collider_set.1, dim).unwrap_err(), "its scales are not positive and finite");
    let mut bad = good;
    bad.resting_keys.insert(crate::engine::found_contact::ContactKey { colliders: (0, 99), features: (0, 0) });
    assert_eq!(bad.check(collider_set.0, collider_set.1, dim).unwrap_err(), "a resting key names no collider");
    // and the engine refuses it whole: its memory is as it was
    let before = e.memory.state().to_vec();
    let mut memory = e.memory.clone();
    memory.contact.as_mut().unwrap().penetration = f64::NAN;
    assert!(e.give_memory(memory).is_err());
    assert_eq!(e.memory.state(), &before[..]);
}

#[test]
fn an_integration_saved_as_data_and_given_back_continues_bit_for_bit() {
    let mut e = engine(&hanging());
    let integrator = e.memory.integration.as_mut().unwrap().live_mut();
    integrator.advance_to(&mut e.system, 0.3, &[], |_, _, _| {}).unwrap();
    let saved: Integration =
        postcard::from_bytes(&postcard::to_stdvec(e.memory.integration.as_ref().unwrap()).unwrap()).unwrap();
    assert!(matches!(saved, Integration::Saved(_)));
    let template = e.memory.integration.as_ref().unwrap().live().clone();
    let mut given_back = saved.into_live(|| Ok(template)).unwrap();
    let original = e.memory.integration.as_mut().unwrap().live_mut();
    let mut system = e.system.clone();
    original.advance_to(&mut e.system, 0.6, &[], |_, _, _| {}).unwrap();
    given_back.live_mut().advance_to(&mut system, 0.6, &[], |_, _, _| {}).unwrap();
    let bits = |y: &[f64]| y.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(original.state()), bits(given_back.live().state()));
}
