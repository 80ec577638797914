//! Unit tests of fast mode's stages, each on its own small inputs with the number it must give: the applied forces,
//! the contacts found, the warm starts, the soft and exact solves, the bounce limiter, sleep, the state check and
//! the step-doubling estimate.

use super::applied_forces::{actors, applied_forces};
use super::find_contacts::find_contacts;
use super::sleep::Sleep;
use super::soft_solve::soft_solve;
use super::solve_velocities::solve_velocities;
use super::warm_start::known_impulses;
use super::FastEngine;
use crate::engine::found_contact::{ContactKey, FoundContact};
use crate::engine::Engine;
use crate::mode::{FastSettings, FastSolver, SoftSolver};
use crate::{Material, ParticleBuilder, RigidBodyBuilder, Shape, World};
use nalgebra::{Point3, Vector3};
use std::collections::BTreeMap;
use tumble_contact::Contact;

const G: f64 = 9.81;
const H: f64 = 1.0 / 240.0;

/// The fast engine of world `w` as it is (the world's own rules for its scene), with `settings`.
fn engine(w: &World, settings: FastSettings) -> FastEngine {
    let compiled = w.compile();
    let collider_set = w.collider_set(&compiled);
    let y = compiled.handles.pack(&w.particles, &w.bodies);
    FastEngine::new(compiled, collider_set, 0.0, y, settings, 1, 1e12)
}

/// A 0.2 m cube of 500 kg/m^3 (4 kg) resting on a ground at z = 0, its faces on the axes, and its handle.
fn resting_cube(friction: f64) -> World {
    let mut w = World::new();
    w.add_ground(0.0, Material::new(0.0, friction)).unwrap();
    let cube = Shape::cuboid(Vector3::repeat(0.1)).unwrap();
    w.add_body(RigidBodyBuilder::from_shape(cube, 500.0).position(Vector3::new(0.0, 0.0, 0.1)).friction(friction))
        .unwrap();
    w
}

#[test]
fn applied_forces_are_gravity_damping_and_loads_and_a_sleeper_is_fixed() {
    // a 2 kg particle moving at 1 m/s along x with damping 0.4: a = g - d v / m = (-0.2, 0, -9.81)
    let mut w = World::new();
    w.add_particle(ParticleBuilder::new(2.0).velocity(Vector3::new(1.0, 0.0, 0.0)).damping(0.4)).unwrap();
    w.add_particle(ParticleBuilder::new(1.0).position(Vector3::new(5.0, 0.0, 0.0))).unwrap();
    let mut e = engine(&w, FastSettings::new(H));
    let mut cx = e.context();
    let states = applied_forces(&mut cx).unwrap();
    assert_eq!(states[0].force, Vector3::new(-0.4, 0.0, -2.0 * G), "m a: gravity and the damper");
    assert_eq!(states[1].force, Vector3::new(0.0, 0.0, -G));
    // the p rates of the first particle are its acceleration
    let q = cx.model.layout.positions();
    assert_eq!(&cx.dy[q..q + 3], &[-0.2, 0.0, -G]);
    // still for the sleep time while the first moves, the second falls asleep and is passed as fixed
    for _ in 0..4 {
        let settings = FastSettings { sleep_time: 0.5, ..FastSettings::new(H) };
        cx.memory.sleep.update(std::iter::empty(), &[1.0, 0.0], &settings, 0.125);
    }
    let states = actors(&cx).unwrap();
    assert!(states[0].is_dynamic() && !states[1].is_dynamic());
    assert_eq!(states[1].force, Vector3::zeros());
}

#[test]
fn a_resting_cube_is_found_at_its_four_corners_with_zero_gap() {
    // by both solvers: the soft one keeps them with their collider pair, the exact one lists them
    for solver in [FastSolver::default(), FastSolver::exact()] {
        let w = resting_cube(0.5);
        let mut e = engine(&w, FastSettings { solver, ..FastSettings::new(H) });
        let mut cx = e.context();
        let mut states = applied_forces(&mut cx).unwrap();
        let found = find_contacts(&mut cx, &mut states, H).unwrap();
        let points: Vec<(Point3<f64>, Vector3<f64>, f64)> = match &cx.memory.pairs {
            Some(kept) => {
                assert!(found.is_empty(), "the soft solver's contacts are kept, not listed");
                kept.last_contacts(H).iter().map(|c| (c.point, c.normal, c.gap)).collect()
            }
            None => {
                found.iter().map(|f| (f.contact.point, f.contact.normal.into_inner(), f.contact.distance)).collect()
            }
        };
        assert_eq!(points.len(), 4, "reduced to the face's four corners");
        for (point, normal, gap) in points {
            // the cube's faces lie on the plane z = 0 to the rounding of its placement
            assert!(gap.abs() < 1e-12, "gap {gap}");
            assert!((point.x.abs() - 0.1).abs() < 1e-12 && (point.y.abs() - 0.1).abs() < 1e-12);
            assert_eq!(normal.abs(), Vector3::z(), "the ground's normal");
        }
        assert!(cx.memory.penetration < 1e-12);
        assert_eq!(cx.report.stages.get(crate::plan::Stage::CollisionDetection), 1);
    }
}

