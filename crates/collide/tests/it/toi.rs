//! Collision time against closed forms (a sphere falling onto a plane, two approaching spheres, a box tipping onto a
//! plane), the three methods agreeing with each other, and the 1000 m/s sphere against a 1 cm wall.

use crate::common;

use common::Rng;
use nalgebra::{Isometry3, Translation3, Vector3};
use tumble_collide::{bisect_collision_time, time_of_impact, Motion, Shape, ToiMethod, ToiOptions};

const METHODS: [ToiMethod; 4] =
    [ToiMethod::Bisection, ToiMethod::ConservativeAdvancement, ToiMethod::ShapeCast, ToiMethod::Auto];

fn options(method: ToiMethod, tolerance: f64) -> ToiOptions {
    ToiOptions { method, tolerance, max_iterations: 10_000 }
}

#[test]
fn sphere_falling_under_gravity_meets_the_plane_at_sqrt_2h_over_g() {
    let (r, z0, g) = (0.1, 1.0, 9.81);
    let sphere = Shape::sphere(r).unwrap();
    let ground = Shape::half_space(Vector3::z()).unwrap();
    let exact = (2.0 * (z0 - r) / g).sqrt();
    let tol = 1e-10;
    let poses = |t: f64| (Isometry3::translation(0.0, 0.0, z0 - 0.5 * g * t * t), Isometry3::identity());
    let b = bisect_collision_time(&sphere, &ground, poses, 0.0, 0.5, tol).unwrap();
    // The bracket holds the exact time (to the rounding of z(t), 1e-15) and is no wider than the tolerance.
    assert!(b.before <= exact + 1e-15 && exact <= b.after + 1e-15, "{b:?} vs {exact}");
    assert!(b.after - b.before <= tol);
    // log2(0.5 / 1e-10) = 32.2 halvings, plus the two end tests.
    assert_eq!(b.steps, 2 + 33);
}

#[test]
fn two_approaching_spheres_meet_when_the_gap_closes() {
    // Radii 0.2 and 0.3, centres 2 m apart, closing at 2 m/s: contact at (2 - 0.5) / 2 = 0.75 s.
    let (a, b) = (Shape::sphere(0.2).unwrap(), Shape::sphere(0.3).unwrap());
    let ma = Motion::new(Isometry3::identity(), Vector3::new(1.5, 0.0, 0.0), Vector3::zeros()).unwrap();
    let mb =
        Motion::new(Isometry3::translation(2.0, 0.0, 0.0), Vector3::new(-0.5, 0.0, 0.0), Vector3::new(3.0, 1.0, 0.0))
            .unwrap();
    for method in METHODS {
        let hit = time_of_impact(&a, &ma, &b, &mb, 1.0, &options(method, 1e-10)).unwrap().expect("they meet");
        // Every method stops at or just before contact: within 1e-9 s, i.e. 2e-9 m of gap at 2 m/s.
        assert!((hit.time - 0.75).abs() < 1e-9 && hit.distance >= 0.0 && hit.distance < 2e-9, "{method:?}: {hit:?}");
    }
    // Moving apart, or passing 0.1 m wide of each other: no contact.
    let apart =
        Motion::new(Isometry3::translation(2.0, 0.0, 0.0), Vector3::new(3.0, 0.0, 0.0), Vector3::zeros()).unwrap();
    let wide =
        Motion::new(Isometry3::translation(2.0, 0.6, 0.0), Vector3::new(-4.0, 0.0, 0.0), Vector3::zeros()).unwrap();
    for method in METHODS {
        for other in [&apart, &wide] {
            assert_eq!(time_of_impact(&a, &ma, &b, other, 1.0, &options(method, 1e-10)).unwrap(), None, "{method:?}");
        }
    }
}

#[test]
fn box_tipping_about_its_centre_touches_when_its_corner_reaches_the_plane() {
    // A box of half extents (a, 0.5, b) spinning about y at w over a plane, centre at height zc: its lowest point is
    // zc - (a |sin th| + b |cos th|), which reaches 0 at th = asin(zc / R) - atan2(b, a), R = hypot(a, b).
    let (a, b, zc, w): (f64, f64, f64, f64) = (0.6, 0.2, 0.5, 2.0);
    let exact = ((zc / a.hypot(b)).asin() - b.atan2(a)) / w;
    let cuboid = Shape::cuboid(Vector3::new(a, 0.5, b)).unwrap();
    let spin = Motion::new(Isometry3::translation(0.0, 0.0, zc), Vector3::zeros(), Vector3::new(0.0, w, 0.0)).unwrap();
    let ground = Shape::half_space(Vector3::z()).unwrap();
    // On the ground (a half-space, whose distance parry computes exactly from the support point) to the time
    // tolerance plus rounding, 1e-9 s. parry's shape cast does not take half-spaces: there a 10 m slab with its top
    // face at z = 0 stands in, for all three methods. Against the slab, distances come from GJK, whose tolerance
    // grows with the size of the shapes (about 1e-8 m here); at a closing speed near 1 m/s that is 1e-7 s.
    let slab = Shape::cuboid(Vector3::new(10.0, 10.0, 1.0)).unwrap();
    let floors = [(&ground, Isometry3::identity(), 1e-9), (&slab, Isometry3::translation(0.0, 0.0, -1.0), 1e-7)];
    for method in METHODS {
        for (other, at, tol) in &floors {
            if method == ToiMethod::ShapeCast && matches!(other, Shape::HalfSpace { .. }) {
                // (Auto falls back to conservative advancement there)
                continue;
            }
            let hit = time_of_impact(&cuboid, &spin, other, &Motion::stationary(*at), 1.0, &options(method, 1e-10))
                .unwrap()
                .unwrap();
            assert!((hit.time - exact).abs() < *tol, "{method:?} on a {}: {} vs {exact}", other.kind(), hit.time);
        }
    }
}

