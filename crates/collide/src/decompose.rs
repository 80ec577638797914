//! Approximate convex decomposition of a closed mesh (parry's VHACD): the convex pieces a moving non-convex body
//! collides with, its mass properties staying the mesh's own. The pieces are the exact hulls of the mesh's triangles
//! in each voxel part, kept per process by a digest of the mesh and the parameters, so a mesh is decomposed once.

use crate::convert::{point_from_parry, point_to_parry};
use crate::convex_hull::ConvexHull;
use crate::error::ShapeError;
use crate::surface_mesh::{label, Fnv, Mesh};
use nalgebra::Point3;
use parry3d_f64::math::Pose;
use parry3d_f64::shape::{Compound, SharedShape};
use parry3d_f64::transformation::vhacd::{VHACDParameters, VHACD};
use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};
use std::time::Instant;

/// The decomposition's parameters.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Decomposition {
    /// Voxels along the mesh's longest side (8 to 256; default 64). Finer resolves thinner walls, at cubic cost.
    pub resolution: u32,
    /// The most convex pieces (1 to 1024; default 32).
    pub max_pieces: u32,
    /// The concavity, as a fraction of the mesh's size, below which a part is not split further (0 to 1; default
    /// 0.01).
    pub concavity: f64,
}

impl Default for Decomposition {
    fn default() -> Self {
        Decomposition { resolution: 64, max_pieces: 32, concavity: 0.01 }
    }
}

/// The most triangles a mesh to decompose may have (its voxelisation visits each).
pub const MAX_DECOMPOSED_TRIANGLES: usize = 1_000_000;

impl Decomposition {
    /// Checks each parameter's range; the error names it.
    pub fn check(&self) -> Result<(), ShapeError> {
        if !(8..=256).contains(&self.resolution) {
            return Err(ShapeError::new("resolution", format!("must be from 8 to 256, got {}", self.resolution)));
        }
        if !(1..=1024).contains(&self.max_pieces) {
            return Err(ShapeError::new("max_pieces", format!("must be from 1 to 1024, got {}", self.max_pieces)));
        }
        if !(self.concavity.is_finite() && (0.0..=1.0).contains(&self.concavity)) {
            return Err(ShapeError::new("concavity", format!("must be from 0 to 1, got {}", self.concavity)));
        }
        Ok(())
    }

    fn digest(&self, mesh: &Mesh) -> u64 {
        let mut h = Fnv(mesh.digest());
        h.add(self.resolution as u64);
        h.add(self.max_pieces as u64);
        h.add(self.concavity.to_bits());
        h.0
    }
}

/// A mesh and its convex pieces.
#[derive(Clone, Debug)]
pub struct Decomposed {
    pub(crate) mesh: Mesh,
    pub(crate) params: Decomposition,
    pub(crate) pieces: Arc<Vec<ConvexHull>>,
    pub(crate) compound: Arc<Compound>,
    /// Seconds the decomposition took when it ran (the first time in a process).
    pub(crate) seconds: f64,
    /// The digest of mesh and parameters.
    key: u64,
}

/// Piece point sets and the time taken, by digest of mesh and parameters.
type Cache = BTreeMap<u64, (Arc<Vec<Vec<Point3<f64>>>>, f64)>;
static CACHE: Mutex<Cache> = Mutex::new(BTreeMap::new());

impl Decomposed {
    /// The decomposition of `mesh` with `params`, from this process's cache when it was made before.
    pub fn new(mesh: &Mesh, params: &Decomposition) -> Result<Decomposed, ShapeError> {
        let key = params.digest(mesh);
        let cached = CACHE.lock().map(|c| c.get(&key).cloned()).unwrap_or(None);
        let (points, seconds) = match cached {
            Some(hit) => hit,
            None => {
                let (points, seconds) = compute(mesh, params)?;
                let made = (Arc::new(points), seconds);
                if let Ok(mut c) = CACHE.lock() {
                    c.insert(key, made.clone());
                }
                made
            }
        };
        Self::from_pieces(mesh, params, &points, seconds)
    }

    /// The decomposition computed afresh, neither read from nor written to the cache (what benchmarks time).
    pub fn uncached(mesh: &Mesh, params: &Decomposition) -> Result<Decomposed, ShapeError> {
        let (points, seconds) = compute(mesh, params)?;
        Self::from_pieces(mesh, params, &points, seconds)
    }

    /// A decomposition whose pieces are given as point sets (as a saved world has them): each piece is their hull.
    pub fn from_pieces(
        mesh: &Mesh,
        params: &Decomposition,
        pieces: &[Vec<Point3<f64>>],
        seconds: f64,
    ) -> Result<Decomposed, ShapeError> {
        params.check()?;
        let hulls: Vec<ConvexHull> = pieces.iter().filter_map(|p| ConvexHull::from_points(p).ok()).collect();
        if hulls.is_empty() {
            return Err(ShapeError::new(
                "mesh",
                format!(
                    "the decomposition of {} has no solid piece: raise `resolution`, or use its convex hull \
                     (shape=\"hull\")",
                    label(&mesh.name)
                ),
            ));
        }
        let parts = hulls.iter().map(|h| (Pose::IDENTITY, SharedShape(Arc::new((*h.polyhedron).clone())))).collect();
        Ok(Decomposed {
            mesh: mesh.clone(),
            params: *params,
            pieces: Arc::new(hulls),
            compound: Arc::new(Compound::new(parts)),
            seconds,
            key: params.digest(mesh),
        })
    }

    /// The mesh decomposed.
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// The parameters used.
    pub fn params(&self) -> &Decomposition {
        &self.params
    }

    /// The convex pieces.
    pub fn pieces(&self) -> &[ConvexHull] {
        &self.pieces
    }

    /// The digest of mesh and parameters (equal for decompositions of the same mesh with the same parameters).
    pub fn key(&self) -> u64 {
        self.key
    }

    /// Seconds the decomposition took when it ran (the first time in this process, or as saved).
    pub fn seconds(&self) -> f64 {
        self.seconds
    }
}

/// The pieces' point sets and the seconds they took, after the parameters' and the mesh's size are checked.
fn compute(mesh: &Mesh, params: &Decomposition) -> Result<(Vec<Vec<Point3<f64>>>, f64), ShapeError> {
    params.check()?;
    if mesh.triangles.len() > MAX_DECOMPOSED_TRIANGLES {
        return Err(ShapeError::new(
            "mesh",
            format!(
                "{} triangles are more than the {MAX_DECOMPOSED_TRIANGLES} a decomposition takes: simplify the mesh, \
                 or use its convex hull (shape=\"hull\")",
                mesh.triangles.len()
            ),
        ));
    }
    let start = Instant::now();
    let points = vhacd(mesh, params);
    Ok((points, start.elapsed().as_secs_f64()))
}

/// The point sets of the pieces, each the vertices of the exact hull of the mesh's triangles in one voxel part.
fn vhacd(mesh: &Mesh, params: &Decomposition) -> Vec<Vec<Point3<f64>>> {
    let vhacd_params = VHACDParameters {
        resolution: params.resolution,
        max_convex_hulls: params.max_pieces,
        concavity: params.concavity,
        ..VHACDParameters::default()
    };
    let points: Vec<_> = mesh.vertices.iter().map(point_to_parry).collect();
    let decomposition = VHACD::decompose(&vhacd_params, &points, &mesh.triangles, true);
    decomposition
        .compute_exact_convex_hulls(&points, &mesh.triangles)
        .into_iter()
        .map(|(vertices, _)| vertices.into_iter().map(point_from_parry).collect())
        .collect()
}
