"""The Section VI rerun (benchmarks/section6.py): its quick run and its helpers.

The quick run (2 starts per map, 3 s exact limits, about 20-30 s) is made once per
module into a temporary folder; the tests check the report, the CSVs and the
consistency of the numbers (the exact optimum never above a heuristic with the
same robots, Algorithm 1 at ``c_max``, ratios recomputed).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from benchmarks import section6
from parcover import Instance, solve
from parcover.io import read_instance

TOL = 1e-9


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The report of ``python -m benchmarks.section6 --quick --out <tmp>/s6.md``."""
    out = tmp_path_factory.mktemp("section6") / "s6.md"
    assert section6.main(["--quick", "--out", str(out)]) == 0
    return out


@pytest.fixture(scope="module")
def paths(quick_run: Path) -> pd.DataFrame:
    return pd.read_csv(quick_run.with_suffix("") / "paths.csv")


@pytest.fixture(scope="module")
def tours(quick_run: Path) -> pd.DataFrame:
    return pd.read_csv(quick_run.with_suffix("") / "tours.csv")


def test_report_names_its_command_machine_and_figures(quick_run: Path) -> None:
    text = quick_run.read_text(encoding="utf-8")
    assert f"python -m benchmarks.section6 --quick --out {quick_run}" in text
    assert "- machine: " in text and "3 s per path solve" in text
    assert "KPOIs are not published" in text
    folder = quick_run.with_suffix("")
    for name in ("fig6.png", "fig5_office-start6.png", "fig5_rooms-start20.png",
                 "fig7ab_office-start6.png", "fig7cd_office-start6.png"):
        assert (folder / name).stat().st_size > 10_000, name
        assert f"{folder.name}/{name}" in text, name


def test_one_row_per_map_and_quick_start(paths: pd.DataFrame) -> None:
    assert sorted(zip(paths["map"], paths["start"])) == [("office", 6), ("office", 20), ("rooms", 6), ("rooms", 20)]
    assert (paths["kpois"] == 19).all()  # 20 positions, one of them the start


def test_algorithm1_reaches_c_max_and_exact_matches_it(paths: pd.DataFrame) -> None:
    # Prop. 1: Algorithm 1's first path is the shortest path to v_max, every other within c_max.
    assert np.allclose(paths["paper_makespan"], paths["c_max"], rtol=TOL)
    # c_max is a lower bound for any robots, so the exact answer with Alg. 1's robots is c_max, proven.
    assert (paths["exact_status"] == "optimal").all()
    assert np.allclose(paths["exact_makespan"], paths["c_max"], rtol=TOL)
    assert (paths["exact_robots_used"] <= paths["paper_robots"]).all()


def test_exact_never_above_a_heuristic_with_the_same_robots(paths: pd.DataFrame) -> None:
    proven = paths[paths["exact_status"] == "optimal"]
    assert (proven["exact_makespan"] <= proven["nn_makespan"] * (1 + TOL)).all()
    assert (proven["nn_robots"] <= proven["paper_robots"]).all()
    # The MST branches are never cut: at most one robot per KPOI, never below c_max.
    assert (paths["mst_robots"] <= paths["kpois"]).all()
    assert (paths["mst_makespan"] >= paths["c_max"] * (1 - TOL)).all()


def test_fewest_robots_within_bound_and_below_the_heuristics(paths: pd.DataFrame) -> None:
    assert (paths["fewest_bound"] <= paths["fewest_robots"]).all()
    proven = paths[paths["fewest_status"] == "optimal"]
    assert not proven.empty
    for heuristic in ("paper_robots", "nn_cmax_robots", "mst_cmax_robots"):
        assert (proven["fewest_robots"] <= proven[heuristic]).all(), heuristic


def test_tours_compare_k_nn_k_ni_and_exact_with_algorithm2s_count(tours: pd.DataFrame) -> None:
    office = tours[(tours["map"] == "office") & (tours["start"] == 6)].set_index("method", drop=False)
    alg2 = office.loc["paper"]
    k = int(alg2["robots"])
    same_k = office[office["robots_limit"] == k]
    assert sorted(same_k["method"]) == ["exact", "kni", "knn"]
    assert np.allclose(office["vs_alg2"], office["makespan"] / alg2["makespan"], rtol=TOL)
    exact = same_k.loc["exact"]
    assert exact["bound"] <= exact["makespan"] * (1 + TOL)
    if exact["status"] == "optimal":
        assert (exact["makespan"] <= same_k["makespan"] * (1 + TOL)).all()


def test_saved_instance_reruns_to_the_same_answer(quick_run: Path, paths: pd.DataFrame) -> None:
    instance = read_instance(quick_run.with_suffix("") / "rooms-start20.json")
    assert instance.start == "20" and instance.kpois == tuple(str(j) for j in range(1, 20))
    row = paths[(paths["map"] == "rooms") & (paths["start"] == 20)].iloc[0]
    result = solve(instance, method="paper")
    assert result.robots == row["paper_robots"]
    assert result.makespan == pytest.approx(row["paper_makespan"], rel=TOL)


def test_rooted_moves_the_start_and_keeps_the_graph() -> None:
    # Nodes 1, 2, 3 on a line at x = 0, 1, 3 (no edges: Euclidean). With node 2 as the
    # start, the KPOIs are 1 then 3, at distances 1 and 2 from it, and 3 apart.
    graph = Instance("1", ("2", "3"), coordinates={"1": (0, 0), "2": (1, 0), "3": (3, 0)})
    moved = section6.rooted(graph, 2, "line-start2")
    assert moved.start == "2" and moved.kpois == ("1", "3") and moved.name == "line-start2"
    assert np.allclose(moved.distances, [[0, 1, 2], [1, 0, 3], [2, 3, 0]])


def test_value_shows_the_bound_only_when_not_proven() -> None:
    assert section6._value(7.0, "optimal", 7.0, ".0f") == "7"
    assert section6._value(7.0, "feasible", 6.0, ".0f") == "7 (≥ 6)"


def test_ratio_lines_divide_by_algorithm1_and_algorithm2() -> None:
    # Office start 6: MST 130 against Alg. 1 100 -> 1.300. Tours with k = 5: 5-NN 150,
    # 5-NI 120, exact 90 (proven) against Alg. 2 100 -> 1.500, 1.200, 0.900.
    paths = pd.DataFrame({"map": ["office"], "start": [6], "mst_makespan": [130.0],
                          "paper_makespan": [100.0], "paper_robots": [8]})
    tours = pd.DataFrame({
        "map": ["office"] * 4, "start": [6] * 4, "method": ["paper", "knn", "kni", "exact"],
        "robots_limit": [None, 5, 5, 5], "robots": [5, 5, 5, 5], "makespan": [100.0, 150.0, 120.0, 90.0],
        "status": ["feasible", "feasible", "feasible", "optimal"], "bound": [2.0, 80.0, 80.0, 90.0],
        "vs_alg2": [1.0, 1.5, 1.2, 0.9],
    })
    text = "\n".join(section6._ratio_lines(paths, tours))
    assert "739 / 569 = 1.299 | 1.300 |" in text
    assert "2440 / 1500 = 1.627 (4 tours) | 1.500 (5 tours) |" in text
    assert "2531 / 1500 = 1.687 (4 tours) | 1.200 (5 tours) |" in text
    assert "| exact / Alg. 2 tour makespan, 5 robots, office | not measured | 0.900 |" in text
