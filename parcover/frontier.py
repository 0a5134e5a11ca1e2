"""The robots-versus-time trade-off: the best makespan for k = 1, 2, ... robots.

It stops at the least ``k`` whose makespan reaches the least possible one (``c_max``
for paths, ``2 c_max`` for tours; paper, Prop. 1), beyond which more robots cannot
help; with ``n`` robots the one-KPOI-each routes always reach it.
"""

from __future__ import annotations

import time

from parcover.instance import Instance
from parcover.problem import Problem, meets_deadline
from parcover.result import Frontier, FrontierPoint, RoutesKind
from parcover.solve import solve

__all__ = ["frontier"]


def frontier(
    instance: Instance,
    routes: RoutesKind = "paths",
    method: str = "exact",
    *,
    time_limit: float | None = None,
    seed: int = 0,
) -> Frontier:
    """Solve the makespan question for k = 1, 2, ... robots with ``method``.

    ``time_limit`` applies to each k. A point is ``optimal`` only where the method
    proved it.
    """
    least = Problem(routes).least_makespan(instance)
    started = time.perf_counter()
    points = []
    for k in range(1, instance.n + 1):
        result = solve(instance, routes, robots=k, method=method, time_limit=time_limit, seed=seed)
        points.append(FrontierPoint(k, result.makespan, result.status, result.bound, result))
        if result.makespan is not None and meets_deadline(result.makespan, least):
            break
    return Frontier(instance.name, routes, method, points, time.perf_counter() - started)
