"""Cheap proven lower bounds that every method reports (design.md section 4).

- Makespan: ``c_max`` for paths and ``2 c_max`` for tours (paper, Prop. 1), and the
  spanning-tree bound ``MST / k``: the ``k`` routes together connect the start and
  every KPOI, so their total length is at least the minimum spanning tree's.
- Robots: ``ceil(MST / deadline)`` by the same argument, and at least 1.
"""

from __future__ import annotations

import math

import numpy as np

from parcover.instance import Instance
from parcover.problem import DEADLINE_ATOL, DEADLINE_RTOL, Problem

__all__ = ["minimum_spanning_tree_length", "makespan_lower_bound", "robots_lower_bound", "lower_bound"]


def minimum_spanning_tree_length(distances: np.ndarray) -> float:
    """Length of a minimum spanning tree of the complete graph ``distances``.

    Prim's algorithm on the dense matrix: O(n^2) time, O(n) extra memory.
    """
    n = len(distances)
    in_tree = np.zeros(n, dtype=bool)
    in_tree[0] = True
    best = np.array(distances[0], dtype=float)
    total = 0.0
    for _ in range(n - 1):
        candidates = np.where(in_tree, np.inf, best)
        j = int(np.argmin(candidates))
        total += float(candidates[j])
        in_tree[j] = True
        np.minimum(best, distances[j], out=best)
    return total


def makespan_lower_bound(instance: Instance, problem: Problem, robots: int) -> float:
    """``max(least makespan, MST / robots)`` for at most ``robots`` routes."""
    return max(problem.least_makespan(instance), minimum_spanning_tree_length(instance.distances) / robots)


def robots_lower_bound(instance: Instance, deadline: float) -> int:
    """``max(1, ceil(MST / deadline))`` for routes within ``deadline``."""
    slack = deadline * (1 + DEADLINE_RTOL) + DEADLINE_ATOL
    return max(1, math.ceil(minimum_spanning_tree_length(instance.distances) / slack - 1e-9))


def lower_bound(instance: Instance, problem: Problem) -> float:
    """The trivial proven bound on the problem's objective."""
    if problem.objective == "makespan":
        assert problem.robots is not None
        return makespan_lower_bound(instance, problem, problem.robots)
    deadline = problem.effective_deadline(instance)
    assert deadline is not None
    return float(robots_lower_bound(instance, deadline))
