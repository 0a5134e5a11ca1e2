"""arcflow == branchprice == setpart == cvxpy on random instances, every answer re-checked from D."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from milp import arcflow, branchprice, cvx, setpart
from milp_helpers import TOL, check_solution, euclidean, graph_metric

METHODS = {"arcflow": arcflow, "branchprice": branchprice, "setpart": setpart, "cvx": cvx}
INSTANCES = [
    ("euclid", 4, 11), ("euclid", 6, 12), ("euclid", 8, 13), ("euclid", 10, 14),
    ("graph", 5, 21), ("graph", 7, 22), ("graph", 9, 23),
]


def make(kind: str, n: int, seed: int) -> np.ndarray:
    """Instance by kind."""
    return euclidean(n, seed) if kind == "euclid" else graph_metric(n, seed)


def c_max(D: np.ndarray, tours: bool) -> float:
    """Least possible makespan."""
    return (2.0 if tours else 1.0) * D[0, 1:].max()


@pytest.mark.parametrize("tours", [False, True], ids=["paths", "tours"])
@pytest.mark.parametrize("kind,n,seed", INSTANCES)
def test_makespan_agrees(kind, n, seed, tours):
    D = make(kind, n, seed)
    for k in (1, 2, 3):
        values = {}
        for name, method in METHODS.items():
            if name == "cvx" and n > 8 and k > 1:
                continue  # the unpruned cvxpy model is slow here; covered on smaller n
            result = method.min_makespan(D, k, tours=tours)
            assert result.status == "optimal", (name, result)
            values[name] = check_solution(D, result, tours=tours, k=k)
        reference = values["setpart"]
        for name, value in values.items():
            assert abs(value - reference) <= TOL * max(1.0, reference), (name, k, values)


@pytest.mark.parametrize("tours", [False, True], ids=["paths", "tours"])
@pytest.mark.parametrize("kind,n,seed", INSTANCES)
def test_robots_agree(kind, n, seed, tours):
    D = make(kind, n, seed)
    least = c_max(D, tours)
    for deadline in (least, 1.6 * least):
        counts = {}
        for name, method in METHODS.items():
            result = method.min_robots(D, deadline, tours=tours)
            assert result.status == "optimal", (name, result)
            check_solution(D, result, tours=tours, deadline=deadline)
            counts[name] = result.objective
        assert len(set(counts.values())) == 1, (deadline, counts)


grid_points = st.lists(
    st.tuples(st.integers(0, 3), st.integers(0, 3)), min_size=4, max_size=8
)


@settings(max_examples=25, deadline=None)
@given(points=grid_points, k=st.integers(1, 3), tours=st.booleans())
def test_coarse_grid_with_coincident_points(points, k, tours):
    """Points on a 4 x 4 lattice: coincident KPOIs and KPOIs at the start are common."""
    P = np.array(points, dtype=float)
    D = np.abs(P[:, None, :] - P[None, :, :]).sum(axis=2)
    deadline = c_max(D, tours) + 1.0
    values, counts = set(), set()
    for method in (arcflow, branchprice, setpart):
        answer = method.min_makespan(D, k, tours=tours)
        assert answer.status == "optimal", (method.__name__, answer)
        values.add(round(check_solution(D, answer, tours=tours, k=k), 6))
        answer = method.min_robots(D, deadline, tours=tours)
        assert answer.status == "optimal", (method.__name__, answer)
        check_solution(D, answer, tours=tours, deadline=deadline)
        counts.add(answer.objective)
    assert len(values) == 1 and len(counts) == 1, (values, counts)
