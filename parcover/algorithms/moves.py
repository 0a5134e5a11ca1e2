"""The moves of ``best``'s local search, on routes as ``[0, v_1, ..., v_m, E]`` lists.

``E`` is the start (tours) or a dummy end at distance 0 from everything (paths), so
both route kinds share every move. :class:`Search` holds the distances (as Python
lists, built once per instance by :func:`_distances`) and the moves:

* inside a route: 2-opt and or-opt (chains of 1-3 KPOIs, maybe reversed);
* between two routes: relocate (chains of 1-3 KPOIs, next to one of their
  :data:`_GRANULARITY` nearest KPOIs), swap and 2-opt*. A move between routes ``a``
  and ``b`` is taken when it lowers ``max(c_a, c_b)``, or keeps it and lowers
  ``c_a + c_b`` (the gain test): the makespan never rises and the sorted route costs
  fall lexicographically;
* route emptying (robots objective) and ruin and recreate (SISR), both putting KPOIs
  back by min-max cheapest insertion (:meth:`Search.insert`).
"""

from __future__ import annotations

import functools
import random
import time
import weakref
from collections.abc import Iterable

import numpy as np

from parcover.instance import Instance
from parcover.problem import Problem, meets_deadline

_CHAIN = 3  # longest chain of KPOIs moved by or-opt / relocate
_GRANULARITY = 20  # relocate tries slots next to this many nearest KPOIs
_STRING = 10  # longest string removed from a route by the ruin
_RUINED = 10  # KPOIs removed per round on average (at most)
_BLINK = 0.01  # probability that the recreate skips an insertion slot

Key = tuple[float, ...]
"""An objective key: makespan and total length; robots first for the robots objective."""


class _Distances:
    """An instance's distances as the search reads them: the matrix with a row and column
    of zeros appended for the end node of paths, as an array and as Python lists (the hot
    loops index lists several times faster than arrays), and the KPOIs by distance.

    Built once per instance by :func:`_distances`, as each is a full pass over the matrix
    (measured at 3000 KPOIs: 0.5 s for the lists alone) and one ``best`` run makes a
    :class:`Search` several times (constructions, improve, fewer_robots).
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


class Search:
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
                            # the gain test (module docstring), inlined (hot loop)
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
                        new = na if na > nb else nb  # the gain test (module docstring)
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
                            new = na if na > nb else nb  # the gain test (module docstring)
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
        of :func:`~parcover.algorithms.starts.min_max_insertion` and :meth:`empty_one_route`."""
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
