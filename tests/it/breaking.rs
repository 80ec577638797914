//! Breakable joints in both modes: a pendulum whose pivot breaks at the angle where its force reaches the bound
//! (the closed form of a rigid pendulum released from the horizontal), a welded box let go of that then lands on
//! the body it was welded to, seeded random chains (shapes, orientations, masses, thresholds) that break and stay
//! finite and deterministic, files and failed calls that keep the broken flags, and bad bounds refused by name.

use crate::common;

use common::{random_shape, state_bits, Lcg};
use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use tumble::{
    FastSettings, JointBuilder, JointHandle, Material, Method, Mode, RigidBodyBuilder, Settings, Shape, World,
    WorldError,
};

const G: f64 = 9.81;

fn accurate() -> World {
    let mut w = World::new();
    w.set_integrator(Settings::tolerances(Method::Dopri5, 1e-10, 1e-12)).unwrap();
    w
}

fn fast() -> World {
    let mut w = World::new();
    w.set_mode(Mode::Fast(FastSettings::new(1.0 / 240.0))).unwrap();
    w
}

/// A rigid pendulum: a ball of mass m and radius r (I = 2/5 m r^2 about its centre) whose centre is L from a
/// pivot at the origin, released at rest from the horizontal. At the angle theta below the horizontal,
/// omega^2 = 2 m g L sin(theta) / I_p and alpha = m g L cos(theta) / I_p (I_p = I + m L^2), and the pivot's force
/// on the ball is m (a - g): its size over m g as a function of theta.
struct Pendulum {
    m: f64,
    r: f64,
    l: f64,
}

