//! The loads of a glued object's welds (`glued.rs`): given what the welds must give each piece over a step (a
//! wrench about its centre), the welds' impulses (each a force at its anchor and a torque) that do it with the least
//! elastic energy in the glue, the sum over welds of |f|^2 / k_f + |tau|^2 / k_t (each bond's stiffness to force
//! and torque, `WeldArm::of`). With B the map from the welds' impulses to the pieces' wrenches and D the
//! compliances, the impulses are x = D^-1 B^T mu with
//! B D^-1 B^T mu = w: a system over the pieces' six unknowns each, singular by the object's rigid motions (the
//! wrenches are first made to balance, which they do but for rounding and the turn over the step), solved by
//! conjugate gradients with a diagonal preconditioner from zero.

use super::glued_parts::{Compound, WeldArm};
use nalgebra::Vector3;
use tumble_contact::BodyState;

/// A wrench (or its multiplier) per piece: linear and angular parts.
type Wrench = (Vector3<f64>, Vector3<f64>);

/// Relative residual the conjugate gradients stop at (the loads are judged against bounds to a few digits).
const RESIDUAL: f64 = 1e-10;

/// The welds' impulses (force on B at the anchor, torque on B) giving each member of `compound` the wrench
/// `needed` (about its centre at the step's start), with the least elastic energy in the glue; zero where the
/// iteration finds
/// nothing (no welds, or wrenches of zero).
pub(super) fn least_loads(
    welds: &[WeldArm],
    compound: &Compound,
    states: &[BodyState],
    mut needed: Vec<Wrench>,
) -> Vec<Wrench> {
    let members = &compound.members;
    let centres: Vec<Vector3<f64>> = members.iter().map(|&a| states[a].position.coords).collect();
    balance(compound, states, &mut needed);
    let n = members.len();
    // B^T mu for weld k: the gradient of mu . B x over its force and torque, then weighted by D^-1
    let impulses = |mu: &[Wrench]| -> Vec<Wrench> {
        welds
            .iter()
            .map(|w| {
                let (ra, rb) = (w.point.coords - centres[w.a], w.point.coords - centres[w.b]);
                let g_f = mu[w.b].0 - mu[w.a].0 + mu[w.b].1.cross(&rb) - mu[w.a].1.cross(&ra);
                let g_t = mu[w.b].1 - mu[w.a].1;
                (g_f * w.stiffness.0, g_t * w.stiffness.1)
            })
            .collect()
    };
    // B x: each weld's force and torque on B, their opposites on A, as wrenches about the pieces' centres
    let wrenches = |x: &[Wrench]| -> Vec<Wrench> {
        let mut out = vec![(Vector3::zeros(), Vector3::zeros()); n];
        for (w, (f, t)) in welds.iter().zip(x) {
            let (ra, rb) = (w.point.coords - centres[w.a], w.point.coords - centres[w.b]);
            out[w.b].0 += f;
            out[w.b].1 += t + rb.cross(f);
            out[w.a].0 -= f;
            out[w.a].1 -= t + ra.cross(f);
        }
        out
    };
    // the diagonal of B D^-1 B^T, for the preconditioner
    let mut diagonal = vec![(Vector3::zeros(), Vector3::zeros()); n];
    for w in welds {
        let (f2, t2) = w.stiffness;
        for (i, r) in [(w.a, w.point.coords - centres[w.a]), (w.b, w.point.coords - centres[w.b])] {
            diagonal[i].0 += Vector3::repeat(f2);
            let turn = Vector3::new(r.y * r.y + r.z * r.z, r.x * r.x + r.z * r.z, r.x * r.x + r.y * r.y);
            diagonal[i].1 += turn * f2 + Vector3::repeat(t2);
        }
    }
    let precondition = |r: &[Wrench]| -> Vec<Wrench> {
        r.iter()
            .zip(&diagonal)
            .map(|((l, a), (dl, da))| {
                (
                    l.component_div(&dl.map(|d| d.max(f64::MIN_POSITIVE))),
                    a.component_div(&da.map(|d| d.max(f64::MIN_POSITIVE))),
                )
            })
            .collect()
    };
    let dot = |a: &[Wrench], b: &[Wrench]| a.iter().zip(b).map(|(x, y)| x.0.dot(&y.0) + x.1.dot(&y.1)).sum::<f64>();
    let axpy = |y: &mut [Wrench], s: f64, x: &[Wrench]| {
        for (a, b) in y.iter_mut().zip(x) {
            a.0 += b.0 * s;
            a.1 += b.1 * s;
        }
    };
    let scale = dot(&needed, &needed).sqrt();
    let mut mu = vec![(Vector3::zeros(), Vector3::zeros()); n];
    if scale == 0.0 || welds.is_empty() {
        return vec![(Vector3::zeros(), Vector3::zeros()); welds.len()];
    }
    let mut r = needed;
    let mut z = precondition(&r);
    let mut p = z.clone();
    let mut rz = dot(&r, &z);
    for _ in 0..12 * n + 50 {
        let ap = wrenches(&impulses(&p));
        let pap = dot(&p, &ap);
        if !(pap > 0.0) {
            break;
        }
        let alpha = rz / pap;
        axpy(&mut mu, alpha, &p);
        axpy(&mut r, -alpha, &ap);
        if dot(&r, &r).sqrt() <= RESIDUAL * scale {
            break;
        }
        z = precondition(&r);
        let next = dot(&r, &z);
        let beta = next / rz;
        rz = next;
        for (pi, zi) in p.iter_mut().zip(&z) {
            pi.0 = zi.0 + pi.0 * beta;
            pi.1 = zi.1 + pi.1 * beta;
        }
    }
    impulses(&mu)
}

