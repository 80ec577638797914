//! Springs in the soft step: Hooke springs with dampers between body points (or a body point and a fixed one),
//! evaluated at the start of every substep where the substeps have moved the bodies, their impulses added before the
//! applied forces' (semi-implicit Euler at the substep, as each substep integrates its velocities).
//!
//! Why not as applied forces: a force evaluated once a step and spread over the n substeps moves a body by
//! (n + 1) / (2 n) of semi-implicit Euler's h^2 F / m. For a spring that is no longer symplectic: the step's matrix
//! has determinant 1 + (n - 1) / (2 n) h^2 k / m - h c / m, so an undamped spring gains energy at any step and a
//! damped one unless c > (n - 1) / (2 n) h k (the cloth drape, c = 0.05 N s/m against 0.055 at 1/480 s and 8
//! substeps, blew up after 1.6 s). Evaluated at every substep a spring is semi-implicit Euler at h / n: stable for
//! (h / n)^2 k / m < 4, energy kept, and contacts and friction see its force a substep at a time.

use super::row::Mover;
use crate::spring::SpringLaw;
use nalgebra::Vector3;

/// A spring of the soft step between a point of body `a` and one of body `b` (either may be a fixed body: a fixed
/// point is a static body there with zero arm), pulling as its law says.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SoftSpring {
    pub a: usize,
    pub b: usize,
    /// The points' arms from the bodies' centres of mass at the step's start (world axes).
    pub ra: Vector3<f64>,
    pub rb: Vector3<f64>,
    pub law: SpringLaw,
}

impl SoftSpring {
    /// Whether every number is finite and stiffness, damping and rest length are not negative.
    pub(crate) fn is_valid(&self) -> bool {
        [self.ra, self.rb].into_iter().flat_map(|v| [v.x, v.y, v.z]).all(f64::is_finite) && self.law.is_valid()
    }
}

/// A spring with its bodies' centres at the step's start and whether each end has an arm (a particle's or a
/// centre's has none: no turn to follow, no torque).
type Entry = (SoftSpring, Vector3<f64>, Vector3<f64>, [bool; 2]);
/// A body's force and torque over a substep.
type Wrench = (Vector3<f64>, Vector3<f64>);

/// An island's springs (their bodies by local index) and room for each body's force and torque of a substep.
pub(crate) struct SpringSet {
    springs: Vec<Entry>,
    wrenches: Vec<Wrench>,
}

impl SpringSet {
    /// No springs.
    pub fn empty() -> SpringSet {
        SpringSet { springs: Vec::new(), wrenches: Vec::new() }
    }

    /// `springs` with local body indices and their bodies' centres at the step's start.
    pub fn new(springs: impl IntoIterator<Item = (SoftSpring, Vector3<f64>, Vector3<f64>)>) -> SpringSet {
        let springs = springs
            .into_iter()
            .map(|(s, xa, xb)| (s, xa, xb, [s.ra != Vector3::zeros(), s.rb != Vector3::zeros()]))
            .collect();
        SpringSet { springs, wrenches: Vec::new() }
    }

    pub fn is_empty(&self) -> bool {
        self.springs.is_empty()
    }

    /// The springs' impulses over a substep of `hs`, from where the bodies are and how they move at its start: every
    /// force is computed before any is applied (a spring's damping reads velocities no other spring has changed
    /// yet). A body's turn comes from its inverse inertia at the step's start, as the contact rows' do.
    pub fn apply(&mut self, movers: &mut [Mover], hs: f64) {
        self.wrenches.clear();
        self.wrenches.resize(movers.len(), (Vector3::zeros(), Vector3::zeros()));
        for (s, xa, xb, [arm_a, arm_b]) in &self.springs {
            let (ma, mb) = (&movers[s.a], &movers[s.b]);
            // each end's point and velocity where the substeps have taken its body
            let end = |m: &Mover, x: &Vector3<f64>, r: &Vector3<f64>, arm: bool| {
                if arm {
                    let r = m.turn * r;
                    (x + m.dp + r, m.v + m.w.cross(&r), r)
                } else {
                    (x + m.dp, m.v, Vector3::zeros())
                }
            };
            let (pa, va, ra) = end(ma, xa, &s.ra, *arm_a);
            let (pb, vb, rb) = end(mb, xb, &s.rb, *arm_b);
            let Some(f) = s.law.force(&pa, &va, &pb, &vb) else { continue };
            let wa = &mut self.wrenches[s.a];
            wa.0 += f;
            if *arm_a {
                wa.1 += ra.cross(&f);
            }
            let wb = &mut self.wrenches[s.b];
            wb.0 -= f;
            if *arm_b {
                wb.1 -= rb.cross(&f);
            }
        }
        for (m, (f, torque)) in movers.iter_mut().zip(&self.wrenches) {
            if m.moves() {
                m.v += f * (m.inv_mass * hs);
                if *torque != Vector3::zeros() {
                    m.w += m.inv_inertia * (torque * hs);
                }
            }
        }
    }
}