impl Pendulum {
    fn pivot_inertia(&self) -> f64 {
        0.4 * self.m * self.r * self.r + self.m * self.l * self.l
    }
    fn omega(&self, theta: f64) -> f64 {
        (2.0 * self.m * G * self.l * theta.sin() / self.pivot_inertia()).sqrt()
    }
    fn force(&self, theta: f64) -> f64 {
        let (s, c) = theta.sin_cos();
        let (w2, alpha) = (self.omega(theta).powi(2), self.m * G * self.l * c / self.pivot_inertia());
        // (x, z): centripetal towards the pivot, tangential along the swing, and gravity's -(0, -g)
        let ax = -w2 * self.l * c - alpha * self.l * s;
        let az = w2 * self.l * s - alpha * self.l * c + G;
        self.m * (ax * ax + az * az).sqrt()
    }
    /// The angle at which the force first reaches `bound` (bisection of the closed form, to 1e-15 rad).
    fn breaking_angle(&self, bound: f64) -> f64 {
        let (mut lo, mut hi) = (0.0, std::f64::consts::FRAC_PI_2);
        assert!(self.force(lo) < bound && self.force(hi) > bound);
        while hi - lo > 1e-15 {
            let mid = 0.5 * (lo + hi);
            if self.force(mid) > bound {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        hi
    }
    /// The pendulum in `w`, its ball a collider when the world has a ground.
    fn build(&self, w: &mut World, bound: f64) -> JointHandle {
        let inertia = Matrix3::identity() * (0.4 * self.m * self.r * self.r);
        let mut ball = RigidBodyBuilder::new(self.m, inertia).position(Vector3::x() * self.l);
        if w.body_count() > 0 {
            ball = ball.shape(Shape::sphere(self.r).unwrap());
        }
        let b = w.add_body(ball).unwrap();
        let joint = JointBuilder::ball(None, Some(b)).anchor_b(-Vector3::x() * self.l).breaking(bound, f64::INFINITY);
        w.add_joint(joint).unwrap()
    }
}

/// Runs the pendulum to 1 s; gives its angular speed and horizontal velocity after the break against the closed
/// form's at the breaking angle (relative errors), and the run's breaks.
fn pendulum_breaks(mut w: World) -> (f64, f64, Vec<(f64, JointHandle)>) {
    let p = Pendulum { m: 2.0, r: 0.1, l: 0.8 };
    let bound = 2.0 * p.m * G;
    let j = p.build(&mut w, bound);
    let run = w.run(1.0, 0.01).unwrap();
    assert!(w.joint(j).unwrap().is_broken());
    let theta = p.breaking_angle(bound);
    let (omega, vx) = (p.omega(theta), p.omega(theta) * p.l * theta.sin());
    let (_, body) = w.bodies().last().unwrap();
    let e_omega = (body.angular_velocity().norm() - omega).abs() / omega;
    let e_vx = (body.velocity().x.abs() - vx).abs() / vx;
    eprintln!("theta {theta:.6} rad: omega {e_omega:e}, v_x {e_vx:e} relative; breaks {:?}", run.joint_breaks);
    (e_omega, e_vx, run.joint_breaks)
}

#[test]
fn a_pendulum_pivot_breaks_where_its_force_reaches_the_bound() {
    // accurate mode locates the break to the time tolerance (1e-10 s, an angular speed change of about alpha
    // times that) under Dopri5 at 1e-10: measured 3e-11 and 1.5e-10 relative, bound 1e-8; the same with a
    // ground far below (the contact engine's event detection carries the break then)
    let mut grounded = accurate();
    grounded.add_ground(-5.0, Material::new(0.0, 0.5)).unwrap();
    for w in [accurate(), grounded] {
        let (e_omega, e_vx, breaks) = pendulum_breaks(w);
        assert!(e_omega < 1e-8 && e_vx < 1e-8, "accurate: {e_omega:e}, {e_vx:e}");
        assert_eq!(breaks.len(), 1);
    }
    // fast mode breaks at the end of the step whose last substep's impulse passes the bound: a step late here
    // (4.2 ms at dt = 1/240 s), measured 0.9 % in omega and 2.8 % in v_x; bound 5 %
    let (e_omega, e_vx, breaks) = pendulum_breaks(fast());
    assert!(e_omega < 0.05 && e_vx < 0.05, "fast: {e_omega:e}, {e_vx:e}");
    assert_eq!(breaks.len(), 1);
}

/// A slab resting on the ground with a small box welded 0.5 m above its top; the weld's bound is half the box's
/// weight, so it breaks at once and the box falls onto the slab (its pair no longer joined, so no longer left
/// untested). Gives the box's height after 3 s and the weld.
fn welded_box_falls_onto_its_slab(mut w: World) -> (f64, bool) {
    w.add_ground(0.0, Material::new(0.0, 0.5)).unwrap();
    let slab = Shape::cuboid(Vector3::new(0.5, 0.5, 0.1)).unwrap();
    let a = w.add_body(RigidBodyBuilder::from_shape(slab, 1000.0).position(Vector3::z() * 0.1)).unwrap();
    let cube = Shape::cuboid(Vector3::new(0.1, 0.1, 0.1)).unwrap();
    let b = w.add_body(RigidBodyBuilder::from_shape(cube, 500.0).position(Vector3::z() * 0.8)).unwrap();
    let weight = 500.0 * 0.2f64.powi(3) * G;
    let weld =
        w.add_joint(JointBuilder::weld(Some(a), Some(b)).anchor_a(Vector3::z() * 0.7).breaking(0.5 * weight, 1e9));
    let weld = weld.unwrap();
    w.run(3.0, 0.1).unwrap();
    // with its only joint broken the world sleeps as one without joints (jointed worlds do not): the box and the
    // slab at rest fall asleep
    assert!(w.report().sleepers > 0 && !w.plan().has("joints"), "{} asleep", w.report().sleepers);
    (w.body(b).unwrap().position().z, w.joint(weld).unwrap().is_broken())
}

#[test]
fn a_box_let_go_by_its_weld_lands_on_the_body_it_was_welded_to() {
    // resting on the slab's top (0.2 m) at its half height 0.1 m: within accurate mode's contact tolerance (1e-4
    // of the scene's size, about 1e-4 m here) and fast mode's soft contacts (their push-out margin, 1 cm)
    let (z, broken) = welded_box_falls_onto_its_slab(accurate());
    assert!(broken && (z - 0.3).abs() < 1e-3, "accurate: z = {z}");
    let (z, broken) = welded_box_falls_onto_its_slab(fast());
    assert!(broken && (z - 0.3).abs() < 1e-2, "fast: z = {z}");
}

/// A seeded random chain hanging from the world: three to five random shapes at random orientations and
/// densities, each joined to the one above by a random kind of joint (ball, hinge, weld, distance) at a bound of
/// 0.5 to 3 times the weight it carries, pushed sideways at the start.
fn random_chain(seed: u64, mut w: World) -> (World, Vec<JointHandle>) {
    let mut rng = Lcg(seed);
    let n = 3 + (rng.next() * 3.0) as usize;
    let mut bodies = Vec::new();
    let mut masses = Vec::new();
    for k in 0..n {
        let axis = Vector3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
        let q = UnitQuaternion::from_scaled_axis(axis);
        let builder = RigidBodyBuilder::from_shape(random_shape(&mut rng), rng.range(200.0, 3000.0))
            .position(Vector3::new(0.0, 0.0, -0.7 * (k as f64 + 1.0)))
            .orientation(q)
            .velocity(Vector3::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), 0.0));
        let b = w.add_body(builder).unwrap();
        masses.push(w.body(b).unwrap().mass());
        bodies.push(b);
    }
    let mut joints = Vec::new();
    for k in 0..n {
        let carried: f64 = masses[k..].iter().sum::<f64>() * G;
        let above = if k == 0 { None } else { Some(bodies[k - 1]) };
        let anchor = Vector3::new(0.0, 0.0, -0.7 * k as f64 - 0.35);
        let (b, x) = (bodies[k], w.body(bodies[k]).unwrap().position());
        let local_b = w.body(b).unwrap().orientation().inverse() * (anchor - x);
        let local_a = match above {
            None => anchor,
            Some(a) => {
                let body = w.body(a).unwrap();
                body.orientation().inverse() * (anchor - body.position())
            }
        };
        let axis = Vector3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 1.0);
        let joint = match (rng.next() * 4.0) as usize {
            0 => JointBuilder::ball(above, Some(b)),
            1 => JointBuilder::hinge(above, Some(b), axis),
            2 => JointBuilder::weld(above, Some(b)),
            _ => JointBuilder::distance(above, Some(b), None),
        };
        let bound = rng.range(0.5, 3.0) * carried;
        let joint = joint.anchor_a(local_a).anchor_b(local_b).breaking(bound, bound);
        joints.push(w.add_joint(joint).unwrap());
    }
    (w, joints)
}

