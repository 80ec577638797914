//! A closed mesh's volume, centre of mass and inertia: against the closed forms of the solids it approximates (the
//! error falling as the mesh is refined), against parry's own integration on random closed meshes, and every
//! mesh that does not bound a solid refused with its reason.

use crate::common;

use common::Rng;
use nalgebra::{Matrix3, Point3, Vector3};
use std::f64::consts::PI;
use tumble_collide::{Mesh, Shape};

/// Relative error of the largest entry of `m` against the diagonal `d`.
fn tensor_error(m: &Matrix3<f64>, d: [f64; 3]) -> f64 {
    (m - Matrix3::from_diagonal(&Vector3::from(d))).amax() / d.iter().cloned().fold(0.0, f64::max)
}

/// (volume error, inertia error) relative to the closed forms, at unit density.
fn errors(mesh: &Mesh, volume: f64, inertia: [f64; 3]) -> (f64, f64) {
    let p = Shape::mesh(mesh.clone()).mass_properties(1.0).unwrap();
    assert!(p.local_com.norm() < 1e-12, "symmetric about the origin: {}", p.local_com);
    ((p.mass - volume).abs() / volume, tensor_error(&p.inertia, inertia))
}

/// Inscribed polygons of n sides lose area as 1 - sin(2 pi / n) n / (2 pi) ~ (2 pi^2 / 3) / n^2: doubling n divides the
/// error by about 4. Each refinement is held to divide it by more than 3 (the n^-2 rate, with room for the
/// higher-order terms at n = 16), and the finest mesh to the square of its angular step (2 pi / n)^2: facets sag by
/// r step^2 / 8 from the surface in each of two directions, and the inertia weighs it by r^2 (a few sags, eight at
/// most).
fn falls_quadratically(errs: &[(u32, f64)]) {
    for w in errs.windows(2) {
        assert!(w[1].1 < w[0].1 / 3.0, "refining {} -> {} segments: error {} -> {}", w[0].0, w[1].0, w[0].1, w[1].1);
    }
    let (n, e) = errs[errs.len() - 1];
    let step = 2.0 * PI / n as f64;
    assert!(e < step * step, "{n} segments: error {e}");
}

#[test]
fn a_meshed_sphere_tends_to_the_sphere() {
    let r = 0.3;
    let volume = 4.0 / 3.0 * PI * r * r * r;
    let mut v_err = Vec::new();
    let mut i_err = Vec::new();
    for n in [16, 32, 64, 128] {
        let (ev, ei) = errors(&Mesh::sphere_mesh(r, n).unwrap(), volume, [0.4 * volume * r * r; 3]);
        v_err.push((n, ev));
        i_err.push((n, ei));
    }
    falls_quadratically(&v_err);
    falls_quadratically(&i_err);
}

#[test]
fn a_meshed_cylinder_and_torus_tend_to_theirs() {
    let (h, r) = (0.4, 0.15);
    let (mut cyl_v, mut cyl_i, mut tor_v, mut tor_i) = (vec![], vec![], vec![], vec![]);
    for n in [16, 32, 64, 128] {
        let v = PI * r * r * 2.0 * h;
        let side = v * (3.0 * r * r + 4.0 * h * h) / 12.0;
        let (ev, ei) = errors(&Mesh::cylinder_mesh(h, r, n).unwrap(), v, [side, side, v * r * r / 2.0]);
        cyl_v.push((n, ev));
        cyl_i.push((n, ei));
        let (big, small) = (0.5, 0.12);
        let v = 2.0 * PI * PI * big * small * small;
        let side = v * (big * big / 2.0 + 5.0 / 8.0 * small * small);
        let axial = v * (big * big + 0.75 * small * small);
        let (ev, ei) = errors(&Mesh::torus_mesh(big, small, n).unwrap(), v, [side, side, axial]);
        tor_v.push((n, ev));
        tor_i.push((n, ei));
    }
    for e in [cyl_v, cyl_i, tor_v, tor_i] {
        falls_quadratically(&e);
    }
}

