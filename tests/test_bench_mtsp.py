"""The min-max mTSP literature section (benchmarks/mtsp_literature.py) on tiny budgets."""

from __future__ import annotations

import math

import pytest

from benchmarks import mtsp_literature as section
from benchmarks.common import ROOT
from parcover.io import read_instance, read_json
from parcover.verify import verify


def test_reference_values_hold_the_published_cplex_bounds():
    table = section.reference_values().set_index(["instance", "m"])
    # Necula et al.'s table (data README): eil51 m=2 222.73 / 222.73, rat99 m=7 210.41 / 443.91.
    assert table.loc[("eil51", 2), "cplex_lb"] == pytest.approx(222.73)
    assert table.loc[("rat99", 7), "cplex_ub"] == pytest.approx(443.9142)
    assert table.loc[("berlin52", 5), "best_known"] == pytest.approx(2440.922)
    for name in section.INSTANCES:
        for m in section.ROBOTS:
            assert not math.isnan(table.loc[(name, m), "cplex_lb"])


def test_cell_eil51_seven_tours_is_proven_at_twice_c_max(tmp_path):
    # eil51, m = 7: the best known 112.0714 equals 2 c_max (data README), so a value at
    # 2 c_max is optimal; node 1 = (37, 52) is the start, the farthest node is 56.04 away.
    row = section.solve_cell("eil51", 7, best_seconds=1.0, exact_seconds=2.0, bound_seconds=2.0,
                             tours_dir=tmp_path)
    instance = read_instance(ROOT / "instances" / "tsplib" / "eil51.tsp")
    verdict = verify(instance, read_json(tmp_path / "eil51-m7.json"))
    assert verdict.robots <= 7 and verdict.makespan == pytest.approx(row["value"])
    assert row["kpois"] == 50
    assert row["2 c_max"] == pytest.approx(112.0714, abs=1e-4)
    assert row["bound"] <= row["value"] * (1 + 1e-9)
    if row["value"] <= row["2 c_max"] * (1 + 1e-6):
        assert row["proven"]


def test_cell_with_column_generation_bound_is_below_the_best_known():
    # eil51, m = 5: best known 118.1338 > 2 c_max, so the colgen bound runs; it must
    # stay below every known solution's value.
    row = section.solve_cell("eil51", 5, best_seconds=0.5, exact_seconds=1.0, bound_seconds=2.0)
    assert not math.isnan(row["colgen bound"])
    assert row["2 c_max"] - 1e-9 <= row["bound"] <= 118.1338
    assert row["bound"] <= row["value"]


def test_table_comparisons_and_targets():
    rows = [
        {"instance": "eil51", "m": 2, "value": 222.7334, "bound": 222.74, "proven": True},
        {"instance": "eil51", "m": 3, "value": 161.0, "bound": 150.0, "proven": False},
    ]
    frame = section.cells_table(rows)
    # CPLEX lower bounds 222.73 and 150.70: the first is beaten, the second not.
    assert list(frame["bound >= CPLEX"]) == [True, False]
    # 161 / 159.5715 - 1 = 0.8955 %.
    assert frame["value vs best %"].iloc[1] == pytest.approx(100 * (161.0 / 159.5715 - 1))
    lines = section.targets(frame, 16)
    assert "1/16" in lines[0] and "not met" in lines[0]
    assert "1/16" in lines[1]
    assert lines[2].endswith("1 (only 2 cell(s) run: quick mode)")
