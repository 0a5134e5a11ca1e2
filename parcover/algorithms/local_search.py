"""``best``: the strongest heuristic, an iterated local search on the best construction.

It runs every registered construction (all methods but ``best``, ``trivial`` and the
exact ones) plus its own min-max cheapest insertion, keeps the best valid answer and
improves it:

* local search with 2-opt and or-opt inside a route and relocate (of chains of 1-3
  KPOIs, next to one of their 20 nearest KPOIs), swap and 2-opt* between two routes. A
  move between routes ``a`` and ``b`` is taken when it lowers ``max(c_a, c_b)``, or
  keeps it and lowers ``c_a + c_b``: the makespan never rises and the sorted route
  costs fall lexicographically, so the longest route shrinks with the total length as
  tie-breaker. After a ruin only the routes it changed (and those changed since) are
  searched, alone or in pairs;
* for the robots objective (paper, Problem 2) the route with the fewest KPOIs is
  repeatedly emptied by cheapest insertion of its KPOIs into the others within the
  deadline; after part of the effort, :func:`fewer_robots` searches the least makespan
  with one robot fewer until it meets the deadline, and again with one fewer;
* ruin and recreate until the search stops (below): strings of consecutive KPOIs are removed
  from the routes nearest a random KPOI (half of the time one of the longest route,
  the makespan's bottleneck) and put back by min-max cheapest insertion in a random
  order (slack induction by string removals, SISR); the result is accepted by
  simulated annealing on the makespan plus a small share of the total length (never
  with more robots), and the best solution met is kept.

When it stops
-------------
A time limit is a cap, not a budget. Without ``iterations``, the search stops at the first of:

1. its value meets a proven lower bound (:func:`parcover.bounds.lower_bound`: ``c_max``
   or ``2 c_max``, the spanning-tree and Held-Karp bounds, the fewest robots they allow):
   nothing can be better, so the answer is optimal;
2. convergence: the annealing temperature has fallen over :func:`patience` rounds
   (``max(100, 10 n)`` for ``n`` KPOIs), and the last ``patience(n)`` rounds found
   nothing better;
3. the time limit.

The temperature falls over rounds, not seconds, so the answer depends on the seed
alone, unless the first rounds show that ``patience(n)`` rounds will not fit in the
time limit: the temperature then falls over the time left instead, as with
``until="limit"``, which spends the whole limit (stops 1 and 2 off). With ``iterations``
the search runs exactly that many rounds (or until the limit). Without a time limit
and without ``iterations``, :data:`DEFAULT_ITERATIONS` rounds.

Routes are handled as ``[0, v_1, ..., v_m, E]`` where ``E`` is the start (tours) or a
dummy end at distance 0 from everything (paths), so both route kinds share every move.

This module holds the driver: :func:`best`, the annealing of :func:`improve` and its
stopping rules, and :func:`fewer_robots`. The moves are in
:mod:`parcover.algorithms.moves`, the constructions it starts from in
:mod:`parcover.algorithms.starts` (:func:`best_construction` and
:func:`min_max_insertion`, importable from here too).
"""

from __future__ import annotations

import dataclasses
import logging
import math
import random
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from milp.core.result import MilpResult
from milp.core.routes import makespan, within
from milp.core.timelimit import TimeLimit, TimeLimitLike, stop_requested
from milp.race import hand_over
from parcover.algorithms.moves import Key, Search
from parcover.algorithms.starts import best_construction, min_max_insertion
from parcover.bounds import lower_bound, robots_lower_bound
from parcover.errors import InputError
from parcover.instance import Instance
from parcover.problem import MethodInfo, Problem, Solution, meets_deadline
from parcover.result import Status

__all__ = ["best", "improve", "fewer_robots", "min_max_insertion", "patience", "DEFAULT_ITERATIONS", "METHODS"]

DEFAULT_ITERATIONS = 30
"""Ruin-and-recreate rounds when neither a time limit nor ``iterations`` is given
(about half a second for 50 KPOIs)."""

#: Rounds of the annealing schedule, and then without a better solution, that end a search:
#: at least, and per KPOI (:func:`patience`).
PATIENCE_MIN, PATIENCE_PER_KPOI = 100, 10
#: Rounds timed before deciding whether the annealing schedule fits in the time limit.
_CALIBRATION_ROUNDS = 5
UNTIL = ("converged", "limit")

log = logging.getLogger(__name__)

