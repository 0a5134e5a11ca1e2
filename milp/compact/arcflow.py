r"""Compact arc-flow MILP (two-index arcs plus distance flow), solved with HiGHS.

The distance-flow idea follows Kara (2011), "Arc based integer programming formulations
for the distance constrained vehicle routing problem" (DCVRP): a continuous variable on
each arc carries the distance travelled so far, which both bounds route lengths and
eliminates subtours.

Notation
--------
Node 0 is the start, :math:`N = \{1..m\}` the KPOIs *after merging* KPOIs at distance 0
(see :mod:`milp.core.merge`), :math:`E` an end node: the sink of open paths with
:math:`d_{iE} = 0`, or the return to the start with :math:`d_{iE} = d_{i0}` for tours.
Arcs :math:`A`: :math:`(0, j)` for :math:`j \in N`; :math:`(i, j)` for
:math:`i \ne j \in N`; :math:`(i, E)` for :math:`i \in N`. :math:`r_j = 0` for paths,
:math:`r_j = d_{j0}` for tours (:math:`r_E = 0`): the least distance still to go after
:math:`j`. :math:`U` is the deadline (``min_robots``) or the makespan of a known valid
solution (``min_makespan``). :math:`L` is the larger of :math:`c_{max}` (paths) /
:math:`2 c_{max}` (tours) and a spanning-tree bound (:func:`makespan_lower_bound`).

Pruning: arc :math:`(i, j)` is dropped when :math:`d_{0i} + d_{ij} + r_j > U`
(with :math:`d_{00} = 0`): no route within :math:`U` can use it.

Variables: :math:`x_a \in \{0, 1\}` (arc used), :math:`z_a \ge 0` (distance travelled on
arrival at the head of :math:`a`), :math:`T` (makespan, ``min_makespan`` only).

.. math::

    (1)&\quad \sum_{a \in \delta^+(0)} x_a \le k \ \text{(min\_makespan)}, \quad
        \sum_{a \in \delta^+(0)} x_a \ge Q \ \text{(min\_robots)} \\
    (2)&\quad \sum_{a \in \delta^-(j)} x_a = 1, \quad \sum_{a \in \delta^+(j)} x_a = 1
        && j \in N \\
    (3)&\quad \sum_{a \in \delta^+(j)} z_a - \sum_{a \in \delta^-(j)} z_a
        = \sum_{a \in \delta^+(j)} d_a x_a && j \in N \\
    (4)&\quad z_{0j} = d_{0j} x_{0j} && j \in N \\
    (5)&\quad (d_{0i} + d_{ij}) x_{ij} \le z_{ij} \le (U - r_j) x_{ij}
        && (i, j) \in A,\ i \ne 0 \\
    (6)&\quad z_{iE} \le T && i \in N \text{ (min\_makespan)} \\
    (7)&\quad \sum_{a \in A} d_a x_a \le k T \ \text{(min\_makespan)}, \quad
        \sum_{a \in A} d_a x_a \le U \sum_{a \in \delta^+(0)} x_a \ \text{(min\_robots)} \\
    (8)&\quad L \le T \le U && \text{(min\_makespan)}

Objective: minimise :math:`T` (``min_makespan``) or :math:`\sum_{a\in\delta^+(0)} x_a`
(``min_robots``, where the deadline enters through (5) with :math:`U` = deadline;
:math:`Q` is the spanning-tree bound of :func:`robots_lower_bound` in :func:`build_model`,
the column-generation bound of :mod:`milp.branchprice.colgen` in :func:`min_robots`).

Why it is exact. (2) makes the used arcs a set of node-disjoint paths from 0 to E plus
possibly cycles inside N. Summing (3) around a cycle inside N gives
:math:`0 = \sum d_a` over its arcs, impossible because after merging every distance
between distinct KPOIs is positive: so only routes 0 -> ... -> E remain. Along a route,
(4) and (3) make :math:`z` the cumulative distance, so :math:`z_{iE}` is the route cost,
bounded by (5) and (6). (5)'s lower bound holds because the distance on arrival at j
via i is at least :math:`d_{0i} + d_{ij}` (triangle inequality). (7) is valid because the
total length of all routes is at most (number of routes) x (largest route); the same
spanning-tree argument bounds the number of routes from below in (1), and so does the
stronger certified bound of :mod:`milp.branchprice.colgen` (the LP over routes), which min_robots
uses for ``Q``; min_makespan reports colgen's makespan bound when HiGHS stops unproven
(as a hard bound on T inside the model it slows HiGHS down). (8): every
KPOI is at distance at most the makespan from the start (twice for tours), and the
routes together contain a spanning tree (see :func:`makespan_lower_bound`).
Pruning with :math:`U` = a known makespan keeps every solution at least as good.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from math import ceil
from pathlib import Path

import highspy
import numpy as np
from scipy import sparse

from milp.branchprice import colgen
from milp.bounds import makespan_lower_bound, robots_lower_bound
from milp.core.highs import BOUND_SLACK, LpSolve, make_lp, solve_lp, write_model
from milp.core.merge import Merged, merge_zero_distances
from milp.core.result import MilpResult, relative_gap
from milp.core.routes import (
    check_distance_matrix,
    check_routes,
    least_makespan,
    makespan,
    route_cost,
    within,
)
from milp.core.timelimit import TimeLimit, TimeLimitLike
from milp.warmstart import good_makespan_routes, nearest_neighbour_order, split_fits, split_min_robots


#: HiGHS search options for this model. The warm start is already good, so HiGHS'
#: primal heuristics (RINS, RENS, reduced-cost sub-MIPs) and root restarts mostly cost
#: time here: about 1.6x faster overall on random Euclidean 10-20 KPOIs (measured).
SEARCH_OPTIONS = {
    "mip_allow_restart": False,
    "mip_heuristic_effort": 0.0,
    "mip_heuristic_run_rins": False,
    "mip_heuristic_run_rens": False,
    "mip_heuristic_run_root_reduced_cost": False,
}
#: Share of a time limit spent at most (roughly) on the warm-start heuristics.
HEURISTIC_SHARE = 0.2
#: Share of a time limit kept back from HiGHS in min_makespan for the column-generation
#: bound, computed only when HiGHS stops before proving the optimum.
BOUND_SHARE = 0.1
#: Seconds per arc to assemble the model and hand it to HiGHS (6.7 microseconds
#: measured at 1000 KPOIs, 865,000 arcs, rounded up), and HiGHS' overrun of its time
#: limit per arc, by objective: its presolve is not interrupted and takes up to 8.6
#: microseconds per arc on the makespan model (1000 KPOIs) but 25-50 on the robots model
#: (200-400 KPOIs, tours). Under a time limit the model is built only when the rest of
#: the limit covers twice set-up plus overrun, and HiGHS' limit is cut by the overrun.
SETUP_SECONDS_PER_ARC = 8e-6
OVERRUN_SECONDS_PER_ARC = {"makespan": 1e-5, "robots": 6e-5}


@dataclass(frozen=True)
class ArcModel:
    """The arc-flow MILP over a merged instance and how to read its columns.

    Attributes
    ----------
    lp : highspy.HighsLp
        The model; columns are ``x`` (one per arc), then ``z`` (one per arc), then ``T``
        for ``min_makespan``.
    merged : Merged
        The merged instance (model node ``c`` stands for ``merged.groups[c - 1]``).
    tail, head : numpy.ndarray
        Arc end points; ``head == m + 1`` is the end node E.
    tours : bool
        Route kind.
    """

    lp: highspy.HighsLp
    merged: Merged
    tail: np.ndarray
    head: np.ndarray
    tours: bool

    @property
    def num_arcs(self) -> int:
        """Number of arcs kept after pruning."""
        return len(self.tail)

    def write(self, path: str | Path) -> Path:
        """Export the model to ``.mps`` or ``.lp`` (see :func:`milp.core.highs.write_model`)."""
        return write_model(self.lp, path)

    def start_vector(self, routes: list[list[int]]) -> np.ndarray:
        """Column values (x, z, and T if present) of model-space ``routes``."""
        D, m = self.merged.D, self.merged.size
        index = np.full((m + 1, m + 2), -1)
        index[self.tail, self.head] = np.arange(self.num_arcs)
        x = np.zeros(self.num_arcs)
        z = np.zeros(self.num_arcs)
        for route in routes:
            stops = [0, *route]
            arrival = np.cumsum(D[stops[:-1], stops[1:]])
            arcs = index[stops[:-1], stops[1:]]
            end = index[route[-1], m + 1]
            if np.any(arcs < 0) or end < 0:
                raise ValueError("warm start uses an arc pruned from the model")
            x[arcs], z[arcs] = 1.0, arrival
            x[end], z[end] = 1.0, arrival[-1] + (D[route[-1], 0] if self.tours else 0.0)
        extra = self.lp.num_col_ - 2 * self.num_arcs
        T = [makespan(D, routes, tours=self.tours)] * extra
        return np.concatenate([x, z, T])

    def routes_from(self, values: np.ndarray) -> list[list[int]]:
        """Model-space routes read from the arc variables of a solution."""
        m = self.merged.size
        used = values[: self.num_arcs] > 0.5
        tails, heads = self.tail[used], self.head[used]
        successor = dict(zip(tails[tails > 0].tolist(), heads[tails > 0].tolist()))
        routes = []
        for first in heads[tails == 0].tolist():
            route = [first]
            while successor[route[-1]] != m + 1:
                route.append(successor[route[-1]])
            routes.append(route)
        if sorted(i for r in routes for i in r) != list(range(1, m + 1)):
            raise AssertionError("arc solution is not a partition into routes")
        return routes


def build_model(
    D: np.ndarray,
    *,
    tours: bool,
    k: int | None = None,
    deadline: float | None = None,
    upper: float | None = None,
) -> ArcModel:
    """Build the arc-flow model for ``min_makespan`` (give ``k``) or ``min_robots``
    (give ``deadline``).

    Parameters
    ----------
    D : numpy.ndarray
        ``(n+1, n+1)`` metric distance matrix, index 0 the start.
    tours : bool
        Tours (return to 0) or open paths.
    k : int, optional
        Robots available: builds the ``min_makespan`` model.
    deadline : float, optional
        Builds the ``min_robots`` model with this deadline as ``U``.
    upper : float, optional
        ``min_makespan`` only: a known achievable makespan, used as ``U`` for pruning and
        in (5), (8). Default: the makespan of :func:`milp.warmstart.good_makespan_routes`.

    Returns
    -------
    ArcModel
    """
    D = check_distance_matrix(D)
    if (k is None) == (deadline is None):
        raise ValueError("give exactly one of k (min_makespan) or deadline (min_robots)")
    merged = merge_zero_distances(D)
    if merged.size == 0:
        raise ValueError("every KPOI is at the start: nothing to model")
    if k is not None:
        if upper is None:
            upper = makespan(merged.D, good_makespan_routes(merged.D, k, tours=tours), tours=tours)
        return _assemble(merged, tours=tours, U=upper, k=k)
    fewest = robots_lower_bound(merged.D, float(deadline), tours=tours)
    return _assemble(merged, tours=tours, U=float(deadline), k=None, fewest=fewest)


def _arcs(D: np.ndarray, *, tours: bool, U: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Tails, heads and lengths of the arcs that can lie on a route within ``U``."""
    m = len(D) - 1
    tail, head = np.nonzero(_kept(D, tours=tours, U=U))
    inner = head <= m
    length = np.zeros(len(tail))
    length[inner] = D[tail[inner], head[inner]]
    if tours:
        length[~inner] = D[tail[~inner], 0]
    return tail, head, length


