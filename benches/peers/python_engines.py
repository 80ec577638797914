"""The peer comparison's scenes in MuJoCo (issue 13; PyBullet's are in ``pybullet_scenes.py``), at its defaults, one
markdown row each: the same scene definitions as tumble's ``examples/fast_scenes.rs`` and ``benches/peers/rapier``
(z up, g = 9.81).

- pile: N cubes of half extent 0.5 m, density 1000, on a 10 x 10 grid at 1.2 m pitch in N / 100 layers 1.2 m apart,
  the lowest bottoms 2 m up, friction 0.5, dt 1/60, 600 steps, without and with sleeping (MuJoCo's ``sleep`` flag;
  ms a step over all of them, the steps alone timed; penetration the deepest contact over the last 100);
- stack: 10 cubes of half extent 0.25 m, density 500, friction 0.6, dt 1/240, 10 s, largest displacement;
- slide: a cube of half extent 0.2 m, density 500, at 2 m/s on a floor with mu 0.5, dt 1/240, 2 s, stop distance
  against v^2 / (2 mu g);
- rest: a cube of half extent 0.5 m, 10 s, largest displacement; bullet: a 5 cm sphere at 1000 m/s against a 1 cm
  static wall, dt 1/60.

Run: ``pip install -r benches/peers/requirements.txt`` then ``python3 benches/peers/python_engines.py 100 1000``.
Not part of CI.
"""

from __future__ import annotations

import sys
import time

import numpy as np

G = 9.81


def _model(dt: float, bodies: list[str], floor_mu: float, extra: str = "", sleep: bool = False):
    import mujoco

    flag = '<flag sleep="enable"/>' if sleep else ""
    # MuJoCo's default arena cannot hold a pile of 10,000 bodies and their contacts: scale it with the bodies.
    memory = f'<size memory="{max(64, len(bodies) // 10)}M"/>'
    xml = f"""<mujoco>
  {memory}
  <option timestep="{dt!r}" gravity="0 0 {-G}">{flag}</option>
  <worldbody>
    <geom type="plane" size="200 200 0.1" friction="{floor_mu} 0.005 0.0001"/>
    {extra}
    {''.join(bodies)}
  </worldbody>
</mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    return model, mujoco.MjData(model)


def _cube(name: str, half: float, density: float, at: tuple[float, float, float], mu: float) -> str:
    x, y, z = at
    return (f'<body name="{name}" pos="{x} {y} {z}"><freejoint/>'
            f'<geom type="box" size="{half} {half} {half}" density="{density}" friction="{mu} 0.005 0.0001"/></body>')


def _penetration(model, data, names: list[str], half: float) -> float:
    """The deepest overlap recomputed from the poses (``overlap.py``), as for every engine."""
    import mujoco

    from overlap import deepest

    ids = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, n) for n in names]
    return deepest([(np.full(3, half), data.xquat[i].copy(), data.xpos[i].copy()) for i in ids])


def pile(n: int, sleep: bool) -> tuple[float, float]:
    import mujoco

    bodies = []
    for k in range(n):
        layer, i, j = k // 100, (k % 100) // 10, k % 10
        bodies.append(_cube(f"c{k}", 0.5, 1000.0, (1.2 * i, 1.2 * j, 2.5 + 1.2 * layer), 0.5))
    model, data = _model(1 / 60, bodies, 0.5, sleep=sleep)
    worst, spent = 0.0, 0.0
    for step in range(600):
        clock = time.perf_counter()
        mujoco.mj_step(model, data)
        spent += time.perf_counter() - clock
        if step >= 500:
            worst = max(worst, _penetration(model, data, [f"c{k}" for k in range(n)], 0.5))
    return spent * 1e3 / 600, worst


def _displacement(model, data, names: list[str], steps: int) -> float:
    import mujoco

    ids = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, n) for n in names]
    mujoco.mj_forward(model, data)
    start = np.array([data.xpos[i].copy() for i in ids])
    worst = 0.0
    for _ in range(steps):
        mujoco.mj_step(model, data)
        worst = max(worst, float(np.max(np.linalg.norm(data.xpos[ids] - start, axis=1))))
    return worst


def _joint_model(dt: float, body: str):
    import mujoco

    xml = f"""<mujoco>
  <option timestep="{dt!r}" gravity="0 0 {-G}"/>
  <worldbody>{body}</worldbody>
</mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    return model, mujoco.MjData(model)


def _chain(horizontal: bool) -> str:
    """The joint scenes' chain as a kinematic tree: each link's frame at its top anchor, a ball joint there."""
    turn = ' quat="0.7071067811865476 0 -0.7071067811865476 0"' if horizontal else ""
    link = ('<body name="l{k}" pos="{pos}"{turn}><joint type="ball"/>'
            '<geom type="capsule" size="0.01 0.04" pos="0 0 -0.05" mass="1"/>')
    xml = "".join(link.format(k=k, pos="0 0 2.5" if k == 0 else "0 0 -0.1", turn=turn if k == 0 else "")
                  for k in range(20))
    xml += ('<body name="weight" pos="0 0 -0.1"><joint type="ball"/>'
            '<geom type="sphere" size="0.1" pos="0 0 -0.1" mass="10"/></body>')
    return xml + "</body>" * 20