#[test]
fn box_box_distance_is_the_gap_in_either_order_parry_431() {
    // parry 0.31.1's box-box distance returned 0.394 here, in one argument order, for a true gap of 0.0409
    // (dimforge/parry#431), which made conservative advancement overshoot into the slab.
    let (a, zc, th): (f64, f64, f64) = (0.6, 0.5, 2.0 * 0.245_304_278_544_563_44);
    let small = Shape::cuboid(Vector3::new(a, 0.5, 0.2)).unwrap();
    let slab = Shape::cuboid(Vector3::new(10.0, 10.0, 1.0)).unwrap();
    let tilted = Motion::new(Isometry3::translation(0.0, 0.0, zc), Vector3::zeros(), Vector3::new(0.0, th, 0.0))
        .unwrap()
        .pose_at(1.0);
    let under = Isometry3::translation(0.0, 0.0, -1.0);
    let gap = zc - (a * th.sin() + 0.2 * th.cos());
    // 1e-12: GJK on shapes of unit size.
    assert!((tumble_collide::distance(&small, &tilted, &slab, &under).unwrap() - gap).abs() < 1e-12);
    assert!((tumble_collide::distance(&slab, &under, &small, &tilted).unwrap() - gap).abs() < 1e-12);
}

#[test]
fn the_three_methods_agree_on_random_moving_polyhedra() {
    let mut rng = Rng(21);
    let mut compared = 0;
    for case in 0..300 {
        let (sa, sb) = (rng.polyhedral_shape(), rng.polyhedral_shape());
        let ma = Motion::new(rng.pose(0.1), rng.vector(0.5), rng.vector(3.0)).unwrap();
        let start_b =
            Isometry3::from_parts(Translation3::from(Vector3::new(3.0, 0.0, 0.0) + rng.vector(0.5)), rng.rotation());
        let mb = Motion::new(start_b, Vector3::new(-3.0, 0.0, 0.0) + rng.vector(1.0), rng.vector(3.0)).unwrap();
        let hits: Vec<_> =
            METHODS.iter().map(|&m| time_of_impact(&sa, &ma, &sb, &mb, 1.0, &options(m, 1e-10)).unwrap()).collect();
        match (hits[0], hits[1], hits[2]) {
            (Some(x), Some(y), Some(z)) => {
                assert_eq!(hits[3], Some(z), "case {case}: Auto on turning shapes is parry's cast");
                compared += 1;
                // All three decide contact through parry's GJK, which resolves distances to about 1e-8 m: at closing
                // speeds of a few m/s, bisection and conservative advancement (both to 1e-10 s) agree to 1e-8 s.
                // parry's cast stops up to ~1e-7 m short of contact (its own distance tolerance): 1e-7 s.
                assert!((x.time - y.time).abs() < 1e-8 && (y.time - z.time).abs() < 1e-7, "case {case}: {hits:?}");
                assert!(hits.iter().flatten().all(|h| (0.0..1e-7).contains(&h.distance)), "case {case}: {hits:?}");
            }
            (None, None, None) => assert_eq!(hits[3], None),
            _ => panic!("case {case}: methods disagree on whether there is a contact: {hits:?}"),
        }
    }
    assert!(compared > 100, "only {compared} of 300 cases met");
}

#[test]
fn a_sphere_at_1000_m_per_s_does_not_tunnel_through_a_1_cm_wall() {
    // In one step of 1/60 s the sphere moves 16.7 m: before the step it is 6 m short of the wall, after it 10 m past.
    let sphere = Shape::sphere(0.05).unwrap();
    let wall = Shape::cuboid(Vector3::new(0.005, 1.0, 1.0)).unwrap();
    let fly =
        Motion::new(Isometry3::translation(-1.0, 0.0, 0.0), Vector3::new(1000.0, 0.0, 0.0), Vector3::zeros()).unwrap();
    let stand = Motion::stationary(Isometry3::translation(5.0, 0.0, 0.0));
    let dt = 1.0 / 60.0;
    let exact = (5.0 - 0.005 - 0.05 + 1.0) / 1000.0;
    // The chapter's plain test at the ends of the step sees nothing to bisect:
    let ends = |t: f64| (fly.pose_at(t), stand.pose_at(t));
    assert_eq!(bisect_collision_time(&sphere, &wall, ends, 0.0, dt, 1e-9).unwrap_err().name, "t1");
    for method in METHODS {
        let hit = time_of_impact(&sphere, &fly, &wall, &stand, dt, &options(method, 1e-12))
            .unwrap()
            .expect("the wall is hit");
        // 1e-12 s of time tolerance is 1e-9 m at 1000 m/s; parry's cast adds its distance tolerance: 1e-11 s.
        assert!((hit.time - exact).abs() < 1e-11, "{method:?}: {} vs {exact}", hit.time);
    }
}

