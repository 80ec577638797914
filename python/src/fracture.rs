//! `Mesh.fracture` and `World.add_fractured` for Python: the arguments converted and forwarded to
//! `tumble::Mesh::fracture` and `tumble::World::add_fractured`; the rules are the library's.

use crate::convert::{invalid, opt_vec3, points as to_points, quat, world_error};
use crate::handles::PyBodyHandle;
use crate::mesh::{mesh_of, new_mesh, PyMesh};
use crate::shapes::shape_err;
use crate::world::PyWorld;
use pyo3::prelude::*;
use tumble::{Cells, Glue};

#[pymethods]
impl PyMesh {
    /// The mesh cut into pieces at the Voronoi cells of `pieces` points drawn inside its solid from `seed` (more
    /// of them near `near`, an impact point, if given), or of the given `points` (N, 3): each cell's share of the
    /// solid, split into its connected parts, as closed meshes named after this one ("vase.001", ...) in its
    /// frame, convex where it is convex; their volumes add up to its own. ValueError naming the argument.
    #[pyo3(signature = (pieces = None, seed = None, points = None, near = None))]
    fn fracture(
        self_: PyRef<'_, Self>,
        py: Python<'_>,
        pieces: Option<usize>,
        seed: Option<u64>,
        points: Option<&Bound<'_, PyAny>>,
        near: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Vec<Py<PyMesh>>> {
        let near = opt_vec3("near", near)?.map(nalgebra::Point3::from);
        let cells = match (points.filter(|p| !p.is_none()), pieces) {
            (Some(p), count) => {
                let p = to_points("points", p)?;
                if count.is_some_and(|n| n != p.len()) {
                    return Err(invalid("pieces", "applies to seeded cells; with `points`, one cell a point"));
                }
                for (name, given) in [("seed", seed.is_some()), ("near", near.is_some())] {
                    if given {
                        return Err(invalid(name, "applies to seeded cells, not to given `points`"));
                    }
                }
                Cells::at(p)
            }
            (None, Some(n)) => {
                let cells = Cells::random(n, seed.unwrap_or(0));
                match near {
                    Some(c) => cells.near(c),
                    None => cells,
                }
            }
            (None, None) => return Err(invalid("pieces", "give a number of pieces, or `points`")),
        };
        let mesh = mesh_of(&self_.as_super().shape).clone();
        let made = py.detach(|| mesh.fracture(&cells)).map_err(shape_err)?;
        made.into_iter().map(|m| new_mesh(py, m)).collect()
    }
}

#[pymethods]
impl PyWorld {
    /// Adds the `pieces` of a fractured object (`Mesh.fracture`'s, or closed meshes in one frame) as bodies of
    /// `density` where they were modelled, the frame at `position` and `orientation` (w, x, y, z), and glues each
    /// pair that shares a face by a weld that breaks past the face's area times `strength` (Pa) pulling it apart,
    /// or the moment that cracks a round face of that area, that load averaged over `window` seconds (0.01 by
    /// default; 0: the load at the instant). Returns the pieces' handles, in order (the welds are
    /// the world's joints; `broken_joints()` and a run's breaks say which broke). `mesh` is the object fractured: the
    /// pieces must fill it (their volumes add up to its own).
    /// ValueError naming the argument; nothing is added then.
    #[pyo3(signature = (mesh, pieces, density = None, strength = None, position = None, orientation = None,
                        friction = None, restitution = None, window = None))]
    #[allow(clippy::too_many_arguments)]
    fn add_fractured(
        &mut self,
        py: Python<'_>,
        mesh: PyRef<'_, PyMesh>,
        pieces: Vec<PyRef<'_, PyMesh>>,
        density: Option<f64>,
        strength: Option<f64>,
        position: Option<&Bound<'_, PyAny>>,
        orientation: Option<&Bound<'_, PyAny>>,
        friction: Option<f64>,
        restitution: Option<f64>,
        window: Option<f64>,
    ) -> PyResult<Vec<PyBodyHandle>> {
        let strength = strength.ok_or_else(|| invalid("strength", "is needed: the glue's strength in pascals"))?;
        let mut glue = Glue::new(density.unwrap_or(tumble::DEFAULT_DENSITY), strength);
        glue.position = opt_vec3("position", position)?.unwrap_or_default();
        if let Some(w) = window {
            glue.window = w;
        }
        if let Some(q) = orientation.filter(|o| !o.is_none()) {
            glue.orientation = quat("orientation", q)?;
        }
        glue.material = crate::material::MaterialArgs {
            friction,
            restitution,
            rolling_resistance: None,
            torsional_resistance: None,
            friction_combine: None,
            restitution_combine: None,
        }
        .material()?;
        let whole = mesh_of(&mesh.as_super().shape).clone();
        let meshes: Vec<tumble::Mesh> = pieces.iter().map(|p| mesh_of(&p.as_super().shape).clone()).collect();
        let mut guard = self.r();
        let world: &mut tumble::World = &mut guard;
        let added = py.detach(|| world.add_fractured(&whole, &meshes, &glue)).map_err(world_error)?;
        Ok(added.bodies.into_iter().map(Into::into).collect())
    }
}

/// The faces `pieces` (closed meshes in one frame) share: for each touching pair `(a, b, area, centre, normal)`,
/// `a < b` indices into the list, the area (m^2), its centroid, and its unit normal out of `a` into `b`, ordered by
/// pair.
#[pyfunction]
#[allow(clippy::type_complexity)]
pub fn shared_faces(pieces: Vec<PyRef<'_, PyMesh>>) -> Vec<(usize, usize, f64, [f64; 3], [f64; 3])> {
    let meshes: Vec<tumble::Mesh> = pieces.iter().map(|p| mesh_of(&p.as_super().shape).clone()).collect();
    tumble::collide::shared_faces(&meshes)
        .into_iter()
        .map(|f| (f.a, f.b, f.area, f.centre.coords.into(), f.normal.into()))
        .collect()
}

/// The bonds that glue `pieces` at `strength` (Pa), as `World.add_fractured` makes them: for each face two pieces
/// share (of at least a twentieth of the median face) `(a, b, area, centre, normal, force, torque)`, the weld's
/// bounds in N and N m.
#[pyfunction]
#[allow(clippy::type_complexity)]
pub fn bonds(pieces: Vec<PyRef<'_, PyMesh>>, strength: f64) -> Vec<(usize, usize, f64, [f64; 3], [f64; 3], f64, f64)> {
    let meshes: Vec<tumble::Mesh> = pieces.iter().map(|p| mesh_of(&p.as_super().shape).clone()).collect();
    tumble::bonds(&meshes, strength)
        .into_iter()
        .map(|(f, force, torque)| (f.a, f.b, f.area, f.centre.coords.into(), f.normal.into(), force, torque))
        .collect()
}
