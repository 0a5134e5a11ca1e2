"""Bridge from an :class:`~parcover.instance.Instance` to the exact models in :mod:`milp`.

The models work on the distance matrix alone (start at index 0); this module hands
them the matrix, a warm start, and maps their answer back to a
:class:`~parcover.problem.Solution`, which :func:`parcover.solve` then verifies
independently. Six methods:

- ``exact`` (the default): ``setpart`` up to :data:`SETPART_FIRST` KPOIs (16 for the
  least makespan, 14 for the fewest robots), where it is
  the fastest (a fraction of a second), after checking, for the least makespan from
  n = 14, whether ``best``'s constructions already meet the trivial lower bound
  (``info["model"]`` is then ``"bounds"``); up to :data:`milp.setpart.MAX_KPOIS` KPOIs
  ``branchprice`` for :data:`BRANCHPRICE_FIRST` seconds, then ``setpart`` if that was
  not enough and the time left covers :func:`milp.setpart.expected_seconds`
  (``branchprice`` is often 5-50x faster there, ``setpart`` always done in 1-4 s); ``branchprice`` above, ``compact`` above its size limit;
  for the least makespan with at most :data:`RACE_ROUTES` robots on 21 to
  :data:`RACE_MAX_KPOIS` KPOIs,
  ``branchprice`` in this process for the whole time, against ``branchcut`` in another
  from :data:`BRANCHPRICE_FIRST` seconds on (from :data:`SEARCH_FIRST_ROUTES` robots, or 2 from
  :data:`SEARCH_FIRST_KPOIS` KPOIs, after ``best``'s and PyVRP's local search for a share
  of the time), on two cores (:func:`_race_makespan`; the
  first proof stops the other; one core: ``branchprice`` alone), and above those sizes
  against ``best``'s local search in the same way; for the fewest robots
  above :data:`ROOT_FIRST_MAX` KPOIs, ``branchprice`` here against PyVRP's search for
  fewer routes in another process, which first proves the q-route LP bound
  (``info["model"]`` ``"colgen"`` when that proves the answer) and stops when its routes
  meet that or the bound ``branchprice``'s root proved (:func:`_race_robots`; one core:
  ``best`` looks for them after the root, :func:`balanced_search`);
  on the first use after installation, when the time limit leaves no room to compile
  ``branchprice``'s pricing (:data:`milp.branchprice.COMPILE_SECONDS`), ``setpart`` to 20
  KPOIs and ``compact`` above;
- ``branchprice``: branch-and-price over ng-routes (:mod:`milp.branchprice`); for the
  fewest robots up to :data:`ROOT_FIRST_MAX` KPOIs it starts from ``best``'s
  construction and runs ``best``'s rounds only if the root bound leaves room;
- ``branchcut``: the least makespan by branch-and-cut over a three-index model
  (:mod:`milp.branchcut`), strongest with 2-3 long routes;
- ``compact``: the compact arc-flow model solved by HiGHS (:mod:`milp.compact.arcflow`);
- ``setpart``: Held-Karp route enumeration and set partitioning by inclusion-exclusion
  counting (:mod:`milp.setpart`), an exact method independent of the compact model,
  for up to 20 KPOIs;
- ``cvxpy``: the compact model written in cvxpy for reading (:mod:`milp.compact.cvx`).

``time_limit`` is seconds from the call or a :class:`~milp.core.timelimit.TimeLimit` shared
with the caller (:func:`parcover.solve` passes one); the warm start and the model
share it.
"""

from __future__ import annotations

import logging
import os
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from milp.core.sizes import (
    BRANCHCUT_MAX_KPOIS,
    BRANCHPRICE_MAX_KPOIS,
    SETPART_MAX_KPOIS,
)
from milp.core.timelimit import TimeLimit, TimeLimitLike
from parcover.errors import InputError
from parcover.instance import Instance
from parcover.problem import MethodInfo, Problem, Solution, meets_deadline
from parcover.result import Status

__all__ = ["METHODS", "branch_and_cut", "branch_and_price", "compact", "cvxpy_model", "exact", "setpart", "warm_start_routes"]

log = logging.getLogger(__name__)

_STATUS = {"optimal": Status.OPTIMAL, "infeasible": Status.INFEASIBLE, "unknown": Status.UNKNOWN}

# The warm start: a fixed number of `best` rounds (deterministic), within this share
# of the exact method's time limit when one is given. The makespan models gain most
# from a good incumbent (their bounds are weak); for the robots objective the
# column-generation master and the model usually settle it, so a short search does.
WARM_SHARE = 0.1
WARM_ROUNDS = {"makespan": 200, "robots": 20}

