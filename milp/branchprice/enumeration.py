r"""Route enumeration: every route that can still be in a solution with at most ``k`` routes.

Branch-and-price (:mod:`milp.branchprice`) decides "at most ``k`` routes within ``U``" at
a node whose LP bound ``z`` lies below ``k``. With duals :math:`\pi` that no route
within ``U`` prices above 1 (Farley's scaling, :mod:`milp.branchprice.colgen` eq. (4)), every route
has reduced cost :math:`\bar c_r = 1 - \pi(r) \ge 0`, and a solution of ``N`` routes
partitioning the KPOIs has :math:`N = z + \sum_r \bar c_r` (:math:`z = \sum_i \pi_i`).
So :math:`N \le k` needs :math:`\bar c_r \le k - z` for each of its routes: only the KPOI
sets of prize at least :math:`1 - (k - z)` can occur (Baldacci, Christofides and Mingozzi,
"An exact algorithm for the vehicle routing problem based on the set partitioning
formulation with additional cuts", Math. Program. 115 (2008), section 4; Baldacci,
Mingozzi and Roberti 2011, section 5). When the gap :math:`k - z` is small there are few
such sets: this module lists them all and a set-covering MIP over them answers the node
(a solution, or a proof that none has at most ``k`` routes), instead of a branching tree.
With subset-row cuts the dual objective is :math:`\sum \pi - \sum \sigma` and a route's
reduced cost is :math:`1 - \pi(r) + \sigma a(r) \ge 1 - \pi(r)` (the cut rows are at most
1 in any solution), so the same prize threshold on :math:`\pi` alone is still a superset.

Listing
-------
Partial routes are grown one KPOI at a time, level by level (level ``q``: ``q`` KPOIs),
as states ``(S, j, l, p)``: KPOI set ``S``, last KPOI ``j``, length ``l``, prize
``p = pi(S)``. Of the states with the same ``(S, j)`` only the shortest is kept (every
completion of the others completes it no longer). A state is dropped when ``p`` plus
the completion bound of :mod:`milp.branchprice.ngroute` (the most prize a walk without 2-cycles
from ``j`` can still collect within ``U - l``, an upper bound for every elementary
tail) is below the threshold. A state that may end (the way home fits for tours, the
node's branching lets it end at ``j``) with ``p`` at or above the threshold is a set of
the family; each set keeps its shortest route.

A set contained in another of the family is not needed for covering (the larger one
covers it, and a covering shortcuts to a partition with no longer routes): only the
maximal sets go to the MIP. If ``S`` is in the family and ``S'`` strictly contains it,
so is ``S + {v}`` for ``v`` in ``S' - S`` (its prize is between theirs, and shortcutting
the route of ``S'`` gives one of ``S + {v}`` no longer than that of ``S'``), so testing
the one-KPOI extensions finds every non-maximal set (at the root; under branching's arc
restrictions some may stay, which only costs the MIP a column). The same holds within
any length ``T``: of the sets whose route is within ``T``, the maximal ones are those
with no one-KPOI extension within ``T`` (:meth:`Family.maximal`), so the least makespan
of a solution from the family is found by covering MIPs over shorter and shorter
subfamilies, each failure a proof.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from milp.core.jit import compiled_layout, njit
from milp.branchprice.ngroute import BUDGET_ROUND, WORD, clock_passed, completion_table, enlarged, grid_step, read_clock

__all__ = ["Family", "routes_within_gap", "KERNELS", "EXTENSIONS_PER_CLOCK"]

#: A level's extension reads the clock after trying this many (state, KPOI) extensions
#: (a few milliseconds' work).
EXTENSIONS_PER_CLOCK = 1 << 20


@dataclass(frozen=True)
class Family:
    """The KPOI sets a listing found, each with its shortest route.

    ``lengths[s]``: the length of set ``s``'s route; ``extended[s]``: the shortest route
    of a set of the family with one KPOI more (inf when there is none), so that ``s`` is
    maximal among the sets within a length ``T`` when ``lengths[s] <= T`` and no
    extension is (``extended[s] > T``, or none at all).
    """

    lengths: np.ndarray
    extended: np.ndarray
    levels: list[tuple[np.ndarray, np.ndarray]]  # (parent, last) of every kept state
    where: np.ndarray  # (level, state) of each set's route

    def __len__(self) -> int:
        return len(self.lengths)

    def maximal(self, within: float = math.inf) -> tuple[list[np.ndarray], np.ndarray]:
        """The routes of the sets maximal among those whose route is within ``within``
        (KPOI sequences), and their lengths."""
        keep = np.flatnonzero(self._is_maximal(within))
        return [_trace(self.levels, int(level), int(index)) for level, index in self.where[keep]], self.lengths[keep]

    def count_maximal(self, within: float = math.inf) -> int:
        """How many routes :meth:`maximal` returns, without tracing them."""
        return int(np.count_nonzero(self._is_maximal(within)))

    def _is_maximal(self, within: float) -> np.ndarray:
        """Per set: whether it is maximal among the sets whose route is within ``within``."""
        extended = np.isfinite(self.extended) & (self.extended <= within)
        return (self.lengths <= within) & ~extended


def routes_within_gap(
    D: np.ndarray,
    back: np.ndarray,
    prize: np.ndarray,
    budget: float,
    threshold: float,
    allowed: np.ndarray,
    can_end: np.ndarray,
    *,
    max_states: int,
    max_sets: int | None = None,
    ends_at: float = math.inf,
) -> Family | None:
    """Every KPOI set whose prize reaches ``threshold`` and which has a route within
    ``budget``, with its shortest route (module docstring).

    Parameters
    ----------
    D, back : numpy.ndarray
        The ``(m+1, m+1)`` metric (positive off the diagonal) and the length added when a
        route ends at each node (``D[:, 0]`` for tours, zeros for paths).
    prize : numpy.ndarray
        ``(m+1,)`` non-negative, ``prize[0] = 0``.
    budget, threshold : float
        Longest route, least prize.
    allowed, can_end : numpy.ndarray
        Arcs the routes may use (row 0: first arcs) and KPOIs they may end at.
    max_states : int
        Give up (return None) when more partial routes than this would be kept: when a
        level extends to more states than are left of it (counted before only the
        shortest of each set and last KPOI is kept, so that the listing stops before
        that filter).
    max_sets : int, optional
        ... or when more than this many (set, last KPOI) states reach the threshold (the
        maximal-set filter and the MIP grow with them).
    ends_at : float
        A ``time.perf_counter()`` value; None is returned once it passes (read every
        :data:`EXTENSIONS_PER_CLOCK` extensions and between the steps after them), or
        once the thread is asked to stop (:func:`milp.branchprice.ngroute.read_clock`).

    Returns
    -------
    Family or None
        The sets, or None when the listing gave up.
    """
    D, back, prize = (compiled_layout(a, np.float64) for a in (D, back, prize))
    allowed, can_end = compiled_layout(allowed, np.bool_), compiled_layout(can_end, np.bool_)
    m1 = len(D)
    words = (m1 + WORD - 1) // WORD
    grid = grid_step(budget, float(D[~np.eye(m1, dtype=bool)].min()) if m1 > 1 else 1.0)
    if grid is None:
        return None  # no completion bound: the listing would not be pruned
    delta, G = grid
    dd = np.floor(D / delta).astype(np.int64)
    table = completion_table(dd, np.floor(back / delta).astype(np.int64), prize, allowed, can_end, G, ends_at)
    if table is None:
        return None
    sets = np.zeros((1, words), np.uint64)
    last, length, gained = np.zeros(1, np.int64), np.zeros(1), np.zeros(1)
    levels: list[tuple[np.ndarray, np.ndarray]] = []  # (parent, last) of every kept state
    found: list[tuple[int, np.ndarray, np.ndarray, np.ndarray]] = []  # level, states, sets, lengths
    total = reached = 0
    while len(last):
        parent, last, length, gained, complete = _extend(sets, last, length, gained, D, back, prize, allowed,
                                                         budget, threshold, table, delta, G, max_states - total,
                                                         ends_at)
        if not complete or read_clock() >= ends_at:
            return None
        sets = sets[parent]
        sets[np.arange(len(last)), last // WORD] |= np.left_shift(np.uint64(1), (last % WORD).astype(np.uint64))
        sets, last, length, gained, parent = _shortest_per_end(sets, last, length, gained, parent)
        total += len(last)
        if read_clock() >= ends_at:
            return None
        levels.append((parent, last))
        ends = np.flatnonzero((gained >= threshold) & can_end[last])
        reached += len(ends)
        if max_sets is not None and reached > max_sets:
            return None
        if len(ends):
            found.append((len(levels) - 1, ends, sets[ends], length[ends] + back[last[ends]]))
    if not found:
        return Family(np.zeros(0), np.zeros(0), levels, np.zeros((0, 2), np.int64))
    if read_clock() >= ends_at:
        return None
    family = np.concatenate([f[2] for f in found])
    lengths = np.concatenate([f[3] for f in found])
    where = np.concatenate([np.stack([np.full(len(f[1]), f[0]), f[1]], axis=1) for f in found])
    order = np.lexsort((lengths, *(family[:, w] for w in range(words))))
    family, lengths, where = family[order], lengths[order], where[order]
    first = np.ones(len(order), dtype=bool)
    first[1:] = np.any(family[1:] != family[:-1], axis=1)
    family, lengths = family[first], lengths[first]
    extended = _shortest_extension(family, lengths, m1, ends_at)
    return None if extended is None else Family(lengths, extended, levels, where[first])


def _trace(levels: list[tuple[np.ndarray, np.ndarray]], level: int, index: int) -> np.ndarray:
    """The KPOIs of the state ``index`` of ``level``, from the start."""
    route = []
    while level >= 0:
        parent, last = levels[level]
        route.append(int(last[index]))
        index, level = int(parent[index]), level - 1
    return np.array(route[::-1], dtype=np.int64)


def _shortest_extension(family: np.ndarray, lengths: np.ndarray, m1: int, ends_at: float) -> np.ndarray | None:
    """For each set of ``family`` (distinct bit rows), the least length of its one-KPOI
    extensions in the family (inf when none is); None when the clock passes ``ends_at``
    first."""
    extended, complete = _extension_lengths(family, lengths, m1, ends_at)
    return extended if complete else None


def _shortest_per_end(sets, last, length, gained, parent):
    """Of the states with the same set and last KPOI, the shortest (the first generated
    among equally short ones), in the order their pairs first occur."""
    if len(last) == 0:
        return sets, last, length, gained, parent
    keep = _first_shortest(sets, last, length)
    return sets[keep], last[keep], length[keep], gained[keep], parent[keep]


#: Odd 64-bit constants of the state hash (the golden ratio's, and SplitMix64's mixer).
_GOLDEN, _MIX = np.uint64(0x9E3779B97F4A7C15), np.uint64(0xBF58476D1CE4E5B9)


@njit(cache=True)
def _row_hash(row, h):  # pragma: no cover - compiled
    """``h`` mixed with the words of the bit row ``row`` (the table's slot before masking)."""
    for w in range(row.shape[0]):
        h ^= row[w] + _GOLDEN + (h << np.uint64(6)) + (h >> np.uint64(2))
    h ^= h >> np.uint64(29)
    h *= _MIX
    return h ^ (h >> np.uint64(32))


@njit(cache=True)
def _same_row(a, b):  # pragma: no cover - compiled
    """Whether the bit rows ``a`` and ``b`` hold the same set (a hash table's key test)."""
    for w in range(a.shape[0]):
        if a[w] != b[w]:
            return False
    return True


@njit(cache=True)
def _table_size(n):  # pragma: no cover - compiled
    """Slots of an open-addressing table for ``n`` keys (a power of two, at least ``2 n``)."""
    size = 1
    while size < 2 * n:
        size <<= 1
    return size


@njit(cache=True)
def _extension_lengths(family, lengths, m1, ends_at):  # pragma: no cover - compiled
    """:func:`_shortest_extension` by one hash table of the family's sets (a binary search
    over the rows as bytes took 6.2 s of a 9.5 s listing of 790,093 sets, eil51 m = 5):
    ``(extended, complete)``, the clock read every 4,096 sets."""
    n = family.shape[0]
    size = _table_size(n)
    mask = np.uint64(size - 1)
    slots = np.full(size, -1, np.int64)
    for s in range(n):
        pos = _row_hash(family[s], np.uint64(0)) & mask
        while slots[pos] != -1:
            pos = (pos + np.uint64(1)) & mask
        slots[pos] = s
    extended = np.full(n, np.inf)
    row = np.empty(family.shape[1], np.uint64)
    for s in range(n):
        if s % 4096 == 0:
            if clock_passed(ends_at):
                return extended, False
        for v in range(1, m1):
            w, flag = v // WORD, np.uint64(1) << np.uint64(v % WORD)
            if family[s, w] & flag:
                continue
            row[:] = family[s]
            row[w] |= flag
            pos = _row_hash(row, np.uint64(0)) & mask
            while slots[pos] != -1:
                t = slots[pos]
                if _same_row(family[t], row):
                    if lengths[t] < extended[s]:
                        extended[s] = lengths[t]
                    break
                pos = (pos + np.uint64(1)) & mask
    return extended, True


@njit(cache=True)
def _first_shortest(sets, last, length):  # pragma: no cover - compiled
    """Indices of the shortest state of each (set, last KPOI) pair, the first of equally
    short ones, by first occurrence: one pass over an open-addressing hash table (a sort
    of the states took ten times as long, 10.5 s for 8.7 million)."""
    n = last.shape[0]
    size = _table_size(n)
    mask = np.uint64(size - 1)
    slots = np.full(size, -1, np.int64)  # a pair's rank in keep, or -1
    keep = np.empty(n, np.int64)
    kept = 0
    for s in range(n):
        pos = _row_hash(sets[s], np.uint64(last[s]) * _GOLDEN) & mask
        while True:
            rank = slots[pos]
            if rank == -1:
                slots[pos] = kept
                keep[kept] = s
                kept += 1
                break
            r = keep[rank]
            if last[r] == last[s] and _same_row(sets[r], sets[s]):
                if length[s] < length[r]:
                    keep[rank] = s
                break
            pos = (pos + np.uint64(1)) & mask
    return keep[:kept]


@njit(cache=True)
def _extend(sets, last, length, gained, D, back, prize, allowed, budget, threshold, table, delta,
            G, room, ends_at):  # pragma: no cover - compiled
    """Every state one KPOI longer that fits the budget (the way home included) and whose
    prize plus completion bound reaches ``threshold``: its parent's index, last KPOI,
    length and prize, and whether the level is complete (False: it stopped at more than
    ``room`` states, or when the clock, read every :data:`EXTENSIONS_PER_CLOCK`
    extensions, passed ``ends_at``)."""
    m1 = D.shape[0]
    size = max(16, min(4 * len(last), room + 1))
    out_parent = np.zeros(size, np.int64)
    out_last = np.zeros(size, np.int64)
    out_length = np.zeros(size)
    out_gained = np.zeros(size)
    count = 0
    tried = 0
    for s in range(len(last)):
        i = last[s]
        tried += m1
        if tried >= EXTENSIONS_PER_CLOCK:
            tried = 0
            if clock_passed(ends_at):
                return out_parent[:count], out_last[:count], out_length[:count], out_gained[:count], False
        for j in range(1, m1):
            if sets[s, j // WORD] & (np.uint64(1) << np.uint64(j % WORD)) or not allowed[i, j]:
                continue
            reach = length[s] + D[i, j]
            if reach + back[j] > budget:
                continue
            p = gained[s] + prize[j]
            b = int(math.floor((budget - reach) / delta * (1.0 + BUDGET_ROUND))) + 1
            if b < 0 or p + table[min(b, G), j] < threshold:
                continue
            if count == room:
                return out_parent[:count], out_last[:count], out_length[:count], out_gained[:count], False
            if count == size:
                size *= 2
                out_parent, out_last = enlarged(out_parent, size), enlarged(out_last, size)
                out_length, out_gained = enlarged(out_length, size), enlarged(out_gained, size)
            out_parent[count], out_last[count], out_length[count], out_gained[count] = s, j, reach, p
            count += 1
    return out_parent[:count], out_last[:count], out_length[:count], out_gained[:count], True


#: Every compiled (numba) function of this module, for :mod:`milp.branchprice.compiling` to check and compile.
KERNELS = (_extend, _first_shortest, _row_hash, _same_row, _table_size, _extension_lengths)
