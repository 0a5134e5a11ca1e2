"""Baseline constructions that the paper's Section VI compares against.

Section VI compares the parallel path algorithm with a minimum spanning tree (MST,
Fig. 5(b)) and nearest neighbour (NN), and the parallel tour algorithm with the
k-TSP constructions kNN and kNI of Prop. 3. The tour-splitting heuristic of
Frederickson, Hecht and Kim (the paper's ref. [9]) is added as the classical
baseline with a performance guarantee.

Every method answers both route kinds and both objectives of
:class:`parcover.problem.Problem`:

- robot limit ``K``: minimise the makespan with at most ``K`` robots (``min(K, n)``
  robots are built; empty routes are dropped);
- deadline (given, or the least makespan ``c_max`` / ``2 c_max``): fewest robots with
  every route within it. Constructions with a robot count ``k`` as parameter
  (``knn``, ``kni``, ``split``) search the least ``k`` that meets the deadline
  (``split`` tries every ``k``; ``knn`` and ``kni`` double ``k``, then bisect,
  :func:`_least_robots`); when none does, routes that miss it are cut greedily into pieces that meet it
  (:func:`_cut_to_limit`). One KPOI per route meets every deadline ``>= c_max``
  (``>= 2 c_max`` for tours, paper Prop. 1), so the answer is always valid.

``knn`` and ``kni`` are not deadline-aware: all ``k`` robots start at once and
take the ``k`` KPOIs nearest the start, so under a tight deadline (``c_max``) they
typically need one robot per KPOI. They are meant for the robot-limit question, as
in the paper's Fig. 7 (4-NN and 4-NI tours).

Routes are lists of KPOI indices (rows of ``instance.distances``); the start (row 0)
is implicit. Travel between two consecutive KPOIs of a route is along the metric
closure, so a robot may pass through KPOIs covered by other robots. Ties are broken
by KPOI order, then by robot number (robots are numbered in the order they are
created), then by position in a route.

References
----------
.. [1] D. J. Rosenkrantz, R. E. Stearns, P. M. Lewis II, "An analysis of several
   heuristics for the traveling salesman problem", SIAM J. Comput. 6(3):563-581,
   1977. https://doi.org/10.1137/0206041
.. [2] G. N. Frederickson, M. S. Hecht, C. E. Kim, "Approximation algorithms for
   some routing problems", SIAM J. Comput. 7(2):178-193, 1978.
   https://doi.org/10.1137/0207017
.. [3] G. A. Croes, "A method for solving traveling-salesman problems", Operations
   Research 6(6):791-812, 1958. https://doi.org/10.1287/opre.6.6.791
"""

from __future__ import annotations

import heapq
import time
from collections.abc import Callable, Sequence

import numpy as np

from parcover.instance import Instance
from parcover.problem import MethodInfo, Problem, Solution, meets_deadline

__all__ = [
    "mst_branches",
    "nearest_neighbour",
    "k_nearest_neighbour",
    "k_nearest_insertion",
    "tour_split",
    "METHODS",
]

Route = list[int]
# A construction with ``k`` robots that gives up (None) once a route breaks a limit.
Build = Callable[[int, float | None], list[Route] | None]

# A 2-opt move must shorten the tour by more than this (relative to its length),
# so that zero distances (coincident KPOIs) and rounding never make it cycle.
_TWO_OPT_RTOL = 1e-12
# Fractions (in 32nds, van der Corput order) of the route where ``split`` first probes each k.
_SPLIT_PROBES = np.array([0, 16, 8, 24, 4, 20, 12, 28, 2, 18, 10, 26, 6, 22, 14, 30,
                          1, 17, 9, 25, 5, 21, 13, 29, 3, 19, 11, 27, 7, 23, 15, 31])
# Length of the neighbour lists of 2-opt's candidate moves, and rows per block when building them.
_NEIGHBOURS = 12
_NEIGHBOUR_BLOCK = 256
# Most first edges whose moves 2-opt evaluates in one numpy pass.
_TWO_OPT_BLOCK = 512
_TWO_OPT_FIRST = 16  # first edges per pass after a move (moves are dense in the first sweep)


# --------------------------------------------------------------------------- methods


