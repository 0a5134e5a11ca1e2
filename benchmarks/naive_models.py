r"""Two MILP models a user would write first, in HiGHS: the peers of :mod:`milp.compact.arcflow`.

These are benchmark baselines, not parcover methods: no merging of coincident KPOIs, no
arc pruning, no warm start, no bound beyond what each model needs to be correct. Both
solve the two problems of the benchmarks on a distance matrix ``D`` (index 0 the
start, ``1..n`` the KPOIs): least makespan with at most ``k`` robots, and fewest robots
whose routes all meet a deadline ``U``, for open paths and for tours.

Both rely on every distance between two different KPOIs being positive (their subtour
elimination does): :func:`check_positive` refuses other inputs. Random Euclidean points,
the benchmark's instances, satisfy it.

Big-M MTZ model (:func:`mtz_min_makespan`, :func:`mtz_min_robots`)
-----------------------------------------------------------------
Nodes :math:`V = \{0..n\}`, arcs :math:`(i, j)`, :math:`i \ne j`; a route leaves 0 and
comes back to 0, the closing arc costing :math:`c_{i0} = d_{i0}` for tours and
:math:`c_{i0} = 0` for paths (the robot stops at :math:`i`); :math:`c_{ij} = d_{ij}`
otherwise. Variables: :math:`x_{ij} \in \{0, 1\}`, :math:`u_i \ge 0` the distance travelled
on arrival at KPOI :math:`i` (Miller-Tucker-Zemlin 1960 with distances, as in
Kara, Laporte and Bektas 2004), :math:`T` the makespan. :math:`M = (n + 1) \max D`
bounds any route's length.

.. math::

    (1)&\quad \sum_{j \in N} x_{0j} \le k \ \text{(makespan)}, \qquad
        \sum_{j \in N} x_{0j} = \sum_{i \in N} x_{i0} \\
    (2)&\quad \sum_{i \ne j} x_{ij} = 1, \quad \sum_{i \ne j} x_{ji} = 1 && j \in N \\
    (3)&\quad u_j \ge u_i + d_{ij} - M (1 - x_{ij}) && i \ne j \in N \\
    (4)&\quad u_j \ge d_{0j} x_{0j} && j \in N \\
    (5)&\quad T \ge u_i + c_{i0} - M (1 - x_{i0}) && i \in N \\
    (6)&\quad T \le U \ \text{(robots)}

minimise :math:`T` (makespan) or :math:`\sum_j x_{0j}` (robots). (3) forbids every cycle
inside :math:`N` (summing it around one gives :math:`0 \ge` its positive length); along a
route :math:`u` is at least the distance travelled, so (5) makes :math:`T` at least every
route's cost.

Plain arc-flow model (:func:`arcflow_min_makespan`, :func:`arcflow_min_robots`)
-----------------------------------------------------------------------------
A plain arc-flow model (Kara 2011 style; the compact model without its pruning,
bounds and warm start). End node
:math:`E`: a sink with :math:`d_{iE} = 0` (paths) or the start again, :math:`d_{iE} = d_{i0}`
(tours). Arcs :math:`(0, j)`, :math:`(i, j)` for :math:`i \ne j \in N`, :math:`(i, E)`.
:math:`r_j = 0` (paths) or :math:`d_{j0}` (tours), :math:`r_E = 0`. Variables
:math:`x_a \in \{0, 1\}`, :math:`z_a \ge 0` the distance on arrival at the head of
:math:`a`, :math:`T`. :math:`U` is the deadline (robots) or, for the makespan, the cost
of one robot visiting every KPOI in nearest-neighbour order (a valid makespan for any
:math:`k \ge 1`; only needed to make (5) a valid big-M).

.. math::

    (1)&\quad \sum_{a \in \delta^+(0)} x_a \le k \ \text{(makespan; robots: minimise it)} \\
    (2)&\quad \sum_{a \in \delta^-(j)} x_a = 1, \quad \sum_{a \in \delta^+(j)} x_a = 1
        && j \in N \\
    (3)&\quad \sum_{a \in \delta^+(j)} z_a - \sum_{a \in \delta^-(j)} z_a
        = \sum_{a \in \delta^+(j)} d_a x_a && j \in N \\
    (4)&\quad z_{0j} = d_{0j} x_{0j} && j \in N \\
    (5)&\quad (d_{0i} + d_{ij}) x_{ij} \le z_{ij} \le (U - r_j) x_{ij}
        && i \in N,\ j \in N \cup \{E\} \\
    (6)&\quad z_{iE} \le T && i \in N \ \text{(} T = U \text{ for robots)}

minimise :math:`T` (makespan) or :math:`\sum_{a \in \delta^+(0)} x_a` (robots).

References
----------
C. E. Miller, A. W. Tucker, R. A. Zemlin (1960), "Integer programming formulation of
traveling salesman problems", J. ACM 7(4), doi:10.1145/321043.321046.
I. Kara (2011), "Arc based integer programming formulations for the distance constrained
vehicle routing problem", LINDI 2011, doi:10.1109/LINDI.2011.6031143.
"""

