r"""The arc-flow model of :mod:`milp.compact.arcflow`, written in cvxpy to be read.

Same notation and constraint numbers as the :mod:`milp.compact.arcflow` docstring; no arc
pruning and no warm start (``warm_start`` is accepted and ignored). The only data
preparation is the merge of KPOIs at distance 0 (:mod:`milp.core.merge`), without which
zero-length cycles would satisfy the distance flow (3). The ``U`` of (5) for
``min_makespan`` is the makespan of the nearest-neighbour split of
:mod:`milp.warmstart` with ``k`` routes: a valid solution, so no optimal route is longer.

Solved with cvxpy's HiGHS interface (``solver=cp.HIGHS``) and the exact-gap options.
Under a time limit, the model is not built when the limit cannot cover twice its
expected set-up (:data:`SETUP_SECONDS_PER_ARC`): the answer is then ``unknown``.
"""

from __future__ import annotations

import time

import cvxpy as cp
import numpy as np

from milp.core.highs import MIP_ABS_GAP, MIP_REL_GAP, THREADS
from milp.core.merge import Merged, merge_zero_distances
from milp.core.result import MilpResult, relative_gap
from milp.core.routes import check_distance_matrix, least_makespan, makespan, within
from milp.warmstart import nearest_neighbour_order, split_min_makespan

#: Seconds per arc (``(m + 1)^2`` of them) for cvxpy to compile the model and HiGHS to
#: presolve it, which no time limit interrupts: 200-250 microseconds measured at 30-100
#: KPOIs, rounded up.
SETUP_SECONDS_PER_ARC = 3e-4


class ArcFlowProgram:
    """Arcs of a merged instance and the cvxpy variables over them.

    Parameters
    ----------
    merged : Merged
        Instance over the start 0, KPOIs ``1..m`` and (implicitly) the end node ``m+1``.
    tours : bool
        Tours (end node = back at the start) or open paths (end node = a free sink).
    """

    def __init__(self, merged: Merged, *, tours: bool) -> None:
        D, m = merged.D, merged.size
        self.merged, self.tours, self.m = merged, tours, m
        self.end = m + 1
        self.arcs = [(0, j) for j in range(1, m + 1)]
        self.arcs += [(i, j) for i in range(1, m + 1) for j in range(1, m + 1) if i != j]
        self.arcs += [(i, self.end) for i in range(1, m + 1)]
        self.length = np.array([self.distance(i, j) for i, j in self.arcs])
        self.still_to_go = np.array([self.distance(j, self.end) if j != self.end and tours else 0.0
                                     for _, j in self.arcs])  # r_j
        self.reach = np.array([D[0, i] + self.distance(i, j) for i, j in self.arcs])  # d_0i + d_ij
        self.used = cp.Variable(len(self.arcs), boolean=True, name="x")  # x_a
        self.distance_on_arrival = cp.Variable(len(self.arcs), nonneg=True, name="z")  # z_a

    def distance(self, i: int, j: int) -> float:
        """``d_ij``, with ``d_iE = d_i0`` for tours and 0 for paths."""
        if j == self.end:
            return float(self.merged.D[i, 0]) if self.tours else 0.0
        return float(self.merged.D[i, j])

    def arcs_where(self, keep) -> np.ndarray:
        """0/1 row vector selecting the arcs ``(i, j)`` with ``keep(i, j)``."""
        return np.array([1.0 if keep(i, j) else 0.0 for i, j in self.arcs])

    def routing_constraints(self, U: float) -> list[cp.Constraint]:
        """Constraints (2)-(5): degrees, distance flow, start arcs, arc distance bounds."""
        x, z = self.used, self.distance_on_arrival
        constraints = []
        for j in range(1, self.m + 1):
            into_j = self.arcs_where(lambda a, b: b == j)
            out_of_j = self.arcs_where(lambda a, b: a == j)
            constraints += [into_j @ x == 1, out_of_j @ x == 1]  # (2)
            constraints += [out_of_j @ z - into_j @ z == (out_of_j * self.length) @ x]  # (3)
        from_start = self.arcs_where(lambda a, b: a == 0) == 1
        inner = ~from_start
        constraints += [z[from_start] == cp.multiply(self.length[from_start], x[from_start])]  # (4)
        constraints += [
            z[inner] >= cp.multiply(self.reach[inner], x[inner]),  # (5) lower
            z[inner] <= cp.multiply(U - self.still_to_go[inner], x[inner]),  # (5) upper
        ]
        return constraints

    def robots_used(self) -> cp.Expression:
        """Number of routes: arcs leaving the start."""
        return self.arcs_where(lambda a, b: a == 0) @ self.used

    def total_distance(self) -> cp.Expression:
        """Sum of all route costs, ``sum_a d_a x_a``."""
        return self.length @ self.used

    def arrival_at_end(self) -> cp.Expression:
        """``z_iE``: the cost of the route ending with ``i``, for every ``i``."""
        return self.distance_on_arrival[self.arcs_where(lambda a, b: b == self.end) == 1]

    def routes(self) -> list[list[int]]:
        """Model-space routes read from the solved ``x``."""
        successor = {i: j for (i, j), value in zip(self.arcs, self.used.value) if value > 0.5}
        firsts = [j for (i, j), value in zip(self.arcs, self.used.value) if value > 0.5 and i == 0]
        routes = []
        for first in firsts:
            route = [first]
            while successor[route[-1]] != self.end:
                route.append(successor[route[-1]])
            routes.append(route)
        return routes


