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