from __future__ import annotations

import time
from math import ceil

import numpy as np
from scipy import sparse

from milp.core.highs import BOUND_SLACK, make_lp, solve_lp
from milp.core.result import MilpResult, relative_gap
from milp.core.routes import check_distance_matrix, makespan, route_cost

__all__ = [
    "arcflow_min_makespan",
    "arcflow_min_robots",
    "check_positive",
    "mtz_min_makespan",
    "mtz_min_robots",
]


def check_positive(D: np.ndarray) -> np.ndarray:
    """``D`` checked (:func:`milp.core.routes.check_distance_matrix`) with every distance between
    two different KPOIs positive, which both models' subtour elimination needs.

    Raises
    ------
    ValueError
        If two different KPOIs are at distance 0.
    """
    D = check_distance_matrix(D)
    inner = D[1:, 1:] + np.eye(len(D) - 1)
    if np.any(inner <= 0):
        raise ValueError("the naive models need positive distances between different KPOIs")
    return D


def mtz_min_makespan(D: np.ndarray, k: int, *, tours: bool,
                     time_limit: float | None = None) -> MilpResult:
    """Least makespan with at most ``k`` robots, big-M MTZ model (module docstring).

    Parameters
    ----------
    D : numpy.ndarray
        ``(n+1, n+1)`` metric, index 0 the start, positive between different KPOIs.
    k : int
        Robots available.
    tours : bool
        Tours (back to 0) or open paths.
    time_limit : float, optional
        Seconds for HiGHS.

    Returns
    -------
    MilpResult
    """
    return _solve_mtz(check_positive(D), tours=tours, k=k, deadline=None, time_limit=time_limit)


def mtz_min_robots(D: np.ndarray, deadline: float, *, tours: bool,
                   time_limit: float | None = None) -> MilpResult:
    """Fewest robots with every route within ``deadline``, big-M MTZ model (module docstring).

    Parameters are those of :func:`mtz_min_makespan`, with ``deadline`` (``U`` in (6))
    for ``k``. The objective is the number of routes.
    """
    return _solve_mtz(check_positive(D), tours=tours, k=None, deadline=deadline,
                      time_limit=time_limit)


def arcflow_min_makespan(D: np.ndarray, k: int, *, tours: bool,
                         time_limit: float | None = None) -> MilpResult:
    """Least makespan with at most ``k`` robots, plain arc-flow model (module docstring).

    Parameters and result as in :func:`mtz_min_makespan`.
    """
    D = check_positive(D)
    U = route_cost(D, _nearest_neighbour_order(D), tours=tours)
    return _solve_arcflow(D, tours=tours, k=k, U=U, time_limit=time_limit)


def arcflow_min_robots(D: np.ndarray, deadline: float, *, tours: bool,
                       time_limit: float | None = None) -> MilpResult:
    """Fewest robots with every route within ``deadline``, plain arc-flow model.

    Parameters and result as in :func:`mtz_min_robots`.
    """
    return _solve_arcflow(check_positive(D), tours=tours, k=None, U=float(deadline),
                          time_limit=time_limit)


def _nearest_neighbour_order(D: np.ndarray) -> list[int]:
    """KPOIs in nearest-neighbour order from the start (ties: lowest index)."""
    left, order, here = set(range(1, len(D))), [], 0
    while left:
        here = min(left, key=lambda j: (D[here, j], j))
        order.append(here)
        left.remove(here)
    return order


