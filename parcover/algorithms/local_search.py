"""``best``: the strongest heuristic, an iterated local search on the best construction.

It runs every registered construction (all methods but ``best``, ``trivial`` and the
exact ones) plus its own min-max cheapest insertion, keeps the best valid answer and
improves it:

* local search with 2-opt and or-opt inside a route and relocate (of chains of 1-3
  KPOIs, next to one of their 20 nearest KPOIs), swap and 2-opt* between two routes. A move between routes ``a`` and ``b`` is
  taken when it lowers ``max(c_a, c_b)``, or keeps it and lowers ``c_a + c_b``: the
  makespan never rises and the sorted route costs fall lexicographically, so the
  longest route shrinks with the total length as tie-breaker;
* for the robots objective (paper, Problem 2) the route with the fewest KPOIs is
  repeatedly emptied by cheapest insertion of its KPOIs into the others within the
  deadline;
* ruin and recreate (a seeded random KPOI and its nearest KPOIs are removed and put
  back by min-max cheapest insertion) while the effort lasts, keeping the best.

Routes are handled as ``[0, v_1, ..., v_m, E]`` where ``E`` is the start (tours) or a
dummy end at distance 0 from everything (paths), so both route kinds share every move.
"""

from __future__ import annotations

import random
import time
from typing import Any

import numpy as np

from parcover.instance import Instance
from parcover.problem import MethodInfo, Problem, Solution, meets_deadline
from parcover.result import Status

__all__ = ["best", "improve", "min_max_insertion", "DEFAULT_ITERATIONS", "METHODS"]

DEFAULT_ITERATIONS = 30
"""Ruin-and-recreate rounds when neither a time limit nor ``iterations`` is given
(about a second for 50 KPOIs)."""

_NOT_STARTS = frozenset({"best", "trivial", "exact", "compact", "setpart", "cvxpy"})
_CHAIN = 3  # longest chain of KPOIs moved by or-opt / relocate
_GRANULARITY = 20  # relocate tries slots next to this many nearest KPOIs

Key = tuple[float, ...]


def best(
    instance: Instance,
    problem: Problem,
    *,
    time_limit: float | None = None,
    seed: int = 0,
    iterations: int | None = None,
) -> Solution:
    """Best registered construction, then iterated local search (module docstring).

    Parameters
    ----------
    instance, problem
        The question; both objectives and both route kinds.
    time_limit
        Seconds for the whole run. Results then may depend on the machine's speed.
    seed
        Seed of the ruin-and-recreate rounds (and of the constructions).
    iterations
        Ruin-and-recreate rounds. Default: :data:`DEFAULT_ITERATIONS` without a time
        limit, unbounded (until the time limit) with one. With both, whichever ends
        first; with iterations alone the result depends only on ``seed``.

    Returns
    -------
    Solution
        Routes in KPOI indices, no bound; ``info`` holds ``start`` (the construction
        started from), ``start_value`` and ``value`` (the objective key: makespan and
        total length, or robots, makespan and total length) and ``iterations``.
    """
    started = time.perf_counter()
    deadline = problem.effective_deadline(instance)
    if deadline is not None and not meets_deadline(problem.least_makespan(instance), deadline):
        return Solution(routes=[], status=Status.INFEASIBLE)
    name, start = best_construction(instance, problem, time_limit=time_limit, seed=seed)
    if iterations is None and time_limit is None:
        iterations = DEFAULT_ITERATIONS
    stop = None if time_limit is None else started + time_limit
    routes, info = improve(instance, problem, start, seed=seed, iterations=iterations, stop=stop)
    return Solution(routes=routes, info={"start": name, **info})


def best_construction(
    instance: Instance, problem: Problem, *, time_limit: float | None, seed: int
) -> tuple[str, list[list[int]]]:
    """The valid construction with the least objective key (name, routes).

    Every registered method except ``best``, ``trivial`` and the exact ones is tried
    (each gets a tenth of the time limit); one that raises or answers invalid routes
    is skipped. :func:`min_max_insertion` always takes part. Ties go to the
    construction listed first (registry order, then ours).
    """
    from parcover.solve import available_methods  # solve imports this module

    search = _Search(instance, problem)
    candidates: list[tuple[str, list[list[int]]]] = []
    share = None if time_limit is None else time_limit / 10
    for name, info in available_methods().items():
        if name in _NOT_STARTS:
            continue
        try:
            solution = info.function(instance, problem, time_limit=share, seed=seed)
        except Exception:  # a failing construction must not break `best`
            continue
        if not solution.drops_deadline and search.valid(solution.routes):
            candidates.append((name, [list(map(int, r)) for r in solution.routes if r]))
    candidates.append(("min_max_insertion", min_max_insertion(instance, problem)))
    return min(candidates, key=lambda c: search.key(search.sequences(c[1])))


