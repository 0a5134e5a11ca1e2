"""The building-scale sections (the grid, and unseen seeds and maps): their quick runs,
their target lines, and (slow) the real grid."""

from __future__ import annotations

import pandas as pd
import pytest

from benchmarks import building_scale, building_scale_makespan, building_scale_makespan_unseen, building_scale_unseen
from benchmarks.common import Config


def test_quick_run_reports_every_cell_and_a_line_per_question(tmp_path):
    section = building_scale.run(Config(quick=True, figures=tmp_path, figures_link="f", log=lambda line: None))
    frame = section.tables["building_scale"]
    quick = building_scale.QUICK
    robots = frame[frame["part"] == "robots"]
    assert len(robots) == len(quick["kinds"]) * len(quick["seeds"]) * len(building_scale.QUESTIONS)
    assert set(robots["kind"]) == set(quick["kinds"])
    assert (frame["status"] != "invalid").all()
    assert all(line.startswith("exact: building scale") for line in section.targets)
    assert "### Results" in section.markdown


def test_quick_unseen_run_reports_every_question_on_an_unseen_map(tmp_path):
    section = building_scale_unseen.run(Config(quick=True, figures=tmp_path, figures_link="f",
                                               log=lambda line: None))
    frame = section.tables["building_scale_unseen"]
    assert len(frame) == len(building_scale.QUESTIONS)
    assert set(frame["kind"]) == {"autolab"} and set(frame["seed"]) == {building_scale_unseen.SEED}
    assert (frame["status"] != "invalid").all()
    assert not {"autolab", "kwing"} & set(building_scale.KINDS)  # unseen by the grid


def test_quick_makespan_run_reports_every_cell_with_a_line_per_kind(tmp_path):
    section = building_scale_makespan.run(Config(quick=True, figures=tmp_path, figures_link="f",
                                                 log=lambda line: None))
    frame = section.tables["building_scale_makespan"]
    quick = building_scale_makespan.QUICK
    assert len(frame) == len(quick["cells"]) * len(quick["kinds"]) * len(quick["seeds"]) * 2  # paths, tours
    assert (frame["status"] != "invalid").all() and set(frame["question"]) == {"makespan k=3"}
    assert len(section.targets) == 2 and all("makespan k=3" in line for line in section.targets)


def test_quick_unseen_makespan_run_reports_every_cell_on_a_seed_the_grid_does_not_use(tmp_path):
    section = building_scale_makespan_unseen.run(Config(quick=True, figures=tmp_path, figures_link="f",
                                                        log=lambda line: None))
    frame = section.tables["building_scale_makespan_unseen"]
    assert len(frame) == 2 and set(frame["routes"]) == {"paths", "tours"}  # one cell, paths and tours
    assert set(frame["seed"]) == {building_scale_unseen.SEED}
    assert building_scale_unseen.SEED not in building_scale_makespan.SEEDS
    assert (frame["status"] != "invalid").all() and set(frame["kind"]) == {"clustered"}
    assert len(section.targets) == 2


def test_a_target_is_met_only_when_every_cell_is_proven_in_time():
    rows = [dict(part="robots", kind="clustered", n=100, seed=s, routes="tours", question="robots U=1 x least",
                 limit=120.0, status=status, objective=8.0, bound=b, seconds=t)
            for s, status, b, t in ((1, "optimal", 8.0, 50.0), (2, "feasible", 4.0, 120.0))]
    line, = building_scale.target_lines(pd.DataFrame(rows))
    assert "not met (1/2 cells)" in line and "seed 2: feasible 8 vs bound 4" in line
    rows[1].update(status="optimal", bound=8.0, seconds=100.0)
    line, = building_scale.target_lines(pd.DataFrame(rows))
    assert ": met:" in line


@pytest.mark.slow
def test_full_grid_runs(tmp_path):
    """The real section (73 minutes): every cell answered validly."""
    section = building_scale.run(Config(quick=False, figures=tmp_path, figures_link="f", log=print))
    assert (section.tables["building_scale"]["status"] != "invalid").all()