def _kept(D: np.ndarray, *, tours: bool, U: float) -> np.ndarray:
    """``keep[i, j]``: whether arc ``(i, j)`` is in the model (column ``m + 1`` is E):
    ``i != j``, ``j != 0``, not ``(0, E)``, and ``d_0i + d_ij + r_j`` within ``U``.

    One float temporary the size of ``D``: :func:`_model_fits` counts the arcs of every
    model first (measured at 3000 KPOIs: 0.02 s, against 0.5 s and five such arrays when
    built with index grids)."""
    m = len(D) - 1
    E = m + 1
    keep = np.empty((m + 1, m + 2), dtype=bool)
    reach = D[0][:, None] + D  # d_0i + d_ij, d_00 = 0
    if tours:
        reach += D[:, 0][None, :]  # + r_j
    keep[:, :E] = within(reach, U)
    keep[:, E] = within(D[0] + (D[:, 0] if tours else 0.0), U)  # r_E = 0
    keep[np.arange(m + 1), np.arange(m + 1)] = False
    keep[:, 0] = False
    keep[0, E] = False
    return keep


def _assemble(
    merged: Merged, *, tours: bool, U: float, k: int | None, fewest: int = 1
) -> ArcModel:
    """Constraint matrix, bounds and objective of the model, numbered as in the docstring."""
    D, m = merged.D, merged.size
    tail, head, length = _arcs(D, tours=tours, U=U)
    A = len(tail)
    E = m + 1
    arc = np.arange(A)
    x, z = arc, A + arc
    T = 2 * A
    num_col = 2 * A + (1 if k is not None else 0)
    rows, cols, vals, lower, upper, names = [], [], [], [], [], []

    def add(r, c, v, lo, hi, name):
        """Append a block of rows given as coordinate triplets (row ids are local)."""
        offset = len(names)
        names.extend(f"{name}_{i}" for i in range(len(lo)))
        rows.append(np.asarray(r) + offset)
        cols.append(np.asarray(c))
        vals.append(np.asarray(v, dtype=np.float64))
        lower.append(np.asarray(lo, dtype=np.float64))
        upper.append(np.asarray(hi, dtype=np.float64))

    from_start = tail == 0
    inner = ~from_start
    s = from_start.sum()
    # (1) at most k routes (min_makespan) / at least Q routes (min_robots)
    bounds = ([-np.inf], [k]) if k is not None else ([fewest], [np.inf])
    add(np.zeros(s), x[from_start], np.ones(s), *bounds, "c1_robots")
    # (2) in-degree and out-degree of each KPOI j (rows j-1 and m+j-1)
    into = head <= m
    add(head[into] - 1, x[into], np.ones(into.sum()), np.ones(m), np.ones(m), "c2_in")
    add(tail[inner] - 1, x[inner], np.ones(inner.sum()), np.ones(m), np.ones(m), "c2_out")
    # (3) distance flow: out z - in z - out d x = 0 at each KPOI
    add(
        np.concatenate([tail[inner] - 1, head[into] - 1, tail[inner] - 1]),
        np.concatenate([z[inner], z[into], x[inner]]),
        np.concatenate([np.ones(inner.sum()), -np.ones(into.sum()), -length[inner]]),
        np.zeros(m),
        np.zeros(m),
        "c3_flow",
    )
    # (4) z_0j = d_0j x_0j
    add(np.tile(np.arange(s), 2), np.concatenate([z[from_start], x[from_start]]),
        np.concatenate([np.ones(s), -length[from_start]]), np.zeros(s), np.zeros(s), "c4_first")
    # (5) (d_0i + d_ij) x <= z <= (U - r_j) x on arcs out of KPOIs
    q = inner.sum()
    reach = D[0, tail[inner]] + length[inner]
    to_go = np.where(head[inner] == E, 0.0, D[head[inner] % E, 0] if tours else 0.0)
    add(np.tile(np.arange(q), 2), np.concatenate([z[inner], x[inner]]),
        np.concatenate([np.ones(q), -reach]), np.zeros(q), np.full(q, np.inf), "c5_low")
    add(np.tile(np.arange(q), 2), np.concatenate([z[inner], x[inner]]),
        np.concatenate([np.ones(q), -(U - to_go)]), np.full(q, -np.inf), np.zeros(q), "c5_up")
    if k is not None:
        ends = head == E  # (6) z_iE <= T
        e = ends.sum()
        add(np.tile(np.arange(e), 2), np.concatenate([z[ends], np.full(e, T)]),
            np.concatenate([np.ones(e), -np.ones(e)]), np.full(e, -np.inf), np.zeros(e), "c6_end")
        # (7) sum d x <= k T
        add(np.zeros(A + 1), np.append(x, T), np.append(length, -k), [-np.inf], [0.0], "c7_total")
    else:  # (7) sum d x <= U sum_{out of 0} x
        add(np.zeros(A), x, length - U * from_start, [-np.inf], [0.0], "c7_total")

    matrix = sparse.coo_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
        shape=(len(np.concatenate(lower)), num_col),
    )
    z_upper = U - np.where(head == E, 0.0, D[head % E, 0] if tours else 0.0)
    col_lower = np.zeros(num_col)
    col_upper = np.concatenate([np.ones(A), np.maximum(z_upper, 0.0)])
    cost = np.zeros(num_col)
    if k is not None:  # (8) L <= T <= U
        L = makespan_lower_bound(D, k, tours=tours)
        col_lower[T], cost[T] = L, 1.0
        col_upper = np.append(col_upper, max(U, L))
    else:
        cost[x[from_start]] = 1.0
    integer = np.arange(num_col) < A
    lp = make_lp(cost, (col_lower, col_upper), matrix,
                 (np.concatenate(lower), np.concatenate(upper)), integer)
    head_name = [str(j) for j in range(m + 1)] + ["E"]
    arc_names = [f"{i}_{head_name[j]}" for i, j in zip(tail.tolist(), head.tolist())]
    lp.col_names_ = ([f"x_{a}" for a in arc_names] + [f"z_{a}" for a in arc_names]
                     + ["T"] * (k is not None))
    lp.row_names_ = names
    return ArcModel(lp, merged, tail, head, tours)