# Of the time limit, the seconds given to the lower bound that may stop the search early
# (its Held-Karp part then runs when expected within a quarter of them: 5% of the limit).
_BOUND_SHARE = 0.2
#: Share of its time :func:`searched_branchcut` gives the local search before branch-and-cut,
#: with 3 routes or more, and with fewer (when ``exact`` asks for the search at all:
#: :func:`parcover.exact.makespan_rival`). With 2 routes branch-and-cut needs its time for
#: the proof (Necula's eil76, proven in 132-206 s, was unproven at 420 s behind a quarter),
#: while 21 s (a twentieth of 420) reached the optimum of eil76 from 3 seeds of 3 and of
#: rat99 from 2 (``milp/README.md``).
SEARCH_FIRST_SHARE, FEW_ROUTES_SEARCH_SHARE = 0.25, 0.05
_ROBOTS_SHARE = 0.4  # of the time limit, robots objective: the rest goes to fewer_robots
_T_FIRST = 0.03  # annealing temperature at the first round, times the start's makespan
_T_LAST = 0.001  # ... and at the last round
_TOTAL_WEIGHT = 0.05  # weight of the total length in the annealed energy


def best(
    instance: Instance,
    problem: Problem,
    *,
    time_limit: TimeLimitLike = None,
    seed: int = 0,
    iterations: int | None = None,
    target: float | None = None,
    until: str = "converged",
) -> Solution:
    """Best registered construction, then iterated local search (module docstring).

    Parameters
    ----------
    instance, problem
        The question; both objectives and both route kinds.
    time_limit
        Seconds for the whole run at most, or a :class:`~milp.core.timelimit.TimeLimit`
        shared with the caller. Results depend on the machine's speed only when the
        limit ends the search (or is predicted to: module docstring).
    seed
        Seed of the ruin-and-recreate rounds (and of the constructions).
    iterations
        Ruin-and-recreate rounds. Default: :data:`DEFAULT_ITERATIONS` without a time
        limit; with one, until the search stops (module docstring, "When it stops").
        With both, whichever ends first; with iterations alone the result depends only
        on ``seed``.
    target
        A proven lower bound on the objective (makespan, or robots): the search stops
        as soon as it is met, as nothing can be better. Default: the trivial lower
        bound (:func:`parcover.bounds.lower_bound`) under a time limit without
        ``iterations``, none otherwise.
    until
        ``"converged"`` (default): under a time limit without ``iterations``, stop at
        the bound, at convergence or at the limit, whichever comes first; ``"limit"``:
        spend the whole time limit (needs one).

    Returns
    -------
    Solution
        Routes in KPOI indices, no bound; ``info`` holds ``start`` (the construction
        started from), ``start_value`` and ``value`` (the objective key: makespan and
        total length, or robots, makespan and total length) and ``iterations``.
    """
    time_limit = TimeLimit.of(time_limit).remaining()
    started = time.perf_counter()
    if until not in UNTIL:
        raise InputError(f"best: until must be one of {', '.join(UNTIL)}, not {until!r}.")
    if until == "limit" and time_limit is None:
        raise InputError("best: until=limit spends the whole time limit; give one.")
    deadline = problem.effective_deadline(instance)
    if deadline is not None and not meets_deadline(problem.least_makespan(instance), deadline):
        return Solution(routes=[], status=Status.INFEASIBLE)
    name, start = best_construction(instance, problem, time_limit=time_limit, seed=seed)
    patience_rounds = None
    if iterations is None and time_limit is None:
        iterations = DEFAULT_ITERATIONS
    elif iterations is None and until == "converged":
        patience_rounds = patience(instance.n)
        if target is None:
            target = lower_bound(instance, problem, seconds=_BOUND_SHARE * time_limit)
    stop = None if time_limit is None else started + time_limit
    if log.isEnabledFor(logging.INFO):
        search = Search(instance, problem)
        log.info("best: starts from %s (%s); %s", name, _describe(search.key(search.sequences(start))),
                 _stopping(iterations, patience_rounds, target, time_limit))
    if problem.objective == "makespan":
        routes, info = improve(instance, problem, start, seed=seed, iterations=iterations, stop=stop,
                               target=target, patience=patience_rounds)
        return Solution(routes=routes, info={"start": name, **info})
    # robots: part of the effort on the robots search, the rest on fewer_robots
    first = None if stop is None else started + _ROBOTS_SHARE * time_limit
    routes, info = improve(instance, problem, start, seed=seed, iterations=iterations, stop=first,
                           target=target, patience=patience_rounds)
    routes, rounds = fewer_robots(instance, problem, routes, seed=seed, iterations=iterations, stop=stop,
                                  patience=patience_rounds, target=target)
    search = Search(instance, problem)
    value = search.key(search.sequences(routes))
    info.update(value=value, iterations=info["iterations"] + rounds)
    return Solution(routes=routes, info={"start": name, **info})


