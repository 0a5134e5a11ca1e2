"""Exact-scaling benchmark: the naive models and CP-SAT agree with set partitioning, and
the section's quick path and ratio arithmetic work."""

from __future__ import annotations

import importlib.util

import numpy as np
import pytest

from benchmarks import exact_scaling, naive_models
from benchmarks.common import Config, euclidean_distances, euclidean_points, run_peer
from milp import setpart
from milp.core.routes import least_makespan, route_cost, within
from parcover import Instance, Solution

HAS_ORTOOLS = importlib.util.find_spec("ortools") is not None
CASES = [(n, tours) for n in (5, 6) for tours in (False, True)]


@pytest.mark.parametrize(("n", "tours"), CASES)
def test_naive_models_match_set_partitioning(n: int, tours: bool) -> None:
    D = euclidean_distances(n, seed=n)
    best = setpart.min_makespan(D, 2, tours=tours).objective
    deadline = 1.2 * least_makespan(D, tours=tours)
    fewest = setpart.min_robots(D, deadline, tours=tours).objective
    for solve in (naive_models.mtz_min_makespan, naive_models.arcflow_min_makespan):
        result = solve(D, 2, tours=tours)
        assert result.status == "optimal"
        assert len(result.routes) <= 2
        assert result.objective == pytest.approx(best, rel=1e-7)
    for solve in (naive_models.mtz_min_robots, naive_models.arcflow_min_robots):
        result = solve(D, deadline, tours=tours)
        assert result.status == "optimal"
        assert result.objective == fewest
        assert all(within(route_cost(D, r, tours=tours), deadline) for r in result.routes)


@pytest.mark.parametrize("tours", [False, True])
def test_compact_cell_matches_set_partitioning(tours: bool) -> None:
    instance = Instance.from_points(euclidean_points(7, 7))
    D = instance.distances
    deadline = 1.2 * least_makespan(D, tours=tours)
    least = exact_scaling.solve_cell(instance, "compact", tours=tours, k=2, deadline=None, limit=30)
    fewest = exact_scaling.solve_cell(instance, "compact", tours=tours, k=None, deadline=deadline,
                                      limit=30)
    assert least["status"] == fewest["status"] == "optimal"
    assert least["objective"] == pytest.approx(setpart.min_makespan(D, 2, tours=tours).objective)
    assert fewest["objective"] == setpart.min_robots(D, deadline, tours=tours).objective


@pytest.mark.parametrize(("gap", "status"), [(1.5e-15, "optimal"), (1e-6, "feasible")])
def test_a_cell_whose_routes_meet_their_bound_is_optimal(monkeypatch, gap: float, status: str) -> None:
    # exact_scaling's n = 50, 2 paths cell: the race's bound 265.36483025112574 for
    # routes of 265.36483025112614 (relative 1.5e-15) was counted unproven, though
    # parcover.solve calls the same answer optimal
    instance = Instance.from_points(euclidean_points(6, 3))
    routes = [[1, 2, 3], [4, 5, 6]]
    value = max(route_cost(instance.distances, r, tours=False) for r in routes)
    monkeypatch.setitem(exact_scaling.PARCOVER_MODELS, "exact",
                        lambda *a, **k: Solution(routes=routes, bound=value * (1 - gap)))
    row = exact_scaling.solve_cell(instance, "exact", tours=False, k=2, deadline=None, limit=1)
    assert row["status"] == status and row["objective"] == value


def test_naive_models_refuse_coincident_kpois() -> None:
    # KPOIs 1 and 2 at the same point: a zero-length cycle would fool both models
    points = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 0.0]])
    D = np.linalg.norm(points[:, None] - points[None], axis=2)
    with pytest.raises(ValueError):
        naive_models.mtz_min_makespan(D, 1, tours=False)


