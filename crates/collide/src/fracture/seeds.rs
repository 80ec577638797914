//! Where a fracture's cells are: points inside the solid, drawn from a seed (more of them near an impact point if
//! one is given) or given by the user.

use super::MAX_PIECES;
use crate::error::ShapeError;
use crate::mesh_overlap::{bounds, winding};
use crate::split_mix::SplitMix;
use crate::surface_mesh::Mesh;
use nalgebra::{Point3, Vector3};

/// A fracture's cells: `Cells::random(pieces, seed)` (`.near(point)` for more of them near a point) or
/// `Cells::at(points)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Cells {
    pieces: usize,
    seed: u64,
    near: Option<Point3<f64>>,
    points: Option<Vec<Point3<f64>>>,
}

/// Draws per point before a seeded fracture gives up finding points inside the solid.
const DRAWS: usize = 10_000;

/// The share of a seeded fracture's points drawn near the point given by `near`, and the radius they are drawn
/// within, as a share of the mesh's size.
const NEAR_SHARE: f64 = 0.5;
const NEAR_RADIUS: f64 = 0.25;

impl Cells {
    /// `pieces` points drawn uniformly inside the solid, from `seed` (the same seed, the same points).
    pub fn random(pieces: usize, seed: u64) -> Cells {
        Cells { pieces, seed, near: None, points: None }
    }

    /// The cells at `points` (each inside the solid, no two at one place): a piece or more for each.
    pub fn at(points: Vec<Point3<f64>>) -> Cells {
        Cells { pieces: points.len(), seed: 0, near: None, points: Some(points) }
    }

    /// Half of a seeded fracture's points drawn within a quarter of the mesh's size of `point` (an impact point),
    /// so that the pieces are smaller there.
    pub fn near(mut self, point: Point3<f64>) -> Cells {
        self.near = Some(point);
        self
    }

    /// The points, checked against `mesh`: each inside its solid.
    pub(super) fn points(&self, mesh: &Mesh) -> Result<Vec<Point3<f64>>, ShapeError> {
        if let Some(points) = &self.points {
            if points.is_empty() || points.len() > MAX_PIECES {
                return Err(ShapeError::new(
                    "points",
                    format!("expected 1 to {MAX_PIECES} points, got {}", points.len()),
                ));
            }
            for (i, p) in points.iter().enumerate() {
                if !p.iter().all(|c| c.is_finite()) {
                    return Err(ShapeError::new("points", format!("point {i} is not finite: {p:?}")));
                }
                if winding(mesh, p) < 0.5 {
                    return Err(ShapeError::new("points", format!("point {i} {p:?} is not inside the mesh's solid")));
                }
                if let Some(j) = points[..i].iter().position(|q| q == p) {
                    return Err(ShapeError::new("points", format!("points {j} and {i} are at one place")));
                }
            }
            return Ok(points.clone());
        }
        if self.pieces == 0 || self.pieces > MAX_PIECES {
            return Err(ShapeError::new("pieces", format!("expected 1 to {MAX_PIECES}, got {}", self.pieces)));
        }
        let (lo, hi) = bounds(mesh);
        let size = (hi - lo).amax();
        if let Some(c) = self.near {
            if !c.iter().all(|x| x.is_finite()) {
                return Err(ShapeError::new("near", format!("expected a finite point, got {c:?}")));
            }
        }
        let mut random = SplitMix(self.seed);
        let near = self.near.map(|c| ((self.pieces as f64 * NEAR_SHARE).ceil() as usize, c));
        let mut out = Vec::with_capacity(self.pieces);
        while out.len() < self.pieces {
            let close = near.filter(|(n, _)| out.len() < *n);
            let mut found = None;
            for _ in 0..DRAWS {
                let p = match close {
                    // uniform in the ball of radius NEAR_RADIUS * size about the point
                    Some((_, c)) => loop {
                        let d = Vector3::new(
                            random.uniform() * 2.0 - 1.0,
                            random.uniform() * 2.0 - 1.0,
                            random.uniform() * 2.0 - 1.0,
                        );
                        if d.norm_squared() <= 1.0 {
                            break c + d * (NEAR_RADIUS * size);
                        }
                    },
                    None => Point3::from(
                        lo + (hi - lo).component_mul(&Vector3::new(
                            random.uniform(),
                            random.uniform(),
                            random.uniform(),
                        )),
                    ),
                };
                if winding(mesh, &p) > 0.5 && !out.contains(&p) {
                    found = Some(p);
                    break;
                }
            }
            match found {
                Some(p) => out.push(p),
                None if close.is_some() => {
                    return Err(ShapeError::new("near", "is not within a quarter of the mesh's size of its solid"))
                }
                None => {
                    return Err(ShapeError::new("pieces", "no point inside the mesh's solid was found: it is too thin"))
                }
            }
        }
        Ok(out)
    }
}
