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
"""

from __future__ import annotations

import functools
import logging
import math
import random
import time
import weakref
from collections.abc import Iterable
from typing import Any

import numpy as np

from milp.deadline import Deadline, TimeLimit
from parcover import exact
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

#: Methods that are not constructions: ourselves, the trivial one and every exact method.
_NOT_STARTS = frozenset({"best", "trivial", *(method.name for method in exact.METHODS)})
_CONSTRUCTION_SHARE = 0.025  # of the time limit, for each construction
_CONSTRUCTIONS_SHARE = 0.5  # of the time limit: no construction starts after it
_QUICK = "nn"  # the construction run when none answered in time and ours would not fit
_INSERTION_SECONDS = 1.5e-6  # min_max_insertion per KPOI pair (1.3 s at 1000 KPOIs, measured)
# Of the time limit, the seconds given to the lower bound that may stop the search early
# (its Held-Karp part then runs when expected within a quarter of them: 5% of the limit).
_BOUND_SHARE = 0.2
_ROBOTS_SHARE = 0.4  # of the time limit, robots objective: the rest goes to fewer_robots
_CHAIN = 3  # longest chain of KPOIs moved by or-opt / relocate
_GRANULARITY = 20  # relocate tries slots next to this many nearest KPOIs
_T_FIRST = 0.03  # annealing temperature at the first round, times the start's makespan
_T_LAST = 0.001  # ... and at the last round
_TOTAL_WEIGHT = 0.05  # weight of the total length in the annealed energy
_STRING = 10  # longest string removed from a route by the ruin
_RUINED = 10  # KPOIs removed per round on average (at most)
_BLINK = 0.01  # probability that the recreate skips an insertion slot

Key = tuple[float, ...]


def best(
    instance: Instance,
    problem: Problem,
    *,
    time_limit: TimeLimit = None,
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
        Seconds for the whole run at most, or a :class:`~milp.deadline.Deadline`
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
    time_limit = Deadline.of(time_limit).remaining()
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
        search = _Search(instance, problem)
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
                                  patience=patience_rounds)
    search = _Search(instance, problem)
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
) -> tuple[list[list[int]], int]:
    """Robots objective: meet the deadline with one route fewer, again and again.

    With ``q = len(routes) - 1`` robots, the least-makespan search (:func:`improve`)
    starts from ``routes`` whose route with the fewest KPOIs is emptied into the others
    (:meth:`_Search.empty_one_route`: min-max cheapest insertion, as there is no
    deadline) and stops as soon as its makespan meets the deadline: those ``q`` routes
    are a better answer, and ``q`` drops by one. Ends at the first ``q`` not reached
    within ``iterations`` rounds (or by convergence, ``patience`` as in :func:`improve`,
    or by ``stop``), or at the spanning-tree bound
    (:func:`parcover.bounds.robots_lower_bound`). Returns the routes and the rounds used.
    """
    deadline = problem.effective_deadline(instance)
    assert deadline is not None
    floor = robots_lower_bound(instance, deadline, tours=problem.tours,
                               seconds=None if stop is None else stop - time.perf_counter())
    rounds = 0
    while len(routes) > floor and (stop is None or time.perf_counter() < stop):
        fewer = Problem(problem.routes, robots=len(routes) - 1)
        search = _Search(instance, fewer)
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


def best_construction(
    instance: Instance, problem: Problem, *, time_limit: float | None, seed: int
) -> tuple[str, list[list[int]]]:
    """The valid construction with the least objective key (name, routes).

    Every registered method except ``best``, ``trivial`` and the exact ones is tried
    (each gets :data:`_CONSTRUCTION_SHARE` of the time limit), then
    :func:`min_max_insertion`. Most constructions cannot be interrupted and some take
    a second at 1000 KPOIs, so under a time limit none starts once
    :data:`_CONSTRUCTIONS_SHARE` of it has passed, and ours (O(n^2)) only when its
    expected time (:data:`_INSERTION_SECONDS`) fits; when it does not and nothing else
    answered, :data:`_QUICK` (then ours if that fails). One that
    raises or answers invalid routes is skipped. Ties go to the construction listed
    first (registry order, then ours).
    """
    from parcover.solve import available_methods  # solve imports this module

    stop = None if time_limit is None else time.perf_counter() + _CONSTRUCTIONS_SHARE * time_limit
    search = _Search(instance, problem)
    candidates: list[tuple[str, list[list[int]]]] = []
    share = None if time_limit is None else time_limit * _CONSTRUCTION_SHARE
    for name, info in available_methods().items():
        if name.split(":")[0] in _NOT_STARTS:  # a label such as best:iterations=5 is best
            continue
        if stop is not None and time.perf_counter() >= stop:
            break
        try:
            solution = info.function(instance, problem, time_limit=share, seed=seed)
        except Exception:  # a failing construction must not break `best`
            continue
        if not solution.drops_deadline and search.valid(solution.routes):
            candidates.append((name, [list(map(int, r)) for r in solution.routes if r]))
    ours_ends = time.perf_counter() + _INSERTION_SECONDS * instance.n**2
    if stop is None or ours_ends <= stop:
        candidates.append(("min_max_insertion", min_max_insertion(instance, problem)))
    elif not candidates:
        # Nothing answered before the stop and ours would not fit (14 s at 3000 KPOIs,
        # run anyway it held `exact --time-limit 3` 10 s): the nearest neighbour
        # answers at once (0.03 s at 3000 KPOIs), ours only if it fails.
        try:
            quick = available_methods()[_QUICK].function(instance, problem, time_limit=share, seed=seed)
            if not quick.drops_deadline and search.valid(quick.routes):
                candidates.append((_QUICK, [list(map(int, r)) for r in quick.routes if r]))
        except Exception:  # as above: a failing construction must not break `best`
            pass
        if not candidates:
            candidates.append(("min_max_insertion", min_max_insertion(instance, problem)))
    return min(candidates, key=lambda c: search.key(search.sequences(c[1])))


def min_max_insertion(instance: Instance, problem: Problem) -> list[list[int]]:
    """Our own construction: KPOIs farthest from the start first, each at the position
    that keeps the makespan least (then adds least length); under a deadline, the
    cheapest position within it, or a new route."""
    search = _Search(instance, problem)
    seqs = search.empty_routes()
    search.insert_all(seqs, search.farthest_first(range(1, instance.n + 1)))
    return [s[1:-1] for s in seqs if len(s) > 2]


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

    Returns
    -------
    tuple
        The best routes found (never worse than ``routes`` by the objective key) and
        an info dict with ``start_value``, ``value`` and ``iterations``.
    """
    if iterations is None and stop is None and patience is None:
        raise ValueError("Give iterations, a stop time or a patience.")
    search = _Search(instance, problem, stop)
    rng = random.Random(seed)
    start = search.sequences(routes)
    start_key = search.key(start)
    current = search.polish(_copy(start))
    current_key = search.key(current)
    incumbent, incumbent_key = _copy(current), current_key
    if start_key < incumbent_key:
        incumbent, incumbent_key = _copy(start), start_key
    began = time.perf_counter()
    scale = max(current_key[-2], search.tol)
    horizon = iterations if iterations is not None else patience
    clocked = stop is not None and patience is None  # does the temperature follow the clock?
    done = last_better = 0
    while (iterations is None or done < iterations) and not search.out_of_time():
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
        if _accepts(candidate_key, current_key, temperature, rng):
            current, current_key = candidate, candidate_key
    final = [s[1:-1] for s in incumbent if len(s) > 2]
    return final, {"start_value": start_key, "value": incumbent_key, "iterations": done}


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