#: For the fewest robots up to this many KPOIs, ``branchprice`` starts from ``best``'s
#: construction alone and runs ``best``'s rounds only when its root bound does not prove
#: that construction (:func:`milp.branchprice.min_robots`' ``improve``): there the root is
#: cheaper than the rounds; above it, long tours make a root without a good incumbent
#: dear (measured: ``milp/README.md``, branch-and-price).
ROOT_FIRST_MAX = 30
#: Above it, when the root's bound does not prove the warm start, ``best`` looks for
#: routes meeting that bound for as long as the root took beyond the warm start, at most
#: this share of the time left (:func:`balanced_search`): at 100 KPOIs the tree may not
#: reach routes that a local search aimed at the root's bound finds (``milp/README.md``).
IMPROVE_SHARE = 0.5
#: ``exact`` runs ``setpart`` alone up to this many KPOIs, per objective. For the fewest
#: robots ``branchprice`` (starting from the root, :data:`ROOT_FIRST_MAX`) overtakes it
#: sooner: measured on 24 questions a size (seeds 1-3 and 11-13, paths and tours, 1.0
#: and 1.2 x the least makespan), 0.29 s against 0.30 s in all at n = 14 (slower on 7),
#: 0.32 against 0.60 s at n = 15 (slower on 1), 0.40 against 1.16 s at n = 16 (never).
SETPART_FIRST = {"makespan": 16, "robots": 14}
#: For the least makespan, ``exact`` first checks whether ``best``'s polished
#: constructions meet the trivial lower bound when ``setpart`` is expected to take at
#: least this long (n >= 14). Measured (seeds 1-3, 11-13, paths and tours): it doubled the
#: time at n = 10 (setpart takes 3 ms there); at n = 14-16 it settles 19 of 109 makespan
#: questions (mostly k = 5) 10-20x faster, about as much as the misses cost (0.02 s
#: each), but only 2 of 72 fewest-robots questions, so it is not tried for those.
QUICK_CHECK_SECONDS = 0.02
#: Seconds ``exact`` gives ``branchprice`` before ``setpart`` on 17 to 20 KPOIs (at most
#: half of the time limit): measured on n = 17-20, ``branchprice`` proves almost every
#: question in under 1.5 s where ``setpart`` takes 1-3 s, and fails on a few in 60 s.
BRANCHPRICE_FIRST = 2.0
#: For the least makespan with at most this many robots above set partitioning's range,
#: ``exact`` races these methods when two cores are free (:func:`_race_makespan`): the
#: first in this process from the start, the second in another process once the first has
#: not proved the answer within :data:`BRANCHPRICE_FIRST` seconds.
#: Measured (``milp/README.md``, branch-and-cut): with 2 routes at n = 22-40 each of the
#: two proves questions in seconds that the other takes 30 s or more for (or does not
#: prove in 60 s), and branch-and-cut proved Necula's eil51, berlin52 and eil76 with 2
#: tours and berlin52 with 3 (18-350 s), where branch-and-price does not within 420 s;
#: with 3 routes on random instances branch-and-price is 5-20x faster.
RACE_ROUTES = 3
RACE_MODELS = ("branchprice", "branchcut")
#: The race's branch-and-cut gives a share of its time to ``best``'s and PyVRP's local
#: search first (:func:`parcover.algorithms.local_search.searched_branchcut`) from this many
#: robots, and with 2 from this many KPOIs (:func:`makespan_rival`). With 3 tours at 50
#: KPOIs the search found shorter routes that branch-and-cut never did. With 2 routes on 30-51 KPOIs (18 cells,
#: random and Necula's) it ended at the same answers and delayed proofs by up to its
#: share (n = 40 tours at 20 s unproven, proven in 18 s without; eil51 30.3 -> 40.9 s); on
#: 69-99 KPOIs (st70, eil76, pr76, rat99, kroA100 with 2 tours) proofs came sooner (pr76
#: 247.6 -> 114.0 s, eil76 343.8 -> 249.5 s), rat99's from a start 6% above the optimum,
#: which branch-and-cut alone never improved, and kroA100's routes and bound were
#: better at the limit (milp/README.md).
SEARCH_FIRST_ROUTES, SEARCH_FIRST_KPOIS = 3, 60
#: The race's rival where branch-and-cut runs alone, with all its time (:func:`makespan_rival`).
BRANCHCUT_ALONE = f"milp.{RACE_MODELS[1]}:min_makespan"
#: ``exact`` races up to this many KPOIs: branch-and-cut's size limit.
RACE_MAX_KPOIS = BRANCHCUT_MAX_KPOIS


