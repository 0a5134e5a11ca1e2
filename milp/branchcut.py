r"""Branch-and-cut over a three-index model: the least makespan with few long routes.

Branch-and-price (:mod:`milp.branchprice`) prices routes by labelling; with 2 routes of
25-40 KPOIs each the labels explode and its root LP stays below 2 routes at the optimum
(Necula's eil51 with 2 tours: 1.98, even 1.99 over elementary routes). This model has
no route variables at all: each robot gets its own copy of the edges, and the routes'
connectivity is imposed by cuts, as in the classical formulations of the min-max
m-TSP (França, Gendreau, Laporte and Müller 1995, "The m-traveling salesman problem
with minmax objective", Transportation Science 29(3), 267-275, doi:10.1287/trsc.29.3.267).
It is a logic-based Benders decomposition with the subproblem's relaxation in the master
(Hooker and Ottosson 2003, Math. Prog. 96, doi:10.1007/s10107-003-0375-9): the master
assigns KPOIs to robots and gives each a 2-matching (a relaxed tour) of bounded length;
the subproblem asks whether a robot's 2-matching is one route, and its infeasibility
proof is the violated subtour-elimination cut (3) below.

Model
-----
Robots :math:`v = 1..k`, KPOIs :math:`N = \{1..n\}` sorted by decreasing distance from
the start (rank :math:`\rho(i)`, 1 the farthest), edges :math:`E` between the start 0
and KPOIs and between KPOIs; for paths also a sink :math:`t` with zero-length edges
:math:`(i, t)` (a path is a cycle through 0 and t). Variables: :math:`x_{ev} \in
\{0, 1\}` (edges at the start for tours in :math:`\{0, 1, 2\}`: a one-KPOI tour uses
its edge twice), :math:`y_{iv} \in \{0, 1\}` (KPOI :math:`i` on robot :math:`v`),
:math:`u_v \in \{0, 1\}` (robot :math:`v` used), :math:`T` the makespan.

.. math::
    \min T \quad \text{s.t.}\quad
    (1)\ \sum_v y_{iv} = 1, \qquad
    (2)\ x_v(\delta(i)) = 2 y_{iv}, \quad x_v(\delta(0)) = 2 u_v \text{ (tours)}, \quad
         x_v(\delta(0)) = x_v(\delta(t)) = u_v \text{ (paths)},

    (3)\ x_v(\delta(S)) \ge 2 y_{iv} \quad (S \subseteq N,\ i \in S), \qquad
    (4)\ \sum_e d_e x_{ev} \le T, \qquad
    (5)\ x_{ev} \le y_{iv}\ (i \in e;\ \le 2 y_{iv} \text{ at the start}), \quad y_{iv} \le u_v,

    (6)\ u_v \ge u_{v+1}, \quad y_{iv} = 0 \text{ for } v > \rho(i), \qquad
    (7)\ L \le T \le U.

(2) and (3) make every used robot's edges one cycle through 0 (tours) or one path from
0 to :math:`t` (paths) over its KPOIs; :math:`\delta(S)` counts the edges to 0 and
:math:`t` too. (6) breaks the robots' symmetry: ordered by their farthest KPOI, robot
:math:`v` holds only KPOIs of rank :math:`v` or more, and the unused robots come last.
(7): :math:`L` from :func:`milp.bounds.makespan_lower_bound`, :math:`U` the warm start's
makespan; edges that cannot lie on a route within :math:`U` are left out
(:math:`d_{0i} + d_{ij} + d_{j0} > U` for tours, :math:`\min(d_{0i}, d_{0j}) + d_{ij} > U`
for paths, by the triangle inequality). Zero distances need no care: (3) forbids
subtours of any length.

Solving
-------
The root LP is solved with cuts (3) separated exactly on fractional points (a
Gomory-Hu tree per robot over the edge values; for paths 0 and :math:`t` merged), each
cut added for every robot (they are interchangeable), for at most :data:`ROOT_SHARE` of
the time. HiGHS has no lazy-constraint callback, so the MIP is then solved, its
solution checked for subtours, the violated cuts added and the MIP solved again, until
a solution has none (it is then optimal: the MIP is a relaxation) or the time is up.
Every MIP is a relaxation, so its dual bound and the root LP value are certified lower
bounds whatever happens.

Against branch-and-price it wins with two long routes at 30-40 KPOIs and loses with
three or more (measurements: ``milp/README.md``, "Branch-and-cut").
"""

from __future__ import annotations

import logging
import math
import time

import highspy
import networkx as nx
import numpy as np

from milp.bounds import makespan_lower_bound
from milp.core.highs import BOUND_SLACK, new_highs
from milp.core.merge import checked_start, merge_zero_distances, model_result
from milp.core.result import MilpResult
from milp.core.routes import check_distance_matrix, makespan
from milp.core.sizes import BRANCHCUT_MAX_KPOIS
from milp.core.timelimit import stop_requested

