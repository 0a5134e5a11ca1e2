"""Re-proving a solution file's ``optimal``, ``infeasible`` and ``bound`` claims.

``parcover verify --certify`` and ``pc.verify(..., certify=True)`` ask the file's own
question again with an exact method other than the one the file names (docs/format.md
section 4), so that a claim is never checked by the code that made it:

- the first of ``setpart`` (at most :data:`milp.setpart.MAX_KPOIS` KPOIs),
  ``branchprice`` and ``compact`` that is not the file's method nor one that ``exact``
  may answer with at this size (:func:`parcover.exact.exact_models`) when the file's
  method is ``exact``.

Outcomes: ``certified`` (every such claim agrees with the proven answer), ``refuted``
(one contradicts a proven optimum, or a claimed bound is above a solution the certifier
found), ``undecided`` (the certifier did not prove within the time limit, and nothing it
found contradicts the file).

Certification sits above both the verifier and the solvers: :func:`verify` (which is
``pc.verify``) runs the independent verifier :func:`parcover.verify.verify`, then, when
asked, :func:`certify`, which solves.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

from parcover.instance import Instance
from parcover.result import Result, RoutesKind, Status
from parcover.verify import Certificate, Verdict
from parcover.verify import verify as check

__all__ = ["Certificate", "certify", "certifier_for", "verify"]


def certifier_for(instance: Instance, method: str | None, objective: str) -> str:
    """The exact method independent of ``method`` on ``objective`` (module docstring)."""
    from milp.setpart import MAX_KPOIS
    from parcover.exact import exact_models

    used = {method} | (exact_models(instance.n, objective) if method == "exact" else set())
    candidates = (("setpart",) if instance.n <= MAX_KPOIS else ()) + ("branchprice", "compact")
    return next((c for c in candidates if c not in used), "compact")


def certify(instance: Instance, fields: Mapping[str, Any], *, time_limit: float = 60.0) -> Certificate:
    """Re-prove the ``status`` and ``bound`` claims of a (structurally valid) result.

    ``fields`` is the parsed result JSON; its question (``routes_kind``, ``objective``,
    ``robots_limit`` / ``deadline``) is asked again within ``time_limit`` seconds.
    """
    from parcover.solve import solve

    status, bound = fields.get("status"), fields.get("bound")
    if status not in ("optimal", "infeasible") and bound is None:
        return Certificate("nothing to certify", None)
    objective = fields.get("objective")
    kind = fields.get("routes_kind", "paths")
    method = certifier_for(instance, fields.get("method"), "makespan" if objective == "makespan" else "robots")
    if objective == "makespan":
        answer = solve(instance, kind, robots=fields.get("robots_limit"), method=method, time_limit=time_limit)
        claimed = fields.get("makespan")
    else:
        answer = solve(instance, kind, deadline=fields.get("deadline"), method=method, time_limit=time_limit)
        claimed = fields.get("robots")
    reasons = []
    if answer.status is Status.INFEASIBLE:
        if status != "infeasible":
            reasons.append(f"{method} proves the question infeasible")
        return Certificate("refuted" if reasons else "certified", method, reasons)
    if status == "infeasible":
        if answer.has_routes:
            reasons.append(f"claimed infeasible, but {method} found a solution of value {answer.value:.10g}")
            return Certificate("refuted", method, reasons)
        return Certificate("undecided", method, [f"{method} neither found a solution nor proved none"])
    found = answer.value if answer.has_routes else None
    if bound is not None and found is not None and bound > found * (1 + 1e-7) + 1e-9:
        reasons.append(f"bound {bound:.10g} is above a solution of value {found:.10g} found by {method}")
    if answer.status is Status.OPTIMAL:
        if status == "optimal" and claimed is not None and abs(claimed - found) > 1e-7 * max(1.0, abs(found)) + 1e-9:
            reasons.append(f"claimed optimal {claimed:.10g}, {method} proves the optimum is {found:.10g}")
        return Certificate("refuted" if reasons else "certified", method, reasons)
    if status == "optimal" and claimed is not None and found is not None and found < claimed * (1 - 1e-7) - 1e-9:
        reasons.append(f"claimed optimal {claimed:.10g}, {method} found {found:.10g}")
    if reasons:
        return Certificate("refuted", method, reasons)
    proven = "-" if answer.bound is None else f"{answer.bound:.10g}"
    return Certificate("undecided", method, [
        f"{method} did not prove within {time_limit:g} s (its bound {proven}, its value "
        f"{'-' if found is None else format(found, '.10g')})"])


_certify = certify  # the function, which the parameter ``certify`` of :func:`verify` hides


def verify(
    instance: Instance,
    solution: Result | Mapping[str, Any] | Sequence[Sequence[str]],
    *,
    routes_kind: RoutesKind | None = None,
    deadline: float | None = None,
    robots_limit: int | None = None,
    certify: bool = False,
    time_limit: float = 60.0,
) -> Verdict:
    """Check a solution against an instance and recompute its costs; optionally re-prove its claims.

    Parameters
    ----------
    instance, solution, routes_kind, deadline, robots_limit
        As for :func:`parcover.verify.verify`, which checks the solution.
    certify
        Also re-prove the file's ``optimal``/``infeasible`` status and its ``bound`` with
        an independent exact method within ``time_limit`` seconds (:func:`certify`; the
        outcome is ``Verdict.certificate``). A :class:`Result` is re-proved as its JSON
        states it; a solution with a false claim, or given as bare routes, is not.

    Returns
    -------
    Verdict
        Costs, makespan, robots and the constraint excesses (see
        :func:`parcover.verify.verify`), and the certificate when ``certify`` ran.

    Raises
    ------
    InvalidSolution
        If the routes are not a partition of the KPOIs into routes from the start
        (every problem is listed).
    InputError
        If ``instance`` is not an :class:`Instance`.
    """
    if certify and isinstance(solution, Result):
        solution = solution.to_dict()  # its claims, as a file would state them, to re-prove
    verdict = check(instance, solution, routes_kind=routes_kind, deadline=deadline, robots_limit=robots_limit)
    if not certify or not isinstance(solution, Mapping) or verdict.false_claims:
        return verdict
    return replace(verdict, certificate=_certify(instance, solution, time_limit=time_limit))