#[test]
fn random_chains_break_stay_finite_and_are_the_same_on_any_thread_count() {
    let mut broke = 0;
    for seed in 0..6u64 {
        for (mode, make) in [("accurate", accurate as fn() -> World), ("fast", fast)] {
            let (mut w, joints) = random_chain(seed, make());
            let run = w.run(1.0, 0.05).unwrap();
            let bits = state_bits(&w);
            assert!(w.bodies().all(|(_, b)| b.position().iter().all(|x| x.is_finite())), "{mode} {seed}");
            // every joint the world calls broken broke once in the run, in time order, and no other did
            let broken: Vec<JointHandle> =
                joints.iter().copied().filter(|&j| w.joint(j).unwrap().is_broken()).collect();
            let mut listed: Vec<JointHandle> = run.joint_breaks.iter().map(|(_, j)| *j).collect();
            assert!(run.joint_breaks.windows(2).all(|p| p[0].0 <= p[1].0), "{mode} {seed}: breaks out of order");
            assert!(run.joint_breaks.iter().all(|(t, _)| *t > 0.0 && *t <= 1.0 + 1e-12));
            listed.sort_by_key(|j| joints.iter().position(|x| x == j));
            assert_eq!(listed, broken, "{mode} {seed}");
            broke += broken.len();
            // the joints that hold still hold: accurate mode projects them to 1e-12 after every step, fast mode's
            // soft rows stretch under the random loads (bound 5 cm, the links are 0.7 m apart)
            let bound = if mode == "accurate" { 1e-9 } else { 0.05 };
            assert!(w.report().joint_error < bound, "{mode} {seed}: joint error {}", w.report().joint_error);
            // the same bits on two threads, and the same breaks
            let (mut two, _) = random_chain(seed, make());
            two.set_threads(2).unwrap();
            let again = two.run(1.0, 0.05).unwrap();
            assert_eq!(state_bits(&two), bits, "{mode} {seed}: threads changed the bits");
            let breaks = |r: &tumble::Run| -> Vec<(u64, u32)> {
                r.joint_breaks.iter().map(|(t, j)| (t.to_bits(), j.index())).collect()
            };
            assert_eq!(breaks(&again), breaks(&run));
        }
    }
    // the bounds are drawn around the loads: some joints break (counted over all seeds and both modes)
    eprintln!("random chains: {broke} joints broke");
    assert!(broke > 0);
}

