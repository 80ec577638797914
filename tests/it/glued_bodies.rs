//! Glued objects in fast mode move as one body, their welds' loads found from the pieces' motion: a glued column's
//! weld carries the top piece's weight and a spinning glued bar's the centripetal force (each breaking 2-3% above
//! the closed form's load and holding 2-3% below it), a tumbling glued object keeps its pieces' relative poses, the
//! same bits come on one thread and two, and seeded random glued objects dropped on the ground neither gain
//! energy over a step nor part.

use nalgebra::{Point3, UnitQuaternion, Vector3};
use tumble::{Cells, FastSettings, Glue, Mesh, Mode, RigidBodyBuilder, Shape, World};
use tumble_collide::SplitMix;

const G: f64 = 9.81;
const DT: f64 = 1.0 / 240.0;

/// A box of half extents `h` as a closed mesh.
fn cuboid(h: [f64; 3], name: &str) -> Mesh {
    let (v, t) = Shape::cuboid(Vector3::from(h)).unwrap().triangle_mesh(8, 1.0);
    Mesh::new(&v, &t, name).unwrap()
}

/// Fast mode at `DT` on `threads` threads, gravity `g`, with a ground plane when `ground`.
fn world(g: f64, ground: bool, threads: usize) -> World {
    let mut w = World::new();
    w.set_mode(Mode::Fast(FastSettings::new(DT))).unwrap();
    w.set_gravity(Vector3::new(0.0, 0.0, -g)).unwrap();
    w.set_threads(threads).unwrap();
    if ground {
        w.add_body(RigidBodyBuilder::fixed(Some(Shape::half_space(Vector3::z()).unwrap()))).unwrap();
    }
    w
}

#[test]
fn a_glued_column_s_weld_carries_the_top_piece_s_weight() {
    // two 0.2 m cubes (8 kg at 1000 kg/m^3) glued one on the other across 0.04 m^2, standing on the ground: the
    // weld holds the top cube up, a force of m g; glue 2% weaker than that breaks, 2% stronger holds (the soft
    // contacts hold the column to far better than 2%, and the average under a steady load rises to the load)
    let col = cuboid([0.1, 0.1, 0.2], "column");
    let halves = col.fracture(&Cells::at(vec![Point3::new(0.0, 0.0, -0.1), Point3::new(0.0, 0.0, 0.1)])).unwrap();
    for (ratio, breaks) in [(0.98, true), (1.02, false)] {
        let mut w = world(G, true, 1);
        let strength = ratio * 8.0 * G / 0.04;
        let glue = Glue { position: Vector3::new(0.0, 0.0, 0.2), ..Glue::new(1000.0, strength) };
        w.add_fractured(&col, &halves, &glue).unwrap();
        let run = w.run(1.0, 0.1).unwrap();
        assert_eq!(!run.joint_breaks.is_empty(), breaks, "glue at {ratio} of the weight");
    }
}

#[test]
fn a_spinning_glued_bar_s_weld_carries_the_centripetal_force() {
    // a 0.4 m bar of two 8 kg cubes spinning at 10 rad/s in free space: each cube's centre circles at 0.1 m, so the
    // weld pulls it in with m r w^2 = 80 N; judged at the instant (window 0), glue 3% weaker breaks in the first
    // step and 3% stronger holds
    let bar = cuboid([0.2, 0.1, 0.1], "bar");
    let halves = bar.fracture(&Cells::at(vec![Point3::new(-0.1, 0.0, 0.0), Point3::new(0.1, 0.0, 0.0)])).unwrap();
    let omega = 10.0;
    for (ratio, breaks) in [(0.97, true), (1.03, false)] {
        let mut w = world(0.0, false, 1);
        let strength = ratio * 8.0 * 0.1 * omega * omega / 0.04;
        let glued = w.add_fractured(&bar, &halves, &Glue { window: 0.0, ..Glue::new(1000.0, strength) }).unwrap();
        for &h in &glued.bodies {
            let p = w.body(h).unwrap().position();
            let spin = Vector3::z() * omega;
            w.set_body_state(h, p, UnitQuaternion::identity(), spin.cross(&p), spin).unwrap();
        }
        let run = w.run(0.5, 0.1).unwrap();
        assert_eq!(!run.joint_breaks.is_empty(), breaks, "glue at {ratio} of the load");
    }
}

/// Each piece's pose relative to the first piece's.
fn relative_poses(w: &World, pieces: &[tumble::BodyHandle]) -> Vec<(Vector3<f64>, UnitQuaternion<f64>)> {
    let first = w.body(pieces[0]).unwrap();
    let (p0, q0) = (first.position(), first.orientation());
    pieces
        .iter()
        .map(|&h| {
            let b = w.body(h).unwrap();
            (q0.inverse() * (b.position() - p0), q0.inverse() * b.orientation())
        })
        .collect()
}