def min_makespan(
    D: np.ndarray,
    k: int,
    *,
    tours: bool,
    time_limit: TimeLimitLike = None,
    warm_start: list[list[int]] | None = None,
) -> MilpResult:
    """Least makespan with at most ``k`` robots.

    Parameters
    ----------
    D : numpy.ndarray
        ``(n+1, n+1)`` metric distance matrix, index 0 the start.
    k : int
        Robots available (at least 1; fewer may be used).
    tours : bool
        Tours (return to 0) or open paths.
    time_limit : float or milp.core.timelimit.TimeLimit, optional
        Seconds for the whole call (heuristic, model, HiGHS, column-generation bound),
        or a deadline shared with the caller; None for no limit. When the rest of the
        limit cannot cover building the model (:func:`_model_fits`), the heuristic's
        routes are returned with the spanning-tree bound.
    warm_start : list of list of int, optional
        A valid solution with at most ``k`` routes; its makespan bounds the model.

    Returns
    -------
    MilpResult
        ``objective`` is the makespan.
    """
    began = time.perf_counter()
    time_limit = TimeLimit.of(time_limit)
    D = check_distance_matrix(D)
    if k < 1:
        raise ValueError("k must be at least 1")
    merged = merge_zero_distances(D)
    if warm_start is not None and len(check_routes(warm_start, len(D) - 1)) > k:
        raise ValueError(f"warm start has more than k={k} routes")
    if merged.size == 0:
        return _proven(D, merged.expand([]), tours, 0.0, began, "every KPOI is at the start")
    start = _best_makespan_start(merged, k, tours, warm_start, time_limit.fraction(HEURISTIC_SHARE))
    upper = makespan(merged.D, start, tours=tours)
    L = makespan_lower_bound(merged.D, k, tours=tours, time_limit=time_limit.remaining())
    if upper <= L * (1 + BOUND_SLACK * 1e-3):
        return _proven(D, merged.expand(start), tours, L, began, "warm start meets the lower bound")
    arcs = int(np.count_nonzero(_kept(merged.D, tours=tours, U=upper)))
    if not _model_fits(arcs, "makespan", time_limit):
        routes = merged.expand(start)
        return _unsolved(D, routes, makespan(D, routes, tours=tours), L, began, arcs)
    model = _assemble(merged, tours=tours, U=upper, k=k)
    solve = solve_lp(model.lp, time_limit=_highs_seconds(time_limit, arcs, "makespan", BOUND_SHARE),
                     start=model.start_vector(start), options=SEARCH_OPTIONS)
    if solve.status != "optimal" and not time_limit.expired():
        # The compact LP bound is weak (milp/README.md): column generation's is far stronger.
        # Computed only now, because as a hard bound on T it slows HiGHS down.
        incumbent = min(upper, solve.objective if solve.objective is not None else upper)
        L = max(L, colgen.makespan_lower_bound(merged.D, k, tours=tours, upper=incumbent, time_limit=time_limit))
    return _makespan_result(D, model, solve, start, L, began)