def fewer_robots(
    instance: Instance,
    problem: Problem,
    routes: list[list[int]],
    *,
    seed: int = 0,
    iterations: int | None = DEFAULT_ITERATIONS,
    stop: float | None = None,
    patience: int | None = None,
    target: float | None = None,
) -> tuple[list[list[int]], int]:
    """Robots objective: meet the deadline with one route fewer, again and again.

    With ``q = len(routes) - 1`` robots, the least-makespan search (:func:`improve`)
    starts from ``routes`` whose route with the fewest KPOIs is emptied into the others
    (:meth:`Search.empty_one_route`: min-max cheapest insertion, as there is no
    deadline) and stops as soon as its makespan meets the deadline: those ``q`` routes
    are a better answer, and ``q`` drops by one. Ends at the first ``q`` not reached
    within ``iterations`` rounds (or by convergence, ``patience`` as in :func:`improve`,
    or by ``stop``), or at the spanning-tree bound
    (:func:`parcover.bounds.robots_lower_bound`) or ``target`` (a bound the caller proved).
    Returns the routes and the rounds used.
    """
    deadline = problem.effective_deadline(instance)
    assert deadline is not None
    floor = robots_lower_bound(instance, deadline, tours=problem.tours,
                               seconds=None if stop is None else stop - time.perf_counter())
    if target is not None:
        floor = max(floor, int(target))
    rounds = 0
    while len(routes) > floor and (stop is None or time.perf_counter() < stop):
        fewer = Problem(problem.routes, robots=len(routes) - 1)
        search = Search(instance, fewer)
        seqs = search.sequences(routes)
        search.empty_one_route(seqs)  # no deadline in the makespan search: always succeeds
        found, info = improve(instance, fewer, [s[1:-1] for s in seqs], seed=seed,
                              iterations=iterations, stop=stop, target=deadline, patience=patience)
        rounds += info["iterations"]
        if not meets_deadline(info["value"][0], deadline):
            break
        routes = found
        log.info("best: %d robots meet the deadline (round %d)", len(routes), rounds)
    return routes, rounds



def race_entrant(D: np.ndarray, k: int, *, tours: bool, warm_start: list[list[int]] | None = None,
                 seed: int = 0, time_limit: float | None = None, routes_file: str | None = None) -> MilpResult:
    """:func:`improve` and then PyVRP as an entrant of :func:`milp.race.race_here` beside
    branch-and-price's least makespan with ``k`` routes on the distance matrix ``D`` (index
    0 the start): from ``warm_start`` (branch-and-price's start; else
    :func:`best_construction`) with its own ``seed``, the annealing until it has converged
    (:func:`patience`; :data:`DEFAULT_ITERATIONS` rounds without a time limit), then
    :func:`parcover.algorithms.fleet.shorter_routes` from its routes, until the time limit
    or the trivial lower bound. On the Necula cells and building-scale makespan cells the
    annealing until the limit ended where it had converged, and PyVRP's searches reached
    those routes sooner, or shorter ones (``milp/README.md``). ``"optimal"`` when its routes
    meet that bound, else ``"feasible"`` with it; the race keeps the better routes and the
    larger bound. With ``routes_file``, each better routes are handed over there as they are
    found (:func:`milp.race.hand_over`): branch-and-price's makespan decisions take them
    (:func:`milp.branchprice.min_makespan`'s ``elsewhere``)."""
    from parcover.algorithms.fleet import shorter_routes  # PyVRP and numba: only when needed

    began = time.perf_counter()
    stop = None if time_limit is None else began + time_limit
    instance, problem = Instance.from_matrix(D), Problem("tours" if tours else "paths", robots=k)
    bound = lower_bound(instance, problem, seconds=None if time_limit is None else _BOUND_SHARE * time_limit)
    start = warm_start or best_construction(instance, problem, time_limit=time_limit, seed=seed)[1]
    hand = None if routes_file is None else lambda found: hand_over(routes_file, found)
    routes, _ = improve(instance, problem, start, seed=seed, iterations=None if stop else DEFAULT_ITERATIONS,
                        stop=stop, target=bound, patience=patience(instance.n) if stop else None, found=hand)
    routes = shorter_routes(D, k, routes, tours=tours, seed=seed, stop=stop, target=bound, found=hand)
    value = makespan(D, routes, tours=tours)
    proven = within(value, bound)
    return MilpResult("optimal" if proven else "feasible", routes=routes, objective=value, bound=bound,
                      seconds=time.perf_counter() - began,
                      message="best's and PyVRP's routes meet the trivial lower bound" if proven
                      else "best's and PyVRP's routes at the time limit")


