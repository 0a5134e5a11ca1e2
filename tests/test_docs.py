"""The documentation is self-contained and its links and API reference build.

- No tracked file points outside the repository (a sibling folder or an absolute path
  of the machine it was written on): a clone must hold everything a user needs.
- Every relative link of README.md and docs/*.md names a file of the repository.
- ``solve --help`` points to the formats in the repository.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

# Pieces joined at run time, so that this file does not contain what it looks for.
_OUTSIDE = [
    "../" + "shared",
    *("/" + top + "/" for top in ("work", "home", "tmp", "Users", "root")),
]
# Files that may name such paths, each for a reason (none today).
_ALLOWED: dict[str, str] = {}
# Developer notes kept outside the repository, by name: a reference to one sends the reader
# to a file a clone does not have (docs/format.md holds the formats).
_OUTSIDE_NOTES = tuple(name + ".md" for name in ("design", "formulations", "style", "paper"))
# Files that still name one, each for a reason (none today).
_NAMING_NOTES: dict[str, str] = {}


def _tracked() -> list[Path]:
    if shutil.which("git") is None or not (ROOT / ".git").exists():
        pytest.skip("not a git checkout: the tracked files are unknown")
    done = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True)
    return [ROOT / name for name in done.stdout.decode().split("\0") if name]


def _outside_pointers(text: str) -> list[str]:
    return [needle for needle in _OUTSIDE if needle in text]


def test_the_check_sees_outside_pointers():
    # what the next test must catch, and must not
    assert _outside_pointers("see " + "../" + "shared/design.md") == ["../" + "shared"]
    assert _outside_pointers("written to /" + "tmp/x.json") == ["/" + "tmp/"]
    assert _outside_pointers("cd /" + "work/main") == ["/" + "work/"]
    assert _outside_pointers("docs/format.md, instances/maps/cave.png, https://example.org/a") == []


def test_no_tracked_file_points_outside_the_repository():
    found = []
    for path in _tracked():
        relative = path.relative_to(ROOT).as_posix()
        if relative in _ALLOWED or not path.is_file():
            continue
        data = path.read_bytes()
        if b"\0" in data[:8192]:  # binary (images)
            continue
        for number, line in enumerate(data.decode("utf-8", "replace").splitlines(), start=1):
            for needle in _outside_pointers(line):
                found.append(f"{relative}:{number}: {needle}")
    assert not found, "files pointing outside the repository:\n" + "\n".join(found)


def test_no_tracked_file_names_notes_outside_the_repository():
    tracked = _tracked()
    names = {path.name for path in tracked}
    notes = [name for name in _OUTSIDE_NOTES if name not in names]
    found = []
    for path in tracked:
        relative = path.relative_to(ROOT).as_posix()
        if relative in _NAMING_NOTES or relative == "tests/test_docs.py" or path.suffix not in (".py", ".md", ".json"):
            continue
        text = path.read_text(encoding="utf-8", errors="replace")
        found += [f"{relative}: {name}" for name in notes if re.search(r"(?<![\w/.-])" + re.escape(name), text)]
    assert not found, "references to notes outside the repository:\n" + "\n".join(found)


LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")


def _doc_pages() -> list[Path]:
    return [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


@pytest.mark.parametrize("page", _doc_pages(), ids=lambda p: p.relative_to(ROOT).as_posix())
def test_relative_links_name_files_of_the_repository(page):
    broken = []
    for target in LINK.findall(page.read_text()):
        if re.match(r"[a-z]+:", target) or target.startswith("#"):
            continue  # a web address or an anchor on the same page
        path = (page.parent / target.split("#")[0]).resolve()
        if not path.exists():
            broken.append(target)
    assert not broken, f"{page.name}: links to missing files: {broken}"


def test_solve_help_points_to_the_format_in_the_repository():
    done = subprocess.run([sys.executable, "-m", "parcover", "solve", "--help"], cwd=ROOT,
                          capture_output=True, text=True)
    assert done.returncode == 0
    assert "docs/format.md" in done.stdout
    assert (ROOT / "docs" / "format.md").is_file()


# -- docs/algorithms.md: the counterexample table is what the files record ------------------

ALGORITHMS = ROOT / "docs" / "algorithms.md"
COUNTEREXAMPLES = ROOT / "instances" / "counterexamples"
ROW = re.compile(
    r"^\|[^|]*\|[^|]*\| `(?P<method>[\w-]+)` \| (?P<kpois>\d+) \| (?P<greedy>[^|]+) \| (?P<optimum>[^|]+) \| "
    r"\[[^\]]+\]\(\.\./instances/counterexamples/(?P<file>[\w.-]+\.json)\) \|$",
    re.M,
)


def _shown(answer: dict, objective: str) -> str:
    if objective == "robots":
        return f"{answer['robots']} robot{'s' if answer['robots'] != 1 else ''}"
    return f"makespan {answer['makespan']:.6g}"


def test_the_counterexample_table_matches_the_files():
    import json

    rows = list(ROW.finditer(ALGORITHMS.read_text()))
    assert sorted(m["file"] for m in rows) == sorted(p.name for p in COUNTEREXAMPLES.glob("*.json"))
    wrong = []
    for m in rows:
        data = json.loads((COUNTEREXAMPLES / m["file"]).read_text())
        q = data["question"]
        kpois = len([k for k in data["kpois"] if k != data["start"]])
        expected = (q["method"], str(kpois), _shown(q["greedy"], q["objective"]), _shown(q["optimum"], q["objective"]))
        shown = (m["method"], m["kpois"], m["greedy"].strip(), m["optimum"].strip())
        if shown != expected:
            wrong.append(f"{m['file']}: the page shows {shown}, the file records {expected}")
    assert not wrong, "\n".join(wrong)


# -- Python examples of the pages run --------------------------------------------------------

PYTHON = re.compile(r"```python\n(.*?)```", re.S)


def _pages_with_python() -> list[str]:
    """README.md and docs/*.md with Python examples (the tutorial has its own test)."""
    pages = [p for p in _doc_pages() if p.name != "tutorial.md" and PYTHON.search(p.read_text())]
    return [p.relative_to(ROOT).as_posix() for p in pages]


@pytest.mark.parametrize("page", _pages_with_python())
def test_python_examples_run(page):
    blocks = PYTHON.findall((ROOT / page).read_text())
    done = subprocess.run([sys.executable, "-c", "\n".join(blocks)], cwd=ROOT, capture_output=True, text=True)
    assert done.returncode == 0, f"{page}: {done.stderr.strip().splitlines()[-1:]}"


# -- the API reference builds -------------------------------------------------------------------


def test_the_api_reference_builds(tmp_path):
    pytest.importorskip("pdoc", reason="pdoc is in the 'test' extra: pip install -e '.[test]'")
    sys.path.insert(0, str(ROOT / "docs"))
    try:
        from build_api import modules
    finally:
        sys.path.pop(0)
    done = subprocess.run([sys.executable, str(ROOT / "docs" / "build_api.py"), str(tmp_path)],
                          cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr.strip()
    pages = {name: tmp_path / (name.replace(".", "/") + ".html") for name in modules()}
    missing = [name for name, page in pages.items() if not page.is_file()]
    assert not missing, f"no page for {missing}"
    assert "parcover.solve" in modules() and "milp.setpart" in modules()
    index = pages["parcover"].read_text()
    assert "Instance" in index and "solve" in index
    assert "Parameters" in pages["parcover.solve"].read_text()  # numpydoc sections rendered
