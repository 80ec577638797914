//! Joints: ball, hinge, slider, weld and distance joints between two rigid bodies, or a body and the world. A joint
//! is described by a `JointBuilder` (its kind, the two ends, anchors in each body's frame, the axis in A's frame,
//! and a hinge's or slider's limits, motor and spring) and added with `World::add_joint`, which checks it and fixes
//! its reference: the bodies' relative rotation when it is added is the joint's zero (a hinge's angle, a weld's
//! hold). A `None` end is the world: its anchor is then a world point.

use crate::handle::Handle;
use crate::spring::BodyHandle;
use nalgebra::{UnitQuaternion, Vector3};
pub use tumble_contact::{JointKind, JointMotor, JointSpring};

/// Handle of a joint.
pub type JointHandle = Handle<Joint>;

/// When a joint breaks: as soon as the force it carries (on B, N) or its torque about B's anchor (N m) exceeds its
/// bound; either may be infinite. With a `window` (s) the load judged is the one carried averaged over about that
/// long (each impulse weighted by e^(-age / window), over the window): an impact's impulse counts in full whatever
/// the step, so the joints that break converge as the step shrinks; without one (0) it is the load at the instant
/// (over fast mode's last substep), which grows without bound as the step shrinks during an impact. A broken joint
/// holds nothing from then on and its bodies collide again.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Breaking {
    pub force: f64,
    pub torque: f64,
    /// (Absent from files written before windows: 0.)
    #[serde(default)]
    pub window: f64,
}

/// Describes a joint to add: `JointBuilder::hinge(a, b, axis).anchor_a(..).anchor_b(..).limits(-1.0, 1.0)`.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct JointBuilder {
    pub(crate) kind: JointKind,
    #[serde(skip)]
    pub(crate) a: Option<BodyHandle>,
    #[serde(skip)]
    pub(crate) b: Option<BodyHandle>,
    /// Anchor on A (A's frame; a world point when A is the world), and on B.
    pub(crate) anchor_a: Vector3<f64>,
    pub(crate) anchor_b: Vector3<f64>,
    /// The axis in A's frame (world axes when A is the world).
    pub(crate) axis: Vector3<f64>,
    pub(crate) limits: Option<(f64, f64)>,
    /// A piston's limits on its turn about the axis (rad).
    #[serde(default)]
    pub(crate) turn_limits: Option<(f64, f64)>,
    pub(crate) motor: Option<JointMotor>,
    pub(crate) spring: Option<JointSpring>,
    /// A soft joint's stiffness (Hz) and damping ratio (fast mode); None: rigid.
    pub(crate) softness: Option<(f64, f64)>,
    /// When it breaks; None: never.
    #[serde(default)]
    pub(crate) breaking: Option<Breaking>,
    /// Whether its two bodies collide with each other (they do not by default).
    #[serde(default)]
    pub(crate) collide: bool,
    /// Whether it binds its bodies into one piece with every body bound to them by other such joints (a glued
    /// object's welds): none of them collide with each other while the joints hold.
    #[serde(default)]
    pub(crate) cluster: bool,
}