def exact(
    instance: Instance,
    problem: Problem,
    *,
    time_limit: TimeLimitLike = None,
    seed: int = 0,
    warm_start: list[list[int]] | None = None,
    export_model: str | None = None,
) -> Solution:
    """Proven optimum within ``time_limit``: :func:`setpart` for small instances,
    :func:`branch_and_price` then :func:`setpart` up to :data:`milp.setpart.MAX_KPOIS`
    KPOIs, :func:`branch_and_price` up to :data:`milp.branchprice.MAX_KPOIS`, else
    :func:`compact` (module docstring).

    ``info["model"]`` names the one that gave the answer. Options as :func:`compact`
    (``warm_start`` is only checked by ``setpart``; ``export_model`` always writes the
    compact model).
    """
    time_limit = TimeLimit.of(time_limit)  # the imports below count against the limit
    if export_model:
        _export(instance, problem, export_model)
    # above branch-and-price's size limit (milp.core.sizes), compact alone, without loading
    # branchprice or setpart (importing branchprice took 0.7 s of a 3 s limit at 3000
    # KPOIs, 0.4 s of it numba)
    if instance.n > BRANCHPRICE_MAX_KPOIS:
        log.info("exact: compact model (more than %d KPOIs)", BRANCHPRICE_MAX_KPOIS)
        return compact(instance, problem, time_limit=time_limit, seed=seed, warm_start=warm_start)
    from milp import setpart as model

    if instance.n <= SETPART_FIRST[problem.objective]:
        if problem.objective == "makespan" and model.expected_seconds(instance.n) >= QUICK_CHECK_SECONDS:
            settled = _meets_trivial_bound(instance, problem, time_limit, seed)
            if settled is not None:
                log.info("exact: best's construction meets the lower bound: optimal")
                return settled
        log.info("exact: setpart (at most %d KPOIs)", SETPART_FIRST[problem.objective])
        return _setpart(model, instance, problem, time_limit, warm_start)
    from milp import branchprice, race  # numba: only when needed

    if not branchprice.ready_within(time_limit.remaining()):
        log.info("exact: branch-and-price not compiled and the time limit leaves no room to compile it")
        fallback = (_setpart(model, instance, problem, time_limit, warm_start) if instance.n <= model.MAX_KPOIS
                    else compact(instance, problem, time_limit=time_limit, seed=seed, warm_start=warm_start))
        return _noting_uncompiled(fallback)
    if instance.n > model.MAX_KPOIS:
        if problem.objective == "makespan" and race.cores() >= 2:
            return _race_makespan(instance, problem, time_limit, seed, warm_start)
        if problem.objective == "robots" and instance.n > ROOT_FIRST_MAX and race.cores() >= 2:
            return _race_robots(instance, problem, time_limit, seed, warm_start)
        log.info("exact: branch-and-price")
        return branch_and_price(instance, problem, time_limit=time_limit, seed=seed, warm_start=warm_start)
    log.info("exact: branch-and-price for at most %g s, then setpart", BRANCHPRICE_FIRST)
    first = branch_and_price(instance, problem, time_limit=_share(time_limit, BRANCHPRICE_FIRST),
                             seed=seed, warm_start=warm_start)
    left = time_limit.remaining()
    if _decided(first) or (left is not None and left < model.expected_seconds(instance.n)):
        return first
    log.info("exact: branch-and-price did not prove it; setpart")
    solution = _setpart(model, instance, problem, time_limit, warm_start)
    return solution if _decided(solution) else first