def mst_branches(
    instance: Instance, problem: Problem, *, time_limit: float | None = None, seed: int = 0
) -> Solution:
    """Routes along the branches of a minimum spanning tree rooted at the start.

    The MST of the metric closure over the start and the KPOIs (Prim's algorithm,
    dense, ``O(n^2)``; ties to the lower KPOI index) is rooted at the start;
    children are visited in KPOI order.
    Its depth-first preorder, cut after every leaf, gives one route per leaf
    (paper Fig. 5(b)): the first leaf in DFS order gets its whole root-to-leaf
    branch; every later leaf gets the part of its branch not yet covered (the
    shared ancestors belong to the first leaf below them). Such a route goes from
    the start straight to its first uncovered node (through the closure), then
    down the tree; a tour returns to the start from the leaf.

    Adaptations (the paper's MST knows neither deadlines nor robot limits):

    - deadline: a branch that misses it is cut greedily into consecutive pieces,
      each the longest that meets it (:func:`_cut_to_limit`);
    - robot limit ``K``: with at most ``K`` leaves the branches are the answer
      (spare robots are not used to shorten them); otherwise the DFS preorder
      is cut into at most ``K`` consecutive pieces with the least makespan
      (:func:`_cut_into`).
    """
    d = instance.distances
    order, leaf = _mst_preorder(d)
    branches: list[Route] = []
    current: Route = []
    for v, is_leaf in zip(order, leaf):
        current.append(v)
        if is_leaf:
            branches.append(current)
            current = []
    if problem.robots is not None:
        if len(branches) <= problem.robots:
            return Solution(routes=branches)
        return Solution(routes=_cut_into(d, order, problem.robots, problem.tours))
    return Solution(routes=_meet_limit(d, branches, _deadline(instance, problem), problem.tours))


def nearest_neighbour(
    instance: Instance, problem: Problem, *, time_limit: float | None = None, seed: int = 0
) -> Solution:
    """Nearest-neighbour paths or tours (the paper's NN baseline, Section VI).

    - Deadline: a robot leaves the start and repeatedly moves to its nearest
      uncovered KPOI; when that move would break the deadline (for tours counting
      the return to the start), the robot stops and a new robot starts from the
      start. (A new robot has cost 0, the least, so robots are in effect built one
      after another.)
    - Robot limit ``K``: ``min(K, n)`` robots start together; each step the robot
      with the least cost so far (the cost walked, without the return of a tour)
      moves to its nearest uncovered KPOI.

    ``O(n^2)`` time, ``O(n)`` memory beyond the distance matrix.
    """
    d = instance.distances
    if problem.robots is not None:
        routes = _grow_nearest(d, min(problem.robots, instance.n), key_tours=False)
        assert routes is not None
        return Solution(routes=routes)
    return Solution(routes=_nearest_until_limit(d, _deadline(instance, problem), problem.tours))


def k_nearest_neighbour(
    instance: Instance, problem: Problem, *, time_limit: float | None = None, seed: int = 0
) -> Solution:
    """kNN (paper Prop. 3): ``k`` robots grow routes by nearest neighbour at once.

    Each step the robot whose current route is cheapest (a tour's cost includes
    the return to the start; ties to the lower robot number) appends its nearest
    uncovered KPOI. Robot limit ``K``: ``k = min(K, n)``. Deadline: the least ``k``
    whose routes meet it (:func:`_least_robots`). For paths under a robot limit this
    is the same construction as ``nn``.

    ``O(n^2 + n log k)`` time per ``k``.
    """
    d = instance.distances

    def build(k: int, limit: float | None) -> list[Route] | None:
        return _grow_nearest(d, k, key_tours=problem.tours, limit=limit)

    return _answer(instance, problem, build)


def k_nearest_insertion(
    instance: Instance, problem: Problem, *, time_limit: float | None = None, seed: int = 0
) -> Solution:
    """kNI (paper Prop. 3): ``k`` robots grow routes by nearest insertion at once.

    The rule, nearest insertion of Rosenkrantz, Stearns and Lewis [1]_ run on ``k``
    routes: each step the robot whose current route is cheapest (tour cost with the
    return; ties to the lower robot number) takes the uncovered KPOI nearest to its
    route (to any of its nodes, the start included) and inserts it where the
    route's cost grows least (between two consecutive nodes, or, for paths, also
    after the last; ties to the earliest position). Robot limit ``K``:
    ``k = min(K, n)``. Deadline: the least ``k`` whose routes meet it.

    ``O(n^2)`` time per ``k`` (:func:`_grow_insertion`); ``O(n)`` memory per robot
    that takes two KPOIs or more (its distances to all KPOIs).
    """
    d = instance.distances

    def build(k: int, limit: float | None) -> list[Route] | None:
        return _grow_insertion(d, k, problem.tours, limit=limit)

    return _answer(instance, problem, build)