#[test]
fn a_meshed_box_is_exact() {
    // Cells of 0.1 m: a 3 x 2 x 5 block has flat faces, so the mesh is the box and only round-off remains (1e-12).
    let cells: Vec<[i32; 3]> = (0..3).flat_map(|x| (0..2).flat_map(move |y| (0..5).map(move |z| [x, y, z]))).collect();
    let mesh = Mesh::from_cells(&cells, 0.1, "block").unwrap();
    let p = Shape::mesh(mesh).mass_properties(700.0).unwrap();
    let (a, b, c) = (0.3, 0.2, 0.5);
    let m = 700.0 * a * b * c;
    assert!((p.mass - m).abs() <= 1e-12 * m);
    assert!((p.local_com - Vector3::new(0.15, 0.1, 0.25)).norm() <= 1e-12);
    let d = [m * (b * b + c * c) / 12.0, m * (a * a + c * c) / 12.0, m * (a * a + b * b) / 12.0];
    assert!(tensor_error(&p.inertia, d) <= 1e-12, "{}", p.inertia);
}

/// A random blob (`common::blob`) of up to 25% bumps, 0.05 to 2 across, moved and turned.
fn blob(rng: &mut Rng, segments: u32) -> Mesh {
    common::blob(rng, segments, 0.25, |rng| (rng.range(0.05, 2.0), rng.pose(1.0)))
}

#[test]
fn random_closed_meshes_agree_with_parry() {
    // Both integrate the same polyhedron exactly, by different sums: they differ by round-off, relative to the
    // blob's size (1e-9 for the volume, the tensor and the centre, allowing for the cancellation of sums of
    // 10^4 signed tetrahedra).
    let mut rng = Rng(30);
    for case in 0..40 {
        let mesh = blob(&mut rng, 24 + 4 * (case % 5) as u32);
        let density = rng.range(10.0, 20000.0);
        let ours = Shape::mesh(mesh.clone()).mass_properties(density).unwrap();
        let verts: Vec<_> = mesh.vertices().iter().map(|p| parry3d_f64::math::Vector::new(p.x, p.y, p.z)).collect();
        let theirs = parry3d_f64::mass_properties::MassProperties::from_trimesh(density, &verts, mesh.triangles());
        let size = mesh.vertices().iter().map(|p| (p - mesh.vertices()[0]).norm()).fold(0.0, f64::max);
        assert!(
            (ours.mass - theirs.mass()).abs() <= 1e-9 * ours.mass,
            "case {case}: {} vs {}",
            ours.mass,
            theirs.mass()
        );
        let com = theirs.local_com;
        assert!((ours.local_com - Vector3::new(com.x, com.y, com.z)).norm() <= 1e-9 * size, "case {case}");
        let it = theirs.reconstruct_inertia_matrix().to_cols_array();
        let it = Matrix3::from_column_slice(&it);
        assert!((ours.inertia - it).amax() <= 1e-9 * ours.inertia.amax(), "case {case}: {} vs {it}", ours.inertia);
    }
}

/// A unit cube's 8 corners and 12 outward triangles.
fn cube() -> (Vec<Point3<f64>>, Vec<[u32; 3]>) {
    let v = (0..8).map(|i| Point3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64)).collect();
    let t = vec![
        [0, 2, 1],
        [1, 2, 3],
        [4, 5, 6],
        [5, 7, 6],
        [0, 1, 4],
        [1, 5, 4],
        [2, 6, 3],
        [3, 6, 7],
        [0, 4, 2],
        [2, 4, 6],
        [1, 3, 5],
        [3, 7, 5],
    ];
    (v, t)
}

fn refused(v: &[Point3<f64>], t: &[[u32; 3]], words: &str) {
    let e = Mesh::new(v, t, "part").unwrap_err();
    assert_eq!(e.name, "mesh");
    assert!(e.reason.contains("mesh \"part\"") && e.reason.contains(words), "{words}: {}", e.reason);
}