def _race_makespan(instance: Instance, problem: Problem, time_limit: TimeLimit, seed: int,
                   warm_start: list[list[int]] | None) -> Solution:
    """The least makespan: :func:`milp.branchprice.min_makespan` in this process for the
    whole time limit, and, unless it has proved the answer within
    :data:`BRANCHPRICE_FIRST` seconds, a rival in another process for the time left
    (:func:`milp.race.race_here`): ``best``'s local search from the same warm start, then
    PyVRP's searches for shorter routes
    (:func:`parcover.algorithms.local_search.race_entrant`), which branch-and-price's tree
    seldom improves on, handing each better routes to branch-and-price as it finds them
    (its decisions then go on below them); for at most :data:`RACE_ROUTES` robots and
    :data:`RACE_MAX_KPOIS` KPOIs ``branchcut`` instead, after the local search for a share
    of the time from :data:`SEARCH_FIRST_ROUTES` robots, or 2 from :data:`SEARCH_FIRST_KPOIS`
    KPOIs (:func:`makespan_rival`, :func:`parcover.algorithms.local_search.searched_branchcut`). The first proof stops
    the other. ``info["model"]`` names the method whose routes are returned (the one that
    proved them, when proven); the bound is the larger of every method's certified bound
    (:func:`parcover.solve` calls routes that meet it optimal)."""
    from milp import branchprice, race

    start = warm_start or warm_start_routes(instance, problem, time_limit, seed)
    kwargs = {"tours": problem.tours, "warm_start": start}
    with tempfile.TemporaryDirectory(prefix="parcover-") as folder:
        routes_file = Path(folder) / "routes"
        # where the rival runs the local search, it hands each better routes to the decisions
        here = {**kwargs, "elsewhere": race.handed_reader(routes_file)}
        rival_kwargs = {**kwargs, "seed": seed + 1, "routes_file": str(routes_file)}
        rival, entrant = makespan_rival(instance.n, problem.robots)
        if entrant == BRANCHCUT_ALONE:  # it takes neither a seed nor a routes file
            rival_kwargs = kwargs
        log.info("exact: branch-and-price, and %s in another process after %g s unless proven by then",
                 rival, BRANCHPRICE_FIRST)
        answers = race.race_here(RACE_MODELS[0], branchprice.min_makespan, {rival: entrant},
                                 (instance.distances, problem.robots), here,
                                 time_limit.remaining(), others_after=BRANCHPRICE_FIRST, others_kwargs=rival_kwargs)
    name, solution = _race_answer(answers, start, RACE_MODELS[0],
                                  lambda a: (a.status not in ("optimal", "infeasible"), a.objective))
    if name is None:
        return solution
    solution.info["model"] = name
    if len(answers) > 1 or solution.status is None:
        solution.info["message"] = "; ".join(f"{n}: {a.message}" for n, a in answers.items())
    if name == "best":  # its own proof is the trivial bound; else the bound is branch-and-price's
        solution.info["model"] = "bounds" if solution.status == Status.OPTIMAL else RACE_MODELS[0]
        solution.info["message"] = f"routes by best's local search and PyVRP ({solution.info['message']})"
    return solution


def makespan_rival(n: int, robots: int) -> tuple[str, str]:
    """The name and entrant (``module:function``) of :func:`_race_makespan`'s rival on ``n``
    KPOIs with ``robots`` robots: branch-and-cut up to :data:`RACE_ROUTES` robots and
    :data:`RACE_MAX_KPOIS` KPOIs, after the local search from :data:`SEARCH_FIRST_ROUTES`
    robots, or with 2 from :data:`SEARCH_FIRST_KPOIS` KPOIs (one route is a TSP, which
    branch-and-cut proves from ``best``'s tour: st70, 4.5 s alone against 7.2 s after the
    search); else the local search alone."""
    if robots > RACE_ROUTES or n > RACE_MAX_KPOIS:
        return "best", "parcover.algorithms.local_search:race_entrant"
    if robots == 1 or (robots < SEARCH_FIRST_ROUTES and n < SEARCH_FIRST_KPOIS):
        return RACE_MODELS[1], BRANCHCUT_ALONE
    return RACE_MODELS[1], "parcover.algorithms.local_search:searched_branchcut"