#[test]
fn a_cube_out_of_reach_of_one_step_has_no_contacts() {
    // at 1 m above the ground and at rest, it falls g h^2 = 1.7e-4 m in a step: far less than the 0.9 m gap
    let mut w = resting_cube(0.5);
    let (h, _) = w.bodies().nth(1).unwrap();
    let b = w.body(h).unwrap().clone();
    w.set_body_state(h, Vector3::new(0.0, 0.0, 1.0), b.orientation(), Vector3::zeros(), Vector3::zeros()).unwrap();
    let mut e = engine(&w, FastSettings::new(H));
    let mut cx = e.context();
    let mut states = applied_forces(&mut cx).unwrap();
    assert!(find_contacts(&mut cx, &mut states, H).unwrap().is_empty());
    assert!(cx.memory.pairs.as_ref().unwrap().last_contacts(H).is_empty());
}

fn key(pair: (u32, u32), features: (u64, u64)) -> ContactKey {
    ContactKey { colliders: pair, features }
}

fn found(pair: (u32, u32), features: (u64, u64)) -> FoundContact {
    let contact = Contact::new(0, 1, Point3::origin(), Vector3::z_axis());
    FoundContact { contact, key: key(pair, features), point_a: Point3::origin(), point_b: Point3::origin() }
}

#[test]
fn the_warm_start_takes_a_contacts_own_impulse_else_its_pairs_share_else_none() {
    let mut previous = BTreeMap::new();
    previous.insert(key((0, 1), (1, 1)), 3.0);
    previous.insert(key((0, 1), (1, 2)), 5.0);
    previous.insert(key((0, 2), (1, 1)), 7.0);
    let now = [found((0, 1), (1, 1)), found((0, 1), (9, 9)), found((0, 1), (8, 8)), found((0, 3), (1, 1))];
    // its own: 3; new to pair (0, 1), which had 3 + 5 and now has three contacts: 8 / 3 each; a new pair: none
    assert_eq!(known_impulses(&previous, &now), vec![Some(3.0), Some(8.0 / 3.0), Some(8.0 / 3.0), None]);
}

#[test]
fn the_soft_step_carries_a_resting_cubes_weight_over_the_step() {
    // settled for a second, the cube's four contacts together push m g h over each step: once their springs have
    // taken the load they carry it to the rounding (measured 2e-16 of it; 1e-12 allows for the summation)
    let mut w = resting_cube(0.5);
    w.set_mode(crate::Mode::Fast(FastSettings { sleep: false, ..FastSettings::new(H) })).unwrap();
    w.step(1.0).unwrap();
    let mut e = engine(&w, FastSettings { sleep: false, ..FastSettings::new(H) });
    // warm starts from the settled world's own last step
    let settled = w.engine.as_ref().unwrap().memory();
    e.set_memory(settled).unwrap();
    let soft = match e.settings.solver {
        FastSolver::Soft(s) => s,
        FastSolver::Exact { .. } => SoftSolver::default(),
    };
    let mut cx = e.context();
    let mut states = applied_forces(&mut cx).unwrap();
    find_contacts(&mut cx, &mut states, H).unwrap();
    soft_solve(&mut cx, &states, H, soft).unwrap();
    let m = 4.0;
    let kept = cx.memory.pairs.as_ref().unwrap();
    let total: f64 = kept.last_contacts(H).iter().map(|c| c.impulse).sum();
    println!(
        "measured: the settled cube's step impulse is {:.3e} of m g h off",
        (total - m * G * H).abs() / (m * G * H)
    );
    assert!((total - m * G * H).abs() < 1e-12 * m * G * H, "{total} against m g h = {}", m * G * H);
    // the stage keeps each contact's impulses for the next step with its pair
    assert_eq!(kept.kept_points(), 4);
    assert!(kept.fits(usize::MAX), "pairs in order, the contacts coloured");
}

