"""What a solver returns: :class:`Status`, :class:`Result` and :class:`Frontier`.

The JSON forms are the contract of docs/format.md section 4.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from enum import Enum
from typing import Any, Literal

__all__ = ["Status", "Result", "Frontier", "FrontierPoint", "RoutesKind", "Objective", "gap", "plural"]

RoutesKind = Literal["paths", "tours"]
Objective = Literal["makespan", "robots"]


class Status(str, Enum):
    """How much a result is worth.

    - ``OPTIMAL``: the value is proven optimal (the solver closed the gap to 1e-9
      relative, or the value meets a proven lower bound).
    - ``FEASIBLE``: the routes are valid, but optimality is not proven; ``bound``
      holds the best proven lower bound.
    - ``INFEASIBLE``: it is proven that no solution exists (e.g. a deadline below
      ``c_max``); there are no routes.
    - ``UNKNOWN``: nothing was found within the limits; there are no routes.
    """

    OPTIMAL = "optimal"
    FEASIBLE = "feasible"
    INFEASIBLE = "infeasible"
    UNKNOWN = "unknown"

    def __str__(self) -> str:
        return self.value

    @property
    def decided(self) -> bool:
        """Whether the answer is proven: ``OPTIMAL`` or ``INFEASIBLE``."""
        return self in (Status.OPTIMAL, Status.INFEASIBLE)


def gap(value: float | None, bound: float | None) -> float | None:
    """Relative gap ``(value - bound) / value``.

    ``None`` when either is missing; 0 when ``value`` is 0 (then the bound, never
    above the value, is 0 too). Never negative.
    """
    if value is None or bound is None:
        return None
    if value == 0:
        return 0.0
    return max(0.0, (value - bound) / value)


@dataclass(frozen=True)
class Result:
    """A solution of one coverage question, with its proof status.

    Every result built by :func:`parcover.solve` has passed :func:`parcover.verify`.

    Attributes
    ----------
    instance
        Instance name.
    routes_kind
        ``"paths"`` or ``"tours"``.
    objective
        ``"makespan"`` (at most ``robots_limit`` robots) or ``"robots"`` (every route
        within ``deadline``).
    robots_limit, deadline
        The constraint the routes were checked against (``None`` when absent).
    method
        Name of the method that produced the routes.
    model
        (A property over ``info["model"]``.) The exact model within ``method`` whose
        answer this is, e.g. ``"branchprice"`` or ``"branchcut"`` for ``exact``: the one
        that proved an ``optimal`` or ``infeasible`` status. ``None`` when the method
        names none.
    status
        See :class:`Status`.
    robots, makespan
        Number of routes and the largest route cost (``None`` without routes).
    bound
        Proven lower bound on the objective's value (robots or makespan).
    gap
        ``(value - bound) / value``; 0 when optimal.
    routes
        One list of ids per robot: the start, then its KPOIs in order (tours list
        the start again at the end).
    route_costs
        Cost of each route, recomputed from the instance.
    seconds
        Wall-clock time of the method.
    info
        Method-specific extras (node counts, the greedy's trace, ...); not part of
        the JSON contract unless a key is documented by the method.
    """

    instance: str
    routes_kind: RoutesKind
    objective: Objective
    robots_limit: int | None
    deadline: float | None
    method: str
    status: Status
    robots: int | None
    makespan: float | None
    bound: float | None
    gap: float | None
    routes: list[list[str]]
    route_costs: list[float]
    seconds: float
    info: dict[str, Any] = field(default_factory=dict, compare=False)

    @property
    def value(self) -> float | None:
        """The objective's value: ``makespan`` or ``robots``."""
        return self.makespan if self.objective == "makespan" else self.robots

    @property
    def model(self) -> str | None:
        """The exact model that answered within :attr:`method` (``info["model"]``), or None."""
        model = self.info.get("model")
        return model if isinstance(model, str) and model else None

    @property
    def has_routes(self) -> bool:
        return bool(self.routes)

    @property
    def note(self) -> str | None:
        """Why an answer is not proven or has no routes (the method's message), else None."""
        if self.info.get("message") and (not self.routes or self.status is not Status.OPTIMAL):
            return str(self.info["message"])
        return None

    def to_dict(self) -> dict[str, Any]:
        """The JSON object of docs/format.md section 4, with ``model`` (:attr:`model`) and
        ``note`` (:attr:`note`) when there is one (optional keys, compatible extensions)."""
        return {
            "instance": self.instance,
            "routes_kind": self.routes_kind,
            "objective": self.objective,
            "robots_limit": self.robots_limit,
            "deadline": self.deadline,
            "method": self.method,
            **({"model": self.model} if self.model else {}),
            "status": self.status.value,
            "robots": self.robots,
            "makespan": self.makespan,
            "bound": self.bound,
            "gap": self.gap,
            "routes": self.routes,
            "route_costs": self.route_costs,
            "seconds": round(self.seconds, 6),
            **({"note": self.note} if self.note else {}),
        }

    def to_json(self) -> str:
        """The JSON object, one key per line."""
        return _json_lines(self.to_dict())

    def headline(self) -> str:
        """One line: status, value and bound with their units, gap (or the note)."""
        if not self.routes:
            return f"{self.status.value}" + (f": {self.note}" if self.note else "")
        value = (plural(self.robots, "robot") if self.objective == "robots"
                 else f"makespan {_num(self.makespan)}")
        gap_text = f"{100 * self.gap:.4g}%" if self.gap is not None else "-"
        return f"{self.status.value}: {value}, bound {self._bound_text()}, gap {gap_text}"

    def _bound_text(self) -> str:
        """The proven bound with what it bounds: ``"3 robots (no fewer)"`` or
        ``"4.5 (makespan: no less)"``."""
        if self.bound is None:
            return "-"
        if self.objective == "robots":
            return f"{_num(self.bound)} robots (no fewer)"
        return f"{_num(self.bound)} (makespan: no less)"

    def summary(self) -> str:
        """A fixed-layout, human-readable summary."""
        question = (
            f"least makespan with at most {self.robots_limit} robots"
            if self.objective == "makespan"
            else "fewest robots"
            + ("" if self.deadline is None else f" within deadline {_num(self.deadline)}")
        )
        lines = [
            f"instance  {self.instance or '(unnamed)'}",
            f"question  {question} ({self.routes_kind})",
            f"method    {self.method}",
            f"status    {self.status.value}",
        ]
        objective = "   (the objective)"
        if self.routes:
            lines += [
                f"robots    {self.robots}" + (objective if self.objective == "robots" else ""),
                f"makespan  {_num(self.makespan)}" + (objective if self.objective == "makespan" else ""),
            ]
        if self.note:
            lines.append(f"note      {self.note}")
        gap_text = f"{100 * self.gap:.4g}%" if self.gap is not None else "-"
        lines.append(f"bound     {self._bound_text()}   gap {gap_text}")
        lines.append(f"time      {self.seconds:.3f} s")
        for r, (route, cost) in enumerate(zip(self.routes, self.route_costs), start=1):
            lines.append(f"  robot {r:>3}  cost {_num(cost):>10}  {' -> '.join(route)}")
        return "\n".join(lines)


@dataclass(frozen=True)
class FrontierPoint:
    """The optimal (or best found) makespan with ``robots`` robots."""

    robots: int
    makespan: float | None
    status: Status
    bound: float | None
    result: Result | None = field(default=None, compare=False, repr=False)

    def to_dict(self) -> dict[str, Any]:
        return {
            "robots": self.robots,
            "makespan": self.makespan,
            "status": self.status.value,
            "bound": self.bound,
        }


@dataclass(frozen=True)
class Frontier:
    """The robots-versus-time trade-off (docs/format.md sections 1 and 4)."""

    instance: str
    routes_kind: RoutesKind
    method: str
    points: list[FrontierPoint]
    seconds: float = 0.0
    #: Why the points end before the least possible makespan (an interrupted run), or ``None``.
    note: str | None = None

    def to_dict(self) -> dict[str, Any]:
        return {
            "instance": self.instance,
            "routes_kind": self.routes_kind,
            "method": self.method,
            "points": [p.to_dict() for p in self.points],
            **({"note": self.note} if self.note else {}),
        }

    def to_json(self) -> str:
        """The JSON object, one key per line."""
        return _json_lines(self.to_dict())

    def summary(self) -> str:
        lines = [
            f"instance  {self.instance or '(unnamed)'}",
            f"frontier  {self.routes_kind}, method {self.method}",
            f"{'robots':>6}  {'makespan':>12}  {'bound':>12}  status",
        ]
        for p in self.points:
            makespan = _num(p.makespan) if p.makespan is not None else "-"
            bound = _num(p.bound) if p.bound is not None else "-"
            lines.append(f"{p.robots:>6}  {makespan:>12}  {bound:>12}  {p.status.value}")
        if self.note:
            lines.append(f"note      {self.note}")
        return "\n".join(lines)


def _json_lines(data: dict[str, Any]) -> str:
    """A JSON object with one top-level key per line and compact values."""
    body = ",\n".join(f"  {json.dumps(k)}: {json.dumps(v, allow_nan=False)}" for k, v in data.items())
    return "{\n" + body + "\n}"


def plural(count: int, noun: str) -> str:
    """``count`` and ``noun``, with an ``s`` unless ``count`` is 1: "1 robot", "3 robots"."""
    return f"{count} {noun}{'' if count == 1 else 's'}"


def _num(x: float | None) -> str:
    return "-" if x is None else f"{x:.6g}"