def _race_robots(instance: Instance, problem: Problem, time_limit: TimeLimit, seed: int,
                 warm_start: list[list[int]] | None) -> Solution:
    """The fewest robots above :data:`ROOT_FIRST_MAX` KPOIs: :func:`milp.branchprice.min_robots`
    in this process for the whole time limit, and, unless it has proved the answer within
    :data:`BRANCHPRICE_FIRST` seconds, PyVRP's search for the fewest routes in another
    process (:func:`parcover.algorithms.fleet.race_entrant`, :func:`milp.race.race_here`).
    Branch-and-price hands the bound its root proves to PyVRP (a file,
    :func:`milp.race.hand_over`), as soon as a certificate proves it (before the root LP
    is solved), and PyVRP stops as soon as its
    routes meet it: optimal then, and branch-and-price is stopped. The other way, PyVRP writes
    each routes fewer than before to a second file, and branch-and-price, polling it between
    pricing rounds, takes them as its incumbent (``elsewhere``): its tree then looks for one
    route fewer than them, whose pricings may stop at the prize that closes the node. This replaces
    :func:`balanced_search`, which takes the same search into this process after the root.
    The entrant proves the q-route LP bound first (and answers at once when the warm start
    meets it). ``info["model"]`` names the bound that proves the answer: ``branchprice``,
    or ``colgen`` (the q-route LP bound) when branch-and-price's is below the routes; the
    message says whose routes these are."""
    from milp import branchprice, race

    start = warm_start or warm_start_routes(instance, problem, time_limit, seed)
    deadline = problem.effective_deadline(instance)
    with tempfile.TemporaryDirectory(prefix="parcover-") as folder:
        bound_file, routes_file = Path(folder) / "bound", Path(folder) / "routes"
        handed = {"bound": 0}

        def proven(floor: int) -> None:
            if floor > handed["bound"]:
                handed["bound"] = floor
                race.hand_over(bound_file, floor)

        def at_root(floor: int, _root_seconds: float) -> None:
            proven(floor)

        log.info("exact: branch-and-price, and PyVRP's search for fewer routes in another process after %g s "
                 "unless proven by then", BRANCHPRICE_FIRST)
        answers = race.race_here(
            "branchprice", branchprice.min_robots, {"pyvrp": "parcover.algorithms.fleet:race_entrant"},
            (instance.distances, deadline),
            {"tours": problem.tours, "warm_start": start,
             "improve": at_root, "proven": proven, "elsewhere": race.handed_reader(routes_file)},
            time_limit.remaining(), others_after=BRANCHPRICE_FIRST,
            others_kwargs={"tours": problem.tours, "bound_file": str(bound_file), "seed": seed, "warm_start": start,
                           "routes_file": str(routes_file)})
    name, solution = _race_answer(answers, start, "branchprice", lambda a: (a.objective, a.status != "optimal"))
    if name is None:
        return solution
    if solution.bound is not None and len(solution.routes) <= solution.bound:
        solution.status = Status.OPTIMAL
    own = answers["branchprice"].bound if "branchprice" in answers else None  # absent when another proved it
    by_branchprice = max(handed["bound"], own or 0)
    solution.info["model"] = ("colgen" if solution.status is Status.OPTIMAL and len(solution.routes) > by_branchprice
                              else "branchprice")
    if len(answers) > 1:
        solution.info["message"] = "; ".join(f"{n}: {a.message}" for n, a in answers.items())
    if name != "branchprice" and solution.routes != start:
        solution.info["message"] = f"routes by PyVRP ({solution.info['message']})"
    return solution


def _race_answer(answers: dict[str, Any], start: list[list[int]] | None, model: str,
                 rank: Callable[[Any], Any]) -> tuple[str | None, Solution]:
    """The race's answer with routes that ``rank`` puts first, and its entrant's name; an
    unproven one gets the largest bound any entrant certified. ``(None, start's routes)``,
    named ``model``, when no entrant answered with routes."""
    answered = {n: a for n, a in answers.items() if a.objective is not None}
    if not answered:
        return None, Solution(routes=start or [], info={"model": model, "message": "; ".join(
            f"{n}: {a.message}" for n, a in answers.items()) or "no answer"})
    name, answer = min(answered.items(), key=lambda item: rank(item[1]))
    solution = _solution(answer)
    bounds = [a.bound for a in answers.values() if a.bound is not None]
    if solution.status is None and bounds:
        solution.bound = max(bounds)
    return name, solution


def _noting_uncompiled(solution: Solution) -> Solution:
    """An unproven fallback answer says why branch-and-price did not run and how to let it."""
    if not _decided(solution):
        from milp.branchprice import COMPILE_SECONDS

        reason = solution.info.get("message")
        solution.info["message"] = "; ".join(filter(None, [reason, (
            "branch-and-price not run: its pricing compiles once per installation (up to "
            f"{COMPILE_SECONDS:g} s) and the time limit leaves less; one solve with a longer "
            "limit, or none, compiles it")]))
    return solution


def _meets_trivial_bound(instance: Instance, problem: Problem, time_limit: TimeLimit,
                         seed: int) -> Solution | None:
    """Optimal routes without a model when ``best``'s polished constructions (no
    ruin-and-recreate round) meet the trivial makespan bound (Prop. 1 and the
    spanning-tree bound, :func:`parcover.bounds.lower_bound`), else ``None``.
    ``info["model"]`` is ``"bounds"``: the bound proved the answer."""
    from parcover.bounds import lower_bound
    from parcover.verify import route_costs

    routes = warm_start_routes(instance, problem, time_limit, seed, rounds=0)
    if not routes:
        return None
    bound = lower_bound(instance, problem, seconds=time_limit.remaining())
    if not meets_deadline(max(route_costs(instance, routes, tours=problem.tours)), bound):
        return None
    return Solution(routes=routes, bound=bound, status=Status.OPTIMAL,
                    info={"model": "bounds", "message": "best's construction meets the trivial lower bound"})