#[test]
fn a_mesh_that_bounds_no_solid_is_refused_with_its_reason() {
    let (v, t) = cube();
    let p = Shape::mesh(Mesh::new(&v, &t, "part").unwrap()).mass_properties(1.0).unwrap();
    assert!((p.mass - 1.0).abs() < 1e-15, "the cube is right: {}", p.mass);
    refused(&v, &t[1..], "not closed");
    let mut flipped = t.clone();
    flipped[3].swap(1, 2);
    refused(&v, &flipped, "not consistently oriented");
    let inside_out: Vec<[u32; 3]> = t.iter().map(|&[a, b, c]| [a, c, b]).collect();
    refused(&v, &inside_out, "inside out");
    let mut degenerate = t.clone();
    degenerate.push([0, 0, 1]);
    refused(&v, &degenerate, "degenerate");
    let mut twice = t.clone();
    twice.push(t[0]);
    refused(&v, &twice, "duplicates");
    let mut nan = v.clone();
    nan[3].x = f64::NAN;
    refused(&nan, &t, "not finite");
    refused(&v, &[[0, 1, 9]], "referring past");
    refused(&v, &[], "no triangles");
    // two tetrahedra sharing one edge: that edge has four triangles
    let w = [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.5], [0.0, 1.0, 0.5], [-1.0, 0.0, 0.5], [0.0, -1.0, 0.5]];
    let w: Vec<Point3<f64>> = w.iter().map(|&p| Point3::from(p)).collect();
    let tet = |a: u32, b: u32| vec![[0, 1, a], [0, a, b], [0, b, 1], [1, b, a]];
    let mut bow = tet(2, 3);
    bow.extend(tet(4, 5));
    let bow =
        if Mesh::new(&w, &tet(2, 3), "").is_ok() { bow } else { bow.iter().map(|&[a, b, c]| [a, c, b]).collect() };
    refused(&w, &bow, "not manifold");
    // a flat, closed pillow (a square's two sides, split along different diagonals) has no volume
    let flat = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]].map(Point3::from).to_vec();
    refused(&flat, &[[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2]], "no volume");
    let e = Mesh::new(&v, &t[1..], "part").unwrap_err();
    assert!(e.reason.contains("hull"), "the error offers the hull: {}", e.reason);
}

#[test]
fn split_vertices_at_one_place_are_one_vertex() {
    // Files split vertices along seams (one copy per normal or texture coordinate): the surface is still closed.
    let (v, t) = cube();
    let mut split = Vec::new();
    let mut tris = Vec::new();
    for tri in &t {
        let k = split.len() as u32;
        split.extend(tri.iter().map(|&i| v[i as usize]));
        tris.push([k, k + 1, k + 2]);
    }
    let m = Mesh::new(&split, &tris, "split").unwrap();
    assert!((m.volume() - 1.0).abs() < 1e-15);
}

#[test]
fn too_many_triangles_are_refused_before_any_work() {
    // Ten million and one triangles (120 MB of indices) over three vertices: refused by count, not checked one by one.
    let v = [Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 0.0, 0.0), Point3::new(0.0, 1.0, 0.0)];
    let t = vec![[0u32, 1, 2]; tumble_collide::MAX_TRIANGLES + 1];
    let e = Mesh::new(&v, &t, "huge").unwrap_err();
    assert!(e.reason.contains("more than the 10000000 allowed"), "{}", e.reason);
    // a decomposition refuses more than a million (its voxelisation visits each), offering the hull
    let big = Mesh::torus_mesh(0.1, 0.03, 710).unwrap();
    assert!(big.triangles().len() > tumble_collide::MAX_DECOMPOSED_TRIANGLES);
    let e = Shape::decomposed(&big, &Default::default()).unwrap_err();
    assert!(e.reason.contains("hull"), "{}", e.reason);
}

#[test]
fn tiny_and_huge_meshes_keep_finite_mass_properties() {
    // A 1 nm and a 1e8 m torus: the sums are scaled by the reference point, so both come out to the closed form's
    // discretisation error (as the 0.5 m one), not to overflow or underflow.
    for scale in [1e-9, 1.0, 1e8] {
        let m = Mesh::torus_mesh(0.5 * scale, 0.12 * scale, 64).unwrap();
        let p = Shape::mesh(m).mass_properties(1000.0).unwrap();
        let v = 2.0 * PI * PI * 0.5 * 0.12 * 0.12 * scale.powi(3);
        assert!(p.inertia.iter().all(|x| x.is_finite()));
        let step = 2.0 * PI / 64.0;
        assert!((p.mass / 1000.0 - v).abs() / v < step * step, "scale {scale:e}: {} vs {v}", p.mass / 1000.0);
    }
}
