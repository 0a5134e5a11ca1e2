"""A simple valid solution to start from: nearest-neighbour order, split optimally.

The order visits every KPOI once (nearest unvisited KPOI next, from the start); it is
then cut into consecutive routes by a dynamic programme, optimally for that order:
least makespan with at most ``k`` routes, or fewest routes within a deadline.
"""

from __future__ import annotations

import numpy as np

from milp.core.timelimit import TimeLimit, TimeLimitLike
from milp.core.routes import route_cost, within


#: Largest number of nearest-neighbour orders tried by :func:`good_makespan_routes`.
MAX_STARTS = 16
#: Seconds per cell of :func:`split_min_makespan`, which cannot be interrupted: ``k + 1``
#: passes over an ``m x m`` table (measured 1.9-2.8 ns at 2000-3000 KPOIs, k = 3-40;
#: doubled for a shared machine).
SPLIT_SECONDS_PER_CELL = 5e-9


def nearest_neighbour_order(D: np.ndarray, first: int | None = None) -> list[int]:
    """All KPOIs ``1..n`` in nearest-neighbour order from the start 0 (or from ``first``)."""
    n = len(D) - 1
    unvisited = np.ones(n + 1, dtype=bool)
    unvisited[0] = False
    order, here = [], 0
    if first is not None:
        unvisited[first] = False
        order, here = [first], first
    for _ in range(n - len(order)):
        candidates = np.flatnonzero(unvisited)
        here = int(candidates[np.argmin(D[here, candidates])])
        unvisited[here] = False
        order.append(here)
    return order


def segment_costs_by_end(D: np.ndarray, order: list[int], *, tours: bool) -> np.ndarray:
    """``cost[b, a]``: route over ``order[a..b]`` (inclusive); ``inf`` when ``a > b``.

    Indexed by end first, so that the splits below scan contiguous rows (measured at 3000
    KPOIs: splitting into 3 routes took 0.43 s by columns, 0.14 s by rows)."""
    seq = np.asarray(order)
    steps = np.concatenate([[0.0], np.cumsum(D[seq[:-1], seq[1:]])])
    back = D[seq, 0] if tours else np.zeros(len(seq))
    cost = D[0, seq][None, :] + steps[:, None]
    cost -= steps[None, :]
    cost += back[:, None]
    index = np.arange(len(seq))
    cost[index[:, None] < index[None, :]] = np.inf
    return cost


def split_min_makespan(D: np.ndarray, order: list[int], k: int, *, tours: bool) -> list[list[int]]:
    """Cut ``order`` into at most ``k`` consecutive routes of least makespan."""
    m = len(order)
    cost = segment_costs_by_end(D, order, tours=tours)
    best = np.full(m + 1, np.inf)
    best[0] = 0.0
    cuts = []
    finals = []
    worst = np.empty((m, m))
    for _ in range(min(k, m)):
        np.maximum(best[None, :m], cost, out=worst)  # end b, start a
        start = np.argmin(worst, axis=1)
        new = np.full(m + 1, np.inf)
        new[1:] = worst[np.arange(m), start]
        cuts.append(start)
        finals.append(new[m])
        best = new
    used = int(np.argmin(finals)) + 1
    routes, end = [], m
    for c in range(used - 1, -1, -1):
        a = int(cuts[c][end - 1])
        routes.append(order[a:end])
        end = a
    return routes[::-1]


def split_fits(m: int, k: int, time_limit: TimeLimit) -> bool:
    """Whether what is left of ``time_limit`` covers :func:`split_min_makespan` of an order
    of ``m`` KPOIs into ``k`` routes (:data:`SPLIT_SECONDS_PER_CELL`)."""
    left = time_limit.remaining()
    return left is None or left >= SPLIT_SECONDS_PER_CELL * (min(k, m) + 1) * m * m


def split_min_robots(
    D: np.ndarray, order: list[int], deadline: float, *, tours: bool
) -> list[list[int]]:
    """Cut ``order`` into the fewest consecutive routes each within ``deadline``.

    Assumes every single-KPOI route meets the deadline (else no split exists).
    """
    m = len(order)
    allowed = within(segment_costs_by_end(D, order, tours=tours), deadline)
    count = np.full(m + 1, np.inf)
    count[0] = 0
    start = np.zeros(m, dtype=int)
    for b in range(m):
        options = np.where(allowed[b, : b + 1], count[: b + 1] + 1, np.inf)
        start[b] = int(np.argmin(options))
        count[b + 1] = options[start[b]]
    if not np.isfinite(count[m]):
        raise ValueError("a single KPOI exceeds the deadline")
    routes, end = [], m
    while end > 0:
        a = int(start[end - 1])
        routes.append(order[a:end])
        end = a
    return routes[::-1]