def min_makespan(
    D: np.ndarray,
    k: int,
    *,
    tours: bool,
    time_limit: float | None = None,
    warm_start: list[list[int]] | None = None,
) -> MilpResult:
    """Least makespan with at most ``k`` robots (cvxpy arc-flow model).

    Same parameters and result as :func:`milp.compact.arcflow.min_makespan`.
    """
    began = time.perf_counter()
    D = check_distance_matrix(D)
    if k < 1:
        raise ValueError("k must be at least 1")
    merged = merge_zero_distances(D)
    if merged.size == 0:
        return _optimal_without_model(merged, 0.0, began)
    if not _model_fits(merged, time_limit):
        return _no_time(merged, began)
    program = ArcFlowProgram(merged, tours=tours)
    order = nearest_neighbour_order(merged.D)
    U = makespan(merged.D, split_min_makespan(merged.D, order, k, tours=tours), tours=tours)
    makespan_T = cp.Variable(name="T")
    constraints = [program.robots_used() <= k]  # (1)
    constraints += program.routing_constraints(U)  # (2)-(5)
    constraints += [program.arrival_at_end() <= makespan_T]  # (6)
    constraints += [program.total_distance() <= k * makespan_T]  # (7)
    L = least_makespan(merged.D, tours=tours)
    constraints += [makespan_T >= L, makespan_T <= max(U, L)]  # (8)
    problem = cp.Problem(cp.Minimize(makespan_T), constraints)
    return _solve(problem, program, D, time_limit, began, robots=False)


def min_robots(
    D: np.ndarray,
    deadline: float,
    *,
    tours: bool,
    time_limit: float | None = None,
    warm_start: list[list[int]] | None = None,
) -> MilpResult:
    """Fewest robots whose routes all meet ``deadline`` (cvxpy arc-flow model).

    Same parameters and result as :func:`milp.compact.arcflow.min_robots`.
    """
    began = time.perf_counter()
    D = check_distance_matrix(D)
    L = least_makespan(D, tours=tours)
    if not within(L, deadline):
        return MilpResult("infeasible", seconds=time.perf_counter() - began,
                          message=f"deadline {deadline} is below the least makespan {L}")
    merged = merge_zero_distances(D)
    if merged.size == 0:
        return _optimal_without_model(merged, 1.0, began)
    if not _model_fits(merged, time_limit):
        return _no_time(merged, began)
    program = ArcFlowProgram(merged, tours=tours)
    U = deadline * (1 + 1e-9) + 1e-9
    constraints = program.routing_constraints(U)  # (2)-(5); (6) is (5) with U = deadline
    constraints += [program.total_distance() <= U * program.robots_used()]  # (7)
    problem = cp.Problem(cp.Minimize(program.robots_used()), constraints)
    return _solve(problem, program, D, time_limit, began, robots=True)


def _solve(problem: cp.Problem, program: ArcFlowProgram, D: np.ndarray,
           time_limit: float | None, began: float, *, robots: bool) -> MilpResult:
    """Solve with cvxpy's HiGHS interface and build the MilpResult."""
    options = {"mip_rel_gap": MIP_REL_GAP, "mip_abs_gap": MIP_ABS_GAP, "threads": THREADS}
    if time_limit is not None:  # HiGHS' limit, less what is spent and what compiling will take
        setup = SETUP_SECONDS_PER_ARC * (program.merged.size + 1) ** 2
        options["time_limit"] = max(float(time_limit) - (time.perf_counter() - began) - setup, 1e-3)
    problem.solve(solver=cp.HIGHS, **options)
    info = problem.solver_stats.extra_stats
    nodes = int(info.mip_node_count)
    if problem.status == cp.INFEASIBLE:
        return MilpResult("infeasible", nodes=nodes, seconds=time.perf_counter() - began,
                          message=problem.status)
    if problem.status not in (cp.OPTIMAL, cp.USER_LIMIT) or info.primal_solution_status != 2:
        return MilpResult("unknown", nodes=nodes, seconds=time.perf_counter() - began,
                          message=problem.status)
    routes = program.merged.expand(program.routes())
    value = float(len(routes)) if robots else makespan(D, routes, tours=program.tours)
    if problem.status == cp.OPTIMAL:
        status, bound = "optimal", value
    else:
        status, bound = "feasible", min(float(info.mip_dual_bound), value)
        if robots:
            bound = float(np.ceil(bound - 1e-6))
    return MilpResult(status, routes, value, bound, relative_gap(value, bound), nodes,
                      time.perf_counter() - began, problem.status)


def _model_fits(merged: Merged, time_limit: float | None) -> bool:
    """Whether ``time_limit`` covers twice the model's expected set-up."""
    return time_limit is None or time_limit >= 2 * SETUP_SECONDS_PER_ARC * (merged.size + 1) ** 2


def _no_time(merged: Merged, began: float) -> MilpResult:
    """``unknown``: the time limit is too short to build the cvxpy model."""
    return MilpResult("unknown", seconds=time.perf_counter() - began,
                      message=f"time limit: too short to build the cvxpy model of {merged.size} KPOIs")


def _optimal_without_model(merged: Merged, value: float, began: float) -> MilpResult:
    """Every KPOI is at the start: one route of cost 0."""
    return MilpResult("optimal", merged.expand([]), value, value, 0.0, 0,
                      time.perf_counter() - began, "every KPOI is at the start")