def min_max_insertion(instance: Instance, problem: Problem) -> list[list[int]]:
    """Our own construction: KPOIs farthest from the start first, each at the position
    that keeps the makespan least (then adds least length); under a deadline, the
    cheapest position within it, or a new route."""
    search = _Search(instance, problem)
    seqs = search.empty_routes()
    order = sorted(range(1, instance.n + 1), key=lambda v: (-search.d[0][v], v))
    search.insert_all(seqs, order)
    return [s[1:-1] for s in seqs if len(s) > 2]


def improve(
    instance: Instance,
    problem: Problem,
    routes: list[list[int]],
    *,
    seed: int = 0,
    iterations: int | None = DEFAULT_ITERATIONS,
    stop: float | None = None,
) -> tuple[list[list[int]], dict[str, Any]]:
    """Iterated local search from valid ``routes`` (KPOI indices).

    Parameters
    ----------
    routes
        A valid starting solution for ``problem``.
    iterations
        Ruin-and-recreate rounds (``None``: until ``stop``).
    stop
        A :func:`time.perf_counter` value at which to stop (``None``: no limit).

    Returns
    -------
    tuple
        The best routes found (never worse than ``routes`` by the objective key) and
        an info dict with ``start_value``, ``value`` and ``iterations``.
    """
    if iterations is None and stop is None:
        raise ValueError("Give iterations or a stop time.")
    search = _Search(instance, problem, stop)
    rng = random.Random(seed)
    start = search.sequences(routes)
    start_key = search.key(start)
    current = search.polish(_copy(start))
    current_key = search.key(current)
    incumbent, incumbent_key = _copy(current), current_key
    if start_key < incumbent_key:
        incumbent, incumbent_key = _copy(start), start_key
    done = 0
    while (iterations is None or done < iterations) and not search.out_of_time():
        candidate = _copy(current)
        search.ruin_and_recreate(candidate, rng)
        candidate = search.polish(candidate)
        candidate_key = search.key(candidate)
        done += 1
        if candidate_key < incumbent_key:
            incumbent, incumbent_key = _copy(candidate), candidate_key
        progress = done / iterations if iterations else 0.0
        threshold = 0.01 * max(0.0, 1.0 - progress)
        if candidate_key < current_key or _within(candidate_key, incumbent_key, threshold, problem):
            current, current_key = candidate, candidate_key
    final = [s[1:-1] for s in incumbent if len(s) > 2]
    return final, {"start_value": start_key, "value": incumbent_key, "iterations": done}


def _copy(seqs: list[list[int]]) -> list[list[int]]:
    return [list(s) for s in seqs]


def _within(key: Key, incumbent: Key, threshold: float, problem: Problem) -> bool:
    """Threshold acceptance: as many robots and a makespan at most ``1 + threshold``
    times the incumbent's."""
    if problem.objective == "robots":
        return key[0] <= incumbent[0] and key[1] <= incumbent[1] * (1 + threshold)
    return key[0] <= incumbent[0] * (1 + threshold)


