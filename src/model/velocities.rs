//! A state in velocity form, fast mode's own: the positions and orientations of y, with each body's velocity and
//! angular velocity where y has its momenta (particles' blocks are velocities in both). Fast mode steps it without
//! turning velocities into momenta and back; the world's state (momenta) is made from it when the world reads it
//! (`to_momenta`), and it is made from the world's when the world sets it (`to_velocities`).

use crate::model::layout::{get3, get_quat, set3};
use crate::model::{Kinematics, Model, Tally};
use nalgebra::UnitQuaternion;
use tumble_integrate::SystemError;

impl Model {
    /// The world's state (momenta) of a state in velocity form, into `out`: P = m v, L = I(q) w (a kinematic body's
    /// blocks are its velocities in both forms).
    pub(crate) fn to_momenta(&self, y: &[f64], out: &mut [f64]) {
        out.copy_from_slice(y);
        let l = self.layout;
        for (j, b) in self.bodies.iter().enumerate().filter(|(_, b)| b.kinematic.is_none()) {
            let q = UnitQuaternion::new_normalize(get_quat(y, l.bq(j)));
            set3(out, l.bp(j), &(get3(y, l.bp(j)) * b.mass));
            set3(out, l.bl(j), &(q * (b.inertia * q.inverse_transform_vector(&get3(y, l.bl(j))))));
        }
    }

    /// A state in velocity form of the world's state (momenta), into `out`: v = P / m, w = I(q)^-1 L.
    pub(crate) fn to_velocities(&self, y: &[f64], out: &mut [f64]) {
        out.copy_from_slice(y);
        let l = self.layout;
        for (j, b) in self.bodies.iter().enumerate().filter(|(_, b)| b.kinematic.is_none()) {
            let q = UnitQuaternion::new_normalize(get_quat(y, l.bq(j)));
            set3(out, l.bp(j), &(get3(y, l.bp(j)) * b.inv_mass));
            set3(out, l.bl(j), &(q * (b.inv_inertia * q.inverse_transform_vector(&get3(y, l.bl(j))))));
        }
    }

    /// The applied forces of a state in velocity form (`force_part`'s, into the p rates of `dy`; the q rates are
    /// left as they are), with the body kinematics read from it; returns those kinematics.
    pub(crate) fn velocity_forces(
        &self,
        tally: &mut Tally,
        t: f64,
        y: &[f64],
        dy: &mut [f64],
        springs: bool,
    ) -> Result<Kinematics, SystemError> {
        let l = self.layout;
        if l.bodies > 0 {
            tally.stages.mark(crate::plan::Stage::Rotation);
        }
        let kin = self.velocity_kinematics(y);
        let q = l.positions();
        self.force_part(tally, &kin, t, y, &mut dy[q..], springs)?;
        Ok(kin)
    }

    /// The kinetic energy of a state in velocity form: 1/2 m v^2 + 1/2 w . I(q) w (kinematic bodies carry none).
    pub(crate) fn velocity_kinetic_energy(&self, y: &[f64]) -> f64 {
        self.kinetic(y, |b, v, local| 0.5 * b.mass * v.norm_squared() + 0.5 * local.dot(&(b.inertia * local)))
    }
}
