"""The independent verifier: recompute everything about a solution from the instance.

It trusts nothing in a solution but its ``routes`` (and ``deadline`` /
``robots_limit`` when present, which it checks). Broken structure raises
:class:`InvalidSolution` listing every problem; a missed deadline or robot limit is
reported as a quantity on the :class:`Verdict` (by how much), PyVRP style. Every claim a
solution file makes (``route_costs``, ``makespan``, ``robots``, ``objective``,
``status``, ``bound``, ``gap``) is compared with what was recomputed, and each false one
is a violation too (``Verdict.false_claims``). Claimed numbers must match to
:data:`CLAIM_REL` relative (plus :data:`CLAIM_ABS`): result files hold full-precision
floats, so only round-off is forgiven.

The verifier depends on nothing that solves: re-proving a file's ``optimal``,
``infeasible`` and ``bound`` claims with an exact method (``--certify``) sits above it,
in :mod:`parcover.certify`, which fills :attr:`Verdict.certificate`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from parcover.errors import InputError
from parcover.instance import Instance
from parcover.problem import meets_deadline
from parcover.result import Result, RoutesKind

__all__ = ["verify", "Verdict", "InvalidSolution", "Certificate", "route_costs"]

_MAX_LISTED = 10
#: A claimed number ``c`` matches a recomputed ``x`` when ``|c - x| <= CLAIM_REL * max(1, |x|)
#: + CLAIM_ABS``.
CLAIM_REL, CLAIM_ABS = 1e-7, 1e-9
_STATUSES = ("optimal", "feasible", "infeasible", "unknown")


class InvalidSolution(ValueError):
    """The routes are not a solution: wrong start, unknown ids, KPOIs missed or twice."""

    def __init__(self, problems: list[str]) -> None:
        self.problems = problems
        super().__init__("; ".join(problems))


@dataclass(frozen=True)
class Certificate:
    """What the independent exact method said about the file's claims
    (:func:`parcover.certify.certify`)."""

    outcome: str  # "certified", "refuted", "undecided" or "nothing to certify"
    method: str | None
    reasons: list[str] = field(default_factory=list)


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
    makespan: float | None  # None for an answer without routes (infeasible or unknown)
    route_costs: list[float]
    total_cost: float
    deadline: float | None
    robots_limit: int | None
    deadline_excess: float
    late_routes: list[int]
    robots_excess: int
    false_claims: tuple[str, ...] = ()
    certificate: Certificate | None = None

    @property
    def feasible(self) -> bool:
        """Valid structure and every given constraint met."""
        return not self.late_routes and self.robots_excess == 0

    @property
    def valid(self) -> bool:
        """Feasible, every claim of the solution file true, and none refuted by
        :func:`parcover.certify.certify` (when it ran)."""
        refuted = self.certificate is not None and self.certificate.outcome == "refuted"
        return self.feasible and not self.false_claims and not refuted

    def violations(self) -> list[str]:
        """One sentence per constraint violation and per false claim (empty when valid)."""
        out = list(self.false_claims)
        if self.certificate is not None and self.certificate.outcome == "refuted":
            out += self.certificate.reasons
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

        An ``infeasible`` or ``unknown`` answer without routes (and without a makespan
        or robots) has nothing to recompute: 0 robots, ``makespan`` None.

    Raises
    ------
    InvalidSolution
        If the routes are not a partition of the KPOIs into routes from the start
        (every problem is listed).
    InputError
        If ``instance`` is not an :class:`Instance`.
    """
    if not isinstance(instance, Instance):
        raise InputError(f"Expected an Instance, got {type(instance).__name__} {instance!r:.60}; "
                         "read a file with pc.load(path).")
    routes, fields = _routes_and_fields(solution)
    if answer_without_routes(routes, fields):
        return Verdict(routes_kind=fields.get("routes_kind") or "paths", robots=0, makespan=None,
                       route_costs=[], total_cost=0.0, deadline=fields.get("deadline"),
                       robots_limit=fields.get("robots_limit"), deadline_excess=0.0, late_routes=[],
                       robots_excess=0)
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
    claims = false_claims(fields, costs, len(routes)) if isinstance(solution, Mapping) else []
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
        false_claims=tuple(claims),
    )