@pytest.mark.skipif(not HAS_ORTOOLS, reason="ortools not installed ([bench] extra)")
@pytest.mark.parametrize(("n", "tours"), CASES)
def test_cpsat_matches_set_partitioning(n: int, tours: bool) -> None:
    D = euclidean_distances(n, seed=n)
    kind = "tours" if tours else "paths"
    best = setpart.min_makespan(D, 2, tours=tours).objective
    answer = run_peer("cpsat", {"distances": D.tolist(), "routes": kind, "robots": 2,
                                "time_limit": 10, "workers": 2}, timeout=120)
    assert answer["status"] == "optimal"
    # rounding each of at most n + 1 arcs down by < 1e-4 (module docstring of the peer)
    assert abs(answer["objective"] - best) <= (n + 1) / answer["scale"]
    assert answer["bound"] <= best + 1e-9
    covered = sorted(i for r in answer["routes"] for i in r)
    assert covered == list(range(1, n + 1)) and len(answer["routes"]) <= 2
    deadline = 1.2 * least_makespan(D, tours=tours)
    fewest = setpart.min_robots(D, deadline, tours=tours).objective
    answer = run_peer("cpsat", {"distances": D.tolist(), "routes": kind, "deadline": deadline,
                                "time_limit": 10, "workers": 2}, timeout=120)
    assert answer["status"] == "optimal" and answer["objective"] == fewest


def test_ratio_counts_unproven_peer_at_its_limit() -> None:
    compact = {"status": "optimal", "seconds": 2.0, "limit": 10.0}
    assert exact_scaling.ratio({"status": "optimal", "seconds": 5.0, "limit": 30.0}, compact) == "2.5"
    # not proven within its 30 s: at least 30 / 2 = 15 times slower
    assert exact_scaling.ratio({"status": "feasible", "seconds": 30.1, "limit": 30.0}, compact) == ">= 15"
    # ours not proven within its 10 s, the peer proven in 5 s: at most 5 / 10 (peer faster)
    assert exact_scaling.ratio({"status": "optimal", "seconds": 5.0, "limit": 30.0},
                               {"status": "feasible", "seconds": 10.0, "limit": 10.0}) == "<= 0.5"
    # neither proven: no ratio
    assert exact_scaling.ratio({"status": "feasible", "seconds": 30.0, "limit": 30.0},
                               {"status": "feasible", "seconds": 10.0, "limit": 10.0}) == "-"


def test_quick_section_on_tiny_grid(tmp_path, monkeypatch) -> None:
    tiny = [dict(n=5, seed=1, routes="paths", k=2, factor=None,
                 models=("exact", "branchprice", "compact", "setpart", "mtz", "plain"), limit=5.0),
            dict(n=5, seed=1, routes="tours", k=None, factor=1.2,
                 models=("exact", "branchprice", "compact", "setpart", "plain"), limit=5.0)]
    monkeypatch.setattr(exact_scaling, "grid", lambda quick: tiny)
    section = exact_scaling.run(Config(quick=True, figures=tmp_path, figures_link="fig"))
    frame = section.tables["exact_scaling"]
    assert len(frame) == 11 and set(frame["status"]) == {"optimal"}
    for _, cell in frame.groupby("problem"):
        assert cell["objective"].max() - cell["objective"].min() <= 1e-7
    ratios = section.tables["exact_scaling_ratios"]
    compact = frame[frame["model"] == "compact"].set_index("problem")["seconds"]
    exact_s = frame[frame["model"] == "exact"].set_index("problem")["seconds"]
    for row in ratios.to_dict("records"):  # ours is parcover's exact
        assert row["ours"] == "exact" and row["exact / ours"] == "-"
        expected = compact[row["problem"]] / max(exact_s[row["problem"]], 1e-3)
        assert row["compact / ours"] == f"{expected:.3g}"
    assert (tmp_path / "exact_scaling.png").exists()
    assert len(section.targets) == 5


def test_full_grid_covers_the_targets() -> None:
    cells = exact_scaling.grid(quick=False)
    assert {c["n"] for c in cells} == {10, 15, 20, 25, 30, 40, 50}
    for routes in ("paths", "tours"):  # the n = 30 target names every seed, paths and tours
        k3 = [c for c in cells if c["routes"] == routes and c["k"] == 3 and "exact" in c["models"]]
        assert sorted((c["n"], c["seed"]) for c in k3) == [(n, s) for n in exact_scaling.SIZES for s in (1, 2, 3)]
    for routes in ("paths", "tours"):
        for k, factor in ((2, None), (3, None), (5, None), (None, 1.0), (None, 1.2)):
            sizes = {c["n"] for c in cells if c["routes"] == routes and c["k"] == k and c["factor"] == factor}
            assert sizes == set(exact_scaling.SIZES), (routes, k, factor)
    assert any(c["models"] == ("plain",) and c["n"] == 20 and c["limit"] >= 120 for c in cells)