def tour_split(
    instance: Instance, problem: Problem, *, time_limit: float | None = None, seed: int = 0
) -> Solution:
    """Frederickson-Hecht-Kim tour splitting (k-SPLITOUR [2]_; the paper's ref. [9]).

    One route through all KPOIs is built by nearest neighbour from the start and
    improved by 2-opt [3]_ (a tour for ``tours``; a path from the start with a free
    end for ``paths``), then cut into ``k`` consecutive pieces, each served by one
    robot from the start (:class:`_TourSplit`):

    - tours (k-SPLITOUR): with ``L`` the tour length, the ``j``-th cut
      (``j = 1..k-1``) is after the last KPOI whose tour-prefix length from the
      start is ``<= (j/k)(L - 2 c_max) + c_max``. With a ``rho``-approximate tour
      the makespan is within ``rho + 1 - 1/k`` of the optimum [2]_. (The basic cut
      rule; the refinement that may move a cut one node on is not implemented.)
    - paths (our analogue): the thresholds are ``(j/k)(L - c_max) + c_max``, so
      that the first piece (which starts at the start) and every later piece plus
      its ``<= c_max`` approach from the start get about equal length.

    Robot limit ``K``: ``k = min(K, n)`` (empty pieces are dropped). Deadline: the
    least ``k`` in ``1..n`` whose pieces meet it (every ``k`` is tried, all at
    once, :meth:`_TourSplit.least_pieces`); when none does, the ``n`` pieces are
    cut to the deadline. 2-opt (:func:`_two_opt`) stops at a local optimum or at
    ``time_limit``.
    """
    d = instance.distances
    started = time.perf_counter()
    first = _grow_nearest(d, 1, key_tours=False)
    assert first is not None
    split = _TourSplit(d, _two_opt(d, first[0], problem.tours, started, time_limit), problem.tours)
    if problem.robots is not None:
        return Solution(routes=split.routes(split.bounds(min(problem.robots, instance.n))))
    limit = _deadline(instance, problem)
    k = split.least_pieces(limit)
    if k is not None:
        return Solution(routes=split.routes(split.bounds(k)))
    return Solution(routes=_meet_limit(d, split.routes(split.bounds(instance.n)), limit, problem.tours))


# ------------------------------------------------------------ objective adaptations


def _deadline(instance: Instance, problem: Problem) -> float:
    """The deadline of the robots objective (given, or the least makespan)."""
    limit = problem.effective_deadline(instance)
    assert limit is not None
    return limit


def _answer(instance: Instance, problem: Problem, build: Build) -> Solution:
    """Answer ``problem`` with a construction parameterised by its robot count.

    ``build(k, limit)`` returns the routes of ``k`` robots, or ``None`` as soon as
    a route breaks ``limit`` (route costs only grow during these constructions,
    by the triangle inequality, so a broken route stays broken).
    """
    d = instance.distances
    n = instance.n
    if problem.robots is not None:
        routes = build(min(problem.robots, n), None)
        assert routes is not None
        return Solution(routes=routes)
    limit = _deadline(instance, problem)
    found = _least_robots(lambda k: build(k, limit), n)
    routes = build(n, None) if found is None else found
    assert routes is not None
    return Solution(routes=_meet_limit(d, routes, limit, problem.tours))


def _least_robots(build: Callable[[int], list[Route] | None], n: int) -> list[Route] | None:
    """Routes of the least ``k`` found for which ``build(k)`` succeeds (not ``None``).

    Searches ``k`` upward by doubling (1, 2, 4, ... capped at ``n``), then bisects
    between the last failing and the first succeeding ``k``: ``O(log n)``
    constructions instead of up to ``n``. It finds the least ``k`` when success is
    monotone in ``k``, which these constructions do not guarantee. ``None`` when
    even ``k = n`` fails.
    """
    failed, k = 0, 1
    routes = build(k)
    while routes is None:
        if k >= n:
            return None
        failed, k = k, min(2 * k, n)
        routes = build(k)
    low, high = failed + 1, k
    while low < high:
        middle = (low + high) // 2
        candidate = build(middle)
        if candidate is None:
            low = middle + 1
        else:
            high, routes = middle, candidate
    return routes


# ---------------------------------------------------------------- costs and cutting


def _route_cost(d: np.ndarray, route: Sequence[int], tours: bool) -> float:
    """Cost of one route from the start (and back to it for tours)."""
    nodes = np.asarray(route, dtype=np.intp)
    cost = float(d[0, nodes[0]] + d[nodes[:-1], nodes[1:]].sum())
    return cost + float(d[nodes[-1], 0]) if tours else cost


def _meet_limit(d: np.ndarray, routes: list[Route], limit: float, tours: bool) -> list[Route]:
    """Keep the routes that meet ``limit``; cut the others with :func:`_cut_to_limit`."""
    out: list[Route] = []
    for route in routes:
        if meets_deadline(_route_cost(d, route, tours), limit):
            out.append(route)
        else:
            out.extend(_cut_to_limit(d, route, limit, tours))
    return out


