"""Joints from Python: a pendulum's period against the elliptic integral in both modes, a motor, bad joints by name,
the plan's joint stage and the report's joint fields."""

import math
import sys

import numpy as np
import pytest

import tumble

K_HALF = 1.854074677301372  # K(1/sqrt 2): the complete elliptic integral at k = sin(45 deg)


def period(w: tumble.World) -> float:
    bob = w.add_body(mass=1.0, inertia=np.eye(3) * 1e-3, position=(1.0, 0.0, 0.0))
    w.add_joint(tumble.Distance(None, bob, world_point=(0.0, 0.0, 0.0)))
    run = w.run(duration=4.0, frame_interval=1e-3)
    x = run.body_positions[:, 0, 0]
    k = np.nonzero((x[:-1] > 0) & (x[1:] <= 0))[0]
    t = run.times[k] + x[k] / (x[k] - x[k + 1]) * (run.times[k + 1] - run.times[k])
    return t[1] - t[0]


def test_a_pendulum_from_90_degrees_keeps_the_elliptic_period():
    exact = 4.0 * math.sqrt(1.0 / 9.81) * K_HALF
    # accurate mode, dopri5 at rtol 1e-10: the bound 1e-6 (measured 1e-10 from Rust)
    assert abs(period(tumble.World(rtol=1e-10, atol=1e-12)) - exact) < 1e-6 * exact
    # fast mode at dt 1/60, 8 substeps: measured 1.9e-5 relative; bound 1e-4
    assert abs(period(tumble.World(mode="fast", dt=1 / 60)) - exact) < 1e-4 * exact


def test_a_hinge_motor_holds_its_speed_and_the_report_counts_rows():
    w = tumble.World(mode="fast", dt=1 / 60, gravity=(0, 0, 0))
    door = w.add_body(tumble.Box(half_extents=(0.5, 0.025, 1.0)), mass=20.0, position=(0.5, 0, 1))
    h = w.add_joint(tumble.Hinge(None, door, anchor_b=(-0.5, 0, 0), world_point=(0, 0, 1), axis=(0, 0, 1),
                                 motor=tumble.Motor(speed=2.0, max_torque=50.0)))
    assert "joints" in w.plan()["stages"]
    w.step(1.0)
    # the motor row meets its target to the solve's rounding (measured 1e-12 rad/s)
    assert abs(w.bodies.angular_velocities[0, 2] - 2.0) < 1e-6
    assert w.report.joint_rows == 6  # three at the anchor, two across the axis, the motor
    # the velocity-level rows let the anchor drift by the centripetal term over a substep, w^2 r hs^2 = 4 * 0.5 /
    # 480^2 = 8.7e-6 m, pulled back each substep (measured 4.3e-6 m); bound 1e-4 m
    assert w.report.joint_error < 1e-4
    w.remove_joint(h)
    assert w.joint_count == 0
    assert "joints" not in w.plan()["stages"]


def test_bad_joints_raise_value_errors_naming_the_argument():
    w = tumble.World(mode="fast", dt=1 / 60)
    a = w.add_body(mass=1.0, inertia=np.eye(3))
    b = w.add_body(mass=1.0, inertia=np.eye(3), position=(1, 0, 0))
    for joint, name in [
        (tumble.Hinge(a, b, axis=(0, 0, 0)), "axis"),
        (tumble.Ball(a, a), "b"),
        (tumble.Hinge(a, b, limits=(1.0, -1.0)), "limits"),
        (tumble.Ball(a, b, anchor_a=(math.nan, 0, 0)), "anchor_a"),
        (tumble.Weld(a, b, anchor_b=(0, math.inf, 0)), "anchor_b"),
    ]:
        with pytest.raises(ValueError, match=name):
            w.add_joint(joint)
    with pytest.raises(ValueError, match="joint"):
        w.add_joint("hinge")
    assert w.joint_count == 0


def test_a_joint_the_mode_cannot_hold_is_refused_where_they_meet():
    # A softness is fast mode's: accurate mode (the default) refuses it when the joint is added, and a world holding
    # one refuses to turn accurate (the error names the mode); fast mode's exact solver has no joint rows. Found by
    # the fuzzer: the step used to refuse it, naming an argument the step does not have.
    w = tumble.World()
    a = w.add_body(mass=1.0, inertia=np.eye(3))
    b = w.add_body(mass=1.0, inertia=np.eye(3), position=(1, 0, 0))
    with pytest.raises(ValueError, match="`softness`"):
        w.add_joint(tumble.Hinge(a, b, softness=(30.0, 1.0)))
    assert w.joint_count == 0
    w.set_mode("fast", dt=1 / 240)
    w.add_joint(tumble.Hinge(a, b, softness=(30.0, 1.0)))
    for args in [("accurate",), ("fast",)]:
        kwargs = {"solver": "exact", "dt": 1 / 240} if args == ("fast",) else {}
        with pytest.raises(ValueError, match="`mode`"):
            w.set_mode(*args, **kwargs)
        assert w.mode == "fast"
    w.step(0.1)
    assert w.joint_count == 1
    # a saved fast world with a soft joint loads (its mode is set before its joints are added)
    assert tumble.World.from_json(w.to_json()).joint_count == 1


