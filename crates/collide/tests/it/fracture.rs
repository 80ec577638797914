//! Fracture: seeded and given cells of convex and non-convex meshes, each piece a closed solid, their volume,
//! centre of mass and inertia adding up to the mesh's, the same seed giving the same bits, shared faces found
//! from the pieces alone, and bad input refused by name.

use nalgebra::{Matrix3, Point3, Vector3};
use tumble_collide::{shared_faces, Cells, MassProperties, Mesh, Shape, MAX_PIECES};

fn props(m: &Mesh) -> MassProperties {
    Shape::Mesh(m.clone()).mass_properties(1.0).unwrap()
}

/// A box of half extents `h` centred at the origin, as a closed mesh (the box shape's own triangles).
fn cuboid(h: [f64; 3], name: &str) -> Mesh {
    let (v, t) = Shape::cuboid(Vector3::from(h)).unwrap().triangle_mesh(8, 1.0);
    Mesh::new(&v, &t, name).unwrap()
}

/// The pieces' mass, centre of mass and inertia about that centre, assembled (parallel axes).
fn assembled(pieces: &[Mesh]) -> MassProperties {
    let parts: Vec<MassProperties> = pieces.iter().map(props).collect();
    let mass: f64 = parts.iter().map(|p| p.mass).sum();
    let com = parts.iter().map(|p| p.local_com * p.mass).sum::<Vector3<f64>>() / mass;
    let inertia = parts
        .iter()
        .map(|p| {
            let d = p.local_com - com;
            p.inertia + (Matrix3::identity() * d.norm_squared() - d * d.transpose()) * p.mass
        })
        .sum();
    MassProperties { mass, local_com: com, inertia }
}

/// Pieces' mass properties against the mesh's, relative to the mesh's scale: 1e-9 is rounding of many cuts and
/// sums (each cut point is exact to ~1e-16 of the size; the sums add a few thousand terms).
fn assert_tiles(mesh: &Mesh, pieces: &[Mesh]) {
    let whole = props(mesh);
    let parts = assembled(pieces);
    let size = whole.mass.cbrt();
    assert!((parts.mass - whole.mass).abs() <= 1e-9 * whole.mass, "volume {} vs {}", parts.mass, whole.mass);
    assert!(
        (parts.local_com - whole.local_com).norm() <= 1e-9 * size,
        "centre {} vs {}",
        parts.local_com,
        whole.local_com
    );
    let scale = whole.inertia.norm();
    assert!((parts.inertia - whole.inertia).norm() <= 1e-9 * scale, "inertia {} vs {}", parts.inertia, whole.inertia);
}

/// Convex, and its hull (its own faces) has its volume: 1e-12 relative is rounding of the two volume sums.
fn is_convex(m: &Mesh) -> bool {
    let hull = Shape::hull_of(m).unwrap().mass_properties(1.0).unwrap().mass;
    m.is_convex() && (hull - m.volume()).abs() <= 1e-12 * m.volume()
}

#[test]
fn a_box_is_cut_into_convex_pieces_that_tile_it() {
    let mesh = cuboid([0.3, 0.2, 0.1], "pane");
    for seed in 0..4 {
        let pieces = mesh.fracture(&Cells::random(20, seed)).unwrap();
        // a convex solid's Voronoi cells are convex and each is one piece
        assert_eq!(pieces.len(), 20);
        assert!(pieces.iter().all(is_convex));
        assert_tiles(&mesh, &pieces);
        assert_eq!(pieces[16].name(), "pane.017");
    }
}

#[test]
fn non_convex_meshes_are_cut_into_closed_pieces_that_tile_them() {
    let torus = Mesh::torus_mesh(0.2, 0.05, 24).unwrap();
    let cup = Mesh::cup_mesh(0.05, 0.08, 0.005, 32).unwrap();
    for (mesh, cells) in [(&torus, 12), (&cup, 16)] {
        for seed in 0..3 {
            let pieces = mesh.fracture(&Cells::random(cells, seed)).unwrap();
            // a cell can hold more than one piece of a non-convex solid, never none
            assert!(pieces.len() >= cells, "{} pieces of {cells} cells", pieces.len());
            assert_tiles(mesh, &pieces);
        }
    }
}

#[test]
fn the_same_seed_gives_the_same_bits_and_another_seed_other_pieces() {
    let mesh = Mesh::sphere_mesh(0.1, 24).unwrap();
    let bits = |seed| -> Vec<u64> {
        let pieces = mesh.fracture(&Cells::random(10, seed)).unwrap();
        pieces.iter().flat_map(|p| p.vertices().iter().flat_map(|v| v.iter().map(|c| c.to_bits()))).collect()
    };
    assert_eq!(bits(7), bits(7));
    assert_ne!(bits(7), bits(8));
}