def _cut_to_limit(d: np.ndarray, sequence: Sequence[int], limit: float, tours: bool) -> list[Route]:
    """Cut ``sequence`` greedily into consecutive routes that each meet ``limit``.

    A route takes the next KPOI while its cost (with the return, for tours) stays
    within ``limit``, otherwise a new route starts at that KPOI. In a metric a
    sub-sequence never costs more than the sequence around it, so this gives the
    fewest consecutive pieces. A single KPOI is always a route of its own, so
    pieces miss ``limit`` only if a KPOI alone does.
    """
    pieces: list[Route] = []
    piece: Route = []
    cost = 0.0
    for v in sequence:
        if piece:
            extended = cost + float(d[piece[-1], v])
            back = float(d[v, 0]) if tours else 0.0
            if meets_deadline(extended + back, limit):
                piece.append(v)
                cost = extended
                continue
            pieces.append(piece)
        piece, cost = [v], float(d[0, v])
    if piece:
        pieces.append(piece)
    return pieces


def _cut_into(d: np.ndarray, sequence: Sequence[int], k: int, tours: bool) -> list[Route]:
    """At most ``k`` consecutive pieces of ``sequence`` with (about) the least makespan.

    Bisection on the makespan ``T``: :func:`_cut_to_limit` gives the fewest pieces
    meeting ``T``; the least ``T`` needing at most ``k`` pieces is found to a
    relative precision of ``1e-9``.
    """
    low = max(float(d[0, v]) * (2 if tours else 1) for v in sequence)
    high = _route_cost(d, sequence, tours)
    for _ in range(100):
        if high - low <= 1e-9 * max(high, 1.0):
            break
        middle = (low + high) / 2
        if len(_cut_to_limit(d, sequence, middle, tours)) <= k:
            high = middle
        else:
            low = middle
    return _cut_to_limit(d, sequence, high, tours)


# -------------------------------------------------------------------- constructions


def _mst_preorder(d: np.ndarray) -> tuple[list[int], list[bool]]:
    """DFS preorder of the MST (Prim, rooted at the start) and which nodes are leaves.

    Children are visited in KPOI order; the start itself is not listed.
    """
    size = d.shape[0]
    parent = np.zeros(size, dtype=np.intp)
    best = np.array(d[0], dtype=float)
    in_tree = np.zeros(size, dtype=bool)
    in_tree[0] = True
    best[0] = np.inf
    children: list[list[int]] = [[] for _ in range(size)]
    for _ in range(size - 1):
        # the nearest node outside the tree (by index among those, not np.argmin(best):
        # with infinite distances every entry ties and index 0 would join again)
        outside = np.flatnonzero(~in_tree)
        v = int(outside[np.argmin(best[outside])])
        in_tree[v] = True
        children[int(parent[v])].append(v)
        best[v] = np.inf
        closer = ~in_tree & (d[v] < best)
        best[closer] = d[v][closer]
        parent[closer] = v
    order: list[int] = []
    leaf: list[bool] = []
    stack = sorted(children[0], reverse=True)
    while stack:
        v = stack.pop()
        order.append(v)
        leaf.append(not children[v])
        stack.extend(sorted(children[v], reverse=True))
    return order, leaf


def _nearest_until_limit(d: np.ndarray, limit: float, tours: bool) -> list[Route]:
    """Sequential nearest neighbour: a new robot when the next move breaks ``limit``."""
    n = d.shape[0] - 1
    covered = np.zeros(n + 1)
    covered[0] = np.inf
    routes: list[Route] = []
    route: Route = []
    end, cost = 0, 0.0
    for _ in range(n):
        v = int(np.argmin(d[end] + covered))
        extended = cost + float(d[end, v])
        back = float(d[v, 0]) if tours else 0.0
        if route and not meets_deadline(extended + back, limit):
            routes.append(route)
            route = []
            v = int(np.argmin(d[0] + covered))
            extended = float(d[0, v])
        route.append(v)
        covered[v] = np.inf
        end, cost = v, extended
    routes.append(route)
    return routes


class _NearestToStart:
    """The uncovered KPOI nearest the start, in amortised ``O(1)``.

    One stable sort of the start's row (ties to the lower KPOI index, as
    ``argmin(d[0] + covered)`` breaks them) and a cursor that skips covered KPOIs.
    """

    def __init__(self, d: np.ndarray, covered: np.ndarray) -> None:
        self.order = np.argsort(d[0, 1:], kind="stable") + 1
        self.covered = covered  # 0 for uncovered KPOIs, inf otherwise (shared, updated by the caller)
        self.cursor = 0

    def next(self) -> int:
        while self.covered[self.order[self.cursor]] != 0:
            self.cursor += 1
        return int(self.order[self.cursor])


def _first_round(
    first: np.ndarray,
    first_costs: np.ndarray,
    first_keys: np.ndarray,
    routes: list[Route],
    costs: list[float],
    heap: list[tuple[float, int]],
    covered: np.ndarray,
) -> list[tuple[float, int]]:
    """The first round of :func:`_grow_nearest` and :func:`_grow_insertion` at once.

    All robots start at cost 0 and are popped in robot order; robot ``r`` takes the
    uncovered KPOI nearest the start, the ``r``-th of ``first``. When every such
    move leaves a positive key (checked by the caller), no robot is popped twice
    before all have moved, so the round is these ``len(first)`` moves, in order.
    Fills ``routes``, ``costs`` and ``covered`` and returns the new heap.
    """
    for r, (v, cost) in enumerate(zip(first.tolist(), first_costs.tolist())):
        routes[r].append(v)
        costs[r] = cost
    covered[first] = np.inf
    heap = [(key, r) for r, key in enumerate(first_keys.tolist())] + heap[len(first) :]
    heapq.heapify(heap)
    return heap


