//! The pile of 50 meshes (`tumble::scenes::meshes::mesh_pile`: cups, rings, stools, pebbles and pegs, density 800,
//! friction 0.5, restitution 0) in Rapier with each mesh's convex decomposition (parry's VHACD, the parameters
//! tumble uses: resolution 64, 32 pieces at most, concavity 0.01), beside tumble's fast mode on the same pile,
//! decomposed and as one hull a mesh; dt 1/240, one thread each, the steps from 0.4 s to 1.4 s timed.

use rapier3d_f64::parry::transformation::vhacd::VHACDParameters;
use rapier3d_f64::prelude::*;
use std::time::Instant;
use tumble::scenes::meshes::mesh_pile;

const DT: f64 = 1.0 / 240.0;
const SETTLE: usize = 96;
const TIMED: usize = 240;

fn rapier_pile() -> (PhysicsWorld, usize) {
    let mut w = super::world(DT);
    super::ground(&mut w, 0.5);
    let (tw, bodies) = mesh_pile(tumble::Mode::fast(DT), 50, false).unwrap();
    let d = tumble::Decomposition::default();
    let params = VHACDParameters {
        resolution: d.resolution,
        max_convex_hulls: d.max_pieces,
        concavity: d.concavity,
        ..VHACDParameters::default()
    };
    let mut pieces = 0;
    for h in bodies {
        let b = tw.body(h).unwrap();
        let c = &b.colliders()[0];
        let mesh = c.shape.source_mesh().expect("a mesh body");
        let vertices: Vec<Vector> = mesh.vertices().iter().map(|p| Vector::new(p.x, p.y, p.z)).collect();
        let (x, a, o) = (b.position(), b.orientation().scaled_axis(), c.offset.translation.vector);
        let body = w.insert_body(
            RigidBodyBuilder::dynamic().translation(Vector::new(x.x, x.y, x.z)).rotation(Vector::new(a.x, a.y, a.z)),
        );
        let collider = ColliderBuilder::convex_decomposition_with_params(&vertices, mesh.triangles(), &params)
            .translation(Vector::new(o.x, o.y, o.z))
            .density(800.0)
            .friction(0.5)
            .restitution(0.0);
        let collider = collider.build();
        pieces += collider.shape().as_compound().map_or(1, |c| c.shapes().len());
        w.insert_collider(collider, Some(body));
    }
    (w, pieces)
}

fn time_rapier() -> (f64, usize) {
    let (mut w, pieces) = rapier_pile();
    for _ in 0..SETTLE {
        w.step();
    }
    let clock = Instant::now();
    for _ in 0..TIMED {
        w.step();
    }
    (clock.elapsed().as_secs_f64() * 1e3 / TIMED as f64, pieces)
}

fn time_tumble(as_hull: bool) -> (f64, usize) {
    let (mut w, _) = mesh_pile(tumble::Mode::fast(DT), 50, as_hull).unwrap();
    w.set_threads(1).unwrap();
    for _ in 0..SETTLE {
        w.step(DT).unwrap();
    }
    let clock = Instant::now();
    for _ in 0..TIMED {
        w.step(DT).unwrap();
    }
    (clock.elapsed().as_secs_f64() * 1e3 / TIMED as f64, w.report().mesh_pieces)
}

pub fn table() {
    println!("| 50-mesh pile, dt 1/240, one thread, steps 0.4 s to 1.4 s | ms a step | convex pieces |\n|---|---|---|");
    let (r, rp) = time_rapier();
    let (t, tp) = time_tumble(false);
    let (h, _) = time_tumble(true);
    println!("| Rapier 0.36.1, VHACD decomposition | {r:.3} | {rp} |");
    println!("| tumble fast mode, decomposition | {t:.3} | {tp} |");
    println!("| tumble fast mode, one hull a mesh | {h:.3} | 50 |");
    println!("tumble decomposed / Rapier: {:.2}x", t / r);
}
