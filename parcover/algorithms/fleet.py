"""The fewest routes within a deadline by PyVRP's iterated local search.

PyVRP (Wouda, Lan and Kool 2024) minimises fixed vehicle costs plus distance; with one
vehicle type whose fixed cost exceeds any total length and whose ``max_distance`` is the
deadline, its search minimises the routes first (the paper's Problem 2, the fewest robots
within ``c_p``) and the total length second. Before that search, the fleet is squeezed
as PyVRP's own ``minimise_fleet`` does: searches with one vehicle fewer than the fewest
routes found so far, each ending at its first routes within the deadline (or after a few
seconds). The two find different routes: on the building-scale questions the squeeze found
one route fewer in about a second on two the other search had left open for 100 s, and
missed routes the other search found on two more (``milp/README.md``). ``exact`` runs
them beside branch-and-price, which hands them the bound its root proves
(:func:`race_entrant`, :func:`parcover.exact._race_robots`). Before them, the entrant
proves the q-route LP bound of :func:`milp.branchprice.colgen.robots_bound`, which
closes in seconds where few long routes keep branch-and-price's ng-route root open for
minutes.

Integer lengths: PyVRP takes integer distances, so lengths are scaled by ``s`` and rounded
*up*, and the deadline becomes ``floor(U s) + n + 1``. Each of a route's at most ``n + 1``
arcs gains less than 1 by its rounding, so every route within ``U`` in floats is within
the integer deadline (the farthest KPOI's own route at ``U = c_max`` included), and every
route within the integer deadline is at most ``(n + 1) / s`` over ``U``; ``s`` makes that
half the shared tolerance of :func:`milp.core.routes.within` at ``U``. The routes are
checked in floats all the same.

Open paths end at a second depot at distance 0 from every KPOI, so a path's length is
the route length PyVRP checks.

The least makespan with ``k`` robots gets the same search as a decision:
:func:`shorter_routes` asks it for ``k`` routes just shorter than the incumbent's longest,
again and again. Beside branch-and-price it follows ``best``'s local search
(:func:`parcover.algorithms.local_search.race_entrant`), and where many routes are about
as long as the farthest KPOI's own it finds what the annealing misses (rat99, 7 tours:
437.26 -> 436.50, the trivial bound 436.44: ``milp/README.md``).
"""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Callable
from typing import Any

import numpy as np

from milp.branchprice import colgen
from milp.core.result import MilpResult
from milp.core.routes import ABS_TOL, REL_TOL, makespan, route_cost, within
from milp.core.timelimit import stop_requested
from milp.race import hand_over, handed_reader

__all__ = ["fewest_routes", "race_entrant", "shorter_routes"]

#: Seconds at most for :func:`race_entrant`'s q-route LP bound (it closed in 3-19 s on the
#: building-scale questions at 100 KPOIs: ``milp/README.md``).
QROUTE_SECONDS = 30.0
#: Seconds at most for each search of :func:`fewest_routes`' squeeze, and the searches (each
#: with the next seed) at one fleet size before the squeeze gives up: where it found one
#: route fewer than the search over the whole fleet, it did so in 0.3-1.7 s, but only from
#: some seeds (clustered seed 2 tours within ``2 c_max``, 8 tours: nothing from seed 0 in
#: 20 s, found from seeds 1, 2 and 3), and where the latter found routes the squeeze did
#: not, the squeeze searched for 100 s in vain (``milp/README.md``).
SQUEEZE_SECONDS, SQUEEZE_SEARCHES = 2.0, 4
#: :func:`shorter_routes`: each search asks for routes this much shorter (relative) than the
#: incumbent's longest and has at most :data:`SHORTER_SECONDS`; without a stop time it
#: ends after :data:`SHORTER_MISSES` searches in a row that found none. On rat99 with 7
#: tours and on four more Necula and building-scale makespan cells, each search that found
#: routes took at most 8 s, and they were 0.01-0.7% shorter (``milp/README.md``).
SHORTER_STEP, SHORTER_SECONDS, SHORTER_MISSES = 1e-4, 20.0, 3