def _grow_nearest(
    d: np.ndarray, k: int, key_tours: bool, limit: float | None = None
) -> list[Route] | None:
    """``k`` robots; the cheapest (path cost, plus the return if ``key_tours``) appends
    its nearest uncovered KPOI. Empty routes are dropped; ``None`` as soon as a
    robot's cost (as ordered) breaks ``limit``.

    A robot still at the start takes the uncovered KPOI nearest the start
    (:class:`_NearestToStart`, amortised ``O(1)``), any other one a masked ``argmin``
    over its end's row (``O(n)``): ``O(n^2)`` time in all, and far less when many
    robots take one KPOI each (the deadline search tries ``k`` up to ``n``)."""
    n = d.shape[0] - 1
    covered = np.zeros(n + 1)
    covered[0] = np.inf
    from_start = _NearestToStart(d, covered)
    routes: list[Route] = [[] for _ in range(k)]
    ends = [0] * k
    costs = [0.0] * k
    heap = [(0.0, r) for r in range(k)]
    first = from_start.order[:k]
    first_costs = d[0, first]
    first_keys = first_costs + d[first, 0] if key_tours else first_costs
    if (first_keys > 0).all():  # robot r takes the r-th KPOI nearest the start (_first_round)
        if limit is not None and not meets_deadline(first_keys, limit).all():
            return None
        heap = _first_round(first, first_costs, first_keys, routes, costs, heap, covered)
        ends[: len(first)] = first.tolist()
    for _ in range(n - sum(map(len, routes))):
        _, r = heapq.heappop(heap)
        v = int(np.argmin(d[ends[r]] + covered)) if routes[r] else from_start.next()
        costs[r] += float(d[ends[r], v])
        routes[r].append(v)
        ends[r] = v
        covered[v] = np.inf
        key = costs[r] + (float(d[v, 0]) if key_tours else 0.0)
        if limit is not None and not meets_deadline(key, limit):
            return None
        heapq.heappush(heap, (key, r))
    return [route for route in routes if route]


def _grow_insertion(d: np.ndarray, k: int, tours: bool, limit: float | None = None) -> list[Route] | None:
    """``k`` robots; the cheapest inserts the uncovered KPOI nearest its route at the
    cheapest position ([1]_, run on ``k`` routes). Empty routes are dropped; ``None``
    as soon as a route breaks ``limit``.

    A robot still at the start takes the uncovered KPOI nearest the start
    (:class:`_NearestToStart`). A robot's distances to every KPOI (the minimum of
    its nodes' rows) are kept from its second step on and updated by one
    ``minimum`` per insertion, so each later step is one masked ``argmin``
    (``O(n)``) plus the insertion costs along its route: ``O(n^2)`` time, and
    ``O(n)`` memory per robot that takes two KPOIs or more."""
    n = d.shape[0] - 1
    covered = np.zeros(n + 1)
    covered[0] = np.inf
    from_start = _NearestToStart(d, covered)
    nearest: dict[int, np.ndarray] = {}  # robot -> distance of every KPOI to its route
    routes: list[Route] = [[] for _ in range(k)]
    costs = [0.0] * k
    heap = [(0.0, r) for r in range(k)]
    first = from_start.order[:k]
    first_costs = d[0, first] + d[first, 0] - d[0, 0] if tours else d[0, first]
    if (first_costs > 0).all():  # robot r takes the r-th KPOI nearest the start (_first_round)
        if limit is not None and not meets_deadline(first_costs, limit).all():
            return None
        heap = _first_round(first, first_costs, first_costs, routes, costs, heap, covered)
    masked = np.empty(n + 1)
    for _ in range(n - sum(map(len, routes))):
        _, r = heapq.heappop(heap)
        route = routes[r]
        if route:
            if r not in nearest:  # its first KPOI came from the start: the route is that KPOI alone
                nearest[r] = np.minimum(d[0], d[route[0]])
            v = int(np.add(nearest[r], covered, out=masked).argmin())
            nodes = np.array([0, *route, 0] if tours else [0, *route], dtype=np.intp)
            growth = d[nodes[:-1], v] + d[v, nodes[1:]] - d[nodes[:-1], nodes[1:]]
            if not tours:
                growth = np.append(growth, d[nodes[-1], v])
            position = int(np.argmin(growth))
            grown = float(growth[position])
        else:
            v = from_start.next()
            position = 0
            grown = float(d[0, v] + d[v, 0] - d[0, 0]) if tours else float(d[0, v])
        route.insert(position, v)
        costs[r] += grown
        if limit is not None and not meets_deadline(costs[r], limit):
            return None
        covered[v] = np.inf
        if r in nearest:
            np.minimum(nearest[r], d[v], out=nearest[r])
        heapq.heappush(heap, (costs[r], r))
    return [route for route in routes if route]


