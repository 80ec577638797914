"""The command line (``python -m tumble``): its arguments checked with argparse's usage errors, never a traceback."""

import subprocess
import sys


def test_the_command_line_refuses_a_bad_duration_with_its_usage_message():
    # `python -m tumble --duration -1` said it with a traceback (issue 16); now argparse's usage error, exit code 2
    for bad in ["-1", "0", "nan", "inf", "abc"]:
        done = subprocess.run([sys.executable, "-m", "tumble", "--duration", bad, "--no-gif"], capture_output=True,
                              text=True, timeout=120)
        assert done.returncode == 2, (bad, done.stderr)
        assert "argument --duration" in done.stderr and "Traceback" not in done.stderr, done.stderr


def run_cli(*args, timeout=300):
    return subprocess.run([sys.executable, "-m", "tumble", *args], capture_output=True, text=True, timeout=timeout)


def test_the_help_is_whole_sentences_without_markup():
    done = run_cli("--help")
    assert done.returncode == 0
    text = done.stdout
    assert "``" not in text and ":class:" not in text
    # every option's help ends a sentence, and every scene is described
    for option in ["--scene", "--duration", "--fps", "--out", "--no-gif", "--view"]:
        assert option in text
    from tumble.__main__ import SCENES, parser

    for action in parser()._actions:
        if action.help:
            assert action.help[0].isupper() and action.help.rstrip().endswith("."), action.help
    listed = [line.split()[0] for line in text.split("scenes:\n")[1].splitlines() if line.strip()]
    assert listed == list(SCENES)


def test_bad_arguments_get_usage_errors(tmp_path):
    a_file = tmp_path / "a-file"
    a_file.write_text("")
    for args, named in [(["--fps", "0"], "--fps"), (["--fps", "many"], "--fps"), (["--scene", "nope"], "--scene"),
                        (["--out", str(a_file)], "--out")]:
        done = run_cli(*args, "--duration", "0.1")
        assert done.returncode == 2, (args, done.stderr)
        assert f"argument {named}" in done.stderr and "Traceback" not in done.stderr, done.stderr


def test_the_default_job_writes_what_it_says_and_times_it(tmp_path):
    done = run_cli("--duration", "0.5", "--out", str(tmp_path))
    assert done.returncode == 0, done.stderr
    for suffix in [".glb", ".gif", ".png", "-report.txt"]:
        path = tmp_path / f"dominoes{suffix}"
        assert path.stat().st_size > 0
        assert f"wrote   {path}" in done.stdout
    timing = [line for line in done.stdout.splitlines() if line.startswith("time ")]
    assert len(timing) == 1 and "run " in timing[0] and "preview " in timing[0] and "% of it" in timing[0]
    # progress went to standard error, which is a pipe here: plain lines, no carriage returns
    assert "\r" not in done.stderr
    assert "run 100% done after" in done.stderr
    # the default job (fast mode) never hears the slow-run line
    assert "accurate mode projects" not in done.stderr


def test_progress_in_a_log_is_occasional_plain_lines():
    import io

    from tumble._progress import Progress

    log = io.StringIO()
    shown = Progress("run", stream=log, terminal=False)
    for k in range(1001):
        shown(k / 1000)
    shown.close()
    lines = log.getvalue().splitlines()
    # a line at each quarter (the clock's ten-second rule never fires in this fast loop)
    assert [line.split()[1] for line in lines] == ["25%", "50%", "75%", "100%"]
    # each with the time left, projected from the time taken
    assert all(" left" in line for line in lines[:3]) and lines[-1].endswith("about 0 s left")
    # the default display (progress=None) puts nothing in a log
    quiet = io.StringIO()
    shown = Progress("run", stream=quiet, terminal=False, quiet_log=True)
    for k in range(1001):
        shown(k / 1000)
    assert quiet.getvalue() == ""
    assert "\r" not in log.getvalue()


def test_the_fracture_scenes_run_and_break(tmp_path):
    """The three scenes of glued pieces run from the command line and write their files; each breaks some of its
    welds and keeps others (the report's breaks, counted from the run)."""
    import tumble

    for name in ("vase-drop", "glass-pane", "wrecking-ball"):
        done = run_cli("--scene", name, "--duration", "0.5", "--out", str(tmp_path), "--no-gif")
        assert done.returncode == 0, done.stderr
        assert (tmp_path / f"{name}.glb").stat().st_size > 1000
    w = tumble.scenes.glass_pane()
    w.run(0.5)
    assert 0 < len(w.broken_joints()) < w.joint_count
