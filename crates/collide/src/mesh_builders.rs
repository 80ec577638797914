//! Closed meshes built in code: solids of revolution (sphere, cylinder, torus, cup, ring) and unions of grid cells
//! (a chair), for scenes, tests and benchmarks that need no downloaded asset.

use crate::error::ShapeError;
use crate::surface_mesh::{integrals, Mesh};
use nalgebra::{Point3, Vector3};
use std::collections::{BTreeMap, BTreeSet};
use std::f64::consts::TAU;

impl Mesh {
    /// The solid swept by turning `profile` ((r, z) points, r >= 0) about the z axis in `segments` steps (3 to
    /// 4096). A profile that starts and ends on the axis (r = 0) bounds a solid by itself (a sphere, a cup); one that
    /// does not is closed from its last point back to its first (a torus).
    pub fn revolve(profile: &[[f64; 2]], segments: u32, name: &str) -> Result<Mesh, ShapeError> {
        if !(3..=4096).contains(&segments) {
            return Err(ShapeError::new("segments", format!("must be from 3 to 4096, got {segments}")));
        }
        if profile.len() < 2 || profile.iter().any(|p| !(p[0] >= 0.0 && p[0].is_finite() && p[1].is_finite())) {
            return Err(ShapeError::new("profile", "needs two or more finite (r >= 0, z) points"));
        }
        let n = segments as usize;
        let on_axis = |p: &[f64; 2]| p[0] == 0.0;
        let open = on_axis(&profile[0]) && on_axis(&profile[profile.len() - 1]);
        if profile[1..profile.len() - 1].iter().any(on_axis) || (!open && profile.iter().any(on_axis)) {
            return Err(ShapeError::new("profile", "only its two end points may lie on the axis"));
        }
        let mut vertices = Vec::new();
        // first vertex of each profile point (a pole has one vertex, a ring `n`)
        let mut first = Vec::with_capacity(profile.len());
        for p in profile {
            first.push(vertices.len() as u32);
            if on_axis(p) {
                vertices.push(Point3::new(0.0, 0.0, p[1]));
            } else {
                for j in 0..n {
                    let a = TAU * j as f64 / n as f64;
                    vertices.push(Point3::new(p[0] * a.cos(), p[0] * a.sin(), p[1]));
                }
            }
        }
        let ring = |k: usize, j: usize| first[k] + (j % n) as u32;
        let mut triangles = Vec::new();
        let bands = if open { profile.len() - 1 } else { profile.len() };
        for k in 0..bands {
            let l = (k + 1) % profile.len();
            for j in 0..n {
                match (on_axis(&profile[k]), on_axis(&profile[l])) {
                    (true, false) => triangles.push([first[k], ring(l, j + 1), ring(l, j)]),
                    (false, true) => triangles.push([first[l], ring(k, j), ring(k, j + 1)]),
                    _ => {
                        triangles.push([ring(k, j), ring(k, j + 1), ring(l, j + 1)]);
                        triangles.push([ring(k, j), ring(l, j + 1), ring(l, j)]);
                    }
                }
            }
        }
        outward(&vertices, &mut triangles);
        Mesh::new(&vertices, &triangles, name)
    }

    /// A sphere of `radius` with `segments` steps around (and half as many from pole to pole).
    pub fn sphere_mesh(radius: f64, segments: u32) -> Result<Mesh, ShapeError> {
        let m = (segments / 2).max(2);
        let profile: Vec<[f64; 2]> = (0..=m)
            .map(|i| {
                let t = std::f64::consts::PI * i as f64 / m as f64;
                let r = if i == 0 || i == m { 0.0 } else { radius * t.sin() };
                [r, -radius * t.cos()]
            })
            .collect();
        Self::revolve(&profile, segments, "sphere")
    }

    /// A cylinder along z from -half_height to half_height.
    pub fn cylinder_mesh(half_height: f64, radius: f64, segments: u32) -> Result<Mesh, ShapeError> {
        let h = half_height;
        Self::revolve(&[[0.0, -h], [radius, -h], [radius, h], [0.0, h]], segments, "cylinder")
    }

    /// A torus about z: tube `minor` radius at `major` radius from the axis, `segments` steps around each.
    pub fn torus_mesh(major: f64, minor: f64, segments: u32) -> Result<Mesh, ShapeError> {
        let profile: Vec<[f64; 2]> = (0..segments)
            .map(|i| {
                let t = TAU * i as f64 / segments as f64;
                [major + minor * t.cos(), minor * t.sin()]
            })
            .collect();
        Self::revolve(&profile, segments, "torus")
    }

    /// A cup: outer `radius` and `height`, walls and bottom `wall` thick, its base at z = 0.
    pub fn cup_mesh(radius: f64, height: f64, wall: f64, segments: u32) -> Result<Mesh, ShapeError> {
        let inner = radius - wall;
        let profile = [[0.0, 0.0], [radius, 0.0], [radius, height], [inner, height], [inner, wall], [0.0, wall]];
        Self::revolve(&profile, segments, "cup")
    }

    /// The union of grid cells (integer coordinates, each a cube of side `cell` from `cell * index`): the faces
    /// between a filled cell and an empty one. Cells that touch along an edge only make a non-manifold surface.
    pub fn from_cells(cells: &[[i32; 3]], cell: f64, name: &str) -> Result<Mesh, ShapeError> {
        let filled: BTreeSet<[i32; 3]> = cells.iter().copied().collect();
        let mut index: BTreeMap<[i32; 3], u32> = BTreeMap::new();
        let mut vertices = Vec::new();
        let mut corner = |c: [i32; 3]| {
            *index.entry(c).or_insert_with(|| {
                vertices.push(Point3::from(Vector3::new(c[0] as f64, c[1] as f64, c[2] as f64) * cell));
                (vertices.len() - 1) as u32
            })
        };
        let mut triangles = Vec::new();
        for c in &filled {
            for axis in 0..3 {
                for side in [0, 1] {
                    let mut next = *c;
                    next[axis] += 2 * side - 1;
                    if filled.contains(&next) {
                        continue;
                    }
                    // the face's corners in order around it, counter-clockwise seen from outside
                    let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                    let mut at = |du: i32, dv: i32| {
                        let mut p = *c;
                        p[axis] += side;
                        p[u] += du;
                        p[v] += dv;
                        corner(p)
                    };
                    let q = [at(0, 0), at(1, 0), at(1, 1), at(0, 1)];
                    let q = if side == 1 { q } else { [q[0], q[3], q[2], q[1]] };
                    triangles.push([q[0], q[1], q[2]]);
                    triangles.push([q[0], q[2], q[3]]);
                }
            }
        }
        Mesh::new(&vertices, &triangles, name)
    }
}

/// Reverses every triangle when the surface encloses a negative volume.
fn outward(vertices: &[Point3<f64>], triangles: &mut [[u32; 3]]) {
    if integrals(vertices, triangles).mass < 0.0 {
        triangles.iter_mut().for_each(|t| t.swap(1, 2));
    }
}
