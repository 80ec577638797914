//! A glued object's parts as its solve and its load solve share them: the object as one body (`Compound`) and each
//! weld's place and stiffness (`WeldArm`).

use crate::model::Model;
use crate::model::ResolvedBody;
use nalgebra::Point3;
use tumble_contact::BodyState;

/// One glued object solved as a body.
pub(super) struct Compound {
    /// Its pieces (actor indices, in order) and the welds that bind them (joint indices, in order).
    pub members: Vec<usize>,
    pub welds: Vec<usize>,
    /// The compound body at the step's start.
    pub state: BodyState,
    /// The break window its breakable welds share (0: judged at the instant, or none breaks).
    pub window: f64,
}

/// A weld as the load solve sees it: its joint, its pieces (by place among the members), where its anchor is
/// (world, at the step's start) and its stiffness to force and to torque (`WeldArm::of`).
pub(super) struct WeldArm {
    pub joint: usize,
    pub a: usize,
    pub b: usize,
    pub point: Point3<f64>,
    pub stiffness: (f64, f64),
}

impl WeldArm {
    pub fn of(model: &Model, y: &[f64], k: usize, members: &[usize]) -> WeldArm {
        let j = &model.joints[k];
        let (ea, eb) = (model.end_state_of(y, j.a), model.end_state_of(y, j.b));
        let place = |end: ResolvedBody| {
            members.binary_search(&end.actor(model.layout).expect("a weld between bodies")).expect("a member")
        };
        // a glued face of area A and radius r = sqrt(A / pi) holds a force sigma A and a torque sigma A r / 4; as a
        // layer of glue it is as stiff to a force as its area and to a torque as its area's second moment, A r^2 / 4
        // (up to a common factor): from the bounds, F and 4 T^2 / F. A weld without bounds: 1 and 1.
        let stiffness = j
            .breaking
            .filter(|b| b.force > 0.0 && b.torque > 0.0)
            .map_or((1.0, 1.0), |b| (b.force, 4.0 * b.torque * b.torque / b.force));
        let point = Point3::from(eb.x + model.anchor_b(k, &(ea, eb)));
        WeldArm { joint: k, a: place(j.a), b: place(j.b), point, stiffness }
    }
}
