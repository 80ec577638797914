//! A soft constraint from physical units, after Catto's soft step (Box2D v3, "Solver2D", 2024): a stiffness in
//! hertz and a damping ratio become, for a (sub)step h, the rate at which a penetration is pushed out and how much of
//! a rigid constraint's impulse is applied. With omega = 2 pi hertz, a1 = 2 zeta + h omega and a2 = h omega a1, the
//! bias rate is omega / a1, the mass scale a2 / (1 + a2) and the impulse scale 1 / (1 + a2): the implicit (stable at
//! any h) discretisation of a spring and damper in the constraint's direction. Zero hertz is a rigid constraint.

use std::f64::consts::TAU;

/// The coefficients of one soft constraint for one substep.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Softness {
    /// Velocity asked per metre of penetration (1/s).
    pub bias_rate: f64,
    /// Fraction of the rigid impulse applied.
    pub mass_scale: f64,
    /// Fraction of the accumulated impulse taken back (the spring's relaxation).
    pub impulse_scale: f64,
}

impl Softness {
    /// A spring of `hertz` with damping ratio `zeta`, stepped by `h`.
    pub fn new(hertz: f64, zeta: f64, h: f64) -> Softness {
        if hertz <= 0.0 {
            return Softness { bias_rate: 0.0, mass_scale: 1.0, impulse_scale: 0.0 };
        }
        let omega = TAU * hertz;
        let a1 = 2.0 * zeta + h * omega;
        let a2 = h * omega * a1;
        let a3 = 1.0 / (1.0 + a2);
        Softness { bias_rate: omega / a1, mass_scale: a2 * a3, impulse_scale: a3 }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_soft_contact_is_the_implicit_step_of_a_damped_spring() {
        // One body of unit effective mass on a spring k = omega^2 with damping c = 2 zeta omega, at penetration s and
        // speed v: implicit Euler gives v' = (v - h (k s + c v) ... ) solved for v'. The soft update
        // v' = v - mass_scale (v + bias_rate s) (accumulated impulse 0) must equal it:
        // v' = (v - h k s) / (1 + h c + h^2 k) (implicit Euler on s' = v, v' = -k s - c v).
        let (hertz, zeta, h) = (30.0, 0.7, 1.0 / 240.0);
        let omega = TAU * hertz;
        let (k, c) = (omega * omega, 2.0 * zeta * omega);
        let soft = Softness::new(hertz, zeta, h);
        for (s, v) in [(-0.01, 0.0), (-0.002, -0.5), (0.0, 1.0)] {
            let implicit = (v - h * k * s) / (1.0 + h * c + h * h * k);
            let ours = v - soft.mass_scale * (v + soft.bias_rate * s);
            // the two are the same algebra: equal to rounding (1e-12 of the speeds involved)
            assert!((implicit - ours).abs() < 1e-12 * (1.0 + v.abs() + k * h * s.abs()), "{implicit} vs {ours}");
        }
        assert_eq!(Softness::new(0.0, 1.0, h), Softness { bias_rate: 0.0, mass_scale: 1.0, impulse_scale: 0.0 });
    }
}
