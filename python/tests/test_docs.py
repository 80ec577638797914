"""The first hour: the READMEs and the pages under docs/ point only to files a clone has, the README stays a short
front door, and the documentation speaks of the project as it is (no issue numbers, no team folders)."""

import os
import re
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
READMES = ["README.md", "python/README.md"]
# every page under docs/ (none when these tests run from an installed copy without the repository around them)
PAGES = sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "docs").glob("*.md"))
LINK = re.compile(r"\]\(([^)#\s]+)?(?:#([^)\s]*))?\)")
ISSUE = re.compile(r"\b[Ii]ssues?\s*#?\d+")


def read(name: str) -> str:
    path = ROOT / name
    if not path.exists():  # an installed copy of the tests without the repository around it
        pytest.skip("the repository's documentation is not next to these tests")
    return path.read_text()


def slug(heading: str) -> str:
    """GitHub's anchor for a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"[`*]|\[([^\]]*)\]\([^)]*\)", r"\1", heading.strip().lower())
    return re.sub(r"[^\w\- ]", "", text).replace(" ", "-")


def anchors(path: Path) -> set[str]:
    text = re.sub(r"```.*?```", "", path.read_text(), flags=re.S)  # no headings inside code blocks
    seen: dict[str, int] = {}
    out = set()
    for heading in re.findall(r"^#{1,6}\s+(.+?)\s*#*\s*$", text, flags=re.M):
        base = slug(heading)
        n = seen.get(base, 0)
        seen[base] = n + 1
        out.add(base if n == 0 else f"{base}-{n}")
    return out


def relative_links(text: str) -> list[tuple[str, str]]:
    """(target, anchor) of every link that is not to another site; target "" for a link within the page."""
    found = [(t or "", a or "") for t, a in LINK.findall(text)]
    return [(t, a) for t, a in found if "://" not in t and not t.startswith("mailto:")]


@pytest.mark.parametrize("name", READMES + PAGES)
def test_links_point_to_files_in_the_clone(name):
    path = ROOT / name
    text = read(name)
    links = relative_links(text)
    if name in READMES:
        assert links, "the README links to the repository's files"
    missing = [t for t, _ in links if t and not (path.parent / t).exists()]
    assert not missing, missing
    # an anchor into a page (or into this one) names one of its headings
    broken = []
    for target, anchor in links:
        page = (path.parent / target) if target else path
        if anchor and page.suffix == ".md" and anchor not in anchors(page):
            broken.append(f"{target}#{anchor}")
    assert not broken, broken
    # no pointers to the team's folders outside the repository
    assert "shared/" not in text


def test_the_readme_is_a_front_door_of_at_most_200_lines():
    lines = read("README.md").splitlines()
    assert len(lines) <= 200, f"README.md has {len(lines)} lines; the detail belongs in docs/"


def test_the_readme_opens_with_the_install_and_test_commands():
    text = read("README.md")
    block = re.search(r"```sh\n(.*?)```", text, flags=re.S)
    assert block and text.index(block.group(0)) < 200, "the README opens with a shell block"
    assert block.group(1).split("\n")[:2] == ["pip install ./python && python -m tumble", ".ci/run"]


@pytest.mark.parametrize("name", ["README.md"] + PAGES)
def test_the_docs_name_no_issues_and_no_team_folders(name):
    text = read(name)
    assert not ISSUE.findall(text), f"{name} names issues: {ISSUE.findall(text)}"
    assert "shared/" not in text, f"{name} points to a folder outside the repository"


def test_every_page_under_docs_is_checked():
    if not (ROOT / "docs").is_dir():
        pytest.skip("the repository's documentation is not next to these tests")
    assert {"docs/API.md", "docs/DESIGN.md"} <= set(PAGES)


# Output folders the programs write (ignored by git): a reference to a file in one names an output, not a source.
OUTPUTS = ("wp/", "out/", "tumble-out/", "DIR/")


def test_file_references_in_the_sources_name_files_of_the_clone():
    """A file named in backticks in a source, stub, manifest or page (`joint_forces.rs`,
    `benches/peers/compare.py`) is a file of the repository: by its path from the root or from the naming file's
    folder, or by its name alone; outputs the programs write are left out. Dead references (a file renamed or
    removed since) fail here."""
    if not (ROOT / ".git").exists():
        pytest.skip("not in a clone of the repository")
    tracked = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True).stdout
    files = tracked.split()
    names = {Path(f).name for f in files}
    paths = set(files)
    dead = []
    for f in files:
        if not f.endswith((".rs", ".py", ".pyi", ".md", ".toml")):
            continue
        text = (ROOT / f).read_text(errors="ignore")
        for ref in re.findall(r"`([\w./-]+\.(?:rs|py|pyi|md|toml))`", text):
            if ref.startswith(OUTPUTS) or ref in paths or Path(ref).name in names:
                continue
            if str(Path(os.path.normpath(Path(f).parent / ref))) in paths:
                continue
            dead.append((f, ref))
    assert not dead, dead


def test_the_top_level_holds_the_layout_and_nothing_stray():
    """The repository's top level is the workspace's layout (and its CI, docs and tool settings): debug output or a
    peer's log committed by mistake fails here."""
    if not (ROOT / ".git").exists():
        pytest.skip("not in a clone of the repository")
    tracked = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True).stdout
    top = {f.split("/")[0] for f in tracked.split()}
    layout = {"Cargo.toml", "Cargo.lock", "src", "crates", "python", "tests", "benches", "examples", "README.md"}
    settings = {"docs", ".ci", ".gitignore", "rustfmt.toml"}
    assert top - layout - settings == set(), top - layout - settings
