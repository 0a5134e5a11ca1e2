"""The independent verifier: recompute everything about a solution from the instance.

It trusts nothing in a solution but its ``routes`` (and ``deadline`` /
``robots_limit`` when present, which it checks). Broken structure raises
:class:`InvalidSolution` listing every problem; a missed deadline or robot limit is
reported as a quantity on the :class:`Verdict` (by how much), PyVRP style.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from parcover.instance import Instance
from parcover.problem import meets_deadline
from parcover.result import Result, RoutesKind

__all__ = ["verify", "Verdict", "InvalidSolution", "route_costs"]

_MAX_LISTED = 10


class InvalidSolution(ValueError):
    """The routes are not a solution: wrong start, unknown ids, KPOIs missed or twice."""

    def __init__(self, problems: list[str]) -> None:
        self.problems = problems
        super().__init__("; ".join(problems))


@dataclass(frozen=True)
class Verdict:
    """What the verifier recomputed for a structurally valid solution.

    Attributes
    ----------
    deadline_excess
        How far the costliest route overshoots the deadline (0 when met or absent).
    late_routes
        Numbers (from 1) of the routes that miss the deadline.
    robots_excess
        How many robots beyond the limit (0 when met or absent).
    """

    routes_kind: RoutesKind
    robots: int
    makespan: float
    route_costs: list[float]
    total_cost: float
    deadline: float | None
    robots_limit: int | None
    deadline_excess: float
    late_routes: list[int]
    robots_excess: int

    @property
    def feasible(self) -> bool:
        """Valid structure and every given constraint met."""
        return not self.late_routes and self.robots_excess == 0

    def violations(self) -> list[str]:
        """One sentence per constraint violation (empty when feasible)."""
        out = []
        if self.late_routes:
            routes = ", ".join(map(str, self.late_routes[:_MAX_LISTED]))
            out.append(
                f"the deadline {self.deadline:g} is missed by {self.deadline_excess:g} "
                f"(route{'s' if len(self.late_routes) > 1 else ''} {routes})"
            )
        if self.robots_excess:
            out.append(
                f"{self.robots} robots exceed the limit of {self.robots_limit} by {self.robots_excess}"
            )
        return out


def verify(
    instance: Instance,
    solution: Result | Mapping[str, Any] | Sequence[Sequence[str]],
    *,
    routes_kind: RoutesKind | None = None,
    deadline: float | None = None,
    robots_limit: int | None = None,
) -> Verdict:
    """Check a solution against an instance and recompute its costs.

    Parameters
    ----------
    instance
        The instance the routes claim to solve.
    solution
        A :class:`Result`, a parsed result JSON object, or a bare list of routes.
    routes_kind
        ``"paths"`` or ``"tours"``; taken from the solution when it says, else
        inferred (tours when every route returns to the start).
    deadline, robots_limit
        Constraints to check; default to the solution's own fields.

    Returns
    -------
    Verdict
        Costs, makespan, robots and the constraint excesses.

    Raises
    ------
    InvalidSolution
        If the routes are not a partition of the KPOIs into routes from the start
        (every problem is listed).
    """
    routes, fields = _routes_and_fields(solution)
    kind = routes_kind or fields.get("routes_kind") or _infer_kind(routes, instance.start)
    if kind not in ("paths", "tours"):
        raise InvalidSolution([f"unknown routes_kind {kind!r}; expected 'paths' or 'tours'"])
    if deadline is None:
        deadline = fields.get("deadline")
    if robots_limit is None:
        robots_limit = fields.get("robots_limit")
    problems = _check_constraint_fields(deadline, robots_limit)
    indices = _route_indices(instance, routes, kind, problems)
    if problems:
        raise InvalidSolution(problems)

    costs = route_costs(instance, indices, tours=kind == "tours")
    makespan = max(costs)
    late = [] if deadline is None else [r + 1 for r, c in enumerate(costs) if not meets_deadline(c, deadline)]
    return Verdict(
        routes_kind=kind,
        robots=len(routes),
        makespan=makespan,
        route_costs=costs,
        total_cost=float(sum(costs)),
        deadline=deadline,
        robots_limit=robots_limit,
        deadline_excess=max(0.0, makespan - deadline) if late else 0.0,
        late_routes=late,
        robots_excess=max(0, len(routes) - robots_limit) if robots_limit is not None else 0,
    )


def route_costs(instance: Instance, routes: Sequence[Sequence[int]], *, tours: bool) -> list[float]:
    """Cost of each route given as KPOI indices (start implicit), from the metric."""
    d = instance.distances
    costs = []
    for route in routes:
        stops = np.array([0, *route, 0] if tours else [0, *route], dtype=np.int64)
        costs.append(float(d[stops[:-1], stops[1:]].sum()))
    return costs


def _routes_and_fields(solution: Any) -> tuple[list[Any], dict[str, Any]]:
    if isinstance(solution, Result):
        return solution.routes, {
            "routes_kind": solution.routes_kind,
            "deadline": solution.deadline,
            "robots_limit": solution.robots_limit,
        }
    if isinstance(solution, Mapping):
        if "routes" not in solution:
            raise InvalidSolution(["the solution has no 'routes'"])
        return solution["routes"], dict(solution)
    return solution, {}


def _infer_kind(routes: Any, start: str) -> RoutesKind:
    closed = isinstance(routes, Sequence) and routes and all(
        isinstance(r, Sequence) and not isinstance(r, str) and len(r) >= 2 and r[-1] == start
        for r in routes
    )
    return "tours" if closed else "paths"


def _check_constraint_fields(deadline: Any, robots_limit: Any) -> list[str]:
    problems = []
    if deadline is not None and (isinstance(deadline, bool) or not isinstance(deadline, (int, float))):
        problems.append(f"deadline must be a number or null, got {deadline!r}")
    if robots_limit is not None and (
        isinstance(robots_limit, bool) or not isinstance(robots_limit, int) or robots_limit < 1
    ):
        problems.append(f"robots_limit must be a whole number >= 1 or null, got {robots_limit!r}")
    return problems


def _route_indices(
    instance: Instance, routes: Any, kind: str, problems: list[str]
) -> list[list[int]]:
    """KPOI indices of each route; appends every structural problem to ``problems``."""
    if isinstance(routes, (str, bytes)) or not isinstance(routes, Sequence):
        problems.append("routes must be a list of lists of ids")
        return []
    if not routes:
        problems.append("there are no routes")
    start = instance.start
    covered_by: dict[int, int] = {}
    out = []
    for r, route in enumerate(routes, start=1):
        if isinstance(route, (str, bytes)) or not isinstance(route, Sequence):
            problems.append(f"route {r} is not a list of ids")
            continue
        route = list(route)
        if not route or route[0] != start:
            problems.append(f"route {r} does not begin at the start {start!r}")
            continue
        body = route[1:]
        if kind == "tours":
            if len(route) < 2 or route[-1] != start:
                problems.append(f"route {r} is a tour but does not return to the start {start!r}")
                continue
            body = route[1:-1]
        if not body:
            problems.append(f"route {r} covers no KPOI")
        indices = []
        for node in body:
            problem = _stop_problem(instance, node, r)
            if problem:
                problems.append(problem)
                continue
            i = instance.index(node)
            if i in covered_by:
                where = "twice in route" if covered_by[i] == r else f"in routes {covered_by[i]} and"
                problems.append(f"KPOI {node!r} is covered {where} {r}")
            covered_by.setdefault(i, r)
            indices.append(i)
        out.append(indices)
    missing = [v for i, v in enumerate(instance.kpois, start=1) if i not in covered_by]
    if missing:
        listed = ", ".join(repr(v) for v in missing[:_MAX_LISTED])
        more = f" and {len(missing) - _MAX_LISTED} more" if len(missing) > _MAX_LISTED else ""
        problems.append(f"{len(missing)} KPOI(s) not covered: {listed}{more}")
    return out


def _stop_problem(instance: Instance, node: Any, r: int) -> str | None:
    if not isinstance(node, str):
        return f"route {r} has a non-string id {node!r}"
    if node == instance.start:
        return f"route {r} lists the start {node!r} as a stop"
    try:
        instance.index(node)
    except KeyError:
        if node in instance.nodes:
            return f"route {r} lists {node!r}, a virtual node, not a KPOI"
        return f"route {r} has unknown id {node!r}"
    return None