/// A 1 kg particle of radius 5 cm touching the ground at 3 m/s down, with restitution `e` (the ground's too).
fn landing(e: f64) -> World {
    let mut w = World::new();
    w.add_ground(0.0, Material::new(e, 0.0)).unwrap();
    let ball = ParticleBuilder::new(1.0)
        .radius(0.05)
        .position(Vector3::new(0.0, 0.0, 0.05))
        .velocity(Vector3::new(0.0, 0.0, -3.0))
        .material(Material::new(e, 0.0));
    w.add_particle(ball).unwrap();
    w
}

#[test]
fn the_exact_solve_bounces_a_particle_at_its_restitution() {
    // the bounce at the step's start, then gravity over the rest of the step (tumble-contact's restitution bias):
    // v = e |v-| - g h = 1.5 - 0.040875 m/s for e = 0.5
    let mut e = engine(&landing(0.5), FastSettings { solver: FastSolver::exact(), ..FastSettings::new(H) });
    let mut cx = e.context();
    let mut states = applied_forces(&mut cx).unwrap();
    let contacts = find_contacts(&mut cx, &mut states, H).unwrap();
    let v = solve_velocities(&mut cx, &states, &contacts, H).unwrap();
    let expected = 0.5 * 3.0 - G * H;
    // a lone particle on something static is solved in closed form: to the rounding
    assert!((v[0].linear.z - expected).abs() < 1e-12, "{} m/s, expected {expected}", v[0].linear.z);
    assert_eq!(cx.report.collisions, 1);
    assert_eq!(cx.memory.previous.len(), contacts.len(), "the normal impulses are kept for the warm start");
}

#[test]
fn the_bounce_limiter_replaces_an_answer_that_gains_energy_by_one_with_less_restitution() {
    // an answer of the particle's bounce that would leave at 4 m/s (more than it came with) is solved again with
    // its restitution scaled back: the answer taken keeps the energy and is at least the one at 98% restitution
    use super::bounce_limiter::limit_bounce_energy;
    use super::solver::Solver;
    let mut e = engine(&landing(1.0), FastSettings { solver: FastSolver::exact(), ..FastSettings::new(H) });
    let mut cx = e.context();
    let mut states = applied_forces(&mut cx).unwrap();
    let found = find_contacts(&mut cx, &mut states, H).unwrap();
    let contacts: Vec<Contact> = found.iter().map(|f| f.contact).collect();
    let settings =
        tumble_contact::StepSettings { bounce_threshold: 0.1, threads: 1, ..tumble_contact::StepSettings::new(H) };
    let friction = crate::mode::FastFriction::Lagged;
    let mut solver = Solver { states: &states, settings, friction, t: 0.0, solves: 0 };
    let previous = vec![0.0; contacts.len()];
    let mut out = solver.solve(&contacts, &previous).unwrap();
    out.velocities[0].linear.z = 4.0;
    let groups = tumble_contact::islands(&states, &contacts);
    limit_bounce_energy(&mut solver, &contacts, &previous, &groups, Vector3::new(0.0, 0.0, -G), &mut out).unwrap();
    let v = out.velocities[0].linear.z;
    let z0 = 0.05;
    // the energy (per kg) at the step's end positions, as the limiter measures it, against the start's
    let energy = |v: f64| 0.5 * v * v + G * (z0 + v * H);
    let before = 0.5 * 3.0 * 3.0 + G * z0;
    assert!(energy(v) <= before + 1e-12 * before, "{} J against {before} J", energy(v));
    assert!(v >= 0.98 * 3.0 - G * H - 1e-12, "{v} m/s: less than the answer at 98% restitution");
    assert!(v < 3.0, "{v} m/s: the bounce was scaled back");
}

