//! `tumble.Mesh`: a closed triangle mesh as a shape (made from arrays, a `trimesh.Trimesh`, or read from an OBJ, STL,
//! PLY or glTF/GLB file), its mass properties the solid's; and the decomposition parameters `add_body` takes.

use crate::convert::{array, invalid, number, points as to_points, repr};
use crate::shapes::{shape_err, triangles_arg, PyConvexHull, PyShape};
use numpy::PyArrayMethods;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use tumble::collide::UpAxis;
use tumble::{Decomposition, Shape};

/// A closed triangle mesh: vertices (V, 3) and triangles (T, 3) wound counter-clockwise seen from outside. A moving
/// body carries its convex decomposition (or its hull, `shape="hull"`), a static one the exact triangles; its mass
/// properties are the solid's.
#[pyclass(module = "tumble._tumble", name = "Mesh", extends = PyShape, frozen)]
pub struct PyMesh;

pub(crate) fn mesh_of(shape: &Shape) -> &tumble::Mesh {
    match shape {
        Shape::Mesh(m) => m,
        Shape::Decomposed(d) => d.mesh(),
        _ => unreachable!("a tumble.Mesh holds a mesh"),
    }
}

pub(crate) fn new_mesh(py: Python<'_>, mesh: tumble::Mesh) -> PyResult<Py<PyMesh>> {
    Py::new(py, PyClassInitializer::from(PyShape { shape: Shape::mesh(mesh) }).add_subclass(PyMesh))
}

/// `up` as given ("y" or "z"), or the format's own for None.
fn up_axis(up: Option<&str>) -> PyResult<UpAxis> {
    up.map_or(Ok(UpAxis::OfFormat), |u| UpAxis::named(u).map_err(shape_err))
}

#[pymethods]
impl PyMesh {
    /// A mesh from `vertices` (V, 3) and `triangles` (T, 3), or from a `trimesh.Trimesh` given alone. Raises
    /// ValueError naming the mesh and what is wrong when it does not bound a solid (not closed, inside out,
    /// degenerate or repeated triangles, no volume).
    #[new]
    #[pyo3(signature = (vertices, triangles = None, name = ""))]
    fn new(
        vertices: &Bound<'_, PyAny>,
        triangles: Option<&Bound<'_, PyAny>>,
        name: &str,
    ) -> PyResult<PyClassInitializer<Self>> {
        let (v, t) = match triangles {
            Some(t) => (to_points("vertices", vertices)?, triangles_arg("triangles", t)?),
            None if vertices.hasattr("faces")? && vertices.hasattr("vertices")? => (
                to_points("vertices", &vertices.getattr("vertices")?)?,
                triangles_arg("triangles", &vertices.getattr("faces")?)?,
            ),
            None => {
                return Err(invalid("triangles", format!("are needed with vertices (got {} alone)", repr(vertices))))
            }
        };
        let mesh = tumble::Mesh::new(&v, &t, name).map_err(shape_err)?;
        Ok(PyClassInitializer::from(PyShape { shape: Shape::mesh(mesh) }).add_subclass(PyMesh))
    }

    /// The meshes of an OBJ, STL, PLY, glTF or GLB file merged into one, each placed by the file's transforms,
    /// scaled by `scale` (file units to metres) and turned so that the file's `up` axis ("y" or "z") is +z; by
    /// default the format's own: +y for glTF and GLB (their specification), the coordinates as given (+z) for OBJ,
    /// STL and PLY.
    #[staticmethod]
    #[pyo3(signature = (path, scale = 1.0, up = None))]
    fn load(py: Python<'_>, path: std::path::PathBuf, scale: f64, up: Option<&str>) -> PyResult<Py<PyMesh>> {
        let up = up_axis(up)?;
        let mesh = py.detach(|| tumble::Mesh::load(&path, scale, up)).map_err(shape_err)?;
        new_mesh(py, mesh)
    }