class _Distances:
    """An instance's distances as the search reads them: the matrix with a row and column
    of zeros appended for the end node of paths, as an array and as Python lists (the hot
    loops index lists several times faster than arrays), and the KPOIs by distance.

    Built once per instance by :func:`_distances`, as each is a full pass over the matrix
    (measured at 3000 KPOIs: 0.5 s for the lists alone) and one ``best`` run makes a
    :class:`_Search` several times (constructions, improve, fewer_robots).
    """

    def __init__(self, distances: np.ndarray) -> None:
        n = len(distances) - 1
        matrix = np.zeros((n + 2, n + 2))
        matrix[: n + 1, : n + 1] = distances
        matrix.flags.writeable = False
        self.n = n
        self.matrix = matrix
        self.rows: list[list[float]] = matrix.tolist()
        self.tol = 1e-9 * max(1.0, float(matrix.max()))

    @functools.cached_property
    def neighbours(self) -> np.ndarray:
        """Row ``v - 1``: every KPOI by distance from KPOI ``v`` (computed when first
        needed: O(n^2 log n), a fifth of a second at 1000 KPOIs)."""
        n = self.n
        return np.argsort(self.matrix[1 : n + 1, 1 : n + 1], axis=1, kind="stable") + 1

    @functools.cached_property
    def near(self) -> list[list[int]]:
        """``near[v]``: the KPOIs nearest v (nearest first), as Python ints for the hot loops."""
        return [[], *self.neighbours[:, :_GRANULARITY].tolist()]


