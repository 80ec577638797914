//! `World` for Python, reading state: time, gravity, handles, state arrays, colliders, energies, the plan and
//! the report.

use crate::convert::{array, frozen, world_error};
use crate::handles::{PyBodyHandle, PyParticleHandle};
use crate::report::{plan_dict, report_dict};
use crate::shapes::PyShape;
use crate::state::PyState;
use crate::world::PyWorld;
use nalgebra::UnitQuaternion;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// One end of a drawn link: what it is attached to, its row, and a point.
type LinkEnd = (&'static str, i64, [f64; 3]);
/// A spring or joint to draw: its kind and two ends.
type Link = (&'static str, LinkEnd, LinkEnd);

/// A body's colliders: each shape with its pose in the body frame (position, quaternion w, x, y, z).
type BodyShapes = Vec<(Py<PyShape>, [f64; 3], [f64; 4])>;

/// A (count, W) array from rows.
fn rows<'py, const W: usize>(
    py: Python<'py>,
    count: usize,
    items: impl Iterator<Item = [f64; W]>,
) -> PyResult<Bound<'py, PyAny>> {
    frozen(py, items.flatten().collect(), &[count, W])
}

#[pymethods]
impl PyWorld {
    /// Current time.
    #[getter]
    fn time(&self) -> f64 {
        self.r().time()
    }

