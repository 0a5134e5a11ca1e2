"""The question asked of a method, and what a method answers.

A :class:`Problem` fixes the route kind and either a robot limit (objective
``makespan``) or a deadline (objective ``robots``); docs/format.md section 1. Methods are
plain callables ``method(instance, problem, *, time_limit, seed) -> Solution`` that
work on KPOI indices; :func:`parcover.solve` turns their :class:`Solution` into a
verified :class:`~parcover.result.Result`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from collections.abc import Callable
from typing import Any, Protocol

from parcover.errors import InputError
from parcover.instance import Instance, finite_float, is_number, is_whole, short_repr
from parcover.result import Objective, RoutesKind, Status

__all__ = [
    "Problem",
    "Solution",
    "Method",
    "MethodInfo",
    "meets_deadline",
    "meets_bound",
    "DEADLINE_RTOL",
    "DEADLINE_ATOL",
]

DEADLINE_RTOL = 1e-9
DEADLINE_ATOL = 1e-9


def meets_deadline(cost: float, deadline: float) -> bool:
    """docs/format.md section 1: ``cost <= deadline * (1 + 1e-9) + 1e-9``."""
    return cost <= deadline * (1 + DEADLINE_RTOL) + DEADLINE_ATOL


def meets_bound(value: float, bound: float) -> bool:
    """Whether ``value`` is no more than the proven lower ``bound`` up to the same
    tolerance as a deadline (:func:`meets_deadline`; HiGHS's MIP gaps are 1e-9 too): then
    it is optimal."""
    return meets_deadline(value, bound)


@dataclass(frozen=True)
class Problem:
    """Which coverage question to answer.

    Parameters
    ----------
    routes
        ``"paths"`` (robots stay where they finish) or ``"tours"`` (they come home).
    robots
        At most this many robots: minimise the makespan.
    deadline
        Every route within this cost: minimise the robots. With neither ``robots``
        nor ``deadline`` the question is the paper's: fewest robots at the least
        possible makespan (``c_max`` for paths, ``2 c_max`` for tours).

    Raises
    ------
    InputError
        On a robot limit below 1, a negative or non-finite deadline, or both given.
    """

    routes: RoutesKind = "paths"
    robots: int | None = None
    deadline: float | None = None

    def __post_init__(self) -> None:
        if self.routes not in ("paths", "tours"):
            raise InputError(f"Unknown route kind {self.routes!r}; expected 'paths' or 'tours'.")
        if self.robots is not None:
            if not is_whole(self.robots) or self.robots < 1:
                raise InputError(f"The robot limit must be a whole number >= 1, got {short_repr(self.robots)}.")
            object.__setattr__(self, "robots", int(self.robots))
        if self.deadline is not None:
            if not is_number(self.deadline):
                raise InputError(f"The deadline must be a number, got {short_repr(self.deadline)}.")
            value = finite_float(self.deadline)
            if value is None or value < 0:
                raise InputError(f"The deadline must be finite and >= 0, got {short_repr(self.deadline)}.")
            object.__setattr__(self, "deadline", value)
        if self.robots is not None and self.deadline is not None:
            raise InputError("Give a robot limit or a deadline, not both.")

    @property
    def objective(self) -> Objective:
        return "makespan" if self.robots is not None else "robots"

    @property
    def tours(self) -> bool:
        return self.routes == "tours"

    def least_makespan(self, instance: Instance) -> float:
        """``c_max`` for paths, ``2 c_max`` for tours (paper, Prop. 1)."""
        return 2 * instance.c_max if self.tours else instance.c_max

    def effective_deadline(self, instance: Instance) -> float | None:
        """The deadline every route must meet: given, or the least makespan for the
        robots objective; ``None`` for the makespan objective."""
        if self.objective == "makespan":
            return None
        return self.deadline if self.deadline is not None else self.least_makespan(instance)


@dataclass
class Solution:
    """What a method returns, in KPOI indices.

    Attributes
    ----------
    routes
        One list per robot of KPOI indices (1..n, rows of ``instance.distances``) in
        visiting order; the start is implicit at the beginning (and the end of tours).
    bound
        A proven lower bound on the objective (makespan or robots), or ``None``.
    status
        Set by methods that prove something (``OPTIMAL``, ``INFEASIBLE``,
        ``UNKNOWN``); ``None`` lets :func:`parcover.solve` decide from the bound.
    drops_deadline
        The method answered without a deadline (the paper's Algorithm 2 as
        published): the result reports deadline ``None`` and the makespan reached.
    info
        Method-specific extras (trace lines, node counts, ...).
    """

    routes: list[list[int]]
    bound: float | None = None
    status: Status | None = None
    drops_deadline: bool = False
    info: dict[str, Any] = field(default_factory=dict)


class Method(Protocol):
    """A solution method: ``method(instance, problem, *, time_limit, seed)``."""

    def __call__(
        self, instance: Instance, problem: Problem, *, time_limit: float | None, seed: int
    ) -> Solution: ...


@dataclass(frozen=True)
class MethodInfo:
    """A method as offered by ``parcover solve --method NAME``.

    Algorithm modules list theirs in a module-level ``METHODS`` tuple, which
    :mod:`parcover.solve` collects.

    Attributes
    ----------
    name
        The ``--method`` name.
    function
        A :class:`Method`.
    description
        One line for ``parcover solve --help``.
    options
        Names of the extra keyword arguments it accepts (e.g. ``"trace"``).
    """

    name: str
    function: Callable[..., Solution]
    description: str
    options: tuple[str, ...] = ()