log = logging.getLogger(__name__)

__all__ = ["min_makespan", "MAX_KPOIS", "ROOT_SHARE"]

#: Largest instance accepted (:data:`milp.core.sizes.BRANCHCUT_MAX_KPOIS`, which says why).
MAX_KPOIS = BRANCHCUT_MAX_KPOIS
#: Share of the time limit the root's cutting-plane loop may use.
ROOT_SHARE = 0.3
#: A cut (3) is added when violated by more than this.
VIOLATION = 1e-6
_INF = highspy.kHighsInf


class _Model:
    """The master (1)-(7) of the module docstring, in HiGHS, and its cut separation."""

    def __init__(self, D: np.ndarray, k: int, *, tours: bool, lower: float, upper: float) -> None:
        n = len(D) - 1
        self.n, self.k, self.tours, self.D = n, k, tours, D
        self.sink = n + 1  # paths only
        order = np.argsort(-D[0, 1:], kind="stable") + 1
        self.rank = np.full(n + 1, -1, dtype=np.int64)  # distance rank of each KPOI (0: farthest)
        self.rank[order] = np.arange(n)
        self.edges = _edges(D, tours=tours, upper=upper)
        E, K = len(self.edges), k
        # columns: x[e, v] at v * E + e, then y[i, v] at K * E + v * n + (i - 1), u[v], T
        self.y0, self.u0 = K * E, K * E + K * n
        self.T = self.u0 + K
        lo = np.zeros(self.T + 1)
        hi = np.ones(self.T + 1)
        for v in range(K):
            for e, (i, j) in enumerate(self.edges):
                ends = [q for q in (i, j) if 1 <= q <= n]
                fits = all(self.rank[q] >= v for q in ends)  # (6)
                hi[v * E + e] = (2.0 if tours and i == 0 else 1.0) if fits else 0.0
            hi[self.y0 + v * n: self.y0 + (v + 1) * n] = (self.rank[1:] >= v).astype(float)
        lo[self.T], hi[self.T] = lower, upper
        self.h = h = new_highs(None)
        h.addVars(self.T + 1, lo, hi)
        h.changeColCost(self.T, 1.0)
        self.integer = np.arange(self.T, dtype=np.int32)
        self._rows: list[tuple[float, float, list[int], list[float]]] = []
        self._build()
        self.cuts = 0

    def x(self, e: int, v: int) -> int:
        return v * len(self.edges) + e

    def y(self, i: int, v: int) -> int:
        return self.y0 + v * self.n + i - 1

    def _build(self) -> None:
        n, k, tours, E = self.n, self.k, self.tours, len(self.edges)
        at: dict[int, list[int]] = {}
        for e, (i, j) in enumerate(self.edges):
            at.setdefault(i, []).append(e)
            at.setdefault(j, []).append(e)
        row = self._rows.append
        for i in range(1, n + 1):  # (1)
            row((1, 1, [self.y(i, v) for v in range(k)], [1.0] * k))
        length = [0.0 if j == self.sink else float(self.D[i, j]) for i, j in self.edges]
        for v in range(k):
            u = self.u0 + v
            for i in range(1, n + 1):  # (2), (5)
                row((0, 0, [self.x(e, v) for e in at[i]] + [self.y(i, v)], [1.0] * len(at[i]) + [-2.0]))
                row((-_INF, 0, [self.y(i, v), u], [1.0, -1.0]))
            ends = [0] if tours else [0, self.sink]
            for node in ends:
                row((0, 0, [self.x(e, v) for e in at[node]] + [u], [1.0] * len(at[node]) + [-2.0 if tours else -1.0]))
            for e, (i, j) in enumerate(self.edges):
                for q in (i, j):
                    if 1 <= q <= n:
                        row((-_INF, 0, [self.x(e, v), self.y(q, v)], [1.0, -2.0 if tours and i == 0 else -1.0]))
            row((-_INF, 0, [self.x(e, v) for e in range(E)] + [self.T], length + [-1.0]))  # (4)
            if v + 1 < k:
                row((0, _INF, [u, u + 1], [1.0, -1.0]))  # (6)
        self._flush()

    def _flush(self) -> None:
        rows, self._rows = self._rows, []
        if not rows:
            return
        starts = np.cumsum([0] + [len(r[2]) for r in rows[:-1]]).astype(np.int32)
        index = np.concatenate([np.asarray(r[2], dtype=np.int32) for r in rows])
        value = np.concatenate([np.asarray(r[3], dtype=np.float64) for r in rows])
        self.h.addRows(len(rows), np.array([r[0] for r in rows], float), np.array([r[1] for r in rows], float),
                       len(index), starts, index, value)

    def separate(self, values: np.ndarray, *, integral: bool) -> int:
        """Add the cuts (3) that ``values`` violates (for every robot); their number.

        Integral points: each connected component of a robot's edges away from the
        start is a violated set. Fractional points: the minimum cuts between the start
        and each KPOI, read off a Gomory-Hu tree of the robot's edge values."""
        found: list[frozenset[int]] = []
        for v in range(self.k):
            graph = self._support(values, v)
            if graph.number_of_nodes() <= 1:
                continue
            parts = [set(c) for c in nx.connected_components(graph) if 0 not in c]
            if parts or integral:
                found += [frozenset(c) for c in parts]
                continue
            tree = nx.gomory_hu_tree(graph)
            for a, b, weight in list(tree.edges(data="weight")):
                tree.remove_edge(a, b)
                side = nx.node_connected_component(tree, a)
                tree.add_edge(a, b, weight=weight)
                found.append(frozenset(side if 0 not in side else set(graph.nodes) - side))
        cuts = 0
        for S in set(found):
            cuts += self._add_cut(S, values)
        self._flush()
        return cuts

    def _support(self, values: np.ndarray, v: int) -> nx.Graph:
        """Robot ``v``'s edge values over the start and its KPOIs (the sink merged with
        the start), as edge capacities."""
        graph = nx.Graph()
        graph.add_node(0)
        graph.add_nodes_from(i for i in range(1, self.n + 1) if values[self.y(i, v)] > VIOLATION)
        for e, (i, j) in enumerate(self.edges):
            value = values[self.x(e, v)]
            if value <= VIOLATION:
                continue
            a, b = (0 if i == self.sink else i), (0 if j == self.sink else j)
            if a in graph and b in graph:
                old = graph[a][b]["capacity"] if graph.has_edge(a, b) else 0.0
                graph.add_edge(a, b, capacity=old + value)
        return graph

    def _add_cut(self, S: frozenset[int], values: np.ndarray) -> int:
        """Queue cut (3) on ``S`` for every robot if ``values`` violates it for one;
        whether it did (1 or 0)."""
        crossing = [e for e, (i, j) in enumerate(self.edges) if (i in S) != (j in S)]
        violated = any(
            sum(values[self.x(e, v)] for e in crossing) < 2 * max(values[self.y(i, v)] for i in S) - VIOLATION
            for v in range(self.k))
        if not violated:
            return 0
        for v in range(self.k):
            i = max(S, key=lambda q: values[self.y(q, v)])
            self._rows.append((0, _INF, [self.x(e, v) for e in crossing] + [self.y(i, v)],
                               [1.0] * len(crossing) + [-2.0]))
            self.cuts += 1
        return 1

    def start(self, routes: list[list[int]]) -> np.ndarray | None:
        """The column vector of ``routes`` (robots ordered by their farthest KPOI), or
        None when a route uses a left-out edge."""
        where = {edge: e for e, edge in enumerate(self.edges)}
        values = np.zeros(self.T + 1)
        for v, route in enumerate(sorted(routes, key=lambda r: min(self.rank[i] for i in r))):
            values[self.u0 + v] = 1.0
            walk = [0, *route, 0 if self.tours else self.sink]
            for a, b in zip(walk, walk[1:]):
                e = where.get((min(a, b), max(a, b)))
                if e is None:
                    return None
                values[self.x(e, v)] += 1.0
            for i in route:
                values[self.y(i, v)] = 1.0
        values[self.T] = makespan(self.D, routes, tours=self.tours)
        return values

    def routes(self, values: np.ndarray) -> list[list[int]]:
        """The routes of an integral point without subtours (start to end, KPOIs only)."""
        out = []
        for v in range(self.k):
            near: dict[int, list[int]] = {}
            for e, (i, j) in enumerate(self.edges):
                for _ in range(int(round(values[self.x(e, v)]))):
                    near.setdefault(i, []).append(j)
                    near.setdefault(j, []).append(i)
            if 0 not in near:
                continue
            route, previous, here = [], 0, near[0][0]
            while here not in (0, self.sink):
                route.append(here)
                onward = [w for w in near[here] if w != previous] or near[here]
                previous, here = here, onward[0]
            out.append(route)
        return out