def _model_fits(arcs: int, objective: str, time_limit: TimeLimit) -> bool:
    """Whether the rest of the time limit covers twice the set-up of a model of ``arcs``
    arcs for ``objective`` (assembly and HiGHS' uninterrupted presolve,
    :data:`SETUP_SECONDS_PER_ARC` and :data:`OVERRUN_SECONDS_PER_ARC`), so that HiGHS
    gets to search."""
    left = time_limit.remaining()
    per_arc = SETUP_SECONDS_PER_ARC + OVERRUN_SECONDS_PER_ARC[objective]
    return left is None or left >= 2 * arcs * per_arc


def _highs_seconds(time_limit: TimeLimit, arcs: int, objective: str, reserve_share: float = 0.0) -> float | None:
    """HiGHS' time limit: the rest of ``clock`` less ``reserve_share`` of it (kept for
    later work) and less HiGHS' expected overrun on a model of ``arcs`` arcs."""
    left = time_limit.remaining()
    if left is None:
        return None
    return max((1 - reserve_share) * left - arcs * OVERRUN_SECONDS_PER_ARC[objective], 0.0)


def _unsolved(
    D: np.ndarray, routes: list[list[int]], value: float, bound: float, began: float, arcs: int
) -> MilpResult:
    """The warm start (objective ``value``), ``feasible`` with ``bound``, when the model
    cannot be built in time."""
    check_routes(routes, len(D) - 1)
    bound = min(bound, value)
    return MilpResult("feasible", routes, value, bound, relative_gap(value, bound), 0,
                      time.perf_counter() - began,
                      f"time limit: no time left to build the model ({arcs} arcs)")


