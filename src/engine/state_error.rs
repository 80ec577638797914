//! How far apart two states are, in metres: what step doubling compares (accurate mode's contact steps, fast
//! mode's opt-in error estimate).

use crate::engine::semi_implicit::Form;
use crate::model::layout::{get3, get_quat};
use crate::model::Model;

/// The largest difference between two states (of `form`) over the `involved` actors (all if `None`) in metres:
/// positions, each body's turn times its radius of gyration, and velocity differences times h.
pub(crate) fn state_difference(
    model: &Model,
    involved: Option<&[bool]>,
    (a, b): (&[f64], &[f64]),
    form: Form,
    h: f64,
) -> f64 {
    let l = model.layout;
    let involved = |k: usize| involved.is_none_or(|i| i[k]);
    let mut e = 0.0f64;
    for i in (0..l.particles).filter(|i| involved(*i)) {
        e = e.max((get3(a, l.px(i)) - get3(b, l.px(i))).amax());
        e = e.max(h * (get3(a, l.pv(i)) - get3(b, l.pv(i))).amax());
    }
    for (j, body) in model.bodies.iter().enumerate().filter(|(j, _)| involved(l.body_actor(*j))) {
        let r = (body.inertia.trace() / (2.0 * body.mass)).sqrt();
        e = e.max((get3(a, l.bx(j)) - get3(b, l.bx(j))).amax());
        // a velocity difference, or a momentum's over the mass (an angular one over the mass times the radius)
        let (dp, dl) = ((get3(a, l.bp(j)) - get3(b, l.bp(j))).amax(), (get3(a, l.bl(j)) - get3(b, l.bl(j))).amax());
        e = e.max(match form {
            Form::Momenta => h * dp / body.mass,
            Form::Velocities => h * dp,
        });
        let (qa, qb) = (get_quat(a, l.bq(j)), get_quat(b, l.bq(j)));
        let turn = (qa - qb).norm().min((qa + qb).norm());
        e = e.max(2.0 * turn * r);
        if r > 0.0 {
            e = e.max(match form {
                Form::Momenta => h * dl / (body.mass * r),
                Form::Velocities => h * dl * r,
            });
        }
    }
    e
}
