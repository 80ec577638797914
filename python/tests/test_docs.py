"""The first hour: the READMEs point only to files a clone has."""

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("readme", ["README.md", "python/README.md"])
def test_readme_links_point_to_files_in_the_clone(readme):
    path = ROOT / readme
    if not path.exists():  # an installed copy of the tests without the repository around it
        pytest.skip("the repository's READMEs are not next to these tests")
    text = path.read_text()
    links = [m for m in re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", text) if "://" not in m]
    assert links, "the README links to the repository's files"
    missing = [m for m in links if not (path.parent / m).exists()]
    assert not missing, missing
    # no pointers to the team's folders outside the repository
    assert "shared/" not in text