#[test]
fn files_copies_and_failed_calls_keep_the_broken_flags() {
    for make in [accurate as fn() -> World, fast] {
        let p = Pendulum { m: 2.0, r: 0.1, l: 0.8 };
        let mut w = make();
        let j = p.build(&mut w, 2.0 * p.m * G);
        // a call interrupted after the break keeps its frames, the world at the last of them with the joint broken
        // as it was there (a failed call leaves the world as it was: tests/it/hardening.rs)
        let interrupted = w.run_with(1.0, 0.01, |done| done < 0.9);
        assert!(matches!(interrupted, Err(WorldError::Interrupted)));
        let kept = w.take_failed_run().expect("the frames done are kept");
        let last = *kept.times.last().unwrap();
        assert!(kept.interrupted && w.time() == last && (0.89..1.0).contains(&last), "stopped at {last}");
        assert_eq!(kept.joint_breaks.len(), 1, "the joint broke before the interrupt");
        assert!(w.joint(j).unwrap().is_broken());
        w.step(0.1).unwrap();
        assert!(w.joint(j).unwrap().is_broken());
        // a file (JSON and binary, with the engine's memory) and a copy go on as the world does
        let mut json = World::from_json(&w.to_json().unwrap()).unwrap();
        let mut bytes = World::from_bytes(&w.to_bytes().unwrap()).unwrap();
        let mut copy = w.clone();
        assert!(json.joints().all(|(_, j)| j.is_broken()) && bytes.joints().all(|(_, j)| j.is_broken()));
        w.step(0.25).unwrap();
        for other in [&mut json, &mut bytes, &mut copy] {
            other.step(0.25).unwrap();
            assert_eq!(state_bits(other), state_bits(&w));
        }
    }
}

#[test]
fn bad_breaking_bounds_are_refused_by_name() {
    let mut w = World::new();
    let b = w.add_body(RigidBodyBuilder::new(1.0, Matrix3::identity())).unwrap();
    for (force, torque) in [(f64::NAN, 1.0), (0.0, 1.0), (1.0, -1.0), (f64::INFINITY, f64::INFINITY)] {
        let e = w.add_joint(JointBuilder::ball(None, Some(b)).breaking(force, torque)).unwrap_err();
        assert!(matches!(&e, WorldError::InvalidArgument { name: "breaking", .. }), "{e}");
    }
    assert_eq!(w.joints().count(), 0);
    // an infinite torque or force alone is a joint that breaks by the other
    assert!(w.add_joint(JointBuilder::ball(None, Some(b)).breaking(5.0, f64::INFINITY)).is_ok());
}