def false_claims(fields: Mapping[str, Any], costs: list[float], robots: int) -> list[str]:
    """One sentence per claim of a solution file that the recomputed ``costs`` refute.

    Checked when present: ``route_costs`` (each), ``makespan``, ``robots``, ``objective``
    (``makespan`` needs a ``robots_limit``, ``robots`` a ``deadline``), ``status``
    (``infeasible``/``unknown`` only without routes, ``optimal`` only with a bound equal
    to the value), ``bound`` (at most the value) and ``gap`` (``(value - bound) / value``,
    0 when the value is at most the bound).
    """
    out: list[str] = []
    makespan = max(costs)
    claimed = fields.get("route_costs")
    if claimed is not None:
        if not _numbers(claimed) or len(claimed) != len(costs):
            out.append(f"route_costs {_short(claimed)} are not {len(costs)} numbers")
        else:
            wrong = [r + 1 for r, (c, x) in enumerate(zip(claimed, costs)) if not _matches(c, x)]
            if wrong:
                r = wrong[0]
                out.append(f"route_costs are false for route(s) {', '.join(map(str, wrong[:_MAX_LISTED]))}: "
                           f"route {r} claims {claimed[r - 1]:.10g}, costs {costs[r - 1]:.10g}")
    for key, true in (("makespan", makespan), ("robots", robots)):
        value = fields.get(key)
        if value is not None and (not _numbers([value]) or not _matches(value, true)):
            out.append(f"{key} claims {_short(value)}, recomputed {true:.10g}")
    objective = fields.get("objective")
    value = None
    if objective is not None:
        if objective == "makespan":
            value = makespan
            if fields.get("robots_limit") is None:
                out.append("objective 'makespan' without a robots_limit")
            if fields.get("deadline") is not None:
                out.append("objective 'makespan' with a deadline (that is a robots answer)")
        elif objective == "robots":
            value = float(robots)
            # A robots answer may have no deadline (the paper's Algorithm 2 for tours has
            # none); a robots_limit marks a makespan answer.
            if fields.get("robots_limit") is not None:
                out.append("objective 'robots' with a robots_limit (that is a makespan answer)")
        else:
            out.append(f"objective {_short(objective)} is neither 'makespan' nor 'robots'")
    status = fields.get("status")
    if status is not None and status not in _STATUSES:
        out.append(f"status {_short(status)} is not one of {', '.join(_STATUSES)}")
    if status in ("infeasible", "unknown"):
        out.append(f"status '{status}' with routes")
    bound, gap = fields.get("bound"), fields.get("gap")
    if bound is not None and not _numbers([bound]):
        out.append(f"bound {_short(bound)} is not a number")
        bound = None
    if bound is not None and value is not None:
        if bound > value and not _matches(bound, value):
            out.append(f"bound {bound:.10g} is above the value {value:.10g}")
        if status == "optimal" and not _matches(bound, value):
            out.append(f"status 'optimal' with bound {bound:.10g} below the value {value:.10g}")
    if status == "optimal" and bound is None:
        out.append("status 'optimal' without a bound")
    if gap is not None:
        if not _numbers([gap]):
            out.append(f"gap {_short(gap)} is not a number")
        elif bound is None:
            out.append(f"gap {gap:g} without a bound")
        elif value is not None:
            true_gap = 0.0 if value <= bound else (value - bound) / value
            if abs(gap - true_gap) > CLAIM_REL + CLAIM_ABS:
                out.append(f"gap claims {gap:.10g}, (value - bound) / value is {true_gap:.10g}")
    return out


def _numbers(values: Any) -> bool:
    return isinstance(values, Sequence) and not isinstance(values, str) and all(
        isinstance(v, (int, float)) and not isinstance(v, bool) and np.isfinite(v) for v in values)


def _matches(claimed: float, true: float) -> bool:
    return abs(claimed - true) <= CLAIM_REL * max(1.0, abs(true)) + CLAIM_ABS


def _short(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def route_costs(instance: Instance, routes: Sequence[Sequence[int]], *, tours: bool) -> list[float]:
    """Cost of each route given as KPOI indices (start implicit), from the metric."""
    d = instance.distances
    costs = []
    for route in routes:
        stops = np.array([0, *route, 0] if tours else [0, *route], dtype=np.int64)
        costs.append(float(d[stops[:-1], stops[1:]].sum()))
    return costs


def answer_without_routes(routes: Any, fields: Mapping[str, Any]) -> bool:
    """A genuine ``infeasible`` or ``unknown`` answer: no routes, no makespan, no robots."""
    return (
        isinstance(routes, list) and routes == []
        and fields.get("status") in ("infeasible", "unknown")
        and fields.get("makespan") is None
        and fields.get("robots") in (None, 0)
    )


def _routes_and_fields(solution: Any) -> tuple[list[Any], dict[str, Any]]:
    if isinstance(solution, Result):
        return solution.routes, {
            "routes_kind": solution.routes_kind,
            "objective": solution.objective,
            "deadline": solution.deadline,
            "robots_limit": solution.robots_limit,
            "status": solution.status.value,
            "makespan": solution.makespan,
            "robots": solution.robots,
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