#[test]
fn two_given_points_halve_a_bar_and_their_shared_face_is_its_section() {
    // a 2 x 0.2 x 0.1 bar cut by the plane halfway between two points on its axis: x = 0.25
    let bar = cuboid([1.0, 0.1, 0.05], "bar");
    let pieces = bar.fracture(&Cells::at(vec![Point3::new(-0.5, 0.0, 0.0), Point3::new(1.0, 0.0, 0.0)])).unwrap();
    assert_eq!(pieces.len(), 2);
    // volumes: 1.25 and 0.75 of the section's 0.02 m^2, to rounding
    assert!((pieces[0].volume() - 1.25 * 0.02).abs() < 1e-15);
    assert!((pieces[1].volume() - 0.75 * 0.02).abs() < 1e-15);
    let faces = shared_faces(&pieces);
    assert_eq!(faces.len(), 1);
    let f = &faces[0];
    assert_eq!((f.a, f.b), (0, 1));
    assert!((f.area - 0.02).abs() < 1e-15, "area {}", f.area);
    assert!((f.centre - Point3::new(0.25, 0.0, 0.0)).norm() < 1e-15);
    assert!((f.normal - Vector3::x()).norm() < 1e-12);
}

#[test]
fn the_faces_of_a_fracture_are_found_and_each_matches_from_both_sides() {
    // every cut face is shared by two pieces: the pieces' surface area is the mesh's plus twice the shared faces'
    let mesh = cuboid([0.3, 0.2, 0.1], "pane");
    let pieces = mesh.fracture(&Cells::random(15, 3)).unwrap();
    let faces = shared_faces(&pieces);
    let area = |m: &Mesh| -> f64 {
        let v = m.vertices();
        m.triangles()
            .iter()
            .map(|t| (v[t[1] as usize] - v[t[0] as usize]).cross(&(v[t[2] as usize] - v[t[0] as usize])).norm() / 2.0)
            .sum()
    };
    let pieces_area: f64 = pieces.iter().map(area).sum();
    let shared: f64 = faces.iter().map(|f| f.area).sum();
    // rounding of the overlaps' clipping: 1e-9 of the area
    assert!(
        (pieces_area - area(&mesh) - 2.0 * shared).abs() < 1e-9 * pieces_area,
        "{pieces_area} {} {shared}",
        area(&mesh)
    );
    assert!(faces.iter().all(|f| f.a < f.b && f.b < pieces.len()));
}

#[test]
fn more_pieces_are_made_near_a_given_point() {
    let mesh = cuboid([0.5, 0.5, 0.05], "pane");
    let corner = Point3::new(0.4, 0.4, 0.0);
    let mean_gap = |cells: Cells| -> f64 {
        let pieces = mesh.fracture(&cells).unwrap();
        let near = pieces.iter().filter(|p| (Point3::from(props(p).local_com) - corner).norm() < 0.3).count();
        near as f64 / pieces.len() as f64
    };
    let even = mean_gap(Cells::random(40, 1));
    let focused = mean_gap(Cells::random(40, 1).near(corner));
    // half of the points within a quarter of the size (0.25 m) of the corner: well over the even share (~0.1)
    assert!(focused >= 2.0 * even, "{focused} near vs {even}");
}

#[test]
fn bad_cells_are_refused_by_name() {
    let mesh = cuboid([0.1, 0.1, 0.1], "box");
    let name = |cells: Cells| mesh.fracture(&cells).unwrap_err().name;
    assert_eq!(name(Cells::random(0, 0)), "pieces");
    assert_eq!(name(Cells::random(MAX_PIECES + 1, 0)), "pieces");
    assert_eq!(name(Cells::at(vec![])), "points");
    assert_eq!(name(Cells::at(vec![Point3::new(1.0, 0.0, 0.0)])), "points");
    assert_eq!(name(Cells::at(vec![Point3::origin(), Point3::origin()])), "points");
    assert_eq!(name(Cells::at(vec![Point3::new(f64::NAN, 0.0, 0.0)])), "points");
    assert_eq!(name(Cells::random(4, 0).near(Point3::new(10.0, 0.0, 0.0))), "near");
    assert_eq!(name(Cells::random(4, 0).near(Point3::new(f64::INFINITY, 0.0, 0.0))), "near");
}