    /// Gravity, as a (3,) array.
    #[getter]
    fn gravity<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        array(py, self.r().gravity().as_slice().to_vec(), &[3])
    }

    /// The whole state now (time, every particle's and body's state, the engine's memory) as a ``tumble.State``.
    fn get_state(&self) -> PyState {
        PyState { inner: std::sync::Mutex::new(self.r().state()) }
    }

    /// Puts a whole state back. A state read from this world, unedited, with its structure and settings unchanged
    /// since, brings the engine's memory back too: the world continues bit for bit as it did from there. Any other
    /// (edited with ``State.replace``, from before a change of structure) starts the world from it afresh, as a new
    /// world built with it would. Static bodies must be where they are (move them with ``set_body_state``).
    /// Raises ValueError naming the array that is wrong; the world is then unchanged.
    fn set_state(&mut self, state: &PyState) -> PyResult<()> {
        self.w().set_state(&state.get()).map_err(world_error)
    }

    /// Returns to time zero with every particle and body as it was added (or set before the first step), the
    /// engine's memory and the report cleared: the world then runs bit for bit as a new one built the same way.
    fn reset(&mut self) {
        self.w().reset()
    }

    /// The contacts of the last step as a dict: ``points`` and ``normals`` (C, 3) (normals from ``a`` toward
    /// ``b``), ``gaps`` (C,) (negative: overlapping), ``impulses`` (C,) normal impulses over the step (N s),
    /// ``forces`` (C,) their mean forces (N), ``a``, ``b``: the particles' or bodies' handles (static bodies
    /// included), and ``bodies``: the (a, b) pairs. Fast mode: every contact of the last step's solve; accurate mode: those of the last contact step
    /// while bodies touch. Empty before the first step and after any change of structure or state.
    fn contacts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let found = self.r().contacts();
        let n = found.len();
        let out = PyDict::new(py);
        let vectors = |f: &dyn Fn(&tumble::ContactInfo) -> [f64; 3]| found.iter().flat_map(f).collect::<Vec<f64>>();
        out.set_item("points", frozen(py, vectors(&|c| c.point.coords.into()), &[n, 3])?)?;
        out.set_item("normals", frozen(py, vectors(&|c| c.normal.into()), &[n, 3])?)?;
        out.set_item("gaps", frozen(py, found.iter().map(|c| c.gap).collect(), &[n])?)?;
        out.set_item("impulses", frozen(py, found.iter().map(|c| c.impulse).collect(), &[n])?)?;
        out.set_item("forces", frozen(py, found.iter().map(|c| c.force).collect(), &[n])?)?;
        let handle = |t: tumble::Target| -> PyResult<Py<PyAny>> {
            Ok(match t {
                tumble::Target::Particle(h) => Py::new(py, PyParticleHandle::from(h))?.into_any(),
                tumble::Target::Body(h) => Py::new(py, PyBodyHandle::from(h))?.into_any(),
            })
        };
        let a = found.iter().map(|c| handle(c.a)).collect::<PyResult<Vec<_>>>()?;
        let b = found.iter().map(|c| handle(c.b)).collect::<PyResult<Vec<_>>>()?;
        let pairs: Vec<(Py<PyAny>, Py<PyAny>)> =
            a.iter().zip(&b).map(|(x, y)| (x.clone_ref(py), y.clone_ref(py))).collect();
        out.set_item("bodies", pairs)?;
        out.set_item("a", a)?;
        out.set_item("b", b)?;
        Ok(out)
    }

    /// A particle's row in the particle arrays.
    fn _particle_row(&self, handle: PyParticleHandle) -> PyResult<usize> {
        self.r().particle_row(handle.into()).map_err(world_error)
    }

    /// A body's row in the body arrays.
    fn _body_row(&self, handle: PyBodyHandle) -> PyResult<usize> {
        self.r().body_row(handle.into()).map_err(world_error)
    }

    /// The particles' handles, in array order.
    fn particle_handles(&self) -> Vec<PyParticleHandle> {
        self.r().particles().map(|(h, _)| h.into()).collect()
    }

    /// The bodies' handles (static ones included), in array order.
    fn body_handles(&self) -> Vec<PyBodyHandle> {
        self.r().bodies().map(|(h, _)| h.into()).collect()
    }

    /// (P, 3) particle positions.
    fn _particle_positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let w = self.r();
        rows(py, w.particle_count(), w.particles().map(|(_, p)| p.position().into()))
    }

    /// (P, 3) particle velocities.
    fn _particle_velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let w = self.r();
        rows(py, w.particle_count(), w.particles().map(|(_, p)| p.velocity().into()))
    }

    /// (B, 3) body positions.
    fn _body_positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let w = self.r();
        rows(py, w.body_count(), w.bodies().map(|(_, b)| b.position().into()))
    }

    /// (B, 3) positions of the bodies' modelled frames' origins.
    fn _body_origins<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let w = self.r();
        rows(py, w.body_count(), w.bodies().map(|(_, b)| b.origin().into()))
    }

    /// Each body's name (None where it has none), in row order.
    fn _body_names(&self) -> Vec<Option<String>> {
        self.r().bodies().map(|(_, b)| b.name().map(str::to_owned)).collect()
    }

    /// Each body's collision groups, in row order.
    fn _body_collision_groups(&self) -> Vec<u32> {
        self.r().bodies().map(|(_, b)| b.collision_groups()).collect()
    }

    /// Whether each body is kinematic, in row order.
    fn _body_kinematic(&self) -> Vec<bool> {
        self.r().bodies().map(|(_, b)| b.is_kinematic()).collect()
    }

    /// Each body's colour as linear RGBA (None where it has none), in row order.
    fn _body_colors(&self) -> Vec<Option<[f64; 4]>> {
        self.r().bodies().map(|(_, b)| b.color()).collect()
    }

    /// (B,) body masses (infinite for static and kinematic bodies).
    fn _body_masses<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let w = self.r();
        array(py, w.bodies().map(|(_, b)| b.mass()).collect(), &[w.body_count()])
    }

    /// (B, 3, 3) world inertia tensors about the centres of mass.
    fn _body_inertias<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let w = self.r();
        let flat = w.bodies().flat_map(|(_, b)| b.world_inertia().transpose().iter().copied().collect::<Vec<_>>());
        array(py, flat.collect(), &[w.body_count(), 3, 3])
    }

    /// (B, 4) body orientations (w, x, y, z).
    fn _body_orientations<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let w = self.r();
        rows(
            py,
            w.body_count(),
            w.bodies().map(|(_, b)| {
                let q: UnitQuaternion<f64> = b.orientation();
                [q.w, q.i, q.j, q.k]
            }),
        )
    }

    /// (B, 3) body velocities.
    fn _body_velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let w = self.r();
        rows(py, w.body_count(), w.bodies().map(|(_, b)| b.velocity().into()))
    }

    /// (B, 3) body angular velocities.
    fn _body_angular_velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let w = self.r();
        rows(py, w.body_count(), w.bodies().map(|(_, b)| b.angular_velocity().into()))
    }

    /// The world's springs and joints as lines to draw: (kind, end a, end b), kind "spring" or the joint's type
    /// ("ball", "hinge", "slider", "piston", "spin-drive", "slide-drive", "weld", "distance", "rope"), each end ("particle", row, [0, 0, 0]), ("body", row,
    /// point in the body frame) or ("world", -1, world point); rows index the run and state arrays.
    fn _links(&self) -> PyResult<Vec<Link>> {
        let w = self.r();
        let end = |a: tumble::Attachment| -> PyResult<LinkEnd> {
            Ok(match a {
                tumble::Attachment::Particle(h) => {
                    ("particle", w.particle_row(h).map_err(world_error)? as i64, [0.0; 3])
                }
                tumble::Attachment::Body(h, p) => ("body", w.body_row(h).map_err(world_error)? as i64, [p.x, p.y, p.z]),
                tumble::Attachment::Point(p) => ("world", -1, [p.x, p.y, p.z]),
            })
        };
        let mut out = Vec::new();
        for (_, s) in w.springs() {
            out.push(("spring", end(s.a())?, end(s.b())?));
        }
        for (_, j) in w.joints() {
            let (pa, pb) = j.anchors();
            let side = |b: Option<tumble::BodyHandle>, p: nalgebra::Vector3<f64>| match b {
                Some(h) => end(tumble::Attachment::Body(h, p)),
                None => end(tumble::Attachment::Point(p)),
            };
            let kind = match j.kind() {
                tumble::JointKind::Ball => "ball",
                tumble::JointKind::Hinge => "hinge",
                tumble::JointKind::Slider => "slider",
                tumble::JointKind::Weld => "weld",
                tumble::JointKind::Piston => "piston",
                tumble::JointKind::Drive { linear: false } => "spin-drive",
                tumble::JointKind::Drive { linear: true } => "slide-drive",
                tumble::JointKind::Distance { rope: false, .. } => "distance",
                tumble::JointKind::Distance { rope: true, .. } => "rope",
            };
            out.push((kind, side(j.a(), pa)?, side(j.b(), pb)?));
        }
        Ok(out)
    }

    /// The joint of each of `_links`' links (None for a spring), in the same order.
    fn _link_joints(&self) -> Vec<Option<crate::handles::PyJointHandle>> {
        let w = self.r();
        w.springs().map(|_| None).chain(w.joints().map(|(h, _)| Some(h.into()))).collect()
    }

    /// Each body's colliders (empty where a body has none) as (shape, position, orientation w x y z) in its body
    /// frame, in array order.
    fn _body_shapes(&self, py: Python<'_>) -> PyResult<Vec<BodyShapes>> {
        self.r()
            .bodies()
            .map(|(_, b)| {
                b.colliders()
                    .iter()
                    .map(|c| {
                        let shape = Py::new(py, PyShape { shape: c.shape.clone() })?;
                        let (t, q) = (c.offset.translation.vector, c.offset.rotation);
                        Ok((shape, [t.x, t.y, t.z], [q.w, q.i, q.j, q.k]))
                    })
                    .collect()
            })
            .collect()
    }

    /// Kinetic energy.
    fn kinetic_energy(&self) -> f64 {
        self.r().kinetic_energy()
    }

    /// Potential energy of gravity, springs and the particles' restoring terms.
    fn potential_energy(&self) -> f64 {
        self.r().potential_energy()
    }

    /// Total linear momentum, (3,).
    fn momentum<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        array(py, self.r().momentum().as_slice().to_vec(), &[3])
    }

    /// Total angular momentum about the origin, (3,).
    fn angular_momentum<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        array(py, self.r().angular_momentum().as_slice().to_vec(), &[3])
    }

    /// The stages the world runs: {"stages": [...], "state_len": int, "method": str, "jacobian": str | None}.
    fn plan<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        plan_dict(py, self.r().plan())
    }

    /// Everything the world's steps have cost so far, as a dict (the package wraps it in `tumble.Report`).
    fn _report<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        report_dict(py, &self.r().report())
    }
}
