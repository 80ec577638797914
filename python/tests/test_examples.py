"""The Python examples (python/examples/) run from a fresh checkout, write their outputs, and the bouncing ball's
impact times match the closed form."""

import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def run_example(name, tmp_path, *extra):
    out = subprocess.run(
        [sys.executable, str(EXAMPLES / f"{name}.py"), "--out", str(tmp_path), "--no-gif", *extra],
        capture_output=True,
        text=True,
        cwd=EXAMPLES,
        timeout=300,
    )
    assert out.returncode == 0, out.stderr
    return out.stdout


def test_bouncing_ball_impacts_match_the_closed_form(tmp_path):
    stdout = run_example("bouncing_ball", tmp_path, "--duration", "3")
    rows = [line.split() for line in stdout.splitlines() if line.strip()[:1].isdigit() and len(line.split()) == 4]
    impacts, apexes = rows[:5], rows[5:]
    assert len(impacts) == 5 and len(apexes) == 4, stdout
    # The apexes are read off frames every 1/240 s: each within g (1/480)^2 / 2 = 2.1e-5 m below e^(2n) H.
    for n, (_, z, exact, _) in enumerate(apexes, start=1):
        assert abs(float(exact) - 0.8 ** (2 * n)) < 1e-12
        assert -2.2e-5 <= float(z) - float(exact) <= 1e-9, apexes
    rows = impacts
    # Each error is within n (1 + 1/e) 1e-10 s of the closed form (the bisection tolerance carried over n bounces).
    for n, (_, t, exact, err) in enumerate(rows, start=1):
        assert abs(float(t) - float(exact)) <= n * (1 + 1 / 0.8) * 1e-10 + 1e-12, rows
    assert (tmp_path / "bouncing-ball.glb").stat().st_size > 0 and (tmp_path / "bouncing-ball.png").exists()


def test_the_pyramid_says_when_it_fell_asleep(tmp_path):
    stdout = run_example("pyramid", tmp_path, "--duration", "2", "--layers", "4")
    line = stdout.strip().splitlines()[-1]
    assert line.startswith("10 cubes;") and "all asleep from t = " in line, line


def test_example_arguments_are_checked(tmp_path):
    for bad in (["--duration", "-1"], ["--count", "0"], ["--count", "x"]):
        done = subprocess.run([sys.executable, str(EXAMPLES / "dominoes.py"), *bad, "--out", str(tmp_path)],
                              capture_output=True, text=True, cwd=EXAMPLES, timeout=120)
        assert done.returncode == 2 and "Traceback" not in done.stderr, done.stderr


@pytest.mark.parametrize("name", ["tumbling_box", "dominoes", "pyramid", "cloth_drape"])
def test_fast_mode_examples_run_and_write_their_outputs(name, tmp_path):
    run_example(name, tmp_path, "--duration", "0.25")
    stem = name.replace("_", "-")
    assert (tmp_path / f"{stem}.glb").stat().st_size > 1000
    assert (tmp_path / f"{stem}.png").exists()


def test_the_ball_stays_in_the_cup_and_not_on_its_hull(tmp_path):
    stdout = run_example("ball_in_cup", tmp_path, "--duration", "2")
    assert "decomposed: the ball ends at" in stdout and "in the cup" in stdout.split("decomposed:")[1].split("\n")[0]
    assert "out of it" in stdout.split("hull:")[1].split("\n")[0], stdout
    assert (tmp_path / "cup.obj").exists() and (tmp_path / "ball-in-cup.glb").stat().st_size > 1000