def _best_makespan_start(
    merged: Merged, k: int, tours: bool, warm_start: list[list[int]] | None,
    time_limit: TimeLimit,
) -> list[list[int]]:
    """The better of the given warm start and the heuristic solution (model space)."""
    candidates = [good_makespan_routes(merged.D, k, tours=tours, time_limit=time_limit)]
    if warm_start is not None:
        candidates.append(merged.reduce(warm_start))
    return min(candidates, key=lambda routes: makespan(merged.D, routes, tours=tours))


def _makespan_result(
    D: np.ndarray, model: ArcModel, solve: LpSolve, start: list[list[int]], L: float, began: float
) -> MilpResult:
    """MilpResult of a makespan solve (falls back on the warm start when nothing better)."""
    if solve.status == "infeasible":
        raise AssertionError("HiGHS reports infeasible although the warm start is valid")
    routes = model.routes_from(solve.values) if solve.values is not None else start
    routes = min([routes, start], key=lambda r: makespan(model.merged.D, r, tours=model.tours))
    routes = model.merged.expand(routes)
    value = makespan(D, routes, tours=model.tours)
    if solve.status == "optimal":
        return _proven(D, routes, model.tours, value, began, solve.message, solve.nodes)
    if within(value, L):
        return _proven(D, routes, model.tours, value, began, "solution meets the lower bound", solve.nodes)
    bound = min(max(L, solve.bound if solve.bound is not None else L), value)
    return MilpResult("feasible", routes, value, bound, relative_gap(value, bound), solve.nodes,
                      time.perf_counter() - began, solve.message)