# The last instance's _Distances (at most one is kept: 0.3 GB of lists at 3000 KPOIs),
# dropped with the instance; Instance compares by identity, so this is keyed by it.
_LAST_DISTANCES: weakref.WeakKeyDictionary[Instance, _Distances] = weakref.WeakKeyDictionary()


def _distances(instance: Instance) -> _Distances:
    """The :class:`_Distances` of ``instance``, built on first use (instances are read-only)."""
    found = _LAST_DISTANCES.get(instance)
    if found is None:
        found = _Distances(instance.distances)
        _LAST_DISTANCES.clear()
        _LAST_DISTANCES[instance] = found
    return found


class _Search:
    """Distances, the route end node and the moves (routes as ``[0, ..., E]`` lists)."""

    def __init__(self, instance: Instance, problem: Problem, stop: float | None = None) -> None:
        self.distances = _distances(instance)
        self.n = instance.n
        self.end = 0 if problem.tours else instance.n + 1
        self.d = self.distances.rows
        self.tol = self.distances.tol
        self.robots = problem.robots
        self.deadline = problem.effective_deadline(instance)
        self.stop = stop

    @property
    def neighbours(self) -> np.ndarray:
        """Every KPOI by distance from each KPOI (:attr:`_Distances.neighbours`)."""
        return self.distances.neighbours

    @property
    def near(self) -> list[list[int]]:
        """The KPOIs nearest each KPOI (:attr:`_Distances.near`)."""
        return self.distances.near

    # ----- bookkeeping -------------------------------------------------------------

    def out_of_time(self) -> bool:
        return self.stop is not None and time.perf_counter() >= self.stop

    def empty_routes(self) -> list[list[int]]:
        return [[0, self.end] for _ in range(self.robots or 0)]

    def sequences(self, routes: list[list[int]]) -> list[list[int]]:
        """``[0, *route, E]`` per route, padded with empty routes up to the robot limit."""
        seqs = [[0, *r, self.end] for r in routes if r]
        return seqs + [[0, self.end] for _ in range((self.robots or 0) - len(seqs))]

    def cost(self, seq: list[int]) -> float:
        d = self.d
        return sum(d[seq[k]][seq[k + 1]] for k in range(len(seq) - 1))

    def key(self, seqs: list[list[int]]) -> Key:
        """Makespan then total length; robots first for the robots objective."""
        costs = [self.cost(s) for s in seqs if len(s) > 2]
        value = (max(costs, default=0.0), sum(costs))
        return value if self.robots is not None else (float(len(costs)), *value)

    def valid(self, routes: list[list[int]]) -> bool:
        """A partition of the KPOIs within the robot limit and the deadline."""
        try:
            visited = sorted(int(v) for r in routes for v in r)
        except (TypeError, ValueError):
            return False
        if visited != list(range(1, self.n + 1)):
            return False
        used = [r for r in routes if len(r)]
        if self.robots is not None and len(used) > self.robots:
            return False
        costs = [self.cost(s) for s in self.sequences(used)]
        return self.deadline is None or all(meets_deadline(c, self.deadline) for c in costs)

    def fits(self, new: float, old: float) -> bool:
        """A changed route cost respects the deadline (or does not grow)."""
        return self.deadline is None or new <= self.deadline or new <= old

    # ----- the search --------------------------------------------------------------

    def polish(self, seqs: list[list[int]], dirty: set[int] | None = None) -> list[list[int]]:
        """Local search to a local optimum (from the routes in ``dirty``, default all),
        then (robots objective) route emptying."""
        self.local_search(seqs, dirty)
        if self.robots is None:
            while not self.out_of_time() and self.empty_one_route(seqs):
                self.local_search(seqs)
        return seqs

    def local_search(self, seqs: list[list[int]], dirty: set[int] | None = None) -> None:
        """Apply improving moves until none is left (or the time is up).

        Only routes in ``dirty`` (default: all) or changed since are examined, alone or
        in pairs: every move's gain depends on the one or two routes it changes, so
        two routes untouched since a pass without improvement have none left.
        """
        active = set(range(len(seqs))) if dirty is None else set(dirty)
        while active and not self.out_of_time():
            changed: set[int] = set()
            for r in sorted(active):
                if r < len(seqs) and (self.two_opt(seqs[r]) | self.or_opt(seqs[r])):
                    changed.add(r)
            self.relocate(seqs, active, changed)
            self.swap(seqs, active, changed)
            self.two_opt_star(seqs, active, changed)
            active = changed

    def two_opt(self, s: list[int]) -> bool:
        """Reverse ``s[i..j]`` while that shortens the route (best move each time)."""
        d, changed = self.d, False
        while not self.out_of_time():
            top, gain = None, self.tol
            for i in range(1, len(s) - 2):
                a, b = s[i - 1], s[i]
                dab = d[a][b]
                for j in range(i + 1, len(s) - 1):
                    c, e = s[j], s[j + 1]
                    g = dab + d[c][e] - d[a][c] - d[b][e]
                    if g > gain:
                        top, gain = (i, j), g
            if top is None:
                return changed
            i, j = top
            s[i : j + 1] = s[i : j + 1][::-1]
            changed = True
        return changed

    def or_opt(self, s: list[int]) -> bool:
        """Move a chain of 1-3 KPOIs (maybe reversed) elsewhere in its route."""
        d, changed = self.d, False
        i = 1
        while i < len(s) - 1 and not self.out_of_time():
            moved = False
            for length in range(1, _CHAIN + 1):
                if i + length > len(s) - 1:
                    break
                chain = s[i : i + length]
                first, last, before, after = chain[0], chain[-1], s[i - 1], s[i + length]
                removal = d[before][first] + d[last][after] - d[before][after]
                rest = s[:i] + s[i + length :]
                top, gain = None, self.tol
                for k in range(len(rest) - 1):
                    u, v = rest[k], rest[k + 1]
                    base = removal + d[u][v]
                    g = base - d[u][first] - d[last][v]
                    if g > gain:
                        top, gain = (k, False), g
                    g = base - d[u][last] - d[first][v]
                    if g > gain:
                        top, gain = (k, True), g
                if top is not None:
                    k, flip = top
                    s[:] = rest[: k + 1] + (chain[::-1] if flip else chain) + rest[k + 1 :]
                    moved = changed = True
                    break
            if not moved:
                i += 1
        return changed

    def relocate(self, seqs: list[list[int]], active: set[int], changed: set[int]) -> None:
        """Move a chain of 1-3 KPOIs (maybe reversed) from one route into another,
        next to one of the :data:`_GRANULARITY` KPOIs nearest its ends or right
        after the start; between routes of which one is in ``active`` or ``changed``
        (the routes changed are added to ``changed``)."""
        d, tol, free = self.d, self.tol, self.deadline is None
        costs = [self.cost(s) for s in seqs]
        where = self.positions(seqs)
        for a in range(len(seqs)):
            i = 1
            while i < len(seqs[a]) - 1 and not self.out_of_time():
                sa = seqs[a]
                top, top_key = None, None
                for length in range(1, _CHAIN + 1):
                    if i + length > len(sa) - 1:
                        break
                    chain = sa[i : i + length]
                    first, last, before, after = chain[0], chain[-1], sa[i - 1], sa[i + length]
                    inner = sum(d[chain[k]][chain[k + 1]] for k in range(length - 1))
                    na = costs[a] - d[before][first] - d[last][after] + d[before][after] - inner
                    ca = costs[a]
                    live = a in active or a in changed
                    for b, k in self.slots(seqs, where, a, first, last):
                        if not (live or b in active or b in changed):
                            continue
                        sb, cb = seqs[b], costs[b]
                        u, v = sb[k], sb[k + 1]
                        base = cb + inner - d[u][v]
                        old = ca if ca > cb else cb
                        for flip in (False, True):
                            x, y = (last, first) if flip else (first, last)
                            nb = base + d[u][x] + d[y][v]
                            # the gain test of the module docstring, inlined (hot loop)
                            new = na if na > nb else nb
                            if not (
                                new < old - tol or (new <= old and na + nb < ca + cb - tol)
                            ):
                                continue
                            if not (free or (self.fits(na, ca) and self.fits(nb, cb))):
                                continue
                            key = (new, na + nb, b, k, flip)
                            if top_key is None or key < top_key:
                                top, top_key = (length, b, k, flip), key
                if top is None:
                    i += 1
                    continue
                length, b, k, flip = top
                chain = sa[i : i + length]
                del sa[i : i + length]
                seqs[b][k + 1 : k + 1] = chain[::-1] if flip else chain
                costs[a], costs[b] = self.cost(sa), self.cost(seqs[b])
                where = self.positions(seqs)
                changed.update((a, b))

    def positions(self, seqs: list[list[int]]) -> dict[int, tuple[int, int]]:
        """Route and position of every KPOI."""
        return {v: (r, k) for r, s in enumerate(seqs) for k, v in enumerate(s[1:-1], 1)}

    def slots(
        self,
        seqs: list[list[int]],
        where: dict[int, tuple[int, int]],
        a: int,
        first: int,
        last: int,
    ) -> set[tuple[int, int]]:
        """Insertion slots ``(b, k)`` (between ``s_b[k]`` and ``s_b[k + 1]``) in routes
        other than ``a``: right after the start, and on either side of a KPOI among
        the nearest to ``first`` or ``last`` (callers break ties by ``(b, k)``)."""
        found = {(b, 0) for b in range(len(seqs)) if b != a}
        near = self.near
        for u in near[first] if first == last else near[first] + near[last]:
            b, k = where[u]
            if b != a:
                found.add((b, k - 1))
                found.add((b, k))
        return found

    def swap(self, seqs: list[list[int]], active: set[int], changed: set[int]) -> None:
        """Exchange one KPOI of a route with one of another (pairs as in
        :meth:`relocate`)."""
        d, tol, free = self.d, self.tol, self.deadline is None
        costs = [self.cost(s) for s in seqs]
        for a in range(len(seqs)):
            for b in range(a + 1, len(seqs)):
                if not ({a, b} & active or {a, b} & changed):
                    continue
                sa, sb = seqs[a], seqs[b]
                for i in range(1, len(sa) - 1):
                    if self.out_of_time():
                        return
                    ca, cb = costs[a], costs[b]
                    old, total = max(ca, cb), ca + cb
                    p, x, q = sa[i - 1], sa[i], sa[i + 1]
                    out_a = ca - d[p][x] - d[x][q]
                    top, top_key = None, None
                    for j in range(1, len(sb) - 1):
                        u, y, v = sb[j - 1], sb[j], sb[j + 1]
                        na = out_a + d[p][y] + d[y][q]
                        nb = cb - d[u][y] - d[y][v] + d[u][x] + d[x][v]
                        new = na if na > nb else nb  # the module docstring's gain test
                        if not (new < old - tol or (new <= old and na + nb < total - tol)):
                            continue
                        if free or (self.fits(na, ca) and self.fits(nb, cb)):
                            key = (new, na + nb)
                            if top_key is None or key < top_key:
                                top, top_key = j, key
                    if top is not None:
                        sa[i], sb[top] = sb[top], sa[i]
                        costs[a], costs[b] = self.cost(sa), self.cost(sb)
                        changed.update((a, b))

    def two_opt_star(self, seqs: list[list[int]], active: set[int], changed: set[int]) -> None:
        """Exchange the tails of two routes (cut after ``s_a[i]`` and ``s_b[j]``; pairs
        as in :meth:`relocate`)."""
        d, tol, free = self.d, self.tol, self.deadline is None
        for a in range(len(seqs)):
            for b in range(a + 1, len(seqs)):
                if not ({a, b} & active or {a, b} & changed):
                    continue
                while not self.out_of_time():
                    sa, sb = seqs[a], seqs[b]
                    pa, ta = self.prefix_suffix(sa)
                    pb, tb = self.prefix_suffix(sb)
                    ca, cb = pa[-1], pb[-1]
                    old, total = max(ca, cb), ca + cb
                    top, top_key = None, None
                    for i in range(len(sa) - 1):
                        pai, dai, tai = pa[i], d[sa[i]], ta[i + 1]
                        for j in range(len(sb) - 1):
                            na = pai + dai[sb[j + 1]] + tb[j + 1]
                            nb = pb[j] + d[sb[j]][sa[i + 1]] + tai
                            new = na if na > nb else nb  # the module docstring's gain test
                            if not (new < old - tol or (new <= old and na + nb < total - tol)):
                                continue
                            if free or (self.fits(na, ca) and self.fits(nb, cb)):
                                key = (new, na + nb)
                                if top_key is None or key < top_key:
                                    top, top_key = (i, j), key
                    if top is None:
                        break
                    i, j = top
                    seqs[a], seqs[b] = sa[: i + 1] + sb[j + 1 :], sb[: j + 1] + sa[i + 1 :]
                    changed.update((a, b))

    def prefix_suffix(self, s: list[int]) -> tuple[list[float], list[float]]:
        """Cost from the start to ``s[k]`` and from ``s[k]`` to the end, per ``k``."""
        d = self.d
        prefix = [0.0]
        for k in range(1, len(s)):
            prefix.append(prefix[-1] + d[s[k - 1]][s[k]])
        suffix = [prefix[-1] - c for c in prefix]
        return prefix, suffix

    # ----- route emptying and ruin and recreate ------------------------------------

    def empty_one_route(self, seqs: list[list[int]]) -> bool:
        """Empty the route with the fewest KPOIs (then the next, ...) by cheapest
        insertion of its KPOIs, farthest first, into the others within the deadline."""
        order = sorted(range(len(seqs)), key=lambda r: (len(seqs[r]), self.cost(seqs[r]), r))
        for r in order:
            others = [list(s) for k, s in enumerate(seqs) if k != r]
            kpois = self.farthest_first(seqs[r][1:-1])
            if all(self.insert(others, v, allow_new=False) for v in kpois):
                seqs[:] = others
                return True
        return False

    def ruin_and_recreate(self, seqs: list[list[int]], rng: random.Random) -> None:
        """Slack induction by string removals (SISR; Christiaens and Vanden Berghe,
        Transportation Science 54(2), 2020, doi:10.1287/trsc.2019.0914).

        Ruin: from a random KPOI (in the longest route half of the time: the makespan's
        bottleneck) and its nearest KPOIs in turn, remove from each route met, up to a
        random number of routes, a string of random length (at most :data:`_STRING`)
        of consecutive KPOIs through that KPOI: on average at most about :data:`_RUINED`
        KPOIs. Recreate: insert them (:meth:`insert`, skipping each slot with
        probability :data:`_BLINK`) in a random order, farthest from the start first or
        nearest first (weights 4, 4, 2).
        """
        n = self.n
        used = [s for s in seqs if len(s) > 2]
        longest_string = min(_STRING, max(1, (n + len(used) - 1) // max(1, len(used))))
        strings = int(rng.uniform(1.0, 4.0 * _RUINED / (1 + longest_string)))
        if rng.random() < 0.5:
            longest = max(range(len(seqs)), key=lambda r: (self.cost(seqs[r]), -r))
            centre = rng.choice(seqs[longest][1:-1] or list(range(1, n + 1)))
        else:
            centre = rng.randint(1, n)
        where = self.positions(seqs)
        ruined: set[int] = set()
        removed: list[int] = []
        for u in self.neighbours[centre - 1]:
            r, k = where[int(u)]
            if r in ruined:
                continue
            size = len(seqs[r]) - 2
            length = rng.randint(1, min(size, longest_string))
            first = rng.randint(max(1, k - length + 1), min(k, size - length + 1))
            removed.extend(seqs[r][first : first + length])
            ruined.add(r)
            if len(ruined) >= strings:
                break
        gone = set(removed)
        for s in seqs:
            s[:] = [v for v in s if v not in gone or v in (0, self.end)]
        if self.robots is None:
            seqs[:] = [s for s in seqs if len(s) > 2]
        order = rng.choices(("random", "far", "near"), weights=(4, 4, 2))[0]
        if order == "random":
            rng.shuffle(removed)
        else:
            removed.sort(key=lambda v: (self.d[0][v] if order == "near" else -self.d[0][v], v))
        for v in removed:
            self.insert(seqs, v, allow_new=True, rng=rng)

    def farthest_first(self, kpois: Iterable[int]) -> list[int]:
        """``kpois`` farthest from the start first (ties by index): the insertion order
        of :func:`min_max_insertion` and :meth:`empty_one_route`."""
        return sorted(kpois, key=lambda v: (-self.d[0][v], v))

    def insert_all(self, seqs: list[list[int]], kpois: list[int]) -> None:
        for v in kpois:
            self.insert(seqs, v, allow_new=True)

    def insert(
        self,
        seqs: list[list[int]],
        v: int,
        *,
        allow_new: bool,
        rng: random.Random | None = None,
    ) -> bool:
        """Put KPOI ``v`` where it keeps the makespan least, then adds least length;
        under a deadline, where it adds least length within it (else a new route when
        ``allow_new``). With ``rng``, each slot is skipped with probability
        :data:`_BLINK` (SISR's blinks). Returns whether it was placed."""
        d = self.d
        costs = [self.cost(s) for s in seqs]
        makespan = max(costs, default=0.0)
        top, top_key, blinked = None, None, False
        for r, s in enumerate(seqs):
            for k in range(len(s) - 1):
                if rng is not None and rng.random() < _BLINK:
                    blinked = True
                    continue
                u, w = s[k], s[k + 1]
                extra = d[u][v] + d[v][w] - d[u][w]
                new = costs[r] + extra
                if self.deadline is not None:
                    if not new <= self.deadline:
                        continue
                    key = (extra, 0.0)
                else:
                    key = (max(new, makespan), extra)
                if top_key is None or key < top_key:
                    top, top_key = (r, k), key
        if top is None and blinked:
            # the slots that would do were all skipped (likely with few slots, over many
            # rounds): a new route would break the robot limit, so try again without blinks
            return self.insert(seqs, v, allow_new=allow_new)
        if top is None:
            if not allow_new:
                return False
            seqs.append([0, v, self.end])
            return True
        r, k = top
        seqs[r].insert(k + 1, v)
        return True


METHODS = (
    MethodInfo(
        "best",
        best,
        "best construction + iterated local search (2-opt, or-opt, relocate, swap, 2-opt*); "
        "stops at a proven bound, at convergence or at the time limit (until=limit: spends it)",
        options=("iterations", "until"),
    ),
)