#[test]
fn a_tumbling_glued_object_keeps_its_pieces_relative_poses() {
    // a box cut into 12 pieces thrown spinning about a skew axis: after 1 s of free flight every piece sits where it
    // was glued relative to the others, to rounding (1e-9 m and rad over 240 steps of rigid motion)
    let mesh = cuboid([0.3, 0.2, 0.1], "box");
    let pieces = mesh.fracture(&Cells::random(12, 5)).unwrap();
    let mut w = world(G, false, 1);
    let glued = w.add_fractured(&mesh, &pieces, &Glue::new(1000.0, 1e6)).unwrap();
    let before = relative_poses(&w, &glued.bodies);
    let centre = glued.bodies.iter().map(|&h| w.body(h).unwrap().position()).sum::<Vector3<f64>>() / 12.0;
    let spin = Vector3::new(3.0, -2.0, 5.0);
    for &h in &glued.bodies {
        let p = w.body(h).unwrap().position();
        let q = w.body(h).unwrap().orientation();
        w.set_body_state(h, p, q, Vector3::new(1.0, 0.0, 4.0) + spin.cross(&(p - centre)), spin).unwrap();
    }
    let run = w.run(1.0, 0.1).unwrap();
    assert!(run.joint_breaks.is_empty());
    for ((p, q), (p1, q1)) in before.iter().zip(relative_poses(&w, &glued.bodies)) {
        assert!((p - p1).norm() < 1e-9 && q.angle_to(&q1) < 1e-9, "{p} -> {p1}");
    }
}

/// The bodies' positions and velocities after a glued pane is hit, on `threads` threads.
fn pane_hit(threads: usize) -> Vec<[f64; 6]> {
    let pane = cuboid([0.4, 0.004, 0.3], "pane");
    let pieces = pane.fracture(&Cells::random(30, 3).near(Point3::origin())).unwrap();
    let mut w = world(G, true, threads);
    let glue = Glue { position: Vector3::new(0.0, 0.0, 0.3), ..Glue::new(2500.0, 2e6) };
    w.add_fractured(&pane, &pieces, &glue).unwrap();
    let ball = RigidBodyBuilder::from_shape(Shape::sphere(0.03).unwrap(), 7800.0)
        .position(Vector3::new(0.0, -0.3, 0.3))
        .velocity(Vector3::new(0.0, 10.0, 0.0));
    w.add_body(ball).unwrap();
    w.run(0.2, 0.1).unwrap();
    w.bodies()
        .map(|(_, b)| {
            let (p, v) = (b.position(), b.velocity());
            [p.x, p.y, p.z, v.x, v.y, v.z]
        })
        .collect()
}

#[test]
fn a_glued_pane_hit_gives_the_same_bits_on_one_thread_and_two() {
    let (one, two) = (pane_hit(1), pane_hit(2));
    assert!(one.iter().zip(&two).all(|(a, b)| a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())));
}

#[test]
fn seeded_glued_objects_dropped_on_the_ground_neither_gain_energy_nor_part() {
    // random boxes cut into 4 to 20 pieces, turned at random, glued 100 times stronger than their weight needs and
    // dropped from 2 cm: no step raises the energy beyond fast mode's bound and no weld breaks
    let mut rng = SplitMix(48);
    for seed in 0..6 {
        let h = [0.05 + 0.2 * rng.uniform(), 0.05 + 0.2 * rng.uniform(), 0.05 + 0.2 * rng.uniform()];
        let mesh = cuboid(h, "box");
        let pieces = mesh.fracture(&Cells::random(4 + (rng.uniform() * 16.0) as usize, seed)).unwrap();
        let axis = Vector3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
        let orientation = UnitQuaternion::from_scaled_axis(axis * 6.0);
        let lowest = mesh.vertices().iter().map(|v| (orientation * v.coords).z).fold(f64::INFINITY, f64::min);
        let weight = 1000.0 * 8.0 * h[0] * h[1] * h[2] * G;
        let mut w = world(G, true, 1);
        let glue = Glue {
            position: Vector3::new(0.0, 0.0, 0.02 - lowest),
            orientation,
            ..Glue::new(1000.0, 100.0 * weight / (h[0] * h[1]).min(h[1] * h[2]).min(h[0] * h[2]))
        };
        w.add_fractured(&mesh, &pieces, &glue).unwrap();
        let run = w.run(1.0, 0.1).unwrap();
        assert!(run.joint_breaks.is_empty(), "seed {seed}: {:?}", run.joint_breaks);
        // fast mode's law (docs/modes.md): pushing an overlap out lifts bodies by at most the deepest penetration,
        // the weight times it, plus rounding (1e-9 of the energies, the weight times a metre here)
        let report = w.report();
        let (gain, bound) = (report.energy_gain.unwrap_or(0.0), weight * (report.max_penetration + 1e-9));
        assert!(gain <= bound, "seed {seed}: a step gained {gain} J (bound {bound} J)");
    }
}