def _setpart(model: Any, instance: Instance, problem: Problem, time_limit: TimeLimit,
             warm_start: list[list[int]] | None) -> Solution:
    """:mod:`milp.setpart` on ``problem``, ``info["model"]`` = ``"setpart"``."""
    solution = _run(model.min_makespan, model.min_robots, instance, problem, time_limit,
                    warm_start=warm_start)
    solution.info["model"] = "setpart"
    return solution


def exact_models(n: int, objective: str, robots: int | None = None) -> set[str]:
    """The methods ``exact`` may answer with on ``n`` KPOIs for ``objective``
    (``"makespan"`` or ``"robots"``; module docstring), with at most ``robots`` robots
    for the least makespan (``None``: any number)."""
    if n <= SETPART_FIRST[objective]:
        return {"setpart", "bounds"}
    if n <= SETPART_MAX_KPOIS:
        return {"branchprice", "setpart"}
    if n > BRANCHPRICE_MAX_KPOIS:
        return {"compact"}
    races = objective == "makespan" and n <= RACE_MAX_KPOIS and (robots is None or robots <= RACE_ROUTES)
    return {"branchprice", "compact"} | ({"branchcut"} if races else set())


def _decided(solution: Solution) -> bool:
    """Whether a model proved its answer (optimal or infeasible)."""
    return solution.status is not None and solution.status.decided


def _share(time_limit: TimeLimit, seconds: float) -> TimeLimit:
    """A deadline ``seconds`` from now, or half of what is left of ``clock`` if sooner."""
    left = time_limit.remaining()
    return TimeLimit(seconds if left is None else min(seconds, 0.5 * left))


def compact(
    instance: Instance,
    problem: Problem,
    *,
    time_limit: TimeLimitLike = None,
    seed: int = 0,
    warm_start: list[list[int]] | None = None,
    export_model: str | None = None,
) -> Solution:
    """Proven optimum of the compact arc-flow model (HiGHS), within ``time_limit``.

    ``warm_start`` (routes of KPOI indices) seeds the solver; without it the ``best``
    heuristic provides one. ``export_model`` writes the model to an ``.mps`` or ``.lp``
    file that any MILP solver can read.
    """
    time_limit = TimeLimit.of(time_limit)  # the import below counts against the limit
    from milp import arcflow

    if export_model:
        _export(instance, problem, export_model)
    return _warm_started(arcflow, "compact", instance, problem, time_limit, seed, warm_start)


def branch_and_price(
    instance: Instance,
    problem: Problem,
    *,
    time_limit: TimeLimitLike = None,
    seed: int = 0,
    warm_start: list[list[int]] | None = None,
) -> Solution:
    """Proven optimum by branch-and-price over ng-routes (:mod:`milp.branchprice`).

    The fewest routes within a deadline by column generation with arc branching; the
    least makespan as a sequence of those decisions. ``warm_start`` as :func:`compact`.
    """
    time_limit = TimeLimit.of(time_limit)  # the import below counts against the limit
    from milp import branchprice

    _check_size(instance, branchprice.MAX_KPOIS, "branchprice")
    if not branchprice.ready_within(time_limit.remaining()):
        routes = warm_start or warm_start_routes(instance, problem, time_limit, seed)
        message = (f"branch-and-price not run: its pricing is compiled on first use (up to "
                   f"{branchprice.COMPILE_SECONDS:g} s, then cached) and the time limit leaves less; "
                   "these are best's routes")
        return Solution(routes=routes or [], info={"model": "branchprice", "message": message})
    options: dict[str, Any] = {}
    if not warm_start and problem.objective == "robots" and instance.n <= ROOT_FIRST_MAX:
        warm_start = warm_start_routes(instance, problem, time_limit, seed, rounds=0)
        options["improve"] = lambda floor, _: warm_start_routes(instance, problem, time_limit, seed, target=floor)
    elif problem.objective == "robots":
        began = time.perf_counter()
        warm_start = warm_start or warm_start_routes(instance, problem, time_limit, seed)
        warm_seconds = time.perf_counter() - began
        options["improve"] = lambda floor, root_seconds: balanced_search(instance, problem, time_limit, seed, floor,
                                                                         root_seconds - warm_seconds)
    return _warm_started(branchprice, "branchprice", instance, problem, time_limit, seed, warm_start, **options)


