"""Hand-derived cases, zero-distance pitfalls, limits, frontier, infeasibility, export."""

from __future__ import annotations

import subprocess
import sys

import highspy
import numpy as np
import pytest

import milp
from milp import arcflow, cvx, setpart
from milp.core.highs import solve_lp
from milp.core.result import MilpResult, relative_gap
from milp_helpers import TOL, check_solution, euclidean, graph_metric

METHODS = [arcflow, setpart, cvx]


def fig1_grid() -> np.ndarray:
    """Paper's Fig. 1: 3x3 grid, start at corner (0, 0), the other 8 cells are KPOIs.

    Unit moves between 4-neighbours, so D is the Manhattan distance between cells.
    """
    cells = [(r, c) for r in range(3) for c in range(3)]  # (0, 0) first: the start
    P = np.array(cells, dtype=float)
    return np.abs(P[:, None, :] - P[None, :, :]).sum(axis=2)


@pytest.mark.parametrize("method", METHODS, ids=lambda m: m.__name__)
def test_fig1_grid_path_makespans(method):
    """k=1: 8 KPOIs, every unit move reaches at most one new cell, so >= 8 moves; the
    snake (0,1),(0,2),(1,2),(1,1),(1,0),(2,0),(2,1),(2,2) takes exactly 8.
    k=2: the far corner (2,2) is at distance c_max = 4, so >= 4; the routes
    (0,1),(0,2),(1,2),(2,2) and (1,0),(2,0),(2,1),(1,1) both cost 4.
    k=3: still >= c_max = 4, and the k=2 routes are valid with 3 robots: 4."""
    D = fig1_grid()
    for k, expected in [(1, 8.0), (2, 4.0), (3, 4.0)]:
        result = method.min_makespan(D, k, tours=False)
        assert result.status == "optimal"
        assert check_solution(D, result, tours=False, k=k) == pytest.approx(expected)


def coincident(n: int = 7, seed: int = 5) -> np.ndarray:
    """Random Euclidean KPOIs where KPOIs 2 and 5 share a position, as do 3 and 6."""
    P = np.random.default_rng(seed).uniform(0, 100, size=(n + 1, 2))
    P[5], P[6] = P[2], P[3]
    return np.linalg.norm(P[:, None, :] - P[None, :, :], axis=2)


def at_start(n: int = 7, seed: int = 6) -> np.ndarray:
    """Random Euclidean KPOIs where KPOIs 1 and 4 lie at the start's position."""
    P = np.random.default_rng(seed).uniform(0, 100, size=(n + 1, 2))
    P[1], P[4] = P[0], P[0]
    return np.linalg.norm(P[:, None, :] - P[None, :, :], axis=2)


@pytest.mark.parametrize("make", [coincident, at_start])
@pytest.mark.parametrize("tours", [False, True], ids=["paths", "tours"])
def test_zero_distances(make, tours):
    D = make()
    for k in (1, 2):
        values = [check_solution(D, m.min_makespan(D, k, tours=tours), tours=tours, k=k)
                  for m in METHODS]
        assert max(values) - min(values) <= TOL * max(values)
    deadline = 1.2 * (2 if tours else 1) * D[0, 1:].max()
    counts = {m.min_robots(D, deadline, tours=tours).objective for m in METHODS}
    assert len(counts) == 1


def test_zero_length_pair_not_a_subtour():
    """Two coincident KPOIs far from the start: a 2-cycle between them must not count.

    One robot must travel to them: makespan = 10 (path) for KPOIs 1, 2 at (10, 0)."""
    D = np.array([[0.0, 10.0, 10.0], [10.0, 0.0, 0.0], [10.0, 0.0, 0.0]])
    for method in METHODS:
        result = method.min_makespan(D, 1, tours=False)
        assert result.status == "optimal" and result.objective == pytest.approx(10.0)
        assert check_solution(D, result, tours=False, k=1) == pytest.approx(10.0)


@pytest.mark.parametrize("tours", [False, True], ids=["paths", "tours"])
def test_every_kpoi_at_start(tours):
    D = np.zeros((4, 4))
    for method in METHODS:
        result = method.min_makespan(D, 2, tours=tours)
        assert result.status == "optimal" and result.objective == 0.0 and result.gap == 0.0
        check_solution(D, result, tours=tours, k=2)
        robots = method.min_robots(D, 0.0, tours=tours)
        assert robots.status == "optimal" and robots.objective == 1


def test_tiny_time_limit_on_hard_instance():
    D = euclidean(40, 3)
    result = arcflow.min_makespan(D, 3, tours=False, time_limit=0.5)
    assert result.status in ("feasible", "unknown")
    assert result.seconds < 1.5
    if result.status == "feasible":
        check_solution(D, result, tours=False, k=3)
        assert result.bound <= result.objective
        assert result.bound >= D[0, 1:].max() - TOL


