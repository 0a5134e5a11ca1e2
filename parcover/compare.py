"""The comparison every claim about an optimum reduces to.

A claim says ``opt RELATION claimed`` (``eq``, ``le``, ``ge``); an exact result brackets
the optimum between its proven bound and its verified value, ``bound <= opt <= value``.
:func:`compare_optimum` says whether the bracket proves the claim (``holds``), refutes it
(a proven optimum or bound on the wrong side, or a verified solution better than the
claim: a witness), or straddles it (``undecided``). :mod:`parcover.props` checks the
paper's claims with it, :func:`parcover.question.check` a file's question.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

from parcover.result import Result, Status

__all__ = ["CheckStatus", "Relation", "Outcome", "compare_optimum", "describe", "brief", "number"]

CheckStatus = Literal["holds", "refuted", "undecided", "error"]
Relation = Literal["eq", "le", "ge"]

_RTOL = 1e-6  # makespans compared with this relative slack (floating-point sums)


@dataclass(frozen=True)
class Outcome:
    """What one instance says about one claim.

    Attributes
    ----------
    status
        ``holds``, ``refuted``, ``undecided`` (the reference's bracket straddles the
        claimed value) or ``error`` (a method raised).
    numbers
        The exact numbers behind the status, one line.
    results
        The results to draw: (greedy, reference), or (reference,) alone.
    """

    status: CheckStatus
    numbers: str
    results: tuple[Result, ...] = ()


def compare_optimum(reference: Result, relation: Relation, claimed: float, what: str) -> Outcome:
    """Decide ``opt RELATION claimed`` from the reference's bracket ``bound <= opt <= value``.

    Parameters
    ----------
    reference
        An exact result; its ``value`` (verified, so ``opt <= value``) and proven
        ``bound`` (``opt >= bound``; ``opt = value`` when optimal).
    relation
        ``"eq"``, ``"le"`` (``opt <= claimed``) or ``"ge"`` (``opt >= claimed``; a
        greedy is optimal exactly when the optimum is not below its value).
    claimed
        The claimed value.
    what
        Label of the claimed value in the numbers line, e.g. ``"paper: 3 paths, makespan 4"``.
    """
    value = reference.value if reference.has_routes and reference.value is not None else math.inf
    if reference.status is Status.OPTIMAL:
        bound = value
    else:
        bound = reference.bound if reference.bound is not None else -math.inf
    tol = _RTOL * max(1.0, abs(claimed))
    below = value < claimed - tol  # opt < claimed, witnessed
    above = bound > claimed + tol  # opt > claimed, proven
    if relation == "le":
        status: CheckStatus = "holds" if value <= claimed + tol else "refuted" if above else "undecided"
    elif relation == "ge":
        status = "holds" if bound >= claimed - tol else "refuted" if below else "undecided"
    else:
        holds = value <= claimed + tol and bound >= claimed - tol
        status = "holds" if holds else "refuted" if (below or above) else "undecided"
    return Outcome(status, f"{what}; {describe(reference)}", (reference,))


def describe(result: Result) -> str:
    """``exact: 2 paths, makespan 4 (optimal)`` or with the bound when not proven."""
    if not result.has_routes:
        return f"{result.method}: no solution ({result.status.value})"
    proof = "optimal" if result.status is Status.OPTIMAL else f"{result.status.value}, bound {number(result.bound)}"
    return f"{brief(result)} ({proof})"


def brief(result: Result) -> str:
    """``paper: 3 paths, makespan 25.1`` (a greedy's numbers, no proof claimed)."""
    return f"{result.method}: {_count(result.robots, result.routes_kind[:-1])}, makespan {number(result.makespan)}"


def _count(count: int | None, noun: str) -> str:
    return f"{count} {noun}{'' if count == 1 else 's'}"


def number(x: float | None) -> str:
    """``x`` to 6 significant digits, ``-`` for None."""
    return "-" if x is None else f"{x:.6g}"