def branch_and_cut(
    instance: Instance,
    problem: Problem,
    *,
    time_limit: TimeLimitLike = None,
    seed: int = 0,
    warm_start: list[list[int]] | None = None,
) -> Solution:
    """Proven least makespan by branch-and-cut over a three-index model
    (:mod:`milp.branchcut`; for few long routes). ``warm_start`` as :func:`compact`."""
    time_limit = TimeLimit.of(time_limit)
    from milp import branchcut

    if problem.objective != "makespan":
        raise InputError("Method 'branchcut' answers the least makespan only (--robots K); "
                         "use exact or branchprice for the fewest robots.")
    _check_size(instance, branchcut.MAX_KPOIS, "branchcut")
    return _warm_started(branchcut, "branchcut", instance, problem, time_limit, seed, warm_start)


def _check_size(instance: Instance, most: int, method: str) -> None:
    """Refuse an instance above a method's size limit with one line."""
    if instance.n > most:
        raise InputError(f"Method {method!r} handles at most {most} KPOIs, this instance has {instance.n}; "
                         "use exact or compact.")


def _warm_started(
    model: Any,
    name: str,
    instance: Instance,
    problem: Problem,
    time_limit: TimeLimitLike,
    seed: int,
    warm_start: list[list[int]] | None,
    **options: Any,
) -> Solution:
    """Run ``model.min_makespan`` / ``model.min_robots`` from ``warm_start`` or, without
    one, from the ``best`` heuristic's routes; the heuristic's time counts against
    ``time_limit``. ``options`` go to the model; ``info["model"]`` is ``name``."""
    time_limit = TimeLimit.of(time_limit)
    start = warm_start or warm_start_routes(instance, problem, time_limit, seed)
    solution = _run(model.min_makespan, getattr(model, "min_robots", None), instance, problem, time_limit,
                    warm_start=start, **options)
    solution.info["model"] = name
    return solution


def _export(instance: Instance, problem: Problem, path: str) -> None:
    """Write the compact model of this question to ``path`` (.mps or .lp)."""
    from milp import arcflow

    if not path.endswith((".mps", ".lp")):
        raise InputError(f"Cannot export the model to {path}: the file must end in .mps or .lp.")
    folder = os.path.dirname(path) or "."
    if not os.path.isdir(folder):
        raise InputError(f"Cannot export the model to {path}: no folder {folder}.")
    model = arcflow.build_model(
        instance.distances,
        tours=problem.tours,
        k=problem.robots,
        deadline=problem.effective_deadline(instance) if problem.robots is None else None,
    )
    try:
        model.write(path)
    except OSError as exc:
        raise InputError(f"Cannot write {path}: {exc.strerror}.") from None


def setpart(
    instance: Instance, problem: Problem, *, time_limit: TimeLimitLike = None, seed: int = 0
) -> Solution:
    """Proven optimum by set partitioning over every subset's cheapest route (n <= 20)."""
    from milp import setpart as model

    _check_size(instance, model.MAX_KPOIS, "setpart")
    return _run(model.min_makespan, model.min_robots, instance, problem, time_limit)


def cvxpy_model(
    instance: Instance, problem: Problem, *, time_limit: TimeLimitLike = None, seed: int = 0
) -> Solution:
    """Proven optimum of the compact model as written in cvxpy (for reading)."""
    from milp import cvx

    return _run(cvx.min_makespan, cvx.min_robots, instance, problem, time_limit)


def warm_start_routes(
    instance: Instance, problem: Problem, time_limit: TimeLimitLike, seed: int, rounds: int | None = None,
    target: float | None = None,
) -> list[list[int]] | None:
    """Routes from the ``best`` heuristic when it is available, else ``None``; it gets
    :data:`WARM_SHARE` of what is left of ``time_limit`` and ``rounds`` ruin-and-recreate
    rounds (default :data:`WARM_ROUNDS`), and stops as soon as it meets ``target`` (a
    proven bound on the objective; default the trivial lower bound,
    :func:`parcover.bounds.lower_bound`, which a quarter of the questions at n = 10-15
    meet: 29 of 120 measured, mostly k = 5; those then take a fraction of the rounds)."""
    from parcover.bounds import lower_bound

    best = _best_heuristic()
    if best is None:
        return None
    budget = TimeLimit.of(time_limit).fraction(WARM_SHARE)
    rounds = WARM_ROUNDS[problem.objective] if rounds is None else rounds
    target = lower_bound(instance, problem, seconds=budget.seconds) if target is None else target
    log.info("warm start: best, %d rounds%s", rounds,
             "" if budget.seconds is None else f", at most {budget.seconds:.3g} s")
    solution = best(instance, problem, time_limit=budget, seed=seed, iterations=rounds, target=target)
    return solution.routes or None