impl JointBuilder {
    fn new(kind: JointKind, a: Option<BodyHandle>, b: Option<BodyHandle>) -> Self {
        JointBuilder {
            kind,
            a,
            b,
            anchor_a: Vector3::zeros(),
            anchor_b: Vector3::zeros(),
            axis: Vector3::x(),
            limits: None,
            turn_limits: None,
            motor: None,
            spring: None,
            softness: None,
            breaking: None,
            collide: false,
            cluster: false,
        }
    }
    /// A ball (spherical) joint: the anchors coincide.
    pub fn ball(a: Option<BodyHandle>, b: Option<BodyHandle>) -> Self {
        Self::new(JointKind::Ball, a, b)
    }
    /// A hinge (revolute) joint about `axis` (A's frame).
    pub fn hinge(a: Option<BodyHandle>, b: Option<BodyHandle>, axis: Vector3<f64>) -> Self {
        Self { axis, ..Self::new(JointKind::Hinge, a, b) }
    }
    /// A slider (prismatic) joint along `axis` (A's frame).
    pub fn slider(a: Option<BodyHandle>, b: Option<BodyHandle>, axis: Vector3<f64>) -> Self {
        Self { axis, ..Self::new(JointKind::Slider, a, b) }
    }
    /// A piston (cylindrical) joint along `axis` (A's frame): the anchors may part along it and B turn about it;
    /// limits, a motor and a spring act on the travel, as a slider's.
    pub fn piston(a: Option<BodyHandle>, b: Option<BodyHandle>, axis: Vector3<f64>) -> Self {
        Self { axis, ..Self::new(JointKind::Piston, a, b) }
    }
    /// A drive about `axis` (A's frame): give it a `motor` (speed in rad/s, torque in N m) that drives B's spin
    /// about the axis relative to A; nothing else is held.
    pub fn spin_drive(a: Option<BodyHandle>, b: Option<BodyHandle>, axis: Vector3<f64>) -> Self {
        Self { axis, ..Self::new(JointKind::Drive { linear: false }, a, b) }
    }
    /// A drive along `axis` (A's frame): give it a `motor` (speed in m/s, force in N) that drives B's anchor along
    /// the axis relative to A's; nothing else is held.
    pub fn slide_drive(a: Option<BodyHandle>, b: Option<BodyHandle>, axis: Vector3<f64>) -> Self {
        Self { axis, ..Self::new(JointKind::Drive { linear: true }, a, b) }
    }
    /// A weld (fixed) joint: no relative motion.
    pub fn weld(a: Option<BodyHandle>, b: Option<BodyHandle>) -> Self {
        Self::new(JointKind::Weld, a, b)
    }
    /// A rigid rod between the anchors, of `length` (None: their distance when added).
    pub fn distance(a: Option<BodyHandle>, b: Option<BodyHandle>, length: Option<f64>) -> Self {
        Self::new(JointKind::Distance { length, rope: false }, a, b)
    }
    /// A rope between the anchors, at most `length` long (None: their distance when added).
    pub fn rope(a: Option<BodyHandle>, b: Option<BodyHandle>, length: Option<f64>) -> Self {
        Self::new(JointKind::Distance { length, rope: true }, a, b)
    }
    /// Anchor on A: in A's frame, or a world point when A is the world.
    pub fn anchor_a(mut self, p: Vector3<f64>) -> Self {
        self.anchor_a = p;
        self
    }
    /// Anchor on B: in B's frame, or a world point when B is the world.
    pub fn anchor_b(mut self, p: Vector3<f64>) -> Self {
        self.anchor_b = p;
        self
    }
    /// The axis (A's frame) of a hinge or slider.
    pub fn axis(mut self, axis: Vector3<f64>) -> Self {
        self.axis = axis;
        self
    }
    /// Lower and upper angle (hinge, rad, within (-pi, pi)) or travel (slider, m).
    pub fn limits(mut self, lower: f64, upper: f64) -> Self {
        self.limits = Some((lower, upper));
        self
    }
    /// A piston's lower and upper turn about its axis (rad, within (-pi, pi)); its `limits` bound its travel.
    pub fn turn_limits(mut self, lower: f64, upper: f64) -> Self {
        self.turn_limits = Some((lower, upper));
        self
    }
    /// A motor of target `speed` and at most `max_force` (N m for a hinge, N for a slider).
    pub fn motor(mut self, speed: f64, max_force: f64) -> Self {
        self.motor = Some(JointMotor { speed, max_force });
        self
    }
    /// A spring towards `target` (angle or travel).
    pub fn spring(mut self, stiffness: f64, damping: f64, target: f64) -> Self {
        self.spring = Some(JointSpring { stiffness, damping, target });
        self
    }
    /// Breaks the joint once the force it carries exceeds `max_force` (N) or its torque about B's anchor exceeds
    /// `max_torque` (N m), in either mode; either may be infinite (not both).
    pub fn breaking(mut self, max_force: f64, max_torque: f64) -> Self {
        self.breaking = Some(Breaking { force: max_force, torque: max_torque, window: 0.0 });
        self
    }
    /// As `breaking`, the load judged averaged over `window` seconds (`Breaking::window`), so that what breaks
    /// converges as the step shrinks (a window of 0 is `breaking`).
    pub fn breaking_averaged(mut self, max_force: f64, max_torque: f64, window: f64) -> Self {
        self.breaking = Some(Breaking { force: max_force, torque: max_torque, window });
        self
    }
    /// Binds the joint's bodies into one piece with every body bound to them by other such joints, as a glued
    /// object's welds do (`World::add_fractured`): no two bodies of a piece collide while its joints hold (pieces of
    /// an object that touch along an edge pushed at each other, and their welds carried it).
    pub fn cluster(mut self, on: bool) -> Self {
        self.cluster = on;
        self
    }
    /// Lets the joint's two bodies collide with each other (Bullet's and Blender's "disable collisions" off, USD's
    /// `collisionEnabled`); by default a joint's bodies do not touch.
    pub fn collide(mut self, collide: bool) -> Self {
        self.collide = collide;
        self
    }
    /// Softness in fast mode: stiffness (Hz) and damping ratio; rigid without.
    pub fn softness(mut self, hertz: f64, damping_ratio: f64) -> Self {
        self.softness = Some((hertz, damping_ratio));
        self
    }
}

/// A joint in a world: its description and the reference fixed when it was added.
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    pub(crate) spec: JointBuilder,
    /// Distance joints: the length in force.
    pub(crate) length: f64,
    /// The axis in B's frame, and B's rotation relative to A's when the joint was added (q_A^-1 q_B).
    pub(crate) axis_b: Vector3<f64>,
    pub(crate) reference: UnitQuaternion<f64>,
    /// Whether it has broken (it then holds nothing).
    pub(crate) broken: bool,
}

impl Joint {
    /// Body A (None: the world).
    pub fn a(&self) -> Option<BodyHandle> {
        self.spec.a
    }
    /// Body B (None: the world).
    pub fn b(&self) -> Option<BodyHandle> {
        self.spec.b
    }
    /// Its kind.
    pub fn kind(&self) -> JointKind {
        self.spec.kind
    }
    /// Its anchors: on A (A's frame, or a world point when A is the world) and on B (likewise).
    pub fn anchors(&self) -> (Vector3<f64>, Vector3<f64>) {
        (self.spec.anchor_a, self.spec.anchor_b)
    }
    /// When it breaks (None: never).
    pub fn breaking(&self) -> Option<Breaking> {
        self.spec.breaking
    }
    /// Whether it has broken (past its `breaking` bounds): it then holds nothing.
    pub fn is_broken(&self) -> bool {
        self.broken
    }
    /// The description it was added with.
    pub fn builder(&self) -> &JointBuilder {
        &self.spec
    }
}
