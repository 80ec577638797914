"""Without an optional extra, the feature that needs it says how to install it in the documentation's words: tumble is
installed from its clone, so the command is ``pip install "./python[EXTRA]"``, not a package index's name."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest

import tumble
from tumble.__main__ import main

ROOT = Path(__file__).resolve().parents[2]


def readme_command(extra: str) -> str:
    """The documentation's command for ``extra`` (checked against it when the repository is around: the README,
    the Python README and the pages under docs/ give it for the viewer, USD and Dask, in one form for every
    extra)."""
    command = f'pip install "./python[{extra}]"'
    pages = [ROOT / "README.md", ROOT / "python" / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
    if pages[0].exists():
        text = "\n".join(p.read_text() for p in pages if p.exists())
        assert 'pip install "./python[' in text
        assert command in text or extra not in ("viewer", "usd", "dask"), command
    return command


@pytest.fixture(scope="module")
def run() -> tumble.Run:
    return tumble.scenes.bouncing_ball().run(0.1)


def test_the_viewer_without_viser_says_the_readmes_command(run: tumble.Run, monkeypatch: pytest.MonkeyPatch,
                                                            tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.setitem(sys.modules, "viser", None)  # import viser raises ImportError
    hint = re.escape(readme_command("viewer"))
    with pytest.raises(ImportError, match=hint):
        run.show(port=0, block=False)
    with pytest.raises(ImportError, match=hint):
        run.export_viewer(tmp_path / "run.html")
    with pytest.raises(ImportError, match=hint):
        tumble.scenes.bouncing_ball().show(port=0, block=False)
    with pytest.raises(SystemExit):
        main(["--view", "--duration", "0.1", "--out", str(tmp_path)])
    assert readme_command("viewer") in capsys.readouterr().err


def test_the_help_of_view_says_the_readmes_command(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit):
        main(["--help"])
    assert readme_command("viewer") in " ".join(capsys.readouterr().out.split())


def test_usd_export_without_usd_core_says_the_readmes_command(run: tumble.Run, monkeypatch: pytest.MonkeyPatch,
                                                              tmp_path: Path) -> None:
    monkeypatch.setitem(sys.modules, "pxr", None)
    with pytest.raises(ImportError, match=re.escape(readme_command("usd"))):
        run.export_usd(tmp_path / "run.usda")


@pytest.mark.parametrize("backend, module", [("dask", "distributed"), ("ray", "ray")])
def test_a_sweep_without_its_backend_says_the_readmes_command(backend: str, module: str,
                                                              monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, module, None)
    with pytest.raises(ImportError, match=re.escape(readme_command(backend))):
        tumble.sweep(tumble.scenes.dominoes, [6], 0.1, backend=backend)


def test_no_hint_in_the_package_names_a_package_index() -> None:
    package = Path(tumble.__file__).parent
    stale = [f"{path.name}:{k + 1}" for path in sorted(package.glob("*.py*"))
             for k, line in enumerate(path.read_text().splitlines()) if "tumble[" in line]
    assert not stale, stale