def _solve_mtz(D: np.ndarray, *, tours: bool, k: int | None, deadline: float | None,
               time_limit: float | None) -> MilpResult:
    """Build the MTZ model (constraints numbered as in the module docstring) and solve it."""
    began = time.perf_counter()
    n = len(D) - 1
    M = (n + 1) * float(D.max())
    tail, head = (a.ravel() for a in np.meshgrid(np.arange(n + 1), np.arange(n + 1), indexing="ij"))
    keep = tail != head
    tail, head = tail[keep], head[keep]
    A = len(tail)
    x, u, T = np.arange(A), A + np.arange(n), A + n  # u[i - 1] is u_i
    out0, in0, inner = tail == 0, head == 0, (tail > 0) & (head > 0)
    rows = _Rows()
    # (1) at most k routes leave 0; as many come back
    if k is not None:
        rows.add([0] * out0.sum(), x[out0], 1.0, -np.inf, k)
    rows.add(np.zeros(A), x, out0.astype(float) - in0.astype(float), 0.0, 0.0)
    # (2) in- and out-degree 1 at each KPOI
    into, outof = head > 0, tail > 0
    rows.add(head[into] - 1, x[into], 1.0, np.ones(n), np.ones(n))
    rows.add(tail[outof] - 1, x[outof], 1.0, np.ones(n), np.ones(n))
    # (3) u_j - u_i - M x_ij >= d_ij - M
    q = inner.sum()
    r = np.arange(q)
    rows.add(np.tile(r, 3), np.concatenate([u[head[inner] - 1], u[tail[inner] - 1], x[inner]]),
             np.concatenate([np.ones(q), -np.ones(q), -np.full(q, M)]),
             D[tail[inner], head[inner]] - M, np.inf)
    # (4) u_j - d_0j x_0j >= 0
    s = out0.sum()
    rows.add(np.tile(np.arange(s), 2), np.concatenate([u[head[out0] - 1], x[out0]]),
             np.concatenate([np.ones(s), -D[0, head[out0]]]), 0.0, np.inf)
    # (5) T - u_i - M x_i0 >= c_i0 - M
    closing = D[tail[in0], 0] if tours else np.zeros(in0.sum())
    e = in0.sum()
    rows.add(np.tile(np.arange(e), 3),
             np.concatenate([np.full(e, T), u[tail[in0] - 1], x[in0]]),
             np.concatenate([np.ones(e), -np.ones(e), -np.full(e, M)]), closing - M, np.inf)
    # (6) T <= U (robots) as T's column bound
    cost = np.zeros(A + n + 1)
    if k is None:
        cost[x[out0]] = 1.0
    else:
        cost[T] = 1.0
    upper = np.concatenate([np.ones(A), np.full(n, np.inf), [np.inf if k is not None else deadline]])
    lp = make_lp(cost, (np.zeros(A + n + 1), upper), rows.matrix(A + n + 1), rows.bounds(),
                 np.arange(A + n + 1) < A)
    solve = solve_lp(lp, time_limit=time_limit)
    used = solve.values[:A] > 0.5 if solve.values is not None else None
    return _result(D, tours, k is None, solve, tail, head, used, end=0, began=began)


def _solve_arcflow(D: np.ndarray, *, tours: bool, k: int | None, U: float,
                   time_limit: float | None) -> MilpResult:
    """Build the plain arc-flow model (numbered as in the module docstring) and solve it."""
    began = time.perf_counter()
    n = len(D) - 1
    E = n + 1
    tail, head = (a.ravel() for a in np.meshgrid(np.arange(n + 1), np.arange(1, n + 2), indexing="ij"))
    keep = (tail != head) & ~((tail == 0) & (head == E))
    tail, head = tail[keep], head[keep]
    A = len(tail)
    length = np.where(head == E, D[tail, 0] if tours else 0.0, D[tail, head % E])
    x, z, T = np.arange(A), A + np.arange(A), 2 * A
    from_start, inner, ends = tail == 0, tail > 0, head == E
    into = head <= n
    rows = _Rows()
    s, q, e = from_start.sum(), inner.sum(), ends.sum()
    # (1) at most k routes (makespan only; for robots their number is the objective)
    if k is not None:
        rows.add(np.zeros(s), x[from_start], 1.0, -np.inf, k)
    # (2) in- and out-degree 1 at each KPOI
    rows.add(head[into] - 1, x[into], 1.0, np.ones(n), np.ones(n))
    rows.add(tail[inner] - 1, x[inner], 1.0, np.ones(n), np.ones(n))
    # (3) out z - in z - out d x = 0
    rows.add(np.concatenate([tail[inner] - 1, head[into] - 1, tail[inner] - 1]),
             np.concatenate([z[inner], z[into], x[inner]]),
             np.concatenate([np.ones(q), -np.ones(into.sum()), -length[inner]]),
             np.zeros(n), np.zeros(n))
    # (4) z_0j - d_0j x_0j = 0
    rows.add(np.tile(np.arange(s), 2), np.concatenate([z[from_start], x[from_start]]),
             np.concatenate([np.ones(s), -length[from_start]]), 0.0, 0.0)
    # (5) (d_0i + d_ij) x <= z <= (U - r_j) x
    to_go = np.where(head[inner] == E, 0.0, D[head[inner] % E, 0] if tours else 0.0)
    pair = np.tile(np.arange(q), 2)
    rows.add(pair, np.concatenate([z[inner], x[inner]]),
             np.concatenate([np.ones(q), -(D[0, tail[inner]] + length[inner])]), 0.0, np.inf)
    rows.add(pair, np.concatenate([z[inner], x[inner]]),
             np.concatenate([np.ones(q), -(U - to_go)]), -np.inf, 0.0)
    # (6) z_iE - T <= 0
    rows.add(np.tile(np.arange(e), 2), np.concatenate([z[ends], np.full(e, T)]),
             np.concatenate([np.ones(e), -np.ones(e)]), -np.inf, 0.0)
    cost = np.zeros(2 * A + 1)
    col_upper = np.concatenate([np.ones(A), np.full(A, np.inf), [np.inf]])
    col_lower = np.zeros(2 * A + 1)
    if k is None:  # T = U
        cost[x[from_start]] = 1.0
        col_lower[T] = col_upper[T] = U
    else:
        cost[T] = 1.0
    lp = make_lp(cost, (col_lower, col_upper), rows.matrix(2 * A + 1), rows.bounds(),
                 np.arange(2 * A + 1) < A)
    solve = solve_lp(lp, time_limit=time_limit)
    used = solve.values[:A] > 0.5 if solve.values is not None else None
    return _result(D, tours, k is None, solve, tail, head, used, end=E, began=began)