def fewest_routes(D: np.ndarray, deadline: float, *, tours: bool, seconds: float, seed: int = 0,
                  floor: int | Callable[[], int] = 1,
                  start: list[list[int]] | None = None,
                  found: Callable[[list[list[int]]], None] | None = None) -> list[list[int]] | None:
    """Routes covering KPOIs ``1..n`` of ``D``, each within ``deadline``, as few as PyVRP
    finds in ``seconds``, or ``start`` (routes within the deadline) when it finds none
    fewer; ``None`` when there are neither.

    First the fleet is squeezed as PyVRP's ``minimise_fleet`` does: each search has one
    vehicle fewer than the fewest routes found so far (a vehicle per KPOI without
    ``start``) and ends at its first routes within the deadline, or after
    :data:`SQUEEZE_SECONDS`, when the next of :data:`SQUEEZE_SEARCHES` seeds tries that
    fleet again; then PyVRP's search over the whole fleet, whose fixed costs
    rank fewer routes first, has the time left. Both stop at ``floor`` routes (a proven
    bound, or a function returning the bound proven so far), and when asked to
    (:func:`milp.core.timelimit.stop_requested`). ``found``, when given, is called with
    each routes fewer than any before, as soon as they are found."""
    began = time.perf_counter()
    data = _pyvrp_data(D, deadline, tours=tours)
    fixed = data.vehicle_type(0).fixed_cost
    proven = floor if callable(floor) else lambda: floor
    best = start

    def left() -> float:
        return seconds - (time.perf_counter() - began)

    def settled() -> bool:  # the routes so far meet the proven bound, or the time is up
        return stop_requested() or left() <= 0 or (best is not None and len(best) <= proven())

    searches = 0  # at this fleet size
    while not settled() and searches < SQUEEZE_SEARCHES:
        fleet = len(D) - 1 if best is None else len(best) - 1
        squeezed = _solve(data.replace(vehicle_types=[data.vehicle_type(0).replace(num_available=fleet)]),
                          min(left(), SQUEEZE_SECONDS), seed + searches, first=True, done=lambda _cost: settled())
        routes = _routes_within(squeezed, D, deadline, tours=tours)
        if routes is None:
            searches += 1
        else:
            best, searches = routes, 0
            if found is not None:
                found(routes)
    if settled():
        return best
    # Fewer routes than the bound's successor cost less than (bound + 1) fixed costs.
    solution = _solve(data, left(), seed, first=False,
                      done=lambda cost: settled() or cost < (proven() + 1) * fixed)
    routes = _routes_within(solution, D, deadline, tours=tours)
    if routes is None or (best is not None and len(routes) >= len(best)):
        return best
    if found is not None:
        found(routes)
    return routes


def shorter_routes(D: np.ndarray, k: int, routes: list[list[int]], *, tours: bool, seed: int = 0,
                   stop: float | None = None, target: float = 0.0,
                   found: Callable[[list[list[int]]], None] | None = None) -> list[list[int]]:
    """At most ``k`` routes covering KPOIs ``1..n`` of ``D`` with a makespan below that of
    ``routes`` (valid ones), by :func:`fewest_routes` at a deadline :data:`SHORTER_STEP`
    below the incumbent's makespan, again from each shorter routes found (and with the
    next seed), until the :func:`time.perf_counter` time ``stop`` (without it, until
    :data:`SHORTER_MISSES` searches in a row find none), until the makespan meets
    ``target`` (a proven lower bound), or when asked to stop
    (:func:`milp.core.timelimit.stop_requested`). Returns the shortest routes met, never
    longer than ``routes``; ``found``, when given, is called with each as it is found."""
    best, value, misses = routes, makespan(D, routes, tours=tours), 0
    while not (within(value, target) or stop_requested()):
        seconds = SHORTER_SECONDS if stop is None else min(SHORTER_SECONDS, stop - time.perf_counter())
        if seconds <= 0 or (stop is None and misses >= SHORTER_MISSES):
            break
        shorter = fewest_routes(D, value * (1 - SHORTER_STEP), tours=tours, seconds=seconds, seed=seed, floor=k)
        seed += 1
        if shorter is None or len(shorter) > k:
            misses += 1
            continue
        best, value, misses = shorter, makespan(D, shorter, tours=tours), 0
        if found is not None:
            found(best)
    return best


def _solve(data: Any, seconds: float, seed: int, *, first: bool, done: Callable[[int], bool]) -> Any:
    """PyVRP's best solution of ``data`` after ``seconds``, or once ``done`` (given the best
    cost) says so, or at its first solution within the deadline when ``first``."""
    from pyvrp import solve
    from pyvrp.stop import FirstFeasible, MaxRuntime, MultipleCriteria

    stops = [MaxRuntime(max(seconds, 0.0)), done] + ([FirstFeasible()] if first else [])
    with warnings.catch_warnings():  # its penalty warnings speak of its own parameters
        warnings.simplefilter("ignore")
        return solve(data, MultipleCriteria(stops), seed=seed, display=False, collect_stats=False).best


