"""Branch-and-cut (milp/branchcut.py) against set partitioning, the compact model and
branch-and-price."""

from __future__ import annotations

import time

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from milp import arcflow, branchcut, branchprice, setpart
from milp.warmstart import nearest_neighbour_order, split_min_makespan
from milp_helpers import TOL, check_solution, euclidean, graph_metric

INSTANCES = [("euclid", 6, 31), ("euclid", 9, 32), ("euclid", 12, 33), ("graph", 7, 34), ("graph", 10, 35)]
ARCFLOW_MAX_KPOIS = 9


def make(kind: str, n: int, seed: int) -> np.ndarray:
    return euclidean(n, seed) if kind == "euclid" else graph_metric(n, seed)


@pytest.mark.parametrize("tours", [False, True], ids=["paths", "tours"])
@pytest.mark.parametrize("kind,n,seed", INSTANCES)
def test_least_makespan_agrees_with_set_partitioning(kind, n, seed, tours):
    """Against set partitioning on every instance, and against the arc-flow model up to
    :data:`ARCFLOW_MAX_KPOIS` (above, it takes 10-80 s a cell on the graph metric's ties;
    its own agreement with set partitioning is ``test_crosscheck``'s)."""
    D = make(kind, n, seed)
    for k in (1, 2, 3, 4):
        answer = branchcut.min_makespan(D, k, tours=tours)
        assert answer.status == "optimal", (k, answer)
        value = check_solution(D, answer, tours=tours, k=k)
        for method in (setpart, arcflow) if n <= ARCFLOW_MAX_KPOIS else (setpart,):
            reference = method.min_makespan(D, k, tours=tours)
            assert reference.status == "optimal"
            assert abs(value - reference.objective) <= TOL * max(1.0, reference.objective), (k, value, reference)


grid_points = st.lists(st.tuples(st.integers(0, 3), st.integers(0, 3)), min_size=4, max_size=9)


@settings(max_examples=30, deadline=None)
@given(points=grid_points, k=st.integers(1, 3), tours=st.booleans())
def test_coincident_kpois_and_kpois_at_the_start(points, k, tours):
    """A 4 x 4 lattice (Manhattan distances): zero-length edges are common; cut (3)
    forbids their subtours without any merging argument."""
    P = np.array(points, dtype=float)
    D = np.abs(P[:, None, :] - P[None, :, :]).sum(axis=2)
    answer = branchcut.min_makespan(D, k, tours=tours)
    assert answer.status == "optimal"
    value = check_solution(D, answer, tours=tours, k=k)
    reference = setpart.min_makespan(D, k, tours=tours).objective
    assert abs(value - reference) <= TOL * max(1.0, reference)


def clustered(n: int, seed: int) -> np.ndarray:
    """Four tight clusters far from each other, the start in the middle."""
    rng = np.random.default_rng(seed)
    centres = np.array([[0, 0], [100, 0], [0, 100], [100, 100]], dtype=float)
    points = np.vstack([[50.0, 50.0], centres[rng.integers(0, 4, n)] + rng.normal(0, 3, (n, 2))])
    return np.linalg.norm(points[:, None] - points[None], axis=-1)


@pytest.mark.parametrize("tours", [False, True], ids=["paths", "tours"])
def test_clustered_instance_with_two_and_three_routes(tours):
    D = clustered(14, 7)
    for k in (2, 3):
        answer = branchcut.min_makespan(D, k, tours=tours)
        assert answer.status == "optimal"
        value = check_solution(D, answer, tours=tours, k=k)
        assert abs(value - setpart.min_makespan(D, k, tours=tours).objective) <= TOL * value


@pytest.mark.parametrize("tours", [False, True], ids=["paths", "tours"])
def test_two_long_routes_agree_with_branch_and_price_at_22_kpois(tours):
    """Beyond set partitioning's range, the second exact method is branch-and-price."""
    D = euclidean(22, 42)
    ours = branchcut.min_makespan(D, 2, tours=tours, time_limit=120)
    theirs = branchprice.min_makespan(D, 2, tours=tours, time_limit=120)
    assert ours.status == theirs.status == "optimal"
    value = check_solution(D, ours, tours=tours, k=2)
    assert abs(value - theirs.objective) <= TOL * value


def test_a_warm_start_is_kept_and_bounds_hold_when_time_runs_out():
    """60 KPOIs with 2 tours in 2 s: not proven; the answer is no worse than the warm
    start, its bound is at most its value, and the limit holds."""
    D = euclidean(60, 5)
    start = split_min_makespan(D, nearest_neighbour_order(D), 2, tours=True)
    began = time.perf_counter()
    answer = branchcut.min_makespan(D, 2, tours=True, time_limit=2.0, warm_start=start)
    assert time.perf_counter() - began <= 2.0 * 1.1 + 0.5
    value = check_solution(D, answer, tours=True, k=2)
    warm = max(sum(D[a, b] for a, b in zip([0, *r], [*r, 0])) for r in start)
    assert value <= warm + TOL
    assert answer.status == "feasible" and 0 < answer.bound < value


def test_a_one_kpoi_tour_is_allowed():
    """One KPOI far out, two near the start on the other side: with 2 tours the far one
    must go alone (its edge to the start used twice); the warm start pairs it."""
    points = np.array([[0, 0], [100, 0], [-1, 1], [-1, -1]], dtype=float)
    D = np.linalg.norm(points[:, None] - points[None], axis=-1)
    answer = branchcut.min_makespan(D, 2, tours=True, warm_start=[[1, 2], [3]])
    assert answer.message.startswith("branch-and-cut")
    assert answer.status == "optimal" and abs(answer.objective - 200.0) <= TOL
    assert [1] in answer.routes


def test_bad_route_count_is_refused():
    with pytest.raises(ValueError):
        branchcut.min_makespan(euclidean(4, 1), 0, tours=True)
