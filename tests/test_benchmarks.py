"""``python -m benchmarks --quick``: the CI smoke run of every benchmark section.

The sections' own logic is tested in ``tests/test_bench_*.py`` on tiny inputs; this runs
the whole quick report once, as CI runs it.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

from benchmarks.__main__ import SECTIONS, main

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module")
def quick_report(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("bench") / "benchmarks.md"
    assert main(["--quick", "--out", str(out)]) == 0
    return out


def test_quick_report_has_header_every_section_and_targets(quick_report):
    text = quick_report.read_text()
    assert "    python -m benchmarks --quick --out" in text  # the command that regenerates it
    assert "cores" in text and "highspy" in text  # machine and versions
    headings = [line for line in text.splitlines() if line.startswith("## ")]
    assert len(headings) == len(SECTIONS) + 1  # one per section, then the targets
    assert headings[-1] == "## Targets"


def test_quick_report_figures_and_tables_exist(quick_report):
    folder = quick_report.with_suffix("")
    for link in [line.split("](")[1].split(")")[0] for line in quick_report.read_text().splitlines() if "![" in line]:
        assert (quick_report.parent / link).is_file(), link
    tables = sorted(folder.glob("*.csv"))
    assert tables
    for table in tables:
        assert not pd.read_csv(table).empty, table.name


def test_unknown_section_is_one_line():
    done = subprocess.run(
        [sys.executable, "-m", "benchmarks", "--sections", "nope"], cwd=ROOT, capture_output=True, text=True
    )
    assert done.returncode == 2
    assert "unknown section 'nope'" in done.stderr
    assert "Traceback" not in done.stderr


def test_rerunning_one_section_keeps_the_others_with_their_provenance(quick_report):
    before = quick_report.read_text()
    assert main(["--quick", "--out", str(quick_report), "--sections", "maps_speed"]) == 0
    after = quick_report.read_text()
    headings = [line for line in after.splitlines() if line.startswith("## ")]
    assert headings == [line for line in before.splitlines() if line.startswith("## ")]
    # the sections not rerun say which command made them, and on what machine
    assert after.count("(machine: ") == len(SECTIONS) - 1
    assert "--sections maps_speed`." in after
