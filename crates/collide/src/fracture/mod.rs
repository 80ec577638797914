//! A closed mesh fractured into pieces: the Voronoi cells of seeded or given points, each cell's share of the
//! solid cut out of the mesh plane by plane (`clip.rs`) and split into its connected parts, each a closed mesh. The
//! pieces tile the solid, so their volumes, centres of mass and inertias add up to the mesh's to rounding; and the
//! faces two pieces share are found from the pieces alone (`bonds.rs`).

mod bonds;
mod clip;
mod seeds;

pub use bonds::{shared_faces, SharedFace};
pub use seeds::Cells;

use crate::error::ShapeError;
use crate::surface_mesh::{extent, label, Mesh};
use clip::Surface;
use nalgebra::Vector3;

/// The most pieces a fracture makes.
pub const MAX_PIECES: usize = 4096;

/// Twice a triangle's area below which, over the size squared, it is a sliver to flip away (`Mesh::new` refuses
/// 1e-14).
const SLIVER: f64 = 1e-12;

/// A cut's tolerance: points within this share of the mesh's size of a cutting plane count as on it.
const ON_PLANE: f64 = 1e-10;

impl Mesh {
    /// The mesh cut into pieces at the Voronoi cells of `cells`' points (seeded points inside the solid, or given
    /// ones): each cell's share of the solid, split into its connected parts, as closed meshes named after this
    /// one (`vase.001`, `vase.002`, ...), in the cells' order, in this mesh's frame (each where it was modelled).
    /// Convex where the mesh is convex. Their volumes add up to the mesh's to rounding. An error names the
    /// argument that is wrong (`pieces`, `points`, `near`) or says why a cut failed.
    pub fn fracture(&self, cells: &Cells) -> Result<Vec<Mesh>, ShapeError> {
        let points = cells.points(self)?;
        let size = extent(self.vertices());
        let tolerance = ON_PLANE * size;
        let whole = Surface { vertices: self.vertices().to_vec(), triangles: self.triangles().to_vec() };
        let mut pieces = Vec::new();
        for (i, p) in points.iter().enumerate() {
            let mut part = whole.clone();
            // the other points nearest first: the cell shrinks fastest, and a point more than twice as far as the
            // part's farthest corner cuts nothing more
            let mut others: Vec<(f64, usize)> =
                points.iter().enumerate().filter(|(j, _)| *j != i).map(|(j, q)| ((q - p).norm(), j)).collect();
            others.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            for (gap, j) in others {
                let reach = part.vertices.iter().map(|v| (v - p).norm()).fold(0.0, f64::max);
                if gap > 2.0 * reach + tolerance {
                    break;
                }
                let normal: Vector3<f64> = (points[j] - p) / gap;
                let offset = normal.dot(&(p.coords + points[j].coords)) / 2.0;
                part = part.below(&normal, offset, tolerance, SLIVER * size * size).map_err(|e| named(self, e))?;
                part.compact();
                if part.triangles.is_empty() {
                    break;
                }
            }
            for component in part.components() {
                let name = format!("{}.{:03}", base_name(self), pieces.len() + 1);
                pieces.push(Mesh::new(&component.vertices, &component.triangles, &name).map_err(|e| named(self, e))?);
            }
        }
        Ok(pieces)
    }
}

/// The pieces' base name: the mesh's, or "piece" for a mesh without one.
fn base_name(mesh: &Mesh) -> &str {
    if mesh.name().is_empty() {
        "piece"
    } else {
        mesh.name()
    }
}

/// A cut's error, said of the mesh being fractured.
fn named(mesh: &Mesh, e: ShapeError) -> ShapeError {
    ShapeError::new("mesh", format!("{} could not be fractured: {}", label(mesh.name()), e.reason))
}

impl Surface {
    /// Drops the vertices no triangle uses, keeping the others' order.
    fn compact(&mut self) {
        let mut index = vec![u32::MAX; self.vertices.len()];
        let mut kept = Vec::new();
        for t in &mut self.triangles {
            for k in t.iter_mut() {
                if index[*k as usize] == u32::MAX {
                    index[*k as usize] = kept.len() as u32;
                    kept.push(self.vertices[*k as usize]);
                }
                *k = index[*k as usize];
            }
        }
        self.vertices = kept;
    }

    /// Its connected parts (triangles joined through shared vertices), each compacted, in the order of their first
    /// triangles.
    fn components(&self) -> Vec<Surface> {
        let mut parent: Vec<usize> = (0..self.vertices.len()).collect();
        fn root(parent: &mut [usize], mut i: usize) -> usize {
            while parent[i] != i {
                parent[i] = parent[parent[i]];
                i = parent[i];
            }
            i
        }
        for t in &self.triangles {
            for k in 1..3 {
                let (a, b) = (root(&mut parent, t[0] as usize), root(&mut parent, t[k] as usize));
                if a != b {
                    parent[a.max(b)] = a.min(b);
                }
            }
        }
        let mut order: Vec<usize> = Vec::new();
        let mut parts: Vec<Surface> = Vec::new();
        for t in &self.triangles {
            let r = root(&mut parent, t[0] as usize);
            let k = match order.iter().position(|&o| o == r) {
                Some(k) => k,
                None => {
                    order.push(r);
                    parts.push(Surface { vertices: self.vertices.clone(), triangles: Vec::new() });
                    parts.len() - 1
                }
            };
            parts[k].triangles.push(*t);
        }
        for p in &mut parts {
            p.compact();
        }
        parts
    }
}