def searched_branchcut(D: np.ndarray, k: int, *, tours: bool, warm_start: list[list[int]] | None = None,
                       seed: int = 0, time_limit: float | None = None,
                       routes_file: str | None = None) -> MilpResult:
    """The race's rival with few long routes: :func:`race_entrant` (``best``'s local search,
    handing each better routes over at ``routes_file``) for :data:`SEARCH_FIRST_SHARE` of
    ``time_limit``, then :func:`milp.branchcut.min_makespan` from its routes for the rest.
    Branch-and-cut improves its warm start seldom (its proofs come from its bound), so it
    and branch-and-price's decisions, which take the handed routes, start from shorter
    routes. Its answer is branch-and-cut's, whose routes are never longer than the ones it
    was given (routes meeting the trivial bound it proves at once)."""
    from milp import branchcut

    began = time.perf_counter()
    share = SEARCH_FIRST_SHARE if k >= 3 else FEW_ROUTES_SEARCH_SHARE
    searched = race_entrant(D, k, tours=tours, warm_start=warm_start, seed=seed, routes_file=routes_file,
                            time_limit=None if time_limit is None else share * time_limit)
    left = None if time_limit is None else max(0.0, time_limit - (time.perf_counter() - began))
    answer = branchcut.min_makespan(D, k, tours=tours, time_limit=left, warm_start=searched.routes)
    return dataclasses.replace(answer, seconds=time.perf_counter() - began,
                               message=f"from best's local search ({searched.objective:.6g}): {answer.message}")


def improve(
    instance: Instance,
    problem: Problem,
    routes: list[list[int]],
    *,
    seed: int = 0,
    iterations: int | None = DEFAULT_ITERATIONS,
    stop: float | None = None,
    target: float | None = None,
    patience: int | None = None,
    found: Callable[[list[list[int]]], None] | None = None,
) -> tuple[list[list[int]], dict[str, Any]]:
    """Iterated local search from valid ``routes`` (KPOI indices).

    Each round ruins and recreates the current solution, brings it to a local optimum
    and accepts it by simulated annealing on :func:`_energy`: a worse candidate is
    taken when its energy exceeds the current one by less than ``-T ln u`` (``u``
    uniform), the temperature ``T`` falling geometrically from :data:`_T_FIRST` to
    :data:`_T_LAST` times the start's makespan over the rounds (``iterations``, or
    ``patience``) or over the time to ``stop``, whichever is shorter: with
    ``patience``, the first :data:`_CALIBRATION_ROUNDS` rounds decide whether the
    rounds fit before ``stop`` (then the clock is ignored, and the answer depends on
    the seed alone). The best solution met is kept.

    Parameters
    ----------
    routes
        A valid starting solution for ``problem``.
    iterations
        Ruin-and-recreate rounds (``None``: until another rule stops the search).
    stop
        A :func:`time.perf_counter` value at which to stop (``None``: no limit).
    target
        Stop as soon as the objective meets it: the makespan within it (as a deadline),
        or at most this many robots.
    patience
        The temperature falls over this many rounds; once it has, stop after this many
        rounds in a row without a better solution (``None``: never).
    found
        Called with the routes of each solution better than the last (the polished start
        first, when better than ``routes``), as soon as it is found.

    Returns
    -------
    tuple
        The best routes found (never worse than ``routes`` by the objective key) and
        an info dict with ``start_value``, ``value`` and ``iterations``.
    """
    if iterations is None and stop is None and patience is None:
        raise ValueError("Give iterations, a stop time or a patience.")
    search = Search(instance, problem, stop)
    rng = random.Random(seed)
    start = search.sequences(routes)
    start_key = search.key(start)
    current = search.polish(_copy(start))
    current_key = search.key(current)
    incumbent, incumbent_key = _copy(current), current_key
    if start_key < incumbent_key:
        incumbent, incumbent_key = _copy(start), start_key
    elif found is not None and incumbent_key < start_key:
        found(_routes(incumbent))
    began = time.perf_counter()
    scale = max(current_key[-2], search.tol)
    horizon = iterations if iterations is not None else patience
    clocked = stop is not None and patience is None  # does the temperature follow the clock?
    done = last_better = 0
    # stop_requested: a race's rival proved the answer, or Ctrl-C (milp.core.timelimit)
    while (iterations is None or done < iterations) and not search.out_of_time() and not stop_requested():
        if target is not None and _meets(incumbent_key, target):
            break
        if patience is not None and done >= patience and done - last_better >= patience:
            break
        if stop is not None and patience is not None and done == _CALIBRATION_ROUNDS:
            clocked = began + (time.perf_counter() - began) * horizon / done > stop
        progress = done / horizon if horizon else 0.0
        if clocked:
            progress = max(progress, (time.perf_counter() - began) / max(stop - began, 1e-9))
        temperature = scale * _T_FIRST * (_T_LAST / _T_FIRST) ** min(progress, 1.0)
        candidate = _copy(current)
        search.ruin_and_recreate(candidate, rng)
        before = {tuple(s) for s in current}
        search.polish(candidate, {r for r, s in enumerate(candidate) if tuple(s) not in before})
        candidate_key = search.key(candidate)
        done += 1
        if candidate_key < incumbent_key:
            incumbent, incumbent_key, last_better = _copy(candidate), candidate_key, done
            log.info("best: round %d, %s", done, _describe(incumbent_key))
            if found is not None:
                found(_routes(incumbent))
        if _accepts(candidate_key, current_key, temperature, rng):
            current, current_key = candidate, candidate_key
    return _routes(incumbent), {"start_value": start_key, "value": incumbent_key, "iterations": done}