    /// The meshes of a file one by one (as `load`, without merging them).
    #[staticmethod]
    #[pyo3(signature = (path, scale = 1.0, up = None))]
    fn load_all(py: Python<'_>, path: std::path::PathBuf, scale: f64, up: Option<&str>) -> PyResult<Vec<Py<PyMesh>>> {
        let up = up_axis(up)?;
        let meshes = py.detach(|| tumble::Mesh::load_all(&path, scale, up)).map_err(shape_err)?;
        meshes.into_iter().map(|m| new_mesh(py, m)).collect()
    }

    /// The solid swept by turning `profile` ((r, z) points, r >= 0) about the z axis in `segments` steps: a
    /// profile from the axis back to the axis bounds a solid (a cup, a sphere), any other is closed from its last
    /// point to its first (a torus).
    #[staticmethod]
    #[pyo3(signature = (profile, segments = 48, name = ""))]
    fn revolve(py: Python<'_>, profile: &Bound<'_, PyAny>, segments: u32, name: &str) -> PyResult<Py<PyMesh>> {
        let profile = crate::convert::rows::<2>("profile", profile)?;
        new_mesh(py, tumble::Mesh::revolve(&profile, segments, name).map_err(shape_err)?)
    }

    /// The vertices (V, 3), as given.
    #[getter]
    fn vertices<'py>(self_: PyRef<'py, Self>, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let m = mesh_of(&self_.as_super().shape);
        array(py, m.vertices().iter().flat_map(|p| [p.x, p.y, p.z]).collect(), &[m.vertices().len(), 3])
    }

    /// The triangles (T, 3), as given.
    #[getter]
    fn triangles<'py>(self_: PyRef<'py, Self>, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let m = mesh_of(&self_.as_super().shape);
        let flat: Vec<u32> = m.triangles().iter().flatten().copied().collect();
        Ok(numpy::PyArray1::from_vec(py, flat).reshape(vec![m.triangles().len(), 3])?.into_any())
    }

    /// The enclosed volume (m^3).
    #[getter]
    fn volume(self_: PyRef<'_, Self>) -> f64 {
        mesh_of(&self_.as_super().shape).volume()
    }

    /// Whether the solid is convex (every vertex on or below every triangle's plane, to 1e-9 of its size).
    #[getter]
    fn is_convex(self_: PyRef<'_, Self>) -> bool {
        mesh_of(&self_.as_super().shape).is_convex()
    }

    /// The name (the file's, or as given).
    #[getter]
    fn name(self_: PyRef<'_, Self>) -> String {
        mesh_of(&self_.as_super().shape).name().to_string()
    }

    /// The convex hull of the vertices, as a `ConvexHull`.
    fn hull(self_: PyRef<'_, Self>, py: Python<'_>) -> PyResult<Py<PyConvexHull>> {
        let shape = Shape::hull_of(mesh_of(&self_.as_super().shape)).map_err(shape_err)?;
        Py::new(py, PyClassInitializer::from(PyShape { shape }).add_subclass(PyConvexHull))
    }

    /// The convex pieces a moving body of this mesh collides with (as `add_body` makes them, from the same cache),
    /// for inspection: a list of `ConvexHull`.
    #[pyo3(signature = (resolution = None, max_pieces = None, concavity = None))]
    fn pieces(
        self_: PyRef<'_, Self>,
        py: Python<'_>,
        resolution: Option<u32>,
        max_pieces: Option<u32>,
        concavity: Option<f64>,
    ) -> PyResult<Vec<Py<PyConvexHull>>> {
        let params = params(resolution, max_pieces, concavity);
        let mesh = mesh_of(&self_.as_super().shape).clone();
        let d = py.detach(|| tumble::collide::Decomposed::new(&mesh, &params)).map_err(shape_err)?;
        d.pieces()
            .iter()
            .map(|h| {
                let shape = Shape::ConvexHull(h.clone());
                Py::new(py, PyClassInitializer::from(PyShape { shape }).add_subclass(PyConvexHull))
            })
            .collect()
    }
}