def _edges(D: np.ndarray, *, tours: bool, upper: float) -> list[tuple[int, int]]:
    """Edges ``(i, j)``, ``i < j``, that can lie on a route within ``upper`` (module
    docstring); for paths also ``(i, n + 1)``, the sink."""
    n = len(D) - 1
    budget = upper * (1 + 1e-9) + 1e-9
    i, j = np.triu_indices(n, k=1)
    i, j = i + 1, j + 1
    reach = D[0, i] + D[i, j] + D[j, 0] if tours else np.minimum(D[0, i], D[0, j]) + D[i, j]
    keep = reach <= budget
    edges = [(0, q) for q in range(1, n + 1)]
    edges += list(zip(i[keep].tolist(), j[keep].tolist()))
    if not tours:
        edges += [(q, n + 1) for q in range(1, n + 1)]
    return edges


def min_makespan(
    D: np.ndarray, k: int, *, tours: bool, time_limit: float | None = None,
    warm_start: list[list[int]] | None = None,
) -> MilpResult:
    """Least makespan with at most ``k`` routes, by branch-and-cut (module docstring).

    Parameters
    ----------
    D : numpy.ndarray
        ``(n+1, n+1)`` metric distance matrix, index 0 the start.
    k : int
        Routes available (at least 1).
    tours : bool
        Tours (return to 0) or open paths.
    time_limit : float, optional
        Seconds for the whole call.
    warm_start : list of list of int, optional
        At most ``k`` routes covering every KPOI (``1..n``): the first incumbent and
        the upper bound ``U``. Without one, each KPOI on its own route while ``k``
        allows it, else the nearest-neighbour split.

    Returns
    -------
    MilpResult
        ``optimal`` when a MIP's optimum has no subtour; else ``feasible`` with the
        larger of the root LP value and the last MIP's dual bound.
    """
    from milp.warmstart import nearest_neighbour_order, split_min_makespan

    began = time.perf_counter()
    if k < 1:
        raise ValueError("k must be at least 1")
    D = check_distance_matrix(D)
    merged = merge_zero_distances(D)
    if merged.size > MAX_KPOIS:
        raise ValueError(f"branch-and-cut handles at most {MAX_KPOIS} KPOIs")
    if merged.size == 0:
        return model_result("optimal", merged, D, [], 0.0, 0.0, 0, began, "every KPOI at the start")
    M = merged.D
    routes = checked_start(merged, D, warm_start, tours=tours, deadline=None, k=k)
    if routes is None:
        routes = split_min_makespan(M, nearest_neighbour_order(M), k, tours=tours)
    value = makespan(M, routes, tours=tours)
    lower = makespan_lower_bound(M, k, tours=tours, time_limit=time_limit)
    if value <= lower * (1 + 1e-9):
        return model_result("optimal", merged, D, routes, value, value, 0, began, "warm start meets the lower bound")
    ends_at = math.inf if time_limit is None else began + time_limit
    model = _Model(M, min(k, merged.size), tours=tours, lower=lower, upper=value)
    h = model.h
    root_ends_at = began + ROOT_SHARE * (ends_at - began)
    while time.perf_counter() < root_ends_at and not stop_requested():
        _set_time(h, root_ends_at)
        h.run()
        if h.getModelStatus() != highspy.HighsModelStatus.kOptimal:
            break
        lower = max(lower, h.getInfo().objective_function_value)
        if model.separate(np.asarray(h.getSolution().col_value), integral=False) == 0:
            break
    log.info("branch-and-cut: makespan %.6g from the warm start, root bound %.6g", value, lower)
    h.changeColsIntegrality(len(model.integer), model.integer,
                            np.full(len(model.integer), highspy.HighsVarType.kInteger))
    mips, nodes = 0, 0
    while time.perf_counter() < ends_at and not stop_requested():  # stop: a race's rival, Ctrl-C
        start = model.start(routes)
        if start is not None:
            solution = highspy.HighsSolution()
            solution.col_value = start
            h.setSolution(solution)
        _set_time(h, ends_at)
        h.run()
        mips += 1
        info = h.getInfo()
        nodes += int(info.mip_node_count)
        if math.isfinite(info.mip_dual_bound):
            lower = max(lower, float(info.mip_dual_bound))
        log.info("branch-and-cut: MIP %d, bound %.6g, %d nodes", mips, lower, nodes)
        if info.primal_solution_status != 2:  # no solution: time limit
            break
        values = np.asarray(h.getSolution().col_value)
        if model.separate(values, integral=True) > 0:
            continue
        found = model.routes(values)
        if makespan(M, found, tours=tours) < value:
            routes, value = found, makespan(M, found, tours=tours)
        if h.getModelStatus() == highspy.HighsModelStatus.kOptimal:
            assert lower <= value * (1 + 1e-9) + BOUND_SLACK, (lower, value)
            return model_result("optimal", merged, D, routes, value, value, nodes, began,
                           f"branch-and-cut: optimum without subtours ({mips} MIPs, {model.cuts} cuts)")
    lower = min(lower, value)
    return model_result("feasible", merged, D, routes, value, lower, nodes, began,
                   f"time limit ({mips} MIPs, {model.cuts} cuts)")


def _set_time(h: highspy.Highs, ends_at: float) -> None:
    left = ends_at - time.perf_counter()
    h.setOptionValue("time_limit", float(max(left, 1e-3)) if math.isfinite(left) else _INF)