def two_opt(D: np.ndarray, route: list[int], *, tours: bool, time_limit: TimeLimit | None = None) -> list[int]:
    """Route improved by segment reversals until none shortens it (first improvement).

    For each first position ``i`` in turn, the reversals of ``route[i..j]`` for every
    ``j > i`` are priced at once (the change of the two arcs that move, ``D`` being
    symmetric) and the first that shortens the route by more than 1e-9 is applied;
    the scan goes on after ``j`` on the new route. Stops early, with the route as it
    is, once ``time_limit`` has passed.
    """
    best = list(route)
    m = len(best)
    improved = m > 1
    while improved:
        improved = False
        for i in range(m - 1):
            if time_limit is not None and time_limit.expired():
                return best
            j = i + 1
            while j < m:
                found = _first_shortening_reversal(D, best, i, j, tours=tours)
                if found is None:
                    break
                best[i : found + 1] = best[i : found + 1][::-1]
                improved, j = True, found + 1
    return best


def _first_shortening_reversal(D: np.ndarray, route: list[int], i: int, j: int, *, tours: bool) -> int | None:
    """Least ``e >= j`` whose reversal of ``route[i..e]`` shortens the route, or None."""
    stops = np.array([0, *route, 0])  # route[p] is stops[p + 1]
    before, first = stops[i], stops[i + 1]
    last = stops[j + 1 : len(route) + 1]  # route[e] for e = j .. m-1
    after = stops[j + 2 : len(route) + 2]
    change = D[before, last] - D[before, first] + D[first, after] - D[last, after]
    if not tours:  # a path ends at route[m-1]: no arc after it
        change[-1] = D[before, last[-1]] - D[before, first]
    hits = np.flatnonzero(change < -1e-9)
    return None if len(hits) == 0 else j + int(hits[0])


def cheapest_insertion(D: np.ndarray, route: list[int], v: int, *, tours: bool) -> list[int]:
    """``route`` with ``v`` inserted where it adds the least cost."""
    stops = np.array([0, *route, 0] if tours else [0, *route])
    added = D[stops[:-1], v] + D[v, stops[1:]] - D[stops[:-1], stops[1:]]
    if not tours:
        added = np.append(added, D[stops[-1], v])
    at = int(np.argmin(added))
    return route[:at] + [v] + route[at:]


def relocate(
    D: np.ndarray, routes: list[list[int]], k: int, *, tours: bool, time_limit: TimeLimit | None = None
) -> list[list[int]]:
    """Move KPOIs off the costliest route while that lowers both routes below it.

    Each accepted move lowers (makespan, number of routes at the makespan)
    lexicographically, so the loop ends. A new route is opened while fewer than ``k``.
    Once ``time_limit`` has passed no further move is searched (the routes stay valid).
    """
    routes = [two_opt(D, r, tours=tours, time_limit=time_limit) for r in routes]
    while time_limit is None or not time_limit.expired():
        costs = [route_cost(D, r, tours=tours) for r in routes]
        worst = int(np.argmax(costs))
        move = _best_relocation(D, routes, worst, costs[worst], k, tours=tours, time_limit=time_limit)
        if move is None:
            break
        routes = move
    return routes


def _best_relocation(
    D: np.ndarray, routes: list[list[int]], worst: int, top: float, k: int, *, tours: bool,
    time_limit: TimeLimit | None = None,
) -> list[list[int]] | None:
    """Routes after the best KPOI move out of route ``worst`` that beats ``top``, or None
    (also when ``time_limit`` passes before every move was priced)."""
    best, best_value = None, top - 1e-9
    targets = [i for i in range(len(routes)) if i != worst]
    if len(routes) < k:
        targets.append(len(routes))  # a new route
    for v in routes[worst]:
        if time_limit is not None and time_limit.expired():
            return None
        rest = two_opt(D, [u for u in routes[worst] if u != v], tours=tours, time_limit=time_limit)
        rest_cost = route_cost(D, rest, tours=tours) if rest else 0.0
        for t in targets:
            grown = cheapest_insertion(D, routes[t] if t < len(routes) else [], v, tours=tours)
            value = max(rest_cost, route_cost(D, grown, tours=tours))
            if value < best_value:
                best_value = value
                best = [r for r in routes] + ([] if t < len(routes) else [[]])
                best[worst], best[t] = rest, two_opt(D, grown, tours=tours, time_limit=time_limit)
    return None if best is None else [r for r in best if r]


def good_makespan_routes(
    D: np.ndarray, k: int, *, tours: bool, time_limit: TimeLimitLike = None
) -> list[list[int]]:
    """Best over several nearest-neighbour orders (each from a different first KPOI,
    improved by 2-opt) of the optimal split followed by relocations.

    ``time_limit`` (seconds from now, or a shared :class:`~milp.core.timelimit.TimeLimit`) ends
    the search: no new order is tried once what is left would not cover its split
    (:func:`split_fits`), and the 2-opt and relocations of the one under way stop where
    they are (at least one order is always split).
    """
    time_limit = TimeLimit.of(time_limit)
    n = len(D) - 1
    firsts = np.unique(np.linspace(1, n, min(n, MAX_STARTS)).round().astype(int))
    candidates = []
    for first in firsts.tolist():
        if candidates and (time_limit.expired() or not split_fits(n, k, time_limit)):
            break
        order = two_opt(D, nearest_neighbour_order(D, first), tours=False, time_limit=time_limit)
        split = split_min_makespan(D, order, k, tours=tours)
        candidates.append(relocate(D, split, k, tours=tours, time_limit=time_limit))
    return min(candidates, key=lambda routes: max(route_cost(D, r, tours=tours) for r in routes))
