"""Cheap proven lower bounds that every method reports (docs/format.md section 4).

- Makespan: ``c_max`` for paths and ``2 c_max`` for tours (paper, Prop. 1), and the
  spanning-tree bound: the ``k`` routes together connect the start and every KPOI, so
  their total length is at least the minimum spanning tree's (plus, for tours, the
  closing arcs); for 21-200 KPOIs also its Held-Karp strengthening, spanning trees under
  Lagrangian prices on the KPOIs' degrees (:func:`milp.bounds.held_karp_makespan_bound`).
- Robots: the fewest routes within the deadline that the same arguments allow, at
  least 1, and at least the number of KPOIs no two of which fit on one route within the
  deadline (a clique of conflicting KPOIs: :func:`milp.bounds.conflict_clique`).

Both are :mod:`milp.bounds`, computed on the instance's distance matrix.
"""

from __future__ import annotations

from milp import bounds
from parcover.instance import Instance
from parcover.problem import Problem

__all__ = ["makespan_lower_bound", "robots_lower_bound", "lower_bound"]


def makespan_lower_bound(instance: Instance, problem: Problem, robots: int, *,
                         seconds: float | None = None) -> float:
    """The larger of the least makespan and the spanning-tree bound (and Held-Karp's when
    it fits in ``seconds``: :func:`milp.bounds.makespan_lower_bound`), for at most
    ``robots`` routes of ``problem``'s kind."""
    return bounds.makespan_lower_bound(instance.distances, robots, tours=problem.tours, time_limit=seconds)


def robots_lower_bound(instance: Instance, deadline: float, *, tours: bool, seconds: float | None = None) -> int:
    """Fewest routes within ``deadline`` allowed by the spanning-tree and conflict-clique
    bounds (>= 1)."""
    return bounds.robots_lower_bound(instance.distances, deadline, tours=tours, time_limit=seconds)


def lower_bound(instance: Instance, problem: Problem, *, seconds: float | None = None) -> float:
    """The trivial proven bound on the problem's objective within ``seconds`` (None: no
    limit): the Held-Karp part only when expected to fit (about a second per bound at
    200 KPOIs, more than a short time limit has left; remembered bounds are free)."""
    if problem.objective == "makespan":
        assert problem.robots is not None
        return makespan_lower_bound(instance, problem, problem.robots, seconds=seconds)
    deadline = problem.effective_deadline(instance)
    assert deadline is not None
    return float(robots_lower_bound(instance, deadline, tours=problem.tours, seconds=seconds))
