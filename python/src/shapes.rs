//! Shapes as Python classes: `Sphere`, `Box`, `Capsule`, `Cylinder`, `ConvexHull`, `TriMesh`, all subclasses of
//! `Shape`, validated on construction (ValueError naming the argument).

use crate::convert::{array, invalid, number, points as to_points, vec3};
use numpy::PyArrayMethods;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use tumble::Shape;

/// A collision and mass shape (base class).
#[pyclass(module = "tumble._tumble", name = "Shape", subclass, frozen)]
pub struct PyShape {
    pub shape: Shape,
}

/// (T, 3) vertex indices: an integer array or a sequence of triples.
pub fn triangles_arg(name: &str, triangles: &Bound<'_, PyAny>) -> PyResult<Vec<[u32; 3]>> {
    let expected = || invalid(name, "expected (T, 3) vertex indices, each in 0 .. 2**32 - 1");
    if let Ok(t) = triangles.extract::<Vec<[u32; 3]>>() {
        return Ok(t);
    }
    let a: numpy::PyReadonlyArray2<'_, i64> = triangles
        .call_method1("astype", ("int64",))
        .and_then(|a| a.extract())
        .or_else(|_| triangles.extract())
        .map_err(|_| expected())?;
    let view = a.as_array();
    if view.ncols() != 3 {
        return Err(invalid(name, format!("expected (T, 3) indices, got shape {:?}", view.shape())));
    }
    let index = |k: i64| u32::try_from(k).map_err(|_| expected());
    view.rows().into_iter().map(|r| Ok([index(r[0])?, index(r[1])?, index(r[2])?])).collect()
}

pub fn shape_err(e: tumble::collide::ShapeError) -> PyErr {
    invalid(e.name, e.reason)
}

/// A shape from its JSON (unpickling: `Shape.__reduce__`).
#[pyfunction]
pub fn _shape_from_json(text: &str) -> PyResult<PyShape> {
    Ok(PyShape { shape: tumble::shape_from_json(text).map_err(crate::convert::world_error)? })
}

#[pymethods]
impl PyShape {
    /// Pickles as the shape's JSON (the scene file's form); it comes back as a `tumble.Shape`.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, (String,))> {
        let rebuild = py.import("tumble._tumble")?.getattr("_shape_from_json")?;
        Ok((rebuild, (tumble::shape_to_json(&self.shape),)))
    }

    /// Mass properties at `density`: a dict with `mass`, `center_of_mass` (3,) and `inertia` (3, 3) about the
    /// centre of mass, in the shape's frame.
    fn mass_properties<'py>(&self, py: Python<'py>, density: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyDict>> {
        let density = number("density", density)?;
        let p = self.shape.mass_properties(density).map_err(shape_err)?;
        let d = PyDict::new(py);
        d.set_item("mass", p.mass)?;
        d.set_item("center_of_mass", array(py, p.local_com.as_slice().to_vec(), &[3])?)?;
        d.set_item("inertia", array(py, p.inertia.transpose().as_slice().to_vec(), &[3, 3])?)?;
        Ok(d)
    }

    /// The surface as (vertices (V, 3), triangles (T, 3)) in the shape's frame.
    /// `subdivisions` (3 ..= 1024, default 24) sets the resolution of curved shapes, `extent` (finite, > 0, default
    /// 10 m) the half-size of a half-space's square.
    #[pyo3(signature = (subdivisions = None, extent = None))]
    fn triangle_mesh<'py>(
        &self,
        py: Python<'py>,
        subdivisions: Option<&Bound<'py, PyAny>>,
        extent: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let subdivisions: i64 = match subdivisions {
            None => 24,
            Some(s) => s.extract().map_err(|_| {
                pyo3::exceptions::PyTypeError::new_err(format!(
                    "invalid argument `subdivisions`: expected an integer, got {s}"
                ))
            })?,
        };
        let extent = extent.map(|e| number("extent", e)).transpose()?.unwrap_or(10.0);
        if !(3..=1024).contains(&subdivisions) {
            return Err(invalid("subdivisions", format!("must be from 3 to 1024, got {subdivisions}")));
        }
        if !(extent.is_finite() && extent > 0.0 && extent <= 1e12) {
            return Err(invalid("extent", format!("must be finite, > 0 and at most 1e12, got {extent}")));
        }
        let (v, t) = self.shape.triangle_mesh(subdivisions as u32, extent);
        let nv = v.len();
        let nt = t.len();
        let verts = array(py, v.iter().flat_map(|p| [p.x, p.y, p.z]).collect(), &[nv, 3])?;
        let tris: Vec<u32> = t.into_iter().flatten().collect();
        let tris = numpy::PyArray1::from_vec(py, tris).reshape(vec![nt, 3])?.into_any();
        Ok((verts, tris))
    }

    /// The distance (m) from this shape, posed at `position` and `orientation` (w, x, y, z), to `other` posed at
    /// `other_position` and `other_orientation`: zero where they overlap.
    fn distance(
        &self,
        position: &Bound<'_, PyAny>,
        orientation: &Bound<'_, PyAny>,
        other: &PyShape,
        other_position: &Bound<'_, PyAny>,
        other_orientation: &Bound<'_, PyAny>,
    ) -> PyResult<f64> {
        let pose = |name: &str, x: &Bound<'_, PyAny>, q_name: &str, q: &Bound<'_, PyAny>| {
            Ok::<_, PyErr>(nalgebra::Isometry3::from_parts(vec3(name, x)?.into(), crate::convert::quat(q_name, q)?))
        };
        let a = pose("position", position, "orientation", orientation)?;
        let b = pose("other_position", other_position, "other_orientation", other_orientation)?;
        tumble::collide::distance(&self.shape, &a, &other.shape, &b).map_err(shape_err)
    }

    /// The shape's kind: "sphere", "box", "capsule", "cylinder", "convex hull", "mesh", "decomposed mesh",
    /// "triangle mesh", "half-space".
    #[getter]
    fn kind(&self) -> &'static str {
        self.shape.kind()
    }

    fn __repr__(&self) -> String {
        match &self.shape {
            Shape::Sphere { radius } => format!("Sphere(radius={radius})"),
            Shape::Cuboid { half_extents: h } => format!("Box(half_extents=({}, {}, {}))", h.x, h.y, h.z),
            Shape::Capsule { half_height, radius } => format!("Capsule(half_height={half_height}, radius={radius})"),
            Shape::Cylinder { half_height, radius } => format!("Cylinder(half_height={half_height}, radius={radius})"),
            Shape::ConvexHull(h) => format!("ConvexHull({} vertices)", h.vertices().len()),
            Shape::TriMesh(m) => format!("TriMesh({} triangles)", m.triangle_count()),
            Shape::Mesh(m) => format!("Mesh(\"{}\", {} triangles)", m.name(), m.triangles().len()),
            Shape::Decomposed(d) => {
                format!(
                    "Mesh(\"{}\", {} triangles, {} pieces)",
                    d.mesh().name(),
                    d.mesh().triangles().len(),
                    d.pieces().len()
                )
            }
            Shape::HalfSpace { normal } => format!("HalfSpace(normal=({}, {}, {}))", normal.x, normal.y, normal.z),
        }
    }
}