def _stretch(model, data) -> float:
    """The sum of the joints' gaps: each child's frame origin against its parent's bottom anchor."""
    import mujoco

    ids = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, f"l{k}") for k in range(20)]
    ids.append(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "weight"))
    gaps = [np.linalg.norm(data.xpos[ids[0]] - np.array([0.0, 0.0, 2.5]))]
    for parent, child in zip(ids, ids[1:]):
        bottom = data.xpos[parent] + data.xmat[parent].reshape(3, 3) @ np.array([0.0, 0.0, -0.1])
        gaps.append(np.linalg.norm(data.xpos[child] - bottom))
    return float(sum(gaps))


def joints() -> None:
    """The joint scenes (``examples/joint_scenes.rs`` in tumble has their definitions): ball and hinge joints in
    MuJoCo's generalized coordinates, which cannot stretch by construction."""
    import mujoco

    print(f"| MuJoCo {mujoco.__version__} (defaults, joints in generalized coordinates) | value |\n|---|---|")
    dt = 1 / 60
    for horizontal, label in ((False, "chain hanging, dt 1/60: stretch after 5 s"),
                              (True, "chain from horizontal, dt 1/60: largest stretch in 5 s")):
        model, data = _joint_model(dt, _chain(horizontal))
        mujoco.mj_forward(model, data)
        spent, worst = 0.0, 0.0
        for _ in range(300):
            clock = time.perf_counter()
            mujoco.mj_step(model, data)
            spent += time.perf_counter() - clock
            mujoco.mj_kinematics(model, data)
            worst = max(worst, _stretch(model, data))
        value = worst if horizontal else _stretch(model, data)
        # MuJoCo resets a simulation whose accelerations blow up (and warns): say so rather than print the reset's 0
        resets = data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number
        shown = f"{value:.2e} m" if resets == 0 else f"unstable ({resets} resets)"
        print(f"| {label} / ms a step | {shown} / {spent * 1e3 / 300:.3f} ms |")
    r = 0.05
    model, data = _joint_model(dt, '<body name="bob"><joint type="hinge" axis="0 1 0"/>'
                                   f'<geom type="sphere" size="{r}" pos="1 0 0" mass="1"/></body>')
    spent, crossings, last = 0.0, [], (0.0, 1.0)
    for k in range(600):
        clock = time.perf_counter()
        mujoco.mj_step(model, data)
        spent += time.perf_counter() - clock
        t, x = (k + 1) * dt, float(data.geom_xpos[0][0])
        if last[1] > 0 and x <= 0:
            crossings.append(last[0] + last[1] / (last[1] - x) * (t - last[0]))
        last = (t, x)
    period = (crossings[-1] - crossings[0]) / (len(crossings) - 1)
    exact = 4 * np.sqrt((1 + 0.4 * r * r) / G) * 1.854074677301372
    print(f"| hinged pendulum from 90 deg, dt 1/60: period error / ms a step | {(period - exact) / exact:+.2e} / "
          f"{spent * 1e3 / 600:.4f} ms |")


def main() -> None:
    import mujoco

    if "joints" in sys.argv[1:]:
        joints()
        return
    sizes = [int(a) for a in sys.argv[1:]] or [100, 1000]
    print(f"| MuJoCo {mujoco.__version__} (defaults) | value |\n|---|---|")
    for n in sizes:
        for sleep, label in ((False, "no sleep"), (True, "sleeping")):
            ms, pen = pile(n, sleep)
            print(f"| pile {n}, {label}: ms a step / penetration (last 100 steps) | {ms:.3f} ms / {pen * 1e3:.3f} mm |")
    dt = 1 / 240
    stack = [_cube(f"s{k}", 0.25, 500.0, (0.0, 0.0, 0.25 + 0.5 * k), 0.6) for k in range(10)]
    model, data = _model(dt, stack, 0.6)
    moved = _displacement(model, data, [f"s{k}" for k in range(10)], 2400)
    print(f"| stack of 10: largest displacement in 10 s | {moved * 1e3:.3f} mm |")
    model, data = _model(dt, [_cube("slide", 0.2, 500.0, (0.0, 0.0, 0.2), 0.5)], 0.5)
    data.qvel[0] = 2.0
    for _ in range(480):
        mujoco.mj_step(model, data)
    exact = 4.0 / (2 * 0.5 * G)
    print(f"| slide: stop distance error | {(data.qpos[0] - exact) / exact * 100:+.3f}% |")
    model, data = _model(dt, [_cube("rest", 0.5, 1000.0, (0.0, 0.0, 0.5), 0.5)], 0.5)
    print(f"| rest: largest displacement in 10 s | {_displacement(model, data, ['rest'], 2400):.2e} m |")
    wall = '<geom type="box" pos="5 0 2" size="0.005 2 2"/>'
    ball = ('<body name="ball" pos="0 0 2"><freejoint/>'
            '<geom type="sphere" size="0.05" density="1000"/></body>')
    model, data = _model(1 / 60, [ball], 0.5, wall)
    data.qvel[0] = 1000.0
    for _ in range(30):
        mujoco.mj_step(model, data)
    x = data.qpos[0]
    print(f"| bullet: ball ends at x (wall at 5 m) | {x:.3f} m ({'held by the wall' if x < 5.0 else 'TUNNELLED'}) |")


if __name__ == "__main__":
    main()
