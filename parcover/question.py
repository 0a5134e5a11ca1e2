"""Asking the question an instance file carries again: :func:`load` reads it with its
instance, :func:`check` asks it with the greedy the claim is about and an exact method,
:func:`render_check` shows the answers side by side.

The block itself (:class:`Question`, :class:`Answer`: its format, validation and JSON)
is :mod:`parcover.question_block`, which :mod:`parcover.io` uses when it reads and writes
a file; this module reads files and solves, above both. Its names are re-exported here.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path

from milp.core.sizes import SETPART_MAX_KPOIS
from parcover.compare import compare_optimum
from parcover.instance import Instance, Metric
from parcover.io import read_instance, read_json
from parcover.question_block import Answer, GreedyLimit, Question, reading_of
from parcover.result import Result

__all__ = ["Answer", "Question", "GreedyLimit", "Check", "check", "render_check", "load", "reading_of",
           "exact_method_for"]


def exact_method_for(instance: Instance) -> str:
    """``setpart`` up to its size limit (:data:`milp.core.sizes.SETPART_MAX_KPOIS` KPOIs), else ``exact``."""
    return "setpart" if instance.n <= SETPART_MAX_KPOIS else "exact"


@dataclass(frozen=True)
class Check:
    """The question asked again: the greedy's and the exact method's results, and the verdict.

    ``refuted`` is true when the greedy's answer answers the question (meets its
    limit; with ``greedy.limit = "none"`` it reaches exactly the question's limit)
    and the exact method proves or witnesses a strictly better value.
    """

    question: Question
    greedy: Result
    reference: Result
    refuted: bool
    reason: str


def check(question: Question, instance: Instance, *, reference: str | None = None,
          time_limit: float | None = None, seed: int = 0) -> Check:
    """Ask ``question`` again with its greedy and the exact ``reference`` method
    (:func:`exact_method_for` by default)."""
    greedy = question.ask_greedy(instance, time_limit=time_limit, seed=seed)
    optimum = question.ask(instance, reference or exact_method_for(instance), time_limit=time_limit, seed=seed)
    stale = _stale(question, greedy)
    if stale:
        return Check(question, greedy, optimum, False, stale)
    value = greedy.robots if question.objective == "robots" else greedy.makespan
    assert value is not None
    outcome = compare_optimum(optimum, "ge", value, f"{greedy.method} {question.objective} {value:.6g}")
    reason = {"refuted": f"{optimum.method} is better than {greedy.method}",
              "holds": f"{greedy.method}'s {question.objective} is optimal here",
              "undecided": f"{optimum.method} could not decide within its limits"}[outcome.status]
    return Check(question, greedy, optimum, outcome.status == "refuted", reason)


def render_check(name: str, outcome: Check) -> str:
    """The question, the greedy's and the exact method's answers side by side, and the verdict."""
    q, greedy, reference = outcome.question, outcome.greedy, outcome.reference
    rows = [
        ("", greedy.method, reference.method),
        ("robots", _cell(greedy.robots), _cell(reference.robots)),
        ("makespan", _cell(greedy.makespan), _cell(reference.makespan)),
        ("status", greedy.status.value, reference.status.value),
        ("recorded", _recorded(q.greedy), _recorded(q.optimum)),
    ]
    widths = [max(len(row[i]) for row in rows) for i in range(3)]
    table = ["  " + "  ".join(cell.ljust(w) for cell, w in zip(row, widths)).rstrip() for row in rows]
    verdict = "refuted" if outcome.refuted else "no longer refuted"
    return "\n".join([f"{name}: claim {q.claim}", f"  question: {q.text}", *table,
                      f"  verdict: {verdict} ({outcome.reason})"])


def _cell(x: float | None) -> str:
    return "-" if x is None else f"{x:.6g}"


def _recorded(answer: Answer) -> str:
    status = f" {answer.status.value}" if answer.status is not None else ""
    return f"{answer.robots} / {answer.makespan:.6g}{status}"


def _stale(question: Question, greedy: Result) -> str:
    """Why the greedy's answer does not answer the question (empty when it does)."""
    if greedy.robots is None or greedy.makespan is None:
        return f"{greedy.method} found no routes ({greedy.status.value})"
    if question.greedy_limit == "question":
        return ""  # solve() verified the routes against the question's limit
    if question.objective == "robots":
        assert question.deadline is not None
        reached = math.isclose(greedy.makespan, question.deadline, rel_tol=1e-9, abs_tol=1e-9)
        return "" if reached else (f"{greedy.method} now reaches makespan {greedy.makespan:.6g}, "
                                   f"not the question's deadline {question.deadline:.6g}")
    return "" if greedy.robots == question.robots else (
        f"{greedy.method} now uses {greedy.robots} robots, not the question's {question.robots}")


def load(path: str | os.PathLike[str], *, metric: Metric | None = None) -> tuple[Instance, Question | None]:
    """The instance of a file and its question (``None`` when it has none)."""
    instance = read_instance(path, metric=metric)  # refuses a bad question block
    if Path(path).suffix.lower() == ".tsp":
        return instance, None
    block = read_json(path).get("question")
    return instance, None if block is None else Question.from_dict(block, instance)
