"""The question block an instance file carries: the claim it refutes and the question that shows it.

An instance file may hold an optional top-level ``"question"`` block (an extension
of docs/format.md section 2, documented in ``instances/README.md``)::

    "question": {
      "claim": "alg1-1-x1.5-paper-1-1-end",
      "routes": "paths",
      "objective": "robots",
      "deadline": 2.1213203435596424,
      "deadline_factor": 1.5,
      "robots": null,
      "method": "paper-1-1-end",
      "reading": "1-1-end",
      "greedy": {"robots": 2, "makespan": 1.4142135623730951},
      "optimum": {"robots": 1, "makespan": 2.0, "status": "optimal", "method": "setpart"}
    }

The question is ``routes`` with ``objective`` ``robots`` (fewest routes within
``deadline``, which is authoritative; ``deadline_factor`` is the same deadline as a
multiple of ``c_max`` and must agree with it) or ``makespan`` (least makespan with at
most ``robots``). ``method`` is the greedy the claim is about and ``reading`` its
reading of the paper's steps (``literal``, ``5d-end``, ``1-1-end``, ``nearest-end``;
``null`` for methods that are not the paper's). ``greedy`` and ``optimum`` record
what each gave. ``greedy.limit`` says how the greedy was asked: ``"question"`` (the
default: the same question) or ``"none"`` (no limit: the paper's Algorithm 2 as
published, whose makespan or tour count the question's limit was then taken from).

:meth:`Question.from_dict` validates a block (one-line :class:`InstanceError`;
:mod:`parcover.io` calls it when it reads a file), :meth:`Question.to_dict` writes it,
:meth:`Question.from_results` builds it from a greedy's and an exact method's results
and :meth:`Question.ask` solves it. Reading it from a file (:func:`parcover.question.load`)
and checking the claim again (:func:`parcover.question.check`) sit above
:mod:`parcover.io`, in :mod:`parcover.question`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal

from parcover.instance import Instance, InstanceError
from parcover.result import Objective, Result, RoutesKind, Status

__all__ = ["Answer", "Question", "GreedyLimit", "reading_of"]

GreedyLimit = Literal["question", "none"]

_FACTOR_RTOL = 1e-6  # deadline_factor x c_max must match the deadline this closely


def reading_of(method: str) -> str | None:
    """The reading of the paper's steps a method implements (``paper`` is ``literal``).

    >>> reading_of("paper"), reading_of("paper-1-1-end"), reading_of("nn")
    ('literal', '1-1-end', None)
    """
    if method == "paper":
        return "literal"
    return method.removeprefix("paper-") if method.startswith("paper-") else None


@dataclass(frozen=True)
class Answer:
    """What one method answered: robots and makespan, with status and method when known."""

    robots: int
    makespan: float
    status: Status | None = None
    method: str | None = None

    @classmethod
    def from_dict(cls, block: Any, where: str) -> Answer:
        if not isinstance(block, dict):
            raise InstanceError(f"{where} must be an object with robots and makespan, got {block!r}.")
        robots = block.get("robots")
        if isinstance(robots, bool) or not isinstance(robots, int) or robots < 1:
            raise InstanceError(f"{where}.robots must be a whole number >= 1, got {robots!r}.")
        makespan = _number(block.get("makespan"), f"{where}.makespan")
        status = block.get("status")
        if status is not None and status not in {s.value for s in Status}:
            raise InstanceError(f"{where}.status must be one of {', '.join(s.value for s in Status)}, got {status!r}.")
        method = block.get("method")
        if method is not None and not (isinstance(method, str) and method):
            raise InstanceError(f"{where}.method must be a method name, got {method!r}.")
        return cls(robots, makespan, Status(status) if status is not None else None, method)

    def to_dict(self) -> dict[str, Any]:
        data: dict[str, Any] = {"robots": self.robots, "makespan": self.makespan}
        if self.status is not None:
            data["status"] = self.status.value
        if self.method is not None:
            data["method"] = self.method
        return data


@dataclass(frozen=True)
class Question:
    """The claim an instance refutes and the question that shows it (module docstring)."""

    claim: str
    routes: RoutesKind
    objective: Objective
    deadline: float | None
    deadline_factor: float | None
    robots: int | None
    method: str
    reading: str | None
    greedy: Answer
    optimum: Answer
    greedy_limit: GreedyLimit = "question"

    # -- reading and writing ----------------------------------------------------------

    @classmethod
    def from_dict(cls, block: Any, instance: Instance) -> Question:
        """Validate a ``"question"`` block against ``instance`` (its ``c_max``).

        Raises
        ------
        InstanceError
            One line naming the first bad entry. Unknown keys are ignored, as at the
            top level of the file.
        """
        if not isinstance(block, dict):
            raise InstanceError(f"question must be an object, got {block!r}.")
        claim = _text(block.get("claim"), "question.claim")
        routes = _choice(block.get("routes"), "question.routes", ("paths", "tours"))
        objective = _choice(block.get("objective"), "question.objective", ("robots", "makespan"))
        method = _text(block.get("method"), "question.method")
        deadline, factor, robots = block.get("deadline"), block.get("deadline_factor"), block.get("robots")
        if objective == "robots":
            deadline = _number(deadline, "question.deadline")
            if robots is not None:
                raise InstanceError(f"question.robots must be null for the robots objective, got {robots!r}.")
        else:
            if isinstance(robots, bool) or not isinstance(robots, int) or robots < 1:
                raise InstanceError(f"question.robots must be a whole number >= 1 for the makespan objective, "
                                    f"got {robots!r}.")
            if deadline is not None or factor is not None:
                raise InstanceError("question.deadline and question.deadline_factor must be null for the "
                                    "makespan objective.")
        if factor is not None:
            factor = _number(factor, "question.deadline_factor")
            if not math.isclose(factor * instance.c_max, deadline, rel_tol=_FACTOR_RTOL, abs_tol=_FACTOR_RTOL):
                raise InstanceError(f"question.deadline_factor {factor:g} x c_max {instance.c_max:.10g} = "
                                    f"{factor * instance.c_max:.10g} is not question.deadline {deadline:.10g}.")
        reading = block.get("reading", reading_of(method))
        if reading != reading_of(method):
            raise InstanceError(f"question.reading {reading!r} is not method {method!r}'s reading "
                                f"{reading_of(method)!r}.")
        greedy = Answer.from_dict(block.get("greedy"), "question.greedy")
        limit = _choice(block["greedy"].get("limit", "question"), "question.greedy.limit", ("question", "none"))
        optimum = Answer.from_dict(block.get("optimum"), "question.optimum")
        return cls(claim, routes, objective, deadline, factor, robots, method, reading, greedy, optimum,
                   limit)  # type: ignore[arg-type]

    def to_dict(self) -> dict[str, Any]:
        """The ``"question"`` block, every key present (``null`` when it has no value)."""
        greedy = self.greedy.to_dict()
        if self.greedy_limit != "question":
            greedy["limit"] = self.greedy_limit
        return {
            "claim": self.claim,
            "routes": self.routes,
            "objective": self.objective,
            "deadline": self.deadline,
            "deadline_factor": self.deadline_factor,
            "robots": self.robots,
            "method": self.method,
            "reading": self.reading,
            "greedy": greedy,
            "optimum": self.optimum.to_dict(),
        }

    @classmethod
    def from_results(cls, claim: str, greedy: Result, optimum: Result, *,
                     deadline_factor: float | None = None) -> Question:
        """The question ``optimum`` answered, with what ``greedy`` and ``optimum`` gave.

        ``greedy`` either answered the same question or ran without a limit (the
        paper's Algorithm 2 as published: ``greedy.deadline`` is ``None``).
        """
        if greedy.robots is None or greedy.makespan is None or optimum.robots is None or optimum.makespan is None:
            raise ValueError("both results need routes to make a question")
        same = (greedy.routes_kind, greedy.deadline, greedy.robots_limit) == (
            optimum.routes_kind, optimum.deadline, optimum.robots_limit)
        unlimited = greedy.deadline is None and greedy.robots_limit is None
        if not (same or unlimited):
            raise ValueError("the greedy answered another question than the optimum")
        return cls(
            claim=claim,
            routes=optimum.routes_kind,
            objective=optimum.objective,
            deadline=optimum.deadline if optimum.objective == "robots" else None,
            deadline_factor=deadline_factor,
            robots=optimum.robots_limit,
            method=greedy.method,
            reading=reading_of(greedy.method),
            greedy=Answer(greedy.robots, greedy.makespan),
            optimum=Answer(optimum.robots, optimum.makespan, optimum.status, optimum.method),
            greedy_limit="question" if same else "none",
        )

    # -- describing and asking ---------------------------------------------------------

    @property
    def text(self) -> str:
        """``paths, fewest robots within deadline 2.12132 (1.5 c_max)`` or ``tours, least makespan with 2 robots``."""
        if self.objective == "robots":
            assert self.deadline is not None
            factor = f" ({self.deadline_factor:g} c_max)" if self.deadline_factor is not None else ""
            return f"{self.routes}, fewest robots within deadline {self.deadline:.6g}{factor}"
        return f"{self.routes}, least makespan with at most {self.robots} robots"

    def ask(self, instance: Instance, method: str, *, time_limit: float | None = None, seed: int = 0) -> Result:
        """Solve this question on ``instance`` with ``method``."""
        from parcover.solve import solve

        return solve(instance, self.routes, robots=self.robots, deadline=self.deadline, method=method,
                     time_limit=time_limit, seed=seed)

    def ask_greedy(self, instance: Instance, *, time_limit: float | None = None, seed: int = 0) -> Result:
        """Run :attr:`method` as the claim runs it (the question, or without a limit)."""
        if self.greedy_limit == "question":
            return self.ask(instance, self.method, time_limit=time_limit, seed=seed)
        from parcover.solve import solve

        return solve(instance, self.routes, method=self.method, time_limit=time_limit, seed=seed)


def _number(x: Any, where: str) -> float:
    if isinstance(x, bool) or not isinstance(x, (int, float)) or not math.isfinite(x) or x < 0:
        raise InstanceError(f"{where} must be a finite number >= 0, got {x!r}.")
    return float(x)


def _text(x: Any, where: str) -> str:
    if not isinstance(x, str) or not x:
        raise InstanceError(f"{where} must be a non-empty string, got {x!r}.")
    return x


def _choice(x: Any, where: str, choices: tuple[str, ...]) -> str:
    if x not in choices:
        raise InstanceError(f"{where} must be {' or '.join(map(repr, choices))}, got {x!r}.")
    return x