/// A sphere of the given radius.
#[pyclass(module = "tumble._tumble", extends = PyShape, frozen)]
pub struct Sphere;

#[pymethods]
impl Sphere {
    #[new]
    fn new(radius: &Bound<'_, PyAny>) -> PyResult<PyClassInitializer<Self>> {
        let radius = number("radius", radius)?;
        Ok(PyClassInitializer::from(PyShape { shape: Shape::sphere(radius).map_err(shape_err)? }).add_subclass(Sphere))
    }
}

/// A box with half extents (x, y, z).
#[pyclass(module = "tumble._tumble", name = "Box", extends = PyShape, frozen)]
pub struct PyBox;

#[pymethods]
impl PyBox {
    #[new]
    fn new(half_extents: &Bound<'_, PyAny>) -> PyResult<PyClassInitializer<Self>> {
        let h = vec3("half_extents", half_extents)?;
        Ok(PyClassInitializer::from(PyShape { shape: Shape::cuboid(h).map_err(shape_err)? }).add_subclass(PyBox))
    }
}

/// A capsule along z: a segment from -half_height to +half_height swept by a ball of the radius.
#[pyclass(module = "tumble._tumble", extends = PyShape, frozen)]
pub struct Capsule;

#[pymethods]
impl Capsule {
    #[new]
    fn new(half_height: &Bound<'_, PyAny>, radius: &Bound<'_, PyAny>) -> PyResult<PyClassInitializer<Self>> {
        let (half_height, radius) = (number("half_height", half_height)?, number("radius", radius)?);
        Ok(PyClassInitializer::from(PyShape { shape: Shape::capsule(half_height, radius).map_err(shape_err)? })
            .add_subclass(Capsule))
    }
}

/// A cylinder along z from -half_height to +half_height.
#[pyclass(module = "tumble._tumble", extends = PyShape, frozen)]
pub struct Cylinder;

#[pymethods]
impl Cylinder {
    #[new]
    fn new(half_height: &Bound<'_, PyAny>, radius: &Bound<'_, PyAny>) -> PyResult<PyClassInitializer<Self>> {
        let (half_height, radius) = (number("half_height", half_height)?, number("radius", radius)?);
        Ok(PyClassInitializer::from(PyShape { shape: Shape::cylinder(half_height, radius).map_err(shape_err)? })
            .add_subclass(Cylinder))
    }
}

/// The convex hull of an (N, 3) point cloud (at least 4 points, not coplanar).
#[pyclass(module = "tumble._tumble", name = "ConvexHull", extends = PyShape, frozen)]
pub struct PyConvexHull;

#[pymethods]
impl PyConvexHull {
    #[new]
    fn new(points: &Bound<'_, PyAny>) -> PyResult<PyClassInitializer<Self>> {
        let p = to_points("points", points)?;
        Ok(PyClassInitializer::from(PyShape { shape: Shape::convex_hull(&p).map_err(shape_err)? })
            .add_subclass(PyConvexHull))
    }
}

/// A triangle mesh (static bodies only): vertices (V, 3) and triangles (T, 3) of vertex indices.
#[pyclass(module = "tumble._tumble", name = "TriMesh", extends = PyShape, frozen)]
pub struct PyTriMesh;

#[pymethods]
impl PyTriMesh {
    #[new]
    fn new(vertices: &Bound<'_, PyAny>, triangles: &Bound<'_, PyAny>) -> PyResult<PyClassInitializer<Self>> {
        let v = to_points("vertices", vertices)?;
        let t = triangles_arg("triangles", triangles)?;
        Ok(PyClassInitializer::from(PyShape { shape: Shape::trimesh(&v, &t).map_err(shape_err)? })
            .add_subclass(PyTriMesh))
    }
}
