"""Static typing: ``mypy --strict -p tumble`` passes on the installed package (its ``.py`` files, the compiled
module's stub ``_tumble.pyi`` and ``py.typed``, as users get them), the stub matches the compiled module (``stubtest``), and a misspelt integrator or
mode name is a type error. The command runs from a temporary directory so that mypy finds the installed ``tumble`` (from the source
directory ``python/`` it would check the source tree instead), with the settings of ``python/pyproject.toml``
(``[tool.mypy]``: the optional modules without type information)."""

from __future__ import annotations

import ast
import importlib.util
import re
import subprocess
import sys
import typing
from pathlib import Path

import pytest

import tumble

requires_mypy = pytest.mark.skipif(importlib.util.find_spec("mypy") is None, reason="mypy is not installed")

CONFIG = Path(__file__).resolve().parents[1] / "pyproject.toml"


@pytest.fixture(scope="module")
def mypy(tmp_path_factory: pytest.TempPathFactory):
    """Runs ``python -m mypy --strict --config-file python/pyproject.toml ARGS`` in a temporary directory (one cache
    for the module's runs); returns (return code, output)."""
    cwd = tmp_path_factory.mktemp("mypy")

    def run(*args: str) -> tuple[int, str]:
        command = [sys.executable, "-m", "mypy", "--strict", "--config-file", str(CONFIG),
                   "--cache-dir", str(cwd / ".mypy_cache"), *args]
        done = subprocess.run(command, cwd=cwd, capture_output=True, text=True, timeout=600)
        return done.returncode, f"$ {' '.join(command)}\n{done.stdout}{done.stderr}"

    return run


@requires_mypy
def test_package_passes_mypy_strict(mypy) -> None:
    code, output = mypy("-p", "tumble")
    assert code == 0, f"mypy --strict on the installed tumble ({Path(tumble.__file__).parent}) failed:\n{output}"


@requires_mypy
def test_the_compiled_module_matches_its_stub(tmp_path: Path) -> None:
    """``stubtest`` compares ``_tumble.pyi`` with the installed compiled module: every class, method, parameter and
    default the stub names is there, and the module has nothing the stub leaves out (but what
    ``tests/stubtest_allowlist.txt`` lists, with its reason; PEP 800's disjoint bases are not checked: pyo3's classes
    all are)."""
    allowlist = Path(__file__).resolve().parent / "stubtest_allowlist.txt"
    command = [sys.executable, "-m", "mypy.stubtest", "--mypy-config-file", str(CONFIG), "--ignore-disjoint-bases",
               "--allowlist", str(allowlist), "tumble._tumble"]
    done = subprocess.run(command, cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, f"$ {' '.join(command)}\n{done.stdout}{done.stderr}"


def _error_lines(output: str, name: str) -> set[int]:
    return {int(m.group(1)) for m in re.finditer(rf"^.*{re.escape(name)}:(\d+): error:", output, re.MULTILINE)}


@requires_mypy
def test_misspelt_names_are_type_errors(mypy, tmp_path: Path) -> None:
    good = tmp_path / "good_names.py"
    good.write_text(
        "import tumble\n"
        "w = tumble.World(integrator='dopri5', mode='accurate', linear_solver='direct')\n"
        "w.set_integrator('rk4')\n"
        "w.set_integrator('implicit-euler', linear_solver='iterative')\n"
        "w.set_mode('fast', solver='soft')\n"
        "w.set_mode('fast', solver='exact')\n"
        "method: tumble.IntegratorName = 'radau5'\n"
        "w.set_integrator(method)\n"
        "mode: tumble.ModeName = w.mode\n"
        "w.set_mode(mode)\n"
        "solver: tumble.SolverName = 'soft'\n"
        "linear: tumble.LinearSolverName = 'iterative'\n"
        "tumble.World(mode='fast', solver=solver)\n"
        "tumble.World(integrator='implicit-euler', linear_solver=linear)\n"
    )
    bad = tmp_path / "bad_names.py"
    bad_lines = [
        "tumble.World().set_integrator('rk5')",
        "tumble.World().set_mode('fsat')",
        "tumble.World(integrator='dopri')",
        "tumble.World(mode='Fast')",
        "tumble.World(mode='fast', solver='soft-step')",
        "tumble.World().set_integrator('implicit-euler', linear_solver='bicgstab')",
        "name: tumble.IntegratorName = 'Euler'",
    ]
    bad.write_text("import tumble\n" + "".join(line + "\n" for line in bad_lines))

    code, output = mypy(str(good))
    assert code == 0, f"correctly spelt names were rejected:\n{output}"
    code, output = mypy(str(bad))
    assert code == 1, f"mypy did not fail on misspelt names:\n{output}"
    assert _error_lines(output, bad.name) == set(range(2, 2 + len(bad_lines))), (
        f"mypy should report exactly one error on each misspelt name (lines 2-{1 + len(bad_lines)}):\n{output}"
    )
    assert "rk5" in output and "fsat" in output


def test_the_stub_takes_its_names_from_the_one_list() -> None:
    """The compiled module's stub imports the Literal names from ``tumble._names`` (one list, not two)."""
    stub = Path(tumble.__file__).parent / "_tumble.pyi"
    imported = {alias.name for node in ast.parse(stub.read_text()).body
                if isinstance(node, ast.ImportFrom) and node.module == "tumble._names" for alias in node.names}
    assert imported == {"IntegratorName", "ModeName", "SolverName", "LinearSolverName", "CombineName"}
    assert all(typing.get_args(getattr(tumble, n)) for n in imported)


def test_literal_names_are_the_accepted_names() -> None:
    """Each alias lists exactly the names the compiled module accepts (its errors list them, in this order)."""
    integrators = typing.get_args(tumble.IntegratorName)
    for method in integrators:
        tumble.World(integrator=method)
    with pytest.raises(ValueError, match="expected one of " + re.escape(", ".join(integrators)) + "$"):
        tumble.World(integrator="rk5")

    assert typing.get_args(tumble.ModeName) == ("accurate", "fast")
    for mode in typing.get_args(tumble.ModeName):
        assert tumble.World(mode=mode).mode == mode
    with pytest.raises(ValueError, match='expected "accurate" or "fast"'):
        tumble.World(mode="fsat")

    assert typing.get_args(tumble.SolverName) == ("soft", "exact", "newton", "clarabel")
    for solver in ("soft", "exact"):
        tumble.World(mode="fast", solver=solver)
    for solver in ("newton", "clarabel"):
        tumble.World(solver=solver)
    with pytest.raises(ValueError, match='expected "soft" or "exact"'):
        tumble.World(mode="fast", solver="soft-step")
    with pytest.raises(ValueError, match='"newton" or "clarabel"'):
        tumble.World(solver="soft-step")

    assert typing.get_args(tumble.LinearSolverName) == ("direct", "iterative")
    for linear in typing.get_args(tumble.LinearSolverName):
        tumble.World(integrator="implicit-euler", linear_solver=linear)
    with pytest.raises(ValueError, match='expected "direct" or "iterative"'):
        tumble.World(integrator="implicit-euler", linear_solver="bicgstab")

    combines = typing.get_args(tumble.CombineName)
    for rule in combines:
        assert tumble.World(friction_combine=rule).combine_rules["friction"] == rule
    with pytest.raises(ValueError, match="must be one of " + re.escape(", ".join(combines)) + ", got"):
        tumble.World(friction_combine="mean")