/// Takes from each member's wrench its share of what the wrenches leave unbalanced (their sum, and their moment
/// about the compound's centre), shared as the momentum of a rigid motion is (by mass, and by inertia): welds only
/// pass load between the pieces.
fn balance(compound: &Compound, states: &[BodyState], needed: &mut [Wrench]) {
    let c = &compound.state;
    let centre = c.position;
    let (mut sum, mut moment) = (Vector3::zeros(), Vector3::zeros());
    for (&a, (l, t)) in compound.members.iter().zip(needed.iter()) {
        sum += l;
        moment += t + (states[a].position - centre).cross(l);
    }
    let (dv, dw) = (sum * c.inv_mass, c.inv_inertia * moment);
    for (&a, (l, t)) in compound.members.iter().zip(needed.iter_mut()) {
        let s = &states[a];
        let r = s.position - centre;
        *l -= (dv + dw.cross(&r)) / s.inv_mass;
        *t -= s.inertia * dw;
    }
}

#[cfg(test)]
mod tests {
    use super::least_loads;
    use crate::engine::fast::glued_parts::{Compound, WeldArm};
    use nalgebra::{Matrix3, Point3, Vector3};
    use tumble_contact::BodyState;

    /// Unit-mass pieces at `at`, their compound, and welds between consecutive pieces at their midpoints.
    fn pieces(at: &[Point3<f64>], loop_back: bool) -> (Vec<BodyState>, Compound, Vec<WeldArm>) {
        let states: Vec<BodyState> = at.iter().map(|&p| BodyState::rigid(1.0, Matrix3::identity() * 0.1, p)).collect();
        let centre = Point3::from(at.iter().map(|p| p.coords).sum::<Vector3<f64>>() / at.len() as f64);
        let inertia = states.iter().fold(Matrix3::zeros(), |s, b| {
            let r = b.position - centre;
            s + b.inertia + Matrix3::identity() * r.norm_squared() - r * r.transpose()
        });
        let state = BodyState::rigid(at.len() as f64, inertia, centre);
        let members: Vec<usize> = (0..at.len()).collect();
        let ends = at.len() - usize::from(!loop_back);
        let welds = (0..ends)
            .map(|k| {
                let (a, b) = (k, (k + 1) % at.len());
                let point = Point3::from((at[a].coords + at[b].coords) / 2.0);
                WeldArm { joint: k, a, b, point, stiffness: (1.0, 0.01) }
            })
            .collect();
        (states, Compound { members, welds: Vec::new(), state, window: 0.0 }, welds)
    }

    #[test]
    fn a_weld_between_two_pieces_carries_what_pulls_them_apart() {
        // pieces at x = -0.5 and 0.5 pulled apart by 3 N s each: the weld at the origin holds B back with -3 N s,
        // no torque (to rounding of the conjugate gradients' 1e-10)
        let (states, compound, welds) = pieces(&[Point3::new(-0.5, 0.0, 0.0), Point3::new(0.5, 0.0, 0.0)], false);
        let needed =
            vec![(Vector3::new(-3.0, 0.0, 0.0), Vector3::zeros()), (Vector3::new(3.0, 0.0, 0.0), Vector3::zeros())];
        let found = least_loads(&welds, &compound, &states, needed);
        assert!((found[0].0 - Vector3::new(3.0, 0.0, 0.0)).norm() < 1e-9 && found[0].1.norm() < 1e-9, "{found:?}");
    }

    #[test]
    fn a_loop_of_welds_gives_each_piece_what_it_needs() {
        // three pieces in a triangle, each welded to the next (a loop: the loads are not fixed by balance alone),
        // one piece pulled out and the others back: the welds' wrenches sum, on every piece, to what it needs
        let at = [Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 0.0, 0.0), Point3::new(0.5, 0.8, 0.0)];
        let (states, compound, welds) = pieces(&at, true);
        let mut needed = vec![
            (Vector3::new(-1.0, -0.5, 0.0), Vector3::zeros()),
            (Vector3::new(2.0, 0.0, 0.0), Vector3::zeros()),
            (Vector3::new(-1.0, 0.5, 0.0), Vector3::zeros()),
        ];
        // balanced: the forces sum to zero, and a torque on the first piece takes the forces' moment away
        let forces: Vector3<f64> =
            needed.iter().zip(&at).map(|((f, _), p)| (p - compound.state.position).cross(f)).sum();
        needed[0].1 = -forces;
        let found = least_loads(&welds, &compound, &states, needed.clone());
        let mut got = [(Vector3::zeros(), Vector3::zeros()); 3];
        for (w, (f, t)) in welds.iter().zip(&found) {
            let (ra, rb) = (w.point - at[w.a], w.point - at[w.b]);
            got[w.b].0 += f;
            got[w.b].1 += t + rb.cross(f);
            got[w.a].0 -= f;
            got[w.a].1 -= t + ra.cross(f);
        }
        let moment: Vector3<f64> =
            needed.iter().zip(&at).map(|((f, t), p)| t + (p - compound.state.position).cross(f)).sum();
        assert!(moment.norm() < 1e-12, "the test's wrenches balance");
        for ((g, n), k) in got.iter().zip(&needed).zip(0..) {
            assert!((g.0 - n.0).norm() < 1e-8 && (g.1 - n.1).norm() < 1e-8, "piece {k}: {g:?} against {n:?}");
        }
    }
}
