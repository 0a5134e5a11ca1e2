"""The robots-versus-time trade-off: the best makespan for k = 1, 2, ... robots.

It stops at the least ``k`` whose makespan reaches the least possible one (``c_max``
for paths, ``2 c_max`` for tours; paper, Prop. 1), beyond which more robots cannot
help; with ``n`` robots the one-KPOI-each routes always reach it. Interrupted
(:func:`milp.core.timelimit.interrupt`, a Ctrl-C in ``parcover frontier``), it ends with
the ``k`` being solved, whose point is the best found so far, and says so in its note.
"""

from __future__ import annotations

import time
from collections.abc import Callable

from milp.core.timelimit import interrupted
from parcover.instance import Instance
from parcover.problem import Problem, meets_deadline
from parcover.result import Frontier, FrontierPoint, Result, RoutesKind, plural
from parcover.solve import INTERRUPTED, available_methods, solve

__all__ = ["frontier"]


def frontier(
    instance: Instance,
    routes: RoutesKind = "paths",
    method: str = "exact",
    *,
    time_limit: float | None = None,
    seed: int = 0,
    progress: Callable[[int, Result], None] | None = None,
) -> Frontier:
    """Solve the makespan question for k = 1, 2, ... robots with ``method``.

    ``time_limit`` applies to each k. A point is ``optimal`` only where the method
    proved it. Methods that take a ``warm_start`` (``exact``) start each k from the
    routes found for k - 1. ``progress(k, result)`` is called after each k.
    """
    least = Problem(routes).least_makespan(instance)
    info = available_methods().get(method)
    warm = info is not None and "warm_start" in info.options
    started = time.perf_counter()
    points: list[FrontierPoint] = []
    note = None
    for k in range(1, instance.n + 1):
        options = {}
        if warm and points and points[-1].result is not None and points[-1].result.routes:
            # k - 1 robots' routes are valid with k robots: a warm start and an upper bound
            options["warm_start"] = points[-1].result.routes
        result = solve(instance, routes, robots=k, method=method, time_limit=time_limit, seed=seed, **options)
        if progress is not None:
            progress(k, result)
        points.append(FrontierPoint(k, result.makespan, result.status, result.bound, result))
        if result.makespan is not None and meets_deadline(result.makespan, least):
            break
        if interrupted():
            note = f"{INTERRUPTED} at {plural(k, 'robot')}: the points end before the least possible makespan"
            break
    return Frontier(instance.name, routes, method, points, time.perf_counter() - started, note)
