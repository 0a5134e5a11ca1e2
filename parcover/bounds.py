"""Cheap proven lower bounds that every method reports (docs/format.md section 4).

- Makespan: ``c_max`` for paths and ``2 c_max`` for tours (paper, Prop. 1), and the
  spanning-tree bound: the ``k`` routes together connect the start and every KPOI, so
  their total length is at least the minimum spanning tree's (plus, for tours, the
  closing arcs); for 21-200 KPOIs also its Held-Karp strengthening, spanning trees under
  Lagrangian prices on the KPOIs' degrees (:func:`milp.bounds.held_karp_makespan_bound`).
- Robots: the fewest routes within the deadline that the same arguments allow, at
  least 1.

Both are :mod:`milp.bounds`, computed on the instance's distance matrix.
"""

from __future__ import annotations

from milp import bounds
from parcover.instance import Instance
from parcover.problem import Problem

__all__ = ["makespan_lower_bound", "robots_lower_bound", "lower_bound"]


def makespan_lower_bound(instance: Instance, problem: Problem, robots: int, *, held_karp: bool = True) -> float:
    """The larger of the least makespan and the spanning-tree bound (and Held-Karp's, unless
    ``held_karp`` is False), for at most ``robots`` routes of ``problem``'s kind."""
    return bounds.makespan_lower_bound(instance.distances, robots, tours=problem.tours, held_karp=held_karp)


def robots_lower_bound(instance: Instance, deadline: float, *, tours: bool, held_karp: bool = True) -> int:
    """Fewest routes within ``deadline`` allowed by the spanning-tree bound (>= 1)."""
    return bounds.robots_lower_bound(instance.distances, deadline, tours=tours, held_karp=held_karp)


def lower_bound(instance: Instance, problem: Problem, *, seconds: float | None = None) -> float:
    """The trivial proven bound on the problem's objective; the Held-Karp part only when
    ``seconds`` (None: no limit) leaves room for it (:func:`milp.bounds.held_karp_seconds`):
    at 200 KPOIs it takes about a second, more than a short time limit has left."""
    robots = problem.objective == "robots"
    held_karp = seconds is None or seconds >= bounds.held_karp_seconds(instance.distances, robots=robots)
    if not robots:
        assert problem.robots is not None
        return makespan_lower_bound(instance, problem, problem.robots, held_karp=held_karp)
    deadline = problem.effective_deadline(instance)
    assert deadline is not None
    return float(robots_lower_bound(instance, deadline, tours=problem.tours, held_karp=held_karp))