class _Rows:
    """Constraint rows collected as coordinate blocks (row ids local to each block)."""

    def __init__(self) -> None:
        self.rows, self.cols, self.vals, self.lower, self.upper = [], [], [], [], []
        self.count = 0

    def add(self, rows, cols, vals, lower, upper) -> None:
        """Append a block; scalars in ``vals``, ``lower``, ``upper`` are broadcast."""
        rows = np.asarray(rows, dtype=np.int64)
        size = int(rows.max()) + 1
        self.rows.append(rows + self.count)
        self.cols.append(np.asarray(cols, dtype=np.int64))
        self.vals.append(np.broadcast_to(np.asarray(vals, dtype=np.float64), rows.shape))
        self.lower.append(np.broadcast_to(np.asarray(lower, dtype=np.float64), (size,)))
        self.upper.append(np.broadcast_to(np.asarray(upper, dtype=np.float64), (size,)))
        self.count += size

    def matrix(self, num_col: int) -> sparse.coo_matrix:
        """The constraint matrix, ``count`` rows by ``num_col`` columns."""
        return sparse.coo_matrix(
            (np.concatenate(self.vals), (np.concatenate(self.rows), np.concatenate(self.cols))),
            shape=(self.count, num_col))

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Row lower and upper bounds."""
        return np.concatenate(self.lower), np.concatenate(self.upper)


def _result(D: np.ndarray, tours: bool, robots: bool, solve, tail: np.ndarray,
            head: np.ndarray, used: np.ndarray | None, *, end: int, began: float) -> MilpResult:
    """A :class:`MilpResult` from a HiGHS solve: routes followed from the used arcs,
    objective recomputed from ``D``, a robots bound rounded up."""
    seconds = time.perf_counter() - began
    if used is None:
        bound = solve.bound
        if robots and bound is not None:
            bound = float(max(1, ceil(bound - BOUND_SLACK)))
        status = "infeasible" if solve.status == "infeasible" else "unknown"
        return MilpResult(status, bound=bound, nodes=solve.nodes, seconds=seconds,
                          message=solve.message)
    successor = dict(zip(tail[used].tolist(), head[used].tolist()))
    firsts = head[used & (tail == 0)].tolist()
    routes = []
    for first in firsts:
        route = [first]
        while successor[route[-1]] != end:
            route.append(successor[route[-1]])
        routes.append(route)
    if sorted(i for r in routes for i in r) != list(range(1, len(D))):
        raise AssertionError("arc solution is not a partition into routes")
    value = float(len(routes)) if robots else makespan(D, routes, tours=tours)
    if solve.status == "optimal":
        return MilpResult("optimal", routes, value, value, 0.0, solve.nodes, seconds, solve.message)
    bound = solve.bound
    if bound is not None:
        bound = float(max(1, ceil(bound - BOUND_SLACK))) if robots else min(bound, value)
    return MilpResult("feasible", routes, value, bound, relative_gap(value, bound), solve.nodes,
                      seconds, solve.message)