def _pyvrp_data(D: np.ndarray, deadline: float, *, tours: bool) -> Any:
    """PyVRP's problem data for the routes within ``deadline`` over ``D`` (module docstring:
    integer lengths, a second depot ending the paths), with a vehicle per KPOI whose fixed
    cost exceeds any total length, so that fewer routes always cost less."""
    from pyvrp import Model

    n = len(D) - 1
    scale = 2 * (n + 1) / (deadline * REL_TOL + ABS_TOL)
    limit = math.floor(deadline * scale) + n + 1
    # Arcs longer than the deadline are never used: capping them keeps the integers small.
    arcs = np.minimum(np.ceil(np.asarray(D, dtype=float) * scale), limit + 1).astype(np.int64)
    np.fill_diagonal(arcs, 0)
    fixed = (n + 1) * (limit + 1)  # more than the total length of routes within the deadline

    model = Model()
    points = [model.add_location(0, 0) for _ in range(n + 1)]
    start = end = model.add_depot(points[0])
    if not tours:
        finish = model.add_location(0, 0)
        end = model.add_depot(finish)
        for point in points:
            model.add_edge(point, finish, distance=0)
    for point in points[1:]:
        model.add_client(point)
    model.add_vehicle_type(num_available=n, start_depot=start, end_depot=end, fixed_cost=fixed,
                           max_distance=limit)
    for i in range(n + 1):
        for j in range(n + 1):
            if i != j:
                model.add_edge(points[i], points[j], distance=int(arcs[i, j]))
    return model.data()


def _routes_within(found: Any, D: np.ndarray, deadline: float, *, tours: bool) -> list[list[int]] | None:
    """The KPOI routes of PyVRP's solution ``found``, or ``None`` unless it is complete and
    every route is within ``deadline`` in floats."""
    if not (found.is_feasible() and found.is_complete()):
        return None
    # Client activities count the clients from 0 in the order added: KPOI i is client i - 1.
    routes = [[activity.idx + 1 for activity in route if activity.is_client()] for route in found.routes()]
    routes = [route for route in routes if route]
    if not all(within(route_cost(D, route, tours=tours), deadline) for route in routes):
        return None
    return routes


def race_entrant(D: np.ndarray, deadline: float, *, tours: bool, bound_file: str, seed: int = 0,
                 time_limit: float | None = None, warm_start: list[list[int]] | None = None,
                 routes_file: str | None = None) -> MilpResult:
    """:func:`fewest_routes` as an entrant of :func:`milp.race.race_here`, beside
    branch-and-price: it stops as soon as its routes meet the bound branch-and-price has
    proved, which that one hands over at ``bound_file`` (:func:`milp.race.hand_over`; nothing
    there until its root proves one), or the bound proved here first: the
    q-route LP bound (:func:`milp.branchprice.colgen.robots_bound`, at most
    :data:`QROUTE_SECONDS`; never below :func:`milp.bounds.robots_lower_bound`'s). Its
    answer is ``"optimal"`` then (the bound is proven; the routes are checked here), else
    ``"feasible"``; when ``warm_start`` (branch-and-price's first routes) already meets the
    q-route bound, those routes, ``"optimal"``, without a search. With ``routes_file``,
    each routes fewer than any before are handed over there (KPOIs ``1..n``) as soon as
    they are found: branch-and-price takes them as its incumbent, and its tree then looks
    for one route fewer (:func:`milp.branchprice.min_robots`' ``elsewhere``)."""
    began = time.perf_counter()
    qroute = colgen.robots_bound(D, deadline, tours=tours,
                                 time_limit=QROUTE_SECONDS if time_limit is None else min(QROUTE_SECONDS, time_limit))
    cheap = qroute.robots()
    proof = f"the q-route LP bound {cheap} ({qroute.bound:.6g} rounded up)"
    if warm_start and len(warm_start) <= cheap:
        return MilpResult("optimal", routes=warm_start, objective=float(len(warm_start)), bound=float(cheap),
                          seconds=time.perf_counter() - began, message=f"{proof} meets the warm start's routes")
    handed, last = handed_reader(bound_file), {"bound": cheap}

    def proven() -> int:
        last["bound"] = max(last["bound"], handed() or 0)
        return last["bound"]

    left = None if time_limit is None else time_limit - (time.perf_counter() - began)
    routes = fewest_routes(D, deadline, tours=tours, seconds=1e9 if left is None else left,
                           seed=seed, floor=proven, start=warm_start,
                           found=None if routes_file is None else lambda found: hand_over(routes_file, found))
    seconds = time.perf_counter() - began
    if routes is None:
        return MilpResult("unknown", seconds=seconds, message="PyVRP found no routes within the deadline")
    bound = proven()  # once more: the root may have ended since the last read
    status = "optimal" if len(routes) <= bound else "feasible"
    whose = proof if bound == cheap else f"branch-and-price's root bound {bound}"
    return MilpResult(status, routes=routes, objective=float(len(routes)), bound=float(bound), seconds=seconds,
                      message=f"PyVRP's routes meet {whose}" if status == "optimal"
                      else "PyVRP's routes at the time limit")
