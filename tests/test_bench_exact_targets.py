"""The exact-targets section: its quick run and its target lines."""

from __future__ import annotations

import pandas as pd

from benchmarks import exact_targets
from benchmarks.common import Config


def test_quick_run_reports_every_cell_and_a_line_per_target(tmp_path):
    section = exact_targets.run(Config(quick=True, figures=tmp_path, figures_link="f", log=lambda line: None))
    frame = section.tables["exact_targets"]
    assert set(frame["model"]) == set(exact_targets.MODELS)
    assert len(frame) == len(exact_targets.QUICK) * 2 * len(exact_targets.MODELS)  # paths and tours
    assert len(section.targets) == len(exact_targets.QUICK)
    assert all(line.startswith("exact: ") for line in section.targets)


def test_a_target_is_met_only_when_every_cell_is_proven_in_time():
    rows = [dict(n=30, problem="makespan k=3", limit=60.0, seeds="unseen", seed=s, routes="paths",
                 model="exact", status=status, objective=1.0, bound=b, seconds=t)
            for s, status, b, t in ((11, "optimal", 1.0, 5.0), (12, "feasible", 0.9, 60.0))]
    line, = exact_targets._target_lines(pd.DataFrame(rows))
    assert "not met (1/2 cells)" in line and "seed 12: feasible" in line
    rows[1].update(status="optimal", bound=1.0, seconds=59.0)
    line, = exact_targets._target_lines(pd.DataFrame(rows))
    assert ": met:" in line