class _Search:
    """Distances, the route end node and the moves (routes as ``[0, ..., E]`` lists)."""

    def __init__(self, instance: Instance, problem: Problem, stop: float | None = None) -> None:
        n = instance.n
        matrix = np.zeros((n + 2, n + 2))
        matrix[: n + 1, : n + 1] = instance.distances
        self.n = n
        self.end = 0 if problem.tours else n + 1
        self.d: list[list[float]] = matrix.tolist()
        self.tol = 1e-9 * max(1.0, float(matrix.max()))
        self.robots = problem.robots
        self.deadline = problem.effective_deadline(instance)
        self.neighbours = np.argsort(matrix[1 : n + 1, 1 : n + 1], axis=1, kind="stable") + 1
        self.stop = stop

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

    def pair_gain(self, ca: float, cb: float, na: float, nb: float) -> bool:
        """The move lowers ``max(c_a, c_b)`` or keeps it and lowers ``c_a + c_b``."""
        old, new = max(ca, cb), max(na, nb)
        if not (self.fits(na, ca) and self.fits(nb, cb)):
            return False
        return new < old - self.tol or (new <= old and na + nb < ca + cb - self.tol)

    # ----- the search --------------------------------------------------------------

    def polish(self, seqs: list[list[int]]) -> list[list[int]]:
        """Local search to a local optimum, then (robots objective) route emptying."""
        self.local_search(seqs)
        if self.robots is None:
            while not self.out_of_time() and self.empty_one_route(seqs):
                self.local_search(seqs)
        return seqs

    def local_search(self, seqs: list[list[int]]) -> None:
        """Apply improving moves until none is left (or the time is up)."""
        improved = True
        while improved and not self.out_of_time():
            improved = False
            for s in seqs:
                improved |= self.two_opt(s)
                improved |= self.or_opt(s)
            improved |= self.relocate(seqs)
            improved |= self.swap(seqs)
            improved |= self.two_opt_star(seqs)

    def two_opt(self, s: list[int]) -> bool:
        """Reverse ``s[i..j]`` while that shortens the route (best move each time)."""
        d, changed = self.d, False
        while True:
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

    def or_opt(self, s: list[int]) -> bool:
        """Move a chain of 1-3 KPOIs (maybe reversed) elsewhere in its route."""
        d, changed = self.d, False
        i = 1
        while i < len(s) - 1:
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

    def relocate(self, seqs: list[list[int]]) -> bool:
        """Move a chain of 1-3 KPOIs (maybe reversed) from one route into another,
        next to one of the :data:`_GRANULARITY` KPOIs nearest its ends or right
        after the start."""
        d, changed = self.d, False
        costs = [self.cost(s) for s in seqs]
        where = self.positions(seqs)
        for a in range(len(seqs)):
            i = 1
            while i < len(seqs[a]) - 1:
                sa = seqs[a]
                top, top_key = None, None
                for length in range(1, _CHAIN + 1):
                    if i + length > len(sa) - 1:
                        break
                    chain = sa[i : i + length]
                    first, last, before, after = chain[0], chain[-1], sa[i - 1], sa[i + length]
                    inner = sum(d[chain[k]][chain[k + 1]] for k in range(length - 1))
                    na = costs[a] - d[before][first] - d[last][after] + d[before][after] - inner
                    for b, k in self.slots(seqs, where, a, first, last):
                        sb, cb = seqs[b], costs[b]
                        u, v = sb[k], sb[k + 1]
                        base = cb + inner - d[u][v]
                        for flip in (False, True):
                            x, y = (last, first) if flip else (first, last)
                            nb = base + d[u][x] + d[y][v]
                            if not self.pair_gain(costs[a], cb, na, nb):
                                continue
                            key = (max(na, nb), na + nb, b, k, flip)
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
                changed = True
        return changed

    def positions(self, seqs: list[list[int]]) -> dict[int, tuple[int, int]]:
        """Route and position of every KPOI."""
        return {v: (r, k) for r, s in enumerate(seqs) for k, v in enumerate(s[1:-1], 1)}

    def slots(
        self, seqs: list[list[int]], where: dict[int, tuple[int, int]], a: int, first: int, last: int
    ) -> list[tuple[int, int]]:
        """Insertion slots ``(b, k)`` (between ``s_b[k]`` and ``s_b[k + 1]``) in routes
        other than ``a``: right after the start, and on either side of a KPOI among
        the nearest to ``first`` or ``last``; in a deterministic order."""
        found = {(b, 0) for b in range(len(seqs)) if b != a}
        for end in {first, last}:
            for u in self.neighbours[end - 1][:_GRANULARITY]:
                b, k = where[int(u)]
                if b != a:
                    found.update(((b, k - 1), (b, k)))
        return sorted(found)

    def swap(self, seqs: list[list[int]]) -> bool:
        """Exchange one KPOI of a route with one of another."""
        d, changed = self.d, False
        costs = [self.cost(s) for s in seqs]
        for a in range(len(seqs)):
            for b in range(a + 1, len(seqs)):
                sa, sb = seqs[a], seqs[b]
                for i in range(1, len(sa) - 1):
                    p, x, q = sa[i - 1], sa[i], sa[i + 1]
                    out_a = costs[a] - d[p][x] - d[x][q]
                    top, top_key = None, None
                    for j in range(1, len(sb) - 1):
                        u, y, v = sb[j - 1], sb[j], sb[j + 1]
                        na = out_a + d[p][y] + d[y][q]
                        nb = costs[b] - d[u][y] - d[y][v] + d[u][x] + d[x][v]
                        if self.pair_gain(costs[a], costs[b], na, nb):
                            key = (max(na, nb), na + nb)
                            if top_key is None or key < top_key:
                                top, top_key = j, key
                    if top is not None:
                        sa[i], sb[top] = sb[top], sa[i]
                        costs[a], costs[b] = self.cost(sa), self.cost(sb)
                        changed = True
        return changed

    def two_opt_star(self, seqs: list[list[int]]) -> bool:
        """Exchange the tails of two routes (cut after ``s_a[i]`` and ``s_b[j]``)."""
        d, changed = self.d, False
        for a in range(len(seqs)):
            for b in range(a + 1, len(seqs)):
                while True:
                    sa, sb = seqs[a], seqs[b]
                    pa, ta = self.prefix_suffix(sa)
                    pb, tb = self.prefix_suffix(sb)
                    ca, cb = pa[-1], pb[-1]
                    top, top_key = None, None
                    for i in range(len(sa) - 1):
                        for j in range(len(sb) - 1):
                            na = pa[i] + d[sa[i]][sb[j + 1]] + tb[j + 1]
                            nb = pb[j] + d[sb[j]][sa[i + 1]] + ta[i + 1]
                            if self.pair_gain(ca, cb, na, nb):
                                key = (max(na, nb), na + nb)
                                if top_key is None or key < top_key:
                                    top, top_key = (i, j), key
                    if top is None:
                        break
                    i, j = top
                    seqs[a], seqs[b] = sa[: i + 1] + sb[j + 1 :], sb[: j + 1] + sa[i + 1 :]
                    changed = True
        return changed

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
            kpois = sorted(seqs[r][1:-1], key=lambda v: (-self.d[0][v], v))
            if all(self.insert(others, v, allow_new=False) for v in kpois):
                seqs[:] = others
                return True
        return False

    def ruin_and_recreate(self, seqs: list[list[int]], rng: random.Random) -> None:
        """Remove a random KPOI (from the longest route half of the time) and up to
        ``q`` of its nearest KPOIs, then reinsert them in a random order."""
        n = self.n
        q = rng.randint(1, max(1, min(n, 3 + n // 10)))
        if rng.random() < 0.5:
            longest = max(range(len(seqs)), key=lambda r: (self.cost(seqs[r]), -r))
            pool = seqs[longest][1:-1] or list(range(1, n + 1))
        else:
            pool = list(range(1, n + 1))
        centre = rng.choice(pool)
        removed = [int(v) for v in self.neighbours[centre - 1][:q]]
        if centre not in removed:
            removed[-1] = centre
        gone = set(removed)
        for s in seqs:
            s[:] = [v for v in s if v not in gone or v in (0, self.end)]
        if self.robots is None:
            seqs[:] = [s for s in seqs if len(s) > 2]
        rng.shuffle(removed)
        self.insert_all(seqs, removed)

    def insert_all(self, seqs: list[list[int]], kpois: list[int]) -> None:
        for v in kpois:
            self.insert(seqs, v, allow_new=True)

    def insert(self, seqs: list[list[int]], v: int, *, allow_new: bool) -> bool:
        """Put KPOI ``v`` where it keeps the makespan least, then adds least length;
        under a deadline, where it adds least length within it (else a new route when
        ``allow_new``). Returns whether it was placed."""
        d = self.d
        costs = [self.cost(s) for s in seqs]
        makespan = max(costs, default=0.0)
        top, top_key = None, None
        for r, s in enumerate(seqs):
            for k in range(len(s) - 1):
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
        "best construction + iterated local search (2-opt, or-opt, relocate, swap, 2-opt*)",
        options=("iterations",),
    ),
)