def _routes(seqs: list[list[int]]) -> list[list[int]]:
    """The KPOI routes of a search's sequences (each from the start to its end, both
    dropped; empty ones left out)."""
    return [s[1:-1] for s in seqs if len(s) > 2]


def patience(n: int) -> int:
    """Rounds over which ``best``'s temperature falls, and then rounds in a row without
    a better solution after which it has converged, for ``n`` KPOIs:
    ``max(PATIENCE_MIN, PATIENCE_PER_KPOI * n)``."""
    return max(PATIENCE_MIN, PATIENCE_PER_KPOI * n)


def _describe(key: Key) -> str:
    """An objective key in words, for the log."""
    if len(key) == 3:
        return f"{key[0]:g} robots, makespan {key[1]:.6g}"
    return f"makespan {key[0]:.6g}, total length {key[1]:.6g}"


def _stopping(iterations: int | None, patience: int | None, target: float | None,
              time_limit: float | None) -> str:
    """Which rules will stop the search, in words, for the log."""
    rules = [] if iterations is None else [f"{iterations} rounds"]
    if target is not None:
        rules.append(f"the lower bound {target:.6g}")
    if patience is not None:
        rules.append(f"{patience} rounds of cooling then {patience} without a better solution")
    if time_limit is not None:
        rules.append(f"{time_limit:.3g} s")
    return "stops at " + (", ".join(rules) or "once")


def _meets(key: Key, target: float) -> bool:
    """Whether the objective of ``key`` meets ``target``: at most ``target`` robots (the
    robots objective's key has three entries), or a makespan within it."""
    return key[0] <= target if len(key) == 3 else meets_deadline(key[0], target)


def _copy(seqs: list[list[int]]) -> list[list[int]]:
    return [list(s) for s in seqs]


def _energy(key: Key) -> float:
    """What the annealing lowers: the makespan plus :data:`_TOTAL_WEIGHT` times the
    total length (``key`` ends with makespan and total length)."""
    return key[-2] + _TOTAL_WEIGHT * key[-1]


def _accepts(candidate: Key, current: Key, temperature: float, rng: random.Random) -> bool:
    """Simulated annealing acceptance; never more robots than the current solution
    (robots objective: the key then has three entries)."""
    if candidate < current:
        return True
    if len(candidate) == 3 and candidate[0] > current[0]:
        return False
    threshold = -temperature * math.log(1.0 - rng.random())
    return _energy(candidate) < _energy(current) + threshold



METHODS = (
    MethodInfo(
        "best",
        best,
        "best construction + iterated local search (2-opt, or-opt, relocate, swap, 2-opt*); "
        "stops at a proven bound, at convergence or at the time limit (until=limit: spends it)",
        options=("iterations", "until"),
    ),
)