#[test]
fn still_actors_fall_asleep_after_the_sleep_time_and_a_touch_wakes_their_group() {
    // steps of 1/8 s and a sleep time of 1/2 s (exact in binary): asleep at the fourth still step, not before
    let (settings, h) = (FastSettings { sleep_time: 0.5, ..FastSettings::new(H) }, 0.125);
    // actors 0 and 1 touch each other; actor 2 is alone and keeps moving
    let touching = [(0, 1)];
    let mut sleep = Sleep::new(3);
    for _ in 0..3 {
        sleep.update(touching.into_iter(), &[0.0, 0.0, 1.0], &settings, h);
    }
    assert_eq!(sleep.count(), 0, "still for less than the sleep time");
    sleep.update(touching.into_iter(), &[0.0, 0.0, 1.0], &settings, h);
    assert!(sleep.asleep(0) && sleep.asleep(1) && !sleep.asleep(2), "the still group sleeps, the mover not");
    // actor 2 bumping into actor 0 wakes 0's whole group
    assert!(sleep.wake_touched([(0, 1), (2, 0)].into_iter(), 3));
    assert_eq!(sleep.count(), 0);
    // one member of a group moving keeps the group awake
    let mut moving = Sleep::new(3);
    for _ in 0..8 {
        moving.update(touching.into_iter(), &[0.0, 1.0, 0.0], &settings, h);
    }
    assert!(!moving.asleep(0) && !moving.asleep(1) && moving.asleep(2));
}

#[test]
fn a_state_past_the_divergence_limit_or_not_finite_fails_the_step() {
    let mut w = World::new();
    w.add_particle(ParticleBuilder::new(1.0)).unwrap();
    let mut e = engine(&w, FastSettings::new(H));
    e.core.divergence_limit = 10.0;
    e.memory.y[0] = 11.0;
    let cx = e.context();
    let err = super::step::check_state(&cx, H).unwrap_err();
    assert!(err.to_string().contains("diverg"), "{err}");
    e.memory.y[0] = f64::NAN;
    let cx = e.context();
    let err = super::step::check_state(&cx, H).unwrap_err();
    assert!(err.to_string().contains("non-finite state"), "{err}");
}

#[test]
fn step_doubling_reports_the_halves_difference_and_follows_the_whole_step() {
    // a particle in free fall, in the soft step's n = 8 substeps: semi-implicit Euler over n substeps falls
    // (n + 1) / (2 n) g h^2, so the step of h and two of h/2 end (1 / (4 n)) g h^2 = g h^2 / 32 apart in position
    let mut w = World::new();
    w.add_particle(ParticleBuilder::new(1.0).position(Vector3::new(0.0, 0.0, 10.0))).unwrap();
    let mut plain = engine(&w, FastSettings::new(H));
    let mut doubled = engine(&w, FastSettings { step_doubling: true, ..FastSettings::new(H) });
    plain.step(H).unwrap();
    doubled.doubled_step(H).unwrap();
    assert_eq!(plain.memory.y, doubled.memory.y, "the world follows the whole step");
    let error = doubled.core.report.step_error.unwrap();
    // velocities agree (both g h): the error is the position's, to the rounding of positions near 10 m
    assert!((error - G * H * H / 32.0).abs() < 1e-14, "{error}");
}

#[test]
fn the_soft_steps_links_hold_springs_by_their_law_and_anchor_pulls_as_springs_to_fixed_points() {
    // a particle pulled to its anchor (stiffness 50) and a spring (k 80, c 0.3, rest 0.4) from it to a fixed point
    let mut w = World::new();
    let anchor = Vector3::new(1.0, 2.0, 3.0);
    let p = w.add_particle(ParticleBuilder::new(1.0).stiffness(50.0).anchor(anchor)).unwrap();
    let point = Vector3::new(0.0, 0.0, 1.0);
    let spring = crate::SpringBuilder::new(crate::Attachment::Particle(p), crate::Attachment::Point(point))
        .stiffness(80.0)
        .damping(0.3)
        .rest_length(0.4);
    w.add_spring(spring).unwrap();
    let mut e = engine(&w, FastSettings::new(H));
    let mut cx = e.context();
    let states = applied_forces(&mut cx).unwrap();
    let (actors, joints, springs) = super::soft_solve::links_at_start(&cx, &states);
    let actors = actors.expect("fixed ends are extra actors");
    assert!(joints.is_empty());
    assert_eq!(springs.len(), 2);
    let law = |k, c, l| tumble_contact::SpringLaw { stiffness: k, damping: c, rest_length: l };
    assert_eq!(springs[0].law, law(80.0, 0.3, 0.4));
    assert_eq!(springs[1].law, law(50.0, 0.0, 0.0), "the anchor pull: a spring of rest length zero");
    assert_eq!(actors[springs[0].b].position.coords, point);
    assert_eq!(actors[springs[1].b].position.coords, anchor);
    assert!(!actors[springs[1].b].is_dynamic());
}
