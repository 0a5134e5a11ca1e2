"""Re-proving a solution file's ``optimal``, ``infeasible`` and ``bound`` claims.

``parcover verify --certify`` and ``pc.verify(..., certify=True)`` ask the file's own
question again with an exact method other than the one that proved the file's claims
(docs/format.md section 4), so that a claim is never checked by the code that made it.
The file's proof is its ``model`` (the model ``exact`` chose, e.g. ``branchprice``; files
written before that key existed do not have it) or else its ``method``; when the method
is ``exact`` without a ``model``, every model ``exact`` may answer with at that size
(:func:`parcover.exact.exact_models`) is left out. The certifier is the first of those
that can reach the question (:func:`certifier_for`) that is not left out:

- ``setpart`` up to :data:`milp.setpart.MAX_KPOIS` KPOIs;
- for the least makespan with at most :data:`parcover.exact.RACE_ROUTES` robots on up to
  :data:`parcover.exact.RACE_MAX_KPOIS` KPOIs, ``branchcut``, then ``branchprice``
  (Necula's eil51, berlin52 and eil76 with 2 tours: only branch-and-cut proves them in
  minutes, so their branch-and-cut proofs stay undecided; eil51 with 3 tours, proven by
  branch-and-price in 84 s: branch-and-cut's bound was 152.94 after 600 s and 154.49
  after 1800 s against the optimum 159.57, on a machine shared with other work);
- else ``branchprice`` (up to :data:`milp.branchprice.MAX_KPOIS` KPOIs), then
  ``branchcut`` for the least makespan (up to its :data:`milp.branchcut.MAX_KPOIS`);
- ``compact`` last: it proves small instances only.

The certifier starts from the file's routes (they passed the verifier), so it has to
prove only that nothing is better; its proof of the bound is its own.

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

from milp.core.timelimit import interrupted
from parcover.instance import Instance
from parcover.result import Result, RoutesKind, Status
from parcover.verify import Certificate, Verdict
from parcover.verify import verify as check

__all__ = ["Certificate", "certify", "certifier_for", "reaching", "verify"]


#: Exact models a file's ``model`` may name, each a method of its own (``bounds``: ``exact``
#: found best's routes at the trivial lower bound).
MODELS = ("setpart", "branchprice", "branchcut", "compact", "cvxpy", "bounds", "colgen")


def certifier_for(instance: Instance, method: str | None, objective: str, *, model: str | None = None,
                  robots: int | None = None) -> str:
    """The exact method independent of the file's proof on ``objective`` (module docstring).

    ``method`` and ``model`` are the file's (``model`` None for files without it);
    ``robots`` the robot limit of a least-makespan question (None: unknown).
    """
    from parcover.exact import exact_models

    if isinstance(model, str) and model in MODELS:
        used = {method, model}
    else:
        used = {method} | (exact_models(instance.n, objective, robots) if method == "exact" else set())
    candidates = reaching(instance.n, objective, robots)
    return next((c for c in candidates if c not in used), "compact")


def reaching(n: int, objective: str, robots: int | None = None) -> tuple[str, ...]:
    """The exact methods that can prove a question on ``n`` KPOIs, most likely first."""
    from milp.core.sizes import BRANCHCUT_MAX_KPOIS, BRANCHPRICE_MAX_KPOIS, SETPART_MAX_KPOIS
    from parcover.exact import RACE_MAX_KPOIS, RACE_ROUTES

    makespan = objective == "makespan"
    cut = ("branchcut",) if makespan and n <= BRANCHCUT_MAX_KPOIS else ()
    price = ("branchprice",) if n <= BRANCHPRICE_MAX_KPOIS else ()
    if n <= SETPART_MAX_KPOIS:
        return ("setpart", *price, *cut, "compact")
    if makespan and robots is not None and robots <= RACE_ROUTES and n <= RACE_MAX_KPOIS:
        return (*cut, *price, "compact")
    return (*price, *cut, "compact")


def certify(instance: Instance, fields: Mapping[str, Any], *, time_limit: float = 60.0) -> Certificate:
    """Re-prove the ``status`` and ``bound`` claims of a (structurally valid) result.

    ``fields`` is the parsed result JSON; its question (``routes_kind``, ``objective``,
    ``robots_limit`` / ``deadline``) is asked again within ``time_limit`` seconds.
    """
    status, bound = fields.get("status"), fields.get("bound")
    if status not in ("optimal", "infeasible") and bound is None:
        return Certificate("nothing to certify", None)
    objective = fields.get("objective")
    kind = fields.get("routes_kind", "paths")
    robots = fields.get("robots_limit") if objective == "makespan" else None
    method = certifier_for(instance, fields.get("method"), "makespan" if objective == "makespan" else "robots",
                           model=fields.get("model"), robots=robots if isinstance(robots, int) else None)
    if objective == "makespan":
        question: dict[str, Any] = {"robots": fields.get("robots_limit")}
        claimed = fields.get("makespan")
    else:
        question = {"deadline": fields.get("deadline")}
        claimed = fields.get("robots")
    answer = _solve(instance, kind, question, method, fields.get("routes"), time_limit)
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
    when = "before it was interrupted (Ctrl-C)" if interrupted() else f"within {time_limit:g} s"
    return Certificate("undecided", method, [
        f"{method} did not prove {when} (its bound {proven}, its value "
        f"{'-' if found is None else format(found, '.10g')})"])


def _solve(instance: Instance, kind: str, question: dict[str, Any], method: str, routes: Any,
           time_limit: float) -> Result:
    """The certifier's answer to the file's question, from the file's routes when the
    certifier takes a warm start and they fit the question (else from its own)."""
    from milp.core.timelimit import TimeLimit
    from parcover.errors import InputError
    from parcover.solve import method_with_options, solve

    limit = TimeLimit(time_limit)
    if routes and "warm_start" in method_with_options(method).options:
        try:
            return solve(instance, kind, **question, method=method, time_limit=limit, warm_start=routes)
        except InputError:  # routes that do not fit the question as asked again (e.g. no deadline)
            pass
    return solve(instance, kind, **question, method=method, time_limit=limit)


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