/// Decomposition parameters, the defaults where not given.
fn params(resolution: Option<u32>, max_pieces: Option<u32>, concavity: Option<f64>) -> Decomposition {
    let d = Decomposition::default();
    Decomposition {
        resolution: resolution.unwrap_or(d.resolution),
        max_pieces: max_pieces.unwrap_or(d.max_pieces),
        concavity: concavity.unwrap_or(d.concavity),
    }
}

/// `decomposition={"resolution": ..., "max_pieces": ..., "concavity": ...}` (any subset; unknown keys are errors).
pub fn decomposition_arg(obj: Option<&Bound<'_, PyAny>>) -> PyResult<Option<Decomposition>> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else { return Ok(None) };
    let dict =
        obj.cast::<PyDict>().map_err(|_| invalid("decomposition", format!("expected a dict, got {}", repr(obj))))?;
    let (mut resolution, mut max_pieces, mut concavity) = (None, None, None);
    for (k, v) in dict.iter() {
        let key: String = k.extract().map_err(|_| invalid("decomposition", "keys must be strings"))?;
        let whole = |name: &str| -> PyResult<u32> {
            v.extract::<u32>().map_err(|_| invalid(name, format!("must be a whole number, got {}", repr(&v))))
        };
        match key.as_str() {
            "resolution" => resolution = Some(whole("resolution")?),
            "max_pieces" => max_pieces = Some(whole("max_pieces")?),
            "concavity" => concavity = Some(number("concavity", &v)?),
            other => {
                return Err(invalid(
                    "decomposition",
                    format!("unknown key \"{other}\" (resolution, max_pieces, concavity)"),
                ))
            }
        }
    }
    let p = params(resolution, max_pieces, concavity);
    p.check().map_err(shape_err)?;
    Ok(Some(p))
}

/// `add_body`'s shape arguments: the shape given first (or as `shape=`, by keyword), and for a mesh how it collides
/// (`shape="decomposed" | "hull" | "exact"`, `decomposition=`).
pub fn shape_args(
    geometry: Option<&Bound<'_, PyAny>>,
    shape: Option<&Bound<'_, PyAny>>,
    decomposition: Option<&Bound<'_, PyAny>>,
) -> PyResult<(Option<Shape>, Option<tumble::MeshShape>)> {
    let decomposition = decomposition_arg(decomposition)?;
    let shape = shape.filter(|s| !s.is_none());
    // the first argument is `shape` to the caller (a keyword `shape=` may hold it instead)
    let geometry = match geometry.filter(|g| !g.is_none()) {
        Some(g) => Some(g.extract::<PyRef<'_, PyShape>>().map_err(|_| {
            pyo3::exceptions::PyTypeError::new_err(format!(
                "invalid argument `shape`: expected a Shape (Sphere, Box, Mesh, ...), got {}",
                repr(g)
            ))
        })?),
        None => None,
    };
    let (geometry, name) = match (geometry, shape) {
        (g, None) => (g.map(|g| g.shape.clone()), None),
        (None, Some(s)) => match s.extract::<PyRef<'_, PyShape>>() {
            Ok(s) => (Some(s.shape.clone()), None),
            Err(_) => return Err(invalid("shape", format!("expected a Shape, got {}", repr(s)))),
        },
        (Some(g), Some(s)) => match s.extract::<String>() {
            Ok(name) => (Some(g.shape.clone()), Some(name)),
            Err(_) => {
                return Err(invalid(
                    "shape",
                    format!("with a shape given first, `shape` is how a mesh collides (\"decomposed\", \"hull\", \"exact\"), got {}", repr(s)),
                ))
            }
        },
    };
    let choice = match (name, decomposition) {
        (None, None) => None,
        (None, Some(d)) => Some(tumble::MeshShape::Decomposed(d)),
        (Some(n), d) => Some(tumble::MeshShape::named(&n, d).map_err(crate::convert::world_error)?),
    };
    Ok((geometry, choice))
}