def balanced_search(instance: Instance, problem: Problem, time_limit: TimeLimit, seed: int, floor: int,
                    seconds: float) -> list[list[int]] | None:
    """``best``, from a seed other than the warm start's, looking for ``floor`` robots (the
    root's bound) for ``seconds`` (what the root took beyond the warm start: the primal side
    catches up with the dual one), at most :data:`IMPROVE_SHARE` of the time left: where
    the root is dear (100 KPOIs in rooms) the heuristic gets as much, where it is cheap
    it costs little."""
    left = time_limit.remaining()
    if left is not None:
        seconds = min(seconds, IMPROVE_SHARE * left)
    best = _best_heuristic()
    if best is None or seconds <= 0:
        return None
    log.info("improve: best for %.3g s, looking for %d robots", seconds, floor)
    return best(instance, problem, time_limit=seconds, seed=seed + 1, target=floor).routes or None


def _best_heuristic() -> Callable[..., Solution] | None:
    """The registered ``best`` heuristic's function, or ``None`` when it is not available
    (its optional dependency missing)."""
    from parcover.solve import available_methods

    method = available_methods().get("best")
    return None if method is None else method.function


def _run(
    min_makespan: Callable[..., Any],
    min_robots: Callable[..., Any],
    instance: Instance,
    problem: Problem,
    time_limit: TimeLimitLike,
    **kwargs: Any,
) -> Solution:
    """Run a model's ``min_makespan`` or ``min_robots`` on ``problem`` with what is left
    of ``time_limit`` (the models take seconds) and map its answer to a Solution."""
    time_limit = TimeLimit.of(time_limit).remaining()
    d = instance.distances
    if problem.objective == "makespan":
        answer = min_makespan(d, problem.robots, tours=problem.tours, time_limit=time_limit, **kwargs)
    else:
        deadline = problem.effective_deadline(instance)
        answer = min_robots(d, deadline, tours=problem.tours, time_limit=time_limit, **kwargs)
    return _solution(answer)


def _solution(answer: Any) -> Solution:
    """A model's :class:`milp.core.result.MilpResult` as a Solution."""
    return Solution(
        routes=[list(r) for r in answer.routes],
        bound=answer.bound,
        # "feasible" maps to None: solve() decides, and may still prove it with its own bounds
        status=_STATUS.get(answer.status),
        info={"nodes": answer.nodes, "solver_seconds": answer.seconds, "message": answer.message},
    )


METHODS = (
    MethodInfo("exact", exact, f"proven optimum: setpart up to {SETPART_FIRST['makespan']} KPOIs, branchprice then "
               f"setpart to {SETPART_MAX_KPOIS}, branchprice to {BRANCHPRICE_MAX_KPOIS} (least makespan with at most "
               f"{RACE_ROUTES} robots to {RACE_MAX_KPOIS} KPOIs: raced against branchcut, from {SEARCH_FIRST_ROUTES} robots or 2 from {SEARCH_FIRST_KPOIS} KPOIs after best's and PyVRP's search, else against them; fewest robots above {ROOT_FIRST_MAX}: "
               "PyVRP looks for routes meeting its bound beside it), compact above (default)",
               ("warm_start", "export_model")),
    MethodInfo("compact", compact, "proven optimum: compact arc-flow MILP in HiGHS", ("warm_start", "export_model")),
    MethodInfo("branchprice", branch_and_price,
               "proven optimum: branch-and-price over ng-routes (column generation, arc branching)",
               ("warm_start",)),
    MethodInfo("branchcut", branch_and_cut,
               "proven least makespan: three-index branch-and-cut (few long routes)", ("warm_start",)),
    MethodInfo("setpart", setpart, f"proven optimum: Held-Karp routes + counting set partitions (n <= {SETPART_MAX_KPOIS})"),
    MethodInfo("cvxpy", cvxpy_model, "proven optimum: the compact model written in cvxpy (slow, for reading)"),
)
