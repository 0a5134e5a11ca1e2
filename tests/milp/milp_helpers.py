"""Instances and an independent solution checker for the milp tests."""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import shortest_path

TOL = 1e-6


def euclidean(n: int, seed: int) -> np.ndarray:
    """Start and ``n`` KPOIs uniform in a 100 x 100 square."""
    points = np.random.default_rng(seed).uniform(0.0, 100.0, size=(n + 1, 2))
    return np.linalg.norm(points[:, None, :] - points[None, :, :], axis=2)


def graph_metric(n: int, seed: int, extra_nodes: int = 4) -> np.ndarray:
    """Shortest-path metric of a random sparse connected graph, restricted to n+1 nodes."""
    rng = np.random.default_rng(seed)
    size = n + 1 + extra_nodes
    order = rng.permutation(size)
    tails = list(order[:-1])  # a random spanning path keeps the graph connected
    heads = list(order[1:])
    for _ in range(size):
        a, b = rng.choice(size, 2, replace=False)
        tails.append(a)
        heads.append(b)
    weights = rng.integers(1, 20, size=len(tails)).astype(float)
    graph = coo_matrix((weights, (tails, heads)), shape=(size, size)).tocsr()
    full = shortest_path(graph, directed=False)
    return full[: n + 1, : n + 1]


def route_cost(D: np.ndarray, route: list[int], tours: bool) -> float:
    """Recomputed from D, independently of milp."""
    stops = [0] + list(route) + ([0] if tours else [])
    return float(sum(D[a, b] for a, b in zip(stops, stops[1:])))


def check_solution(D, result, *, tours, k=None, deadline=None):
    """Assert that ``result`` is a valid answer; return its recomputed makespan."""
    n = len(D) - 1
    assert result.status in ("optimal", "feasible")
    assert all(len(route) >= 1 for route in result.routes)
    assert sorted(i for route in result.routes for i in route) == list(range(1, n + 1))
    costs = [route_cost(D, route, tours) for route in result.routes]
    if k is not None:
        assert len(result.routes) <= k
        assert abs(max(costs) - result.objective) <= TOL * max(1.0, max(costs))
    if deadline is not None:
        assert all(c <= deadline * (1 + 1e-9) + 1e-9 for c in costs)
        assert result.objective == len(result.routes)
    assert result.bound is not None and result.bound <= result.objective + TOL
    if result.status == "optimal":
        assert result.gap == 0.0 and result.bound == result.objective
    else:
        assert result.gap == (result.objective - result.bound) / result.objective
    return max(costs)