def _two_opt(
    d: np.ndarray, order: Route, tours: bool, started: float, time_limit: float | None
) -> Route:
    """2-opt [3]_ on a tour (or a path with a fixed start and a free end).

    Best-improvement per first edge: for each edge ``(a, b)`` of the route in turn,
    the reversal of ``b..c`` with the largest gain ``d(a,b) + d(c,e) - d(a,c) -
    d(b,e)`` is applied (ties to the first ``c`` along the route) when the gain
    exceeds ``_TWO_OPT_RTOL`` times the route length; sweeps repeat until none
    does, or until ``time_limit``. For a path, the edge after the last KPOI leads
    to a free end of cost 0. The moves are found in blocks of consecutive first
    edges (:class:`_TwoOpt`); the move applied is always the one this sequential
    rule applies.
    """
    state = _TwoOpt(d, order, tours)
    improved = True
    while improved:
        improved = False
        i, size = 0, _TWO_OPT_FIRST
        while i < state.last - 1:
            if time_limit is not None and time.perf_counter() - started > time_limit:
                return state.route()
            stop = min(i + size, state.last - 1)
            move = state.first_move(i, stop)
            if move is None:
                i, size = stop, min(2 * size, _TWO_OPT_BLOCK)
                continue
            state.reverse(*move)
            improved = True
            i, size = move[0] + 1, _TWO_OPT_FIRST
    return state.route()


class _TwoOpt:
    """A route under 2-opt, and its best move for each first edge of a block.

    Only candidate moves are evaluated: a positive gain needs ``d(a,c) < d(a,b)`` or
    ``d(b,e) < d(c,e)``, so ``c`` is nearer to ``a`` than ``b`` is, or ``b`` is nearer
    to ``e`` than ``e``'s predecessor on the route is (neighbour lists,
    :class:`_Neighbours`); the move through the last edge is always a candidate.
    Every other move has a gain ``<= 0`` (up to rounding far below the
    tolerance), so the best candidate is the best move, and its gain is the same
    floating-point expression. The lists serve both tests because
    ``Instance.distances`` is symmetric.
    """

    def __init__(self, d: np.ndarray, order: Route, tours: bool) -> None:
        self.d = d
        self.tours = tours
        self.sequence = np.array([0, *order, 0], dtype=np.intp)  # the last 0 is a path's free end
        m = len(self.sequence)
        self.last = m - 2  # the move whose e is the final node
        self.edges = d[self.sequence[:-1], self.sequence[1:]].astype(float)
        if not tours:
            self.edges[-1] = 0.0
        self.near = _Neighbours(d)
        # position[x]: index of KPOI x in `sequence`; entering[x]: length of the edge into it.
        self.position = np.full(d.shape[0], -1, dtype=np.intp)
        self.position[self.sequence[1:-1]] = np.arange(1, m - 1)
        self.entering = np.full(d.shape[0], -np.inf)
        self.entering[self.sequence[1:-1]] = self.edges[: m - 2]
        self._update_far()

    def _update_far(self) -> None:
        """The KPOIs whose entering edge reaches past their neighbour list."""
        self.far = (self.entering > self.near.radius).nonzero()[0]

    def route(self) -> Route:
        """The KPOIs in route order (start and end left out)."""
        return [int(v) for v in self.sequence[1:-1]]

    def first_move(self, start: int, stop: int) -> tuple[int, int] | None:
        """The first edge ``i`` in ``start..stop-1`` with an improving move, and the
        end ``j`` of the reversal ``sequence[i+1..j]``; ``None`` when there is none."""
        d, seq, edges = self.d, self.sequence, self.edges
        first = np.arange(start, stop)
        a, b, ab = seq[first], seq[first + 1], edges[first]
        rows, cs = self.near.within_rows(a, ab)
        held_rows, es = self.near.holding_rows(b)
        far = self.far
        rows_e = np.concatenate((held_rows, np.repeat(np.arange(len(first)), len(far))))
        es = np.concatenate((es, np.tile(far, len(first))))
        keep = d[b[rows_e], es] < self.entering[es]
        rows = np.concatenate((rows, rows_e[keep], np.arange(len(first))))
        js = np.concatenate((self.position[cs], self.position[es[keep]] - 1, np.full(len(first), self.last)))
        keep = js >= first[rows] + 2
        rows, js = rows[keep], js[keep]
        new_second = d[b[rows], seq[js + 1]]
        if not self.tours:
            new_second[js == self.last] = 0.0
        gain = ab[rows] + edges[js] - d[a[rows], seq[js]] - new_second
        if not (gain > 0).any():
            return None
        good = gain > _TWO_OPT_RTOL * max(float(edges.sum()), 1.0)
        if not good.any():
            return None
        row = rows[good].min()
        mine = rows == row
        top = gain[mine].max()
        return int(first[row]), int(js[mine][gain[mine] == top].min())

    def reverse(self, i: int, j: int) -> None:
        """Reverse ``sequence[i+1..j]`` and update the edges, positions and entering edges."""
        d, seq, edges = self.d, self.sequence, self.edges
        seq[i + 1 : j + 1] = seq[i + 1 : j + 1][::-1].copy()
        edges[i + 1 : j] = edges[i + 1 : j][::-1].copy()
        edges[i] = d[seq[i], seq[i + 1]]
        edges[j] = d[seq[j], seq[j + 1]] if (self.tours or j < self.last) else 0.0
        self.position[seq[i + 1 : j + 1]] = np.arange(i + 1, j + 1)
        self.entering[seq[i + 1 : j + 2]] = edges[i : j + 1]
        self.entering[0] = -np.inf
        self._update_far()