def min_robots(
    D: np.ndarray,
    deadline: float,
    *,
    tours: bool,
    time_limit: TimeLimitLike = None,
    warm_start: list[list[int]] | None = None,
) -> MilpResult:
    """Fewest robots whose routes all meet ``deadline``.

    Parameters
    ----------
    D : numpy.ndarray
        ``(n+1, n+1)`` metric distance matrix, index 0 the start.
    deadline : float
        Largest allowed route cost ``U`` (tolerance ``U (1 + 1e-9) + 1e-9``).
    tours : bool
        Tours (return to 0) or open paths.
    time_limit : float or milp.core.timelimit.TimeLimit, optional
        Seconds for the whole call (column generation, heuristic, model, HiGHS), or a
        deadline shared with the caller; None for no limit. When the rest of the limit
        cannot cover building the model (:func:`_model_fits`), the heuristic's routes are
        returned with the bound found so far.
    warm_start : list of list of int, optional
        A valid solution whose routes all meet the deadline.

    Returns
    -------
    MilpResult
        ``objective`` is the number of routes; ``"infeasible"`` (without calling a
        solver) when the deadline is below ``c_max`` (paths) / ``2 c_max`` (tours).
    """
    began = time.perf_counter()
    time_limit = TimeLimit.of(time_limit)
    D = check_distance_matrix(D)
    L = least_makespan(D, tours=tours)
    if not within(L, deadline):
        return MilpResult("infeasible", seconds=time.perf_counter() - began,
                          message=f"deadline {deadline} is below the least makespan {L}")
    merged = merge_zero_distances(D)
    if warm_start is not None:
        given = check_routes(warm_start, len(D) - 1)
        if not all(within(route_cost(D, r, tours=tours), deadline) for r in given):
            raise ValueError("a warm-start route exceeds the deadline")
    if merged.size == 0:
        return _proven(D, merged.expand([]), tours, 1, began, "every KPOI is at the start")
    info = colgen.robots_bound(merged.D, deadline, tours=tours, time_limit=time_limit.fraction(HEURISTIC_SHARE),
                               routes=True)
    fewest = info.robots()
    given = [info.routes] + ([merged.reduce(warm_start)] if warm_start is not None else [])
    start = _robots_start(merged, deadline, fewest, tours, given, time_limit.fraction(HEURISTIC_SHARE))
    if len(start) <= fewest:
        return _proven(D, merged.expand(start), tours, len(start), began,
                       "heuristic meets the column-generation bound")
    arcs = int(np.count_nonzero(_kept(merged.D, tours=tours, U=float(deadline))))
    if not _model_fits(arcs, "robots", time_limit):
        return _unsolved(D, merged.expand(start), float(len(start)), float(fewest), began, arcs)
    model = _assemble(merged, tours=tours, U=float(deadline), k=None, fewest=fewest)
    solve = solve_lp(model.lp, time_limit=_highs_seconds(time_limit, arcs, "robots"),
                     start=model.start_vector(start), options=SEARCH_OPTIONS)
    if solve.status == "infeasible":
        raise AssertionError("HiGHS reports infeasible although the warm start is valid")
    routes = model.routes_from(solve.values) if solve.values is not None else start
    routes = model.merged.expand(min([routes, start], key=len))
    if solve.status == "optimal":
        return _proven(D, routes, tours, len(routes), began, solve.message, solve.nodes)
    bound = min(max(fewest, ceil((solve.bound or 1.0) - BOUND_SLACK)), len(routes))
    return MilpResult("feasible", routes, float(len(routes)), float(bound),
                      relative_gap(len(routes), bound), solve.nodes, time.perf_counter() - began,
                      solve.message)