#[test]
fn bad_collision_time_queries_are_refused_by_name() {
    let s = Shape::sphere(0.5).unwrap();
    let still = Motion::stationary(Isometry3::identity());
    let far =
        Motion::new(Isometry3::translation(3.0, 0.0, 0.0), Vector3::new(-10.0, 0.0, 0.0), Vector3::zeros()).unwrap();
    let ok = options(ToiMethod::Bisection, 1e-9);
    assert_eq!(time_of_impact(&s, &still, &s, &far, 0.0, &ok).unwrap_err().name, "t_end");
    assert_eq!(
        time_of_impact(&s, &still, &s, &far, 1.0, &options(ToiMethod::Bisection, -1.0)).unwrap_err().name,
        "tolerance"
    );
    assert_eq!(time_of_impact(&s, &still, &s, &still, 1.0, &ok).unwrap_err().name, "motion_a");
    let tight = ToiOptions { max_iterations: 3, ..options(ToiMethod::ConservativeAdvancement, 1e-15) };
    let spinning =
        Motion::new(Isometry3::translation(3.0, 0.0, 0.0), Vector3::new(-10.0, 0.0, 0.0), Vector3::new(0.0, 0.0, 50.0))
            .unwrap();
    let cube = Shape::cuboid(Vector3::repeat(0.5)).unwrap();
    assert_eq!(time_of_impact(&s, &still, &cube, &spinning, 1.0, &tight).unwrap_err().name, "options");
    let poses = |t: f64| (Isometry3::identity(), far.pose_at(t));
    assert_eq!(bisect_collision_time(&s, &s, poses, 1.0, 0.0, 1e-9).unwrap_err().name, "t1");
    assert_eq!(bisect_collision_time(&s, &s, poses, 0.0, 1.0, 0.0).unwrap_err().name, "tolerance");
    assert_eq!(bisect_collision_time(&s, &s, poses, 0.25, 1.0, 1e-9).unwrap_err().name, "t0");
    let ground = Shape::half_space(Vector3::z()).unwrap();
    let above =
        Motion::new(Isometry3::translation(0.0, 0.0, 2.0), Vector3::new(0.0, 0.0, -10.0), Vector3::zeros()).unwrap();
    assert_eq!(
        time_of_impact(&s, &above, &ground, &still, 1.0, &options(ToiMethod::ShapeCast, 1e-9)).unwrap_err().name,
        "shape"
    );
}

#[test]
fn first_contact_follows_any_path_and_sees_a_pass_through() {
    use tumble_collide::first_contact;
    // A ball thrown at 1000 m/s along a falling arc, x = -1 + 1000 t, z = 0.5 - g t^2 / 2, past a 1 cm wall at
    // x = 5 (1 m tall, centred at z = 0.5): apart at both ends of the 1/60 s interval; the first touch is when
    // x + r reaches the wall face, t = (5 - 0.005 - 0.05 + 1) / 1000.
    let ball = Shape::sphere(0.05).unwrap();
    let wall = Shape::cuboid(Vector3::new(0.005, 1.0, 0.5)).unwrap();
    let at_wall = Isometry3::translation(5.0, 0.0, 0.5);
    let g = 9.81;
    let poses = |t: f64| Ok((Isometry3::translation(-1.0 + 1000.0 * t, 0.0, 0.5 - 0.5 * g * t * t), at_wall));
    // distance shrinks at most at the speed: sqrt(1000^2 + (g t)^2) <= 1000.001 over the interval
    let hit = first_contact(&ball, &wall, poses, 0.0, 1.0 / 60.0, 1000.001, &options(ToiMethod::Bisection, 1e-12))
        .unwrap()
        .expect("the wall is hit");
    let exact = (5.0 - 0.005 - 0.05 + 1.0) / 1000.0;
    // 1e-12 s of tolerance, 1e-9 m at 1000 m/s; GJK to ~1e-9 m: 1e-11 s
    assert!((hit.time - exact).abs() < 1e-11, "{} vs {exact}", hit.time);
    // already touching at the start: refused
    let touching = |_: f64| Ok((Isometry3::translation(4.95, 0.0, 0.5), at_wall));
    assert_eq!(
        first_contact(&ball, &wall, touching, 0.0, 1.0, 1.0, &options(ToiMethod::Bisection, 1e-9)).unwrap_err().name,
        "t0"
    );
}