@pytest.mark.parametrize("name", ["pendulum", "chain", "newtons_cradle", "door", "ragdoll"])
def test_the_jointed_scenes_run_with_their_joints_held(name):
    w = getattr(tumble.scenes, name)()
    assert "joints" in w.plan()["stages"]
    assert "sleeping" not in w.plan()["stages"]  # jointed bodies do not sleep
    w.step(0.5)
    # measured: the pendulum 0 (projected), the chain 0, the cradle 1e-7, the door 1e-6, the ragdoll 3e-4 m through
    # its landing; 1e-3 m is far below anything a viewer would see
    assert w.report.joint_error < 1e-3
    assert w.report.joint_rows > 0



def test_accurate_mode_takes_limits_motors_and_ropes_as_the_docs_say():
    doc = " ".join(sys.modules[tumble.Hinge.__module__].__doc__.split())
    assert "no limits" not in doc and "limits, motors" in doc
    # a limit: a door thrown at 5 rad/s into its limit of 1 rad stops there
    w = tumble.World(gravity=(0, 0, 0), rtol=1e-8)
    door = w.add_body(tumble.Box(half_extents=(0.5, 0.025, 1.0)), mass=20.0, position=(0.5, 0, 1),
                      angular_velocity=(0, 0, 5.0))
    w.add_joint(tumble.Hinge(None, door, anchor_b=(-0.5, 0, 0), world_point=(0, 0, 1), axis=(0, 0, 1),
                             limits=(-1.0, 1.0)))
    run = w.run(2.0)
    angle = 2 * np.arctan2(run.body_orientations[:, 0, 3], run.body_orientations[:, 0, 0])
    assert angle.max() < 1.0 + 1e-2 and abs(angle[-1] - 1.0) < 1e-2
    # a motor: the door driven at 2 rad/s reaches that speed
    w = tumble.World(gravity=(0, 0, 0), rtol=1e-8)
    door = w.add_body(tumble.Box(half_extents=(0.5, 0.025, 1.0)), mass=20.0, position=(0.5, 0, 1))
    w.add_joint(tumble.Hinge(None, door, anchor_b=(-0.5, 0, 0), world_point=(0, 0, 1), axis=(0, 0, 1),
                             motor=tumble.Motor(speed=2.0, max_torque=50.0)))
    w.step(1.0)
    assert abs(w.bodies.angular_velocities[0, 2] - 2.0) < 1e-6
    # a rope: a ball 0.5 m beside its 1 m rope's end falls freely until it is taut, then hangs on it
    w = tumble.World(rtol=1e-8)
    bob = w.add_body(mass=1.0, inertia=np.eye(3) * 1e-3, position=(0.5, 0.0, 0.0))
    w.add_joint(tumble.Distance(None, bob, world_point=(0, 0, 0), length=1.0, rope=True))
    run = w.run(2.0, frame_interval=1e-2)
    reach = np.linalg.norm(run.body_positions[:, 0], axis=1)
    assert reach[5] < 0.99  # slack at first
    assert reach.max() < 1.0 + 1e-6 and abs(reach[-1] - 1.0) < 1e-6
    # softness is the one option accurate mode refuses, by name, as the docs say
    assert "softness" in doc
    with pytest.raises(ValueError, match="`softness`"):
        w.add_joint(tumble.Ball(None, bob, world_point=(0, 0, 0), softness=(5.0, 1.0)))


def test_a_pistons_turn_limits_stop_its_spin_and_bad_ones_name_the_argument():
    # a ball spun at 3 rad/s about a vertical piston with turn limits (-0.2, 0.5) comes to rest turned 0.5 rad
    # (accurate mode holds a reached limit at its tolerance: bound 1e-5 rad)
    w = tumble.World()
    ball = w.add_body(tumble.Sphere(radius=0.1), mass=1.0, angular_velocity=(0.0, 0.0, 3.0))
    w.add_joint(tumble.Piston(None, ball, axis=(0.0, 0.0, 1.0), turn_limits=(-0.2, 0.5)))
    w.step(1.0)
    wq, _, _, zq = w.bodies.orientations[0]
    assert abs(2.0 * np.arctan2(zq, wq) - 0.5) < 1e-5
    for bad in [(1.0, -1.0), (-4.0, 0.0), ("a", 1.0), 3.0]:
        with pytest.raises(ValueError, match="turn_limits"):
            w.add_joint(tumble.Piston(None, ball, axis=(0.0, 0.0, 1.0), turn_limits=bad))