@pytest.mark.parametrize("tours", [False, True], ids=["paths", "tours"])
def test_a_stopped_solve_reports_a_valid_stronger_bound(tours):
    # HiGHS is stopped at once (0.2 s), so the bound comes from column generation: it must be
    # no weaker than the spanning-tree bound and never above the optimum (set partitioning).
    D = euclidean(11, 5)
    stopped = arcflow.min_makespan(D, 3, tours=tours, time_limit=0.2)
    optimum = setpart.min_makespan(D, 3, tours=tours).objective
    assert arcflow.makespan_lower_bound(D, 3, tours=tours) - TOL <= stopped.bound <= optimum + TOL
    check_solution(D, stopped, tours=tours, k=3)


@pytest.mark.parametrize("tours", [False, True], ids=["paths", "tours"])
@pytest.mark.parametrize("D", [euclidean(7, 31), graph_metric(6, 32)], ids=["euclid", "graph"])
def test_frontier(D, tours):
    results = milp.frontier(D, tours=tours)
    values = [check_solution(D, r, tours=tours, k=k) for k, r in enumerate(results, start=1)]
    assert all(r.status == "optimal" for r in results)
    assert all(a >= b - TOL for a, b in zip(values, values[1:]))
    least = (2 if tours else 1) * D[0, 1:].max()
    assert values[-1] == pytest.approx(least)
    assert all(v > least + TOL for v in values[:-1])
    for k, value in enumerate(values, start=1):
        assert value == pytest.approx(setpart.min_makespan(D, k, tours=tours).objective)


@pytest.mark.parametrize("tours", [False, True], ids=["paths", "tours"])
def test_deadline_below_c_max_is_infeasible(tours, monkeypatch):
    D = euclidean(6, 41)
    deadline = 0.999 * (2 if tours else 1) * D[0, 1:].max()

    def no_solver(*args, **kwargs):
        raise AssertionError("a solver was called")

    monkeypatch.setattr(arcflow, "solve_lp", no_solver)
    for method in METHODS:
        result = method.min_robots(D, deadline, tours=tours)
        assert result.status == "infeasible" and result.routes == [] and result.objective is None


@pytest.mark.parametrize("suffix", [".mps", ".lp"])
@pytest.mark.parametrize("tours", [False, True], ids=["paths", "tours"])
def test_export_reread_same_optimum(tmp_path, suffix, tours):
    D = euclidean(6, 51)
    deadline = 1.5 * (2 if tours else 1) * D[0, 1:].max()
    for model in (arcflow.build_model(D, tours=tours, k=2),
                  arcflow.build_model(D, tours=tours, deadline=deadline)):
        direct = solve_lp(model.lp, time_limit=None)
        path = model.write(tmp_path / f"model{suffix}")
        h = highspy.Highs()
        h.setOptionValue("output_flag", False)
        h.setOptionValue("mip_rel_gap", 1e-9)
        assert h.readModel(str(path)) == highspy.HighsStatus.kOk
        h.run()
        assert h.getModelStatus() == highspy.HighsModelStatus.kOptimal
        assert direct.status == "optimal"
        assert h.getInfo().objective_function_value == pytest.approx(direct.objective, rel=1e-7)


def test_warm_start_is_used_and_checked():
    D = euclidean(8, 61)
    optimum = setpart.min_makespan(D, 2, tours=False)
    warm = arcflow.min_makespan(D, 2, tours=False, warm_start=optimum.routes)
    assert warm.objective == pytest.approx(optimum.objective)
    with pytest.raises(ValueError):
        arcflow.min_makespan(D, 2, tours=False, warm_start=[[1, 2]])
    with pytest.raises(ValueError):
        arcflow.min_makespan(D, 1, tours=False, warm_start=optimum.routes)


def test_setpart_refuses_large_instances():
    with pytest.raises(ValueError, match="2\\^n"):
        setpart.min_makespan(euclidean(setpart.MAX_KPOIS + 1, 1), 2, tours=False)


def test_result_status_and_gap():
    with pytest.raises(ValueError):
        MilpResult("done")
    assert relative_gap(None, 1.0) is None and relative_gap(2.0, None) is None
    assert relative_gap(0.0, 0.0) == 0.0
    assert relative_gap(4.0, 3.0) == 0.25


def test_solving_prints_nothing_on_stdout():
    # HiGHS 1.16 prints a banner when a process builds its first Highs; milp absorbs it (when
    # a model module is first used, since `import milp` loads nothing), so parcover's console
    # output and JSON stay clean. A fresh process, as a user's would be.
    code = (
        "import numpy as np, milp;"
        "D = np.array([[0., 1.], [1., 0.]]); milp.min_makespan(D, 1, tours=False); milp.setpart"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout == ""