def _robots_start(
    merged: Merged, deadline: float, fewest: int, tours: bool,
    given: list[list[list[int]]], time_limit: TimeLimit,
) -> list[list[int]]:
    """Fewest routes found by the heuristics and the ``given`` solutions, model space.

    ``given`` are valid route sets in model space (empty ones are skipped): the
    column-generation master's and the caller's warm start. The nearest-neighbour split
    gives a count ``h``; then ``q = fewest, ..., h - 1`` routes are tried with
    :func:`milp.warmstart.good_makespan_routes` until one meets the deadline or
    ``clock`` runs out or would not cover the split (:func:`milp.warmstart.split_fits`).
    """
    order = nearest_neighbour_order(merged.D)
    candidates = [split_min_robots(merged.D, order, deadline, tours=tours)]
    candidates += [routes for routes in given if routes]
    for q in range(fewest, min(map(len, candidates))):
        if time_limit.expired() or not split_fits(merged.size, q, time_limit):
            break  # q only grows (at 3000 KPOIs the split into 41 routes alone takes 0.7 s)
        routes = good_makespan_routes(merged.D, q, tours=tours, time_limit=time_limit)
        if within(makespan(merged.D, routes, tours=tours), deadline):
            candidates.append(routes)
            break
    return min(candidates, key=len)


def _proven(
    D: np.ndarray, routes: list[list[int]], tours: bool, value: float, began: float,
    message: str, nodes: int = 0,
) -> MilpResult:
    """An ``optimal`` result (bound = objective, gap 0) after checking the routes."""
    check_routes(routes, len(D) - 1)
    return MilpResult("optimal", routes, float(value), float(value), 0.0, nodes,
                      time.perf_counter() - began, message)