class _Neighbours:
    """Each row's ``_NEIGHBOURS`` nearest columns, for the candidate moves of :class:`_TwoOpt`.

    ``radius[x]`` is the next distance in row ``x`` after its list: every ``y`` with
    ``matrix[x, y] < radius[x]`` is in the list of ``x``. Built in blocks of rows with
    ``argpartition``: ``O(n^2)`` time, ``O(n)`` memory per row of a block.
    """

    def __init__(self, matrix: np.ndarray) -> None:
        size = matrix.shape[0]
        count = min(_NEIGHBOURS, size - 1)
        self.matrix = matrix
        self.lists = np.empty((size, count), dtype=np.intp)
        self.dist = np.empty((size, count))
        self.radius = np.empty(size)
        for top in range(0, size, _NEIGHBOUR_BLOCK):
            rows = np.asarray(matrix[top : top + _NEIGHBOUR_BLOCK])
            block = slice(top, top + len(rows))
            parted = np.argpartition(rows, count, axis=1)  # count <= size - 1: column `count` exists
            self.lists[block] = parted[:, :count]
            self.dist[block] = np.take_along_axis(rows, parted[:, :count], 1)
            self.radius[block] = np.take_along_axis(rows, parted[:, count : count + 1], 1)[:, 0]
        # The reverse lists (column y -> the rows whose list holds y), as CSR.
        flat = self.lists.ravel()
        by_column = np.argsort(flat, kind="stable")
        self.holders = np.repeat(np.arange(size), count)[by_column]
        self.holder_start = np.searchsorted(flat[by_column], np.arange(size + 1))

    def within_rows(self, xs: np.ndarray, rs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Pairs ``(k, y)`` with ``matrix[xs[k], y] < rs[k]``, as two arrays."""
        short = rs <= self.radius[xs]
        hit = short[:, None] & (self.dist[xs] < rs[:, None])
        rows, cols = hit.nonzero()
        ys = self.lists[xs[rows], cols]
        extra_rows, extra_ys = [rows], [ys]
        for k in np.flatnonzero(~short):
            found = (self.matrix[xs[k]] < rs[k]).nonzero()[0]
            extra_rows.append(np.full(len(found), k))
            extra_ys.append(found)
        return np.concatenate(extra_rows), np.concatenate(extra_ys)

    def holding_rows(self, ys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Pairs ``(k, x)`` with column ``ys[k]`` in the list of row ``x``, as two arrays."""
        begin, end = self.holder_start[ys], self.holder_start[ys + 1]
        counts = end - begin
        rows = np.repeat(np.arange(len(ys)), counts)
        offsets = np.arange(int(counts.sum())) - np.repeat(np.cumsum(counts) - counts, counts)
        return rows, self.holders[np.repeat(begin, counts) + offsets]


class _TourSplit:
    """Cuts of one route through all KPOIs into consecutive pieces (k-SPLITOUR [2]_).

    Piece costs come from prefix lengths along the route, so each piece costs
    ``O(1)`` (a binary search for its boundary aside).
    """

    def __init__(self, d: np.ndarray, order: Route, tours: bool) -> None:
        self.d = d
        self.order = np.asarray(order, dtype=np.intp)
        self.tours = tours
        # prefix[i]: length along the route from the start to order[i]
        self.prefix = d[0, self.order[0]] + np.concatenate(
            ([0.0], np.cumsum(d[self.order[:-1], self.order[1:]]))
        )
        back = float(d[self.order[-1], 0]) if tours else 0.0
        self.c_max = float(d[0, 1:].max())
        self.spare = float(self.prefix[-1]) + back - (2 if tours else 1) * self.c_max

    def bounds(self, k: int) -> np.ndarray:
        """Piece boundaries ``0 = b_0 < ... = n`` (empty pieces removed): cut ``j`` is
        after the last KPOI with prefix ``<= c_max + (j/k) * spare``, where ``spare``
        is ``L - 2 c_max`` for tours and ``L - c_max`` for paths."""
        thresholds = self.c_max + np.arange(1, k) / k * self.spare
        cuts = np.searchsorted(self.prefix, thresholds, side="right")
        bounds = np.concatenate(([0], np.maximum.accumulate(cuts), [len(self.order)]))
        return bounds[np.concatenate(([True], np.diff(bounds) > 0))]

    def _boundary(self, j: np.ndarray, k: np.ndarray) -> np.ndarray:
        """Boundary ``b_j`` of :meth:`bounds` (``0 <= j <= k``, empty pieces kept),
        elementwise, by the same floating-point expressions."""
        n = len(self.order)
        step = np.where(j > 0, j, 1) if self.spare < 0 else j  # decreasing thresholds: max is at j = 1
        cut = np.searchsorted(self.prefix, self.c_max + step / k * self.spare, side="right")
        return np.where(j == 0, 0, np.where(j == k, n, cut))

    def _misses(self, j: np.ndarray, k: np.ndarray, limit: float) -> np.ndarray:
        """Whether piece ``j`` of the ``k`` pieces is non-empty and misses ``limit``
        (elementwise). A piece ``[a, b)`` costs ``d(s, order[a])`` plus its length
        along the route (``prefix[b-1] - prefix[a]``), plus ``d(order[b-1], s)``
        for tours."""
        j, k = np.broadcast_arrays(j, k)
        a, b = self._boundary(j, k), self._boundary(np.minimum(j + 1, k), k)
        piece = (j < k) & (a < b)
        a, b = a[piece], b[piece]
        cost = self.d[0, self.order[a]] + self.prefix[b - 1] - self.prefix[a]
        if self.tours:
            cost = cost + self.d[self.order[b - 1], 0]
        missed = np.zeros(piece.shape, dtype=bool)
        missed[piece] = ~meets_deadline(cost, limit)
        return missed

    def least_pieces(self, limit: float) -> int | None:
        """The least ``k`` in ``1..n`` whose pieces all meet ``limit`` (``None`` if none).

        All ``k`` are tested together, and a ``k`` is dropped at the first piece
        found to miss ``limit``: first probes, the pieces at 32 fractions of the
        route (costly pieces cluster along it) and those about the 32 KPOIs
        costliest to serve alone, then every piece in order, 8, 16, 32, ... pieces
        per pass. After a pass every ``k`` up to the pieces tested is
        decided, so the least surviving one is the answer. When most ``k`` fail at
        a probe (paths at ``c_max``, typically) far fewer than the ``n^2 / 2``
        pieces of all ``k`` are evaluated; otherwise up to all of them.
        """
        alive = np.arange(1, len(self.order) + 1)
        k = alive[:, None]
        probes = [k * _SPLIT_PROBES // 32]
        if self.spare > 0:
            # The pieces that hold the KPOIs costliest to serve alone (about: any piece may be probed).
            alone = self.d[0, self.order] + (self.d[self.order, 0] if self.tours else 0.0)
            hot = np.argsort(-alone, kind="stable")[: len(_SPLIT_PROBES)]
            share = (self.prefix[hot] - self.c_max) / self.spare
            probes.append(np.clip(np.ceil(share[None, :] * k).astype(np.intp) - 1, 0, k - 1))
        alive = alive[~self._misses(np.hstack(probes), k, limit).any(axis=1)]
        done, step = 0, 8
        while alive.size:
            j = np.arange(done, done + step)
            alive = alive[~self._misses(j[None, :], alive[:, None], limit).any(axis=1)]
            done += step
            decided = alive[alive <= done]
            if decided.size:
                return int(decided[0])
            alive, step = alive[alive > done], 2 * step
        return None

    def routes(self, bounds: np.ndarray) -> list[Route]:
        """The pieces as routes."""
        return [[int(v) for v in self.order[a:b]] for a, b in zip(bounds[:-1], bounds[1:])]


METHODS = (
    MethodInfo(
        "mst", mst_branches, "branches of a minimum spanning tree rooted at the start (paper Fig. 5(b))"
    ),
    MethodInfo("nn", nearest_neighbour, "nearest neighbour; a new robot when the deadline would break"),
    MethodInfo("knn", k_nearest_neighbour, "k robots grow routes by nearest neighbour (paper Prop. 3)"),
    MethodInfo("kni", k_nearest_insertion, "k robots grow routes by nearest insertion (paper Prop. 3)"),
    MethodInfo("split", tour_split, "Frederickson-Hecht-Kim: one 2-opt route cut into k pieces"),
)
