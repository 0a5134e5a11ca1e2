r"""Pricing over ng-routes: the most valuable route within a length budget, by labelling.

The column-generation master of :mod:`milp.branchprice` asks, for KPOI prizes
:math:`\pi_i \ge 0` (its duals), for routes from the start 0 whose length is at most
:math:`U` and whose prize :math:`\sum_{i} a_{ir} \pi_i` exceeds 1 (a negative reduced
cost, the column cost being 1), and for the largest prize :math:`M` over all such routes
(the certificate of :mod:`milp.branchprice.colgen`, eq. (4): :math:`\sum_i \pi_i / \max(M, 1)` is a
lower bound on the LP). This is an elementary orienteering problem; it is relaxed to
*ng-routes* (Baldacci, Mingozzi and Roberti 2011, "New route relaxation and pricing
strategies for the vehicle routing problem", Oper. Res. 59(5), 1269-1283,
doi:10.1287/opre.1110.0975), which contain every elementary route, so that the largest
prize over them is still a valid :math:`M`.

ng-routes
---------
Each KPOI :math:`i` has a neighbourhood :math:`N_i` (itself and its ``size - 1``
nearest KPOIs). A partial route carries a memory :math:`\Pi \subseteq N`; it may extend
to :math:`j` only if :math:`j \notin \Pi`, and then :math:`\Pi' = (\Pi \cap N_j) \cup
\{j\}`. Revisiting a KPOI is allowed once the route has "forgotten" it (moved to KPOIs
whose neighbourhoods do not contain it); such a walk counts the KPOI's prize once per
visit (:math:`a_{ir}` visits).

Labelling (exact)
-----------------
A label is ``(node j, length l, prize p, memory Pi)``, the end of a partial route.
Labels are extended in order of increasing length (a binary heap). A label ``e``
*dominates* ``f`` at the same node when :math:`l_e \le l_f`, :math:`p_e \ge p_f` and
:math:`\Pi_e \subseteq \Pi_f`: every extension of ``f`` is then an extension of ``e`` with
no smaller prize and no longer length, so ``f`` is dropped (Baldacci et al., section 4).
A label at ``j`` is feasible while :math:`l + r_j \le U`, with :math:`r_j = d_{j0}` for
tours (the way home) and 0 for paths; every feasible label is a route ending at ``j``
unless branching forbids ending there.

Labelling both ways
-------------------
The exact labelling runs forward from the start and backward from the ends (the routes
reversed: from a virtual start over the way home :math:`r_j` to the last KPOI, the arcs
reversed, home over the first arc), each extending only labels no longer than
:math:`U/2`, and joins a forward label ``f`` at ``i`` to a backward label ``b`` at ``j``
over an allowed arc when :math:`l_f + d_{ij} + l_b \le U` and :math:`\Pi_f \cap \Pi_b =
\emptyset` (Righini and Salani 2006, Discrete Optimization 3; with ng-memories Baldacci et
al., section 4). Every route ``0, v_1, ..., v_n`` is found: at its last ``v_k`` whose
prefix is at most :math:`U/2` long, the prefix label was extended and the suffix from
:math:`v_{k+1}` is shorter than :math:`U/2`, so its backward label was too: a join (``k``
= 0: a backward route; ``k \ge n - 1``: a forward route). Dominance on either side keeps
this (a dominating label joins the same partner with no smaller prize, its memory a subset),
and a walk with a cycle the memories forbid is never joined (the KPOI is in both memories),
so the growing of the neighbourhoods below still ends. A cut's count along a route is the
sum over its runs within the cut's memory of half their visits to the triple, rounded
down, the same either way along the route; at the join the two halves of one run add one
count when both have an odd number of visits, so a join pays the penalties of the cuts
whose parities are set on both sides. The two halves hold far fewer labels than one
labelling to :math:`U` (their number grows fast with the length): measured on two pricing
calls of 60 KPOIs in rooms, 4 tours, one labelling 980 M -> 193 M units of work (5.0 s ->
2.1 s) and 28.6 G -> 4.7 G (180 s -> 42 s). For tours on a symmetric metric with symmetric
branching the backward labelling is the forward one and runs once.

Completion bounds
-----------------
A label whose prize plus an upper bound on what its completion can still collect is at
most the best prize known (at least the threshold 1) cannot lead to a better route and is
pruned. The bound :math:`g(b, j)` is the largest prize of a *walk* from ``j`` without
2-cycles (no ``u -> v -> u``; other repetitions allowed) whose discretised length is at
most ``b``: with a grid step :math:`\delta`,
:math:`d'_{ij} = \lfloor d_{ij}/\delta \rfloor`, :math:`r'_j = \lfloor r_j/\delta \rfloor`,

.. math::
    g(b, j) = \max\bigl(0 \text{ if } r'_j \le b,\;
              \max_{k:\, d'_{jk} \le b} \pi_k + g(b - d'_{jk}, k)\bigr),

a dynamic programme over ``b = 0..G`` (the q-route bound of Christofides, Mingozzi and
Toth 1981 run backwards), where the walk from ``k`` may not go back to ``j`` at once
(each ``(b, k)`` keeps its best walk and the best one through another first step: their
2-cycle elimination). A real completion of length :math:`s` with
:math:`l + s + r \le U` has discretised length at most :math:`\lfloor (U - l)/\delta
\rfloor` (a sum of floors is at most the floor of the sum), so :math:`g` bounds every
completion whose KPOIs are distinct and differ from ``j``: every tail of an elementary
route. That is all the certificate needs: a label on the way to an elementary route ``R``
is kept, or pruned because ``R`` cannot beat the best prize, or dominated by a label
that reaches at least ``R``'s prize with ``R``'s tail, to which the same holds. So the
best prize found is at least every elementary route's (ng-routes with 2-cycles may be
pruned; measured: fewest tours within 2 c_max, n = 50, one exact pricing 7.9 s -> 2.0 s).
The same table bounds whole routes: :math:`\max_j \pi_j + g(b_j, j)` over the first KPOIs
is at least every elementary route's prize (:func:`walk_bound`), which certifies Farley's
bound after a heuristic call too (:attr:`PricingResult.prize_bound`). The grid needs :math:`d'_{ij} \ge 1` for all arcs (no
zero-length cycles), i.e. :math:`\delta` at most the smallest distance; when that would
need more than ``MAX_GRID`` steps, no completion bound is used (still exact, slower).

Subset-row cuts
---------------
With cuts (:func:`cut_coefficients`) a label also carries one parity bit per cut; a
visit to a cut's triple with the bit set costs the cut's dual, and ``e`` dominates ``f``
only if :math:`p_e` minus the duals of the cuts where ``e``'s bit is set and ``f``'s is
not is still at least :math:`p_f` (Jepsen et al. 2008). The completion bound ignores the
cuts, which only lower prizes, so it stays an upper bound.

Growing the neighbourhoods (decremental state-space relaxation)
---------------------------------------------------------------
The exact labelling remembers only part of each neighbourhood, :math:`\Pi_i \subseteq
N_i`, starting from :math:`\{i\}` (:data:`DSSR_START`): fewer memories, more dominance,
and every ng-route is still a :math:`\Pi`-route, so its best prize bounds theirs. When
the best route found has a cycle the :math:`N_i` forbid (KPOI :math:`v` visited twice
and in the neighbourhood of every KPOI between), :math:`v` is added to the
:math:`\Pi` of those KPOIs and the labelling runs again, until the best route is an
ng-route (then its prize is at least every elementary route's) or no route beats the threshold
(Righini and Salani 2008, Networks 51; with ng-routes Martinelli, Pecin and Poggi 2014,
Oper. Res. Letters 42). The :math:`\Pi` grow over the whole search. Each complete
labelling's best prize bounds every elementary route's, so when the clock stops a later
one, the last complete one still certifies Farley's bound (:attr:`PricingResult.prize_bound`):
in dense rooms the relaxation takes tens of labellings, the last ones the longest. On fewest tours
within 1.2 x 2 c_max, n = 50 (four long tours), the proving pricing did 5-14x less work
(seeds 1 and 3: 0.97 G -> 70 M, 3.3 G -> 0.36 G).

Heuristic pricing
-----------------
With ``exact=False`` dominance ignores the memories (a label with a shorter length and
a larger prize at the same node wins), which keeps few labels per node; the routes it
returns are genuine ng-routes, but it may miss the best one, so its :math:`M` certifies
nothing. Column generation uses it first and the exact labelling only when it finds no
column. Its labels are also tested on arrival against those already extended at their
node (all of them no longer): most are dominated there, and dropping them before the heap
saves its push and pop (the exact dominance, with memories, rarely holds that early).
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numba import objmode

from milp.core.jit import compiled_layout, njit
from milp.core.progress import Every
from milp.core.timelimit import stop_requested

log = logging.getLogger(__name__)

__all__ = ["Pricing", "PricingResult", "cut_coefficients", "ng_neighbourhoods", "NG_SIZE", "MAX_GRID", "MAX_CUTS",
           "KERNELS", "CUT_KERNELS"]

#: Neighbourhood size of the ng-relaxation (KPOI itself included); Baldacci et al. use 8.
NG_SIZE = 16
#: The exact labelling starts from neighbourhoods of this size and grows them where its
#: best routes have cycles the full ng-neighbourhoods forbid (decremental state-space
#: relaxation, module docstring).
DSSR_START = 1
#: Most grid steps of the completion bound.
MAX_GRID = 4000
#: The heuristic dominance drops a label when more than this many labels already extended
#: at its node (each shorter) have at least its prize and the first this many do not
#: dominate it (their cut parities may cost them more than it): scanning on costs more
#: than the label is worth (with many cuts a label was compared with thousands; the
#: measurements are in milp/README.md).
HEURISTIC_SCAN = 16
#: The labelling reads the clock after this much work (labels, dominance tests, candidates).
CLOCK_EVERY = 20_000
#: Bits of a ``uint64`` word: KPOI sets (neighbourhoods, memories) are rows of such words,
#: KPOI ``j`` bit ``j % WORD`` of word ``j // WORD``.
WORD = 64
#: Most joins of the bidirectional labelling held at once (:func:`_join`); when full, only
#: the best ``max_routes`` are kept.
JOINS_HELD = 1 << 14
#: Most subset-row cuts the pricing handles: one bit of a ``uint64`` word each (``cut_bits``,
#: ``cut_memory``, a label's parity).
MAX_CUTS = WORD
#: The grid step is the shortest distance shrunk by this relative margin, so that round-off
#: in ``d / delta`` cannot floor the shortest arc to 0 grid steps (a zero-length cycle).
GRID_MARGIN = 1e-9
#: The budget left, in grid steps, is enlarged by this relative amount before it is floored,
#: so that a completion using the budget exactly is not lost to round-off in the division.
BUDGET_ROUND = 1e-12


@dataclass
class PricingResult:
    """What one pricing call found.

    Attributes
    ----------
    best : float
        The largest route prize found; with ``exact`` and ``complete`` it is the largest
        prize of every ng-route within the budget, or ``threshold`` when none exceeds it.
    routes : list of numpy.ndarray
        Routes (KPOIs in visiting order, no 0) with prize above the threshold, best first.
    exact : bool
        Whether ``best`` is certified (exact dominance and the label limit not reached).
    work : int
        Labels created, dominance tests made and extension candidates looked at.
    prize_bound : float
        An upper bound on the prize (less cut penalties) of every elementary route within
        the budget, certified whatever ``exact`` says, so Farley's bound with it holds after
        a heuristic call, or an exact one the clock stopped, too: the completion table's
        (:func:`walk_bound`; ``inf`` without a grid), or, when lower, the least best prize
        of the complete exact labellings (the decremental relaxation's labellings each
        bound every elementary route: module docstring).
    """

    best: float
    routes: list[np.ndarray]
    exact: bool
    work: int
    prize_bound: float = math.inf


def _bits(words: np.ndarray, count: int) -> np.ndarray:
    """The first ``count`` bits of a row of ``uint64`` words, as bools."""
    return np.unpackbits(words.view(np.uint8), bitorder="little")[:count].astype(bool)


def ng_neighbourhoods(D: np.ndarray, size: int = NG_SIZE) -> np.ndarray:
    """Bit masks of the ng-neighbourhoods: row ``i`` holds ``i`` and its ``size - 1``
    nearest KPOIs (row 0, the start, is empty). Shape ``(m+1, words)``, ``uint64``."""
    m = len(D) - 1
    words = m // WORD + 1
    masks = np.zeros((m + 1, words), dtype=np.uint64)
    for i in range(1, m + 1):
        others = np.argsort(D[i, 1:], kind="stable")[:size] + 1
        for j in {i, *others.tolist()}:
            masks[i, j // WORD] |= np.uint64(1) << np.uint64(j % WORD)
    return masks


class Pricing:
    """Pricing over ng-routes for one distance matrix and route kind.

    Parameters
    ----------
    D : numpy.ndarray
        ``(m+1, m+1)`` metric with every off-diagonal distance positive (merge zero
        distances first, :func:`milp.core.merge.merge_zero_distances`).
    tours : bool
        Tours (the budget includes the way back) or paths.
    ng_size : int
        Neighbourhood size of the ng-relaxation.
    """

    def __init__(self, D: np.ndarray, *, tours: bool, ng_size: int = NG_SIZE) -> None:
        self.D = compiled_layout(D, np.float64)
        self.m = len(D) - 1
        self.back = self.D[:, 0].copy() if tours else np.zeros(self.m + 1)
        self.neighbourhoods = ng_neighbourhoods(self.D, ng_size)
        self.neighbours = [set(np.flatnonzero(_bits(row, self.m + 1)).tolist()) for row in self.neighbourhoods]
        # the part of each neighbourhood the exact labelling remembers (grown by _forbid)
        self.remembered = self.neighbourhoods & ng_neighbourhoods(self.D, min(DSSR_START, ng_size))
        off = self.D[~np.eye(self.m + 1, dtype=bool)]
        self.shortest = float(off.min()) if off.size else 1.0
        # the routes walked backwards (module docstring, labelling both ways): from a virtual
        # start over the way home r_j to the last KPOI, then the arcs reversed, and home
        # over the first arc 0 -> i
        self.reversed_D = self.D.T.copy()
        self.reversed_D[0, :] = self.back
        self.reversed_back = self.D[0, :].copy()
        #: Tours on a symmetric metric: a route walked backwards is a tour of the same
        #: instance, so the backward labelling is the forward one (when branching is symmetric too).
        self.symmetric = tours and bool(np.array_equal(self.D, self.D.T))

    def price(
        self,
        prize: np.ndarray,
        budget: float,
        *,
        allowed: np.ndarray,
        can_end: np.ndarray,
        exact: bool,
        threshold: float = 1.0,
        max_routes: int = 60,
        ends_at: float = math.inf,
        cut_bits: np.ndarray | None = None,
        cut_memory: np.ndarray | None = None,
        penalties: np.ndarray | None = None,
        on_prize_bound: Callable[[float], None] | None = None,
    ) -> PricingResult:
        """Routes within ``budget`` with prize above ``threshold``, and the largest prize.

        Parameters
        ----------
        prize : numpy.ndarray
            ``(m+1,)`` non-negative prizes, ``prize[0] = 0``.
        budget : float
            Largest route length ``U`` (tolerance already applied by the caller).
        allowed : numpy.ndarray
            ``(m+1, m+1)`` bool, arcs the routes may use (branching), row 0 the first arcs.
        can_end : numpy.ndarray
            ``(m+1,)`` bool, KPOIs a route may end at (for tours: arcs back to 0 allowed).
        exact : bool
            Exact dominance (certified ``best``) or the faster heuristic one.
        threshold : float
            Only routes with a larger prize are returned.
        max_routes : int
            At most this many routes, the most valuable first.
        ends_at : float
            A ``time.perf_counter()`` value: the labelling stops there (checked every
            :data:`CLOCK_EVERY` units of work), and ``best`` is then not
            certified.
        cut_bits : numpy.ndarray, optional
            ``(m+1,)`` ``uint64``: bit ``t`` of ``cut_bits[j]`` is set when KPOI ``j`` is in the
            triple of subset-row cut ``t`` (at most :data:`MAX_CUTS` cuts).
        cut_memory : numpy.ndarray, optional
            ``(m+1,)`` ``uint64``: bit ``t`` of ``cut_memory[j]`` is set when KPOI ``j`` is in
            the memory of cut ``t`` (limited-memory cuts, :func:`cut_coefficients`).
        penalties : numpy.ndarray, optional
            ``(MAX_CUTS,)`` non-negative: a route loses ``penalties[t]`` of prize each time
            :func:`cut_coefficients` counts a pair for cut ``t`` (minus the cut's dual).
        on_prize_bound : callable, optional
            Called, during an exact pricing, with the bound on every elementary route's
            prize that each complete labelling certifies (the value
            :attr:`PricingResult.prize_bound` would have if the pricing stopped there), so
            that a caller can use it before a long pricing ends.
        """
        prize, allowed, can_end = (compiled_layout(prize, np.float64), compiled_layout(allowed, np.bool_),
                                   compiled_layout(can_end, np.bool_))
        if cut_bits is None:
            cut_bits, cut_memory = np.zeros(self.m + 1, dtype=np.uint64), np.zeros(self.m + 1, dtype=np.uint64)
            penalties = np.zeros(MAX_CUTS)
        grid = grid_step(budget, self.shortest)
        delta, G = grid if grid is not None else (1.0, 0)
        table = self._completion_table(self.D, self.back, prize, allowed, can_end, grid, ends_at)
        if table is None:  # the clock stopped it
            return PricingResult(float(threshold), [], False, 0)
        prize_bound = walk_bound(self.D, prize, allowed, table, delta, G, budget, self.back, can_end)
        prizes = Prizes(prize, cut_bits, cut_memory, penalties)
        if not exact:
            labels = Labels(*_label(Arcs(self.D, self.back, allowed, can_end, self.neighbourhoods), prizes,
                                    Budget(budget, table, delta, G, budget), threshold, False, ends_at))
            routes = [_trace(int(labels.ends[r, 0]), labels.parents, labels.nodes)
                      for r in most_valuable(labels.ends[:, 1], max_routes)]
            return PricingResult(float(labels.best), routes, False, int(labels.work), prize_bound)
        backward = self._backward(prize, allowed, can_end, grid, ends_at)
        if backward is None:
            return PricingResult(float(threshold), [], False, 0, prize_bound)
        forward = Arcs(self.D, self.back, allowed, can_end, self.remembered)
        total, labellings, progress = 0, 0, Every(log)
        while True:
            best, routes, work, complete = self._label_both_ways(
                forward, backward, prizes, Budget(budget, table, delta, G, budget / 2), threshold, max_routes, ends_at)
            total += work
            if complete:  # a relaxation of the elementary routes, labelled to the end
                prize_bound = min(prize_bound, best)
                if on_prize_bound is not None:
                    on_prize_bound(prize_bound)
            labellings += 1
            if progress.due():
                log.info("exact pricing: %d labellings so far (ng-memories growing), best route prize %.6g "
                         "(at most 1: no column left), %.0f M units of work", labellings, best, total / 1e6)
            forbidden = [self._forbid(r) for r in routes]
            if not routes or not forbidden[0] or not complete:
                # the best route is an ng-route: its prize is the best of every ng-route
                kept = [r for r, f in zip(routes, forbidden) if not f]
                return PricingResult(best, kept, complete, int(total), prize_bound)

    def _completion_table(self, D: np.ndarray, back: np.ndarray, prize: np.ndarray, allowed: np.ndarray,
                          can_end: np.ndarray, grid: tuple[float, int] | None, ends_at: float) -> np.ndarray | None:
        """The completion bound ``g`` on the grid (module docstring) for routes on ``D``,
        a table of ``inf`` without a grid, None when the clock stopped it."""
        if grid is None:
            return np.full((1, self.m + 1), np.inf)
        delta, G = grid
        return completion_table(np.floor(D / delta).astype(np.int64), np.floor(back / delta).astype(np.int64),
                                prize, allowed, can_end, G, ends_at)

    def _backward(self, prize: np.ndarray, allowed: np.ndarray, can_end: np.ndarray,
                  grid: tuple[float, int] | None, ends_at: float) -> tuple[Arcs, np.ndarray] | tuple[()] | None:
        """What the backward labelling walks on, with its completion table; ``()`` when it
        is the forward labelling (:attr:`symmetric`, branching symmetric too); None when the
        clock stopped the table.

        Backwards, the first arcs are the ends allowed (``can_end``), an arc ``j -> i`` is
        allowed when ``i -> j`` is, and a route may end at the KPOIs the start may go to."""
        if (self.symmetric and np.array_equal(allowed[1:, 1:], allowed[1:, 1:].T)
                and np.array_equal(allowed[0, 1:], can_end[1:])):
            return ()
        reversed_allowed = allowed.T.copy()
        reversed_allowed[0, :] = can_end
        reversed_can_end = allowed[0, :].copy()
        table = self._completion_table(self.reversed_D, self.reversed_back, prize, reversed_allowed,
                                       reversed_can_end, grid, ends_at)
        if table is None:
            return None
        return Arcs(self.reversed_D, self.reversed_back, reversed_allowed, reversed_can_end, self.remembered), table

    def _label_both_ways(self, forward: Arcs, backward: tuple[Arcs, np.ndarray] | tuple[()], prizes: Prizes,
                         budget: Budget, threshold: float, max_routes: int,
                         ends_at: float) -> tuple[float, list[np.ndarray], int, bool]:
        """One exact labelling both ways (module docstring): ``(best, routes, work, complete)``,
        the ``max_routes`` most valuable routes of the forward ends, the backward ends
        (reversed) and the joins, without repeats."""
        ahead = Labels(*_label(forward, prizes, budget, threshold, True, ends_at))
        if backward:
            arcs, table = backward
            behind = Labels(*_label(arcs, prizes, budget._replace(table=table), threshold, True, ends_at))
        else:
            behind = ahead
        best, pairs, values, work, joined = _join(_halves(ahead), _halves(behind), forward.D, forward.allowed,
                                                  budget.U, threshold, max_routes, prizes.penalties, ends_at)
        found = [(float(ahead.ends[r, 1]), _trace(int(ahead.ends[r, 0]), ahead.parents, ahead.nodes))
                 for r in most_valuable(ahead.ends[:, 1], max_routes)]
        if backward:
            found += [(float(behind.ends[r, 1]), _trace(int(behind.ends[r, 0]), behind.parents, behind.nodes)[::-1])
                      for r in most_valuable(behind.ends[:, 1], max_routes)]
        found += [(float(values[r]), np.concatenate((_trace(int(pairs[r, 0]), ahead.parents, ahead.nodes),
                                                     _trace(int(pairs[r, 1]), behind.parents, behind.nodes)[::-1])))
                  for r in most_valuable(values, max_routes)]
        routes, seen = [], set()
        for value, route in sorted(found, key=lambda vr: -vr[0]):
            key = tuple(route.tolist())
            if self.symmetric:  # a tour walked backwards is the same column
                key = min(key, key[::-1])
            if key not in seen and len(routes) < max_routes:
                seen.add(key)
                routes.append(route)
        best = max(float(ahead.best), float(behind.best), float(best))
        complete = bool(ahead.complete and behind.complete and joined)
        return best, routes, int(ahead.work + (behind.work if backward else 0) + work), complete

    def _forbid(self, route: np.ndarray) -> bool:
        """Whether ``route`` has a cycle the ng-neighbourhoods forbid; if so, remember
        each such cycle's KPOI along it from now on (so the labelling forbids it too).

        A KPOI ``v`` visited at positions ``p < q`` closes a forbidden cycle when ``v``
        is in the neighbourhood of every KPOI visited in between (the memory kept it).
        """
        memory: set[int] = set()
        seen: dict[int, int] = {}
        forbidden = False
        for q, v in enumerate(route.tolist()):
            if v in memory:
                forbidden = True
                for u in route[seen[v] + 1:q].tolist():
                    self.remembered[u, v // WORD] |= np.uint64(1) << np.uint64(v % WORD)
            memory = (memory & self.neighbours[v]) | {v}
            seen[v] = q
        return forbidden


def walk_bound(D: np.ndarray, prize: np.ndarray, allowed: np.ndarray, table: np.ndarray, delta: float,
               G: int, budget: float, back: np.ndarray, can_end: np.ndarray) -> float:
    r"""An upper bound on the prize of every elementary route within ``budget`` (cut
    penalties, which only lower prizes, ignored), read off the completion table:
    :math:`\max_j \pi_j + g(b_j, j)` over the first KPOIs ``j`` the node allows, with
    :math:`b_j` the grid steps left after the first arc (``inf`` without a grid).

    Proof: an elementary route ``0 -> j -> tail`` collects :math:`\pi_j` and its tail's
    prizes; the tail is a tail of an elementary route from ``j``, within the length left,
    which :math:`g` bounds (module docstring, completion bounds), read with the same
    rounding as :func:`_completion`. Routes of one KPOI (no tail) are bounded by
    :math:`\pi_j + 0`, and :math:`g \ge 0` wherever the route may end. So Farley's bound
    :math:`\sum_i \pi_i / \max(M, 1)` with this :math:`M` is certified after any pricing
    call, heuristic ones included (the elementary routes are all the certificate needs,
    as for the exact labelling's pruning).
    """
    if G == 0:
        return math.inf
    best = 0.0
    for j in range(1, len(D)):
        if not allowed[0, j] or D[0, j] + back[j] > budget:
            continue
        rest = _completion(table, delta, G, budget, D[0, j], j)
        if rest == -np.inf:
            continue
        best = max(best, float(prize[j] + rest))
    return best


def grid_step(budget: float, shortest: float) -> tuple[float, int] | None:
    """``(delta, G)`` of the completion bound, or None when the grid would be too fine."""
    if budget <= 0 or shortest <= 0:
        return None
    delta = shortest / (1.0 + GRID_MARGIN)
    G = int(math.floor(budget / delta)) + 1
    if G > MAX_GRID:
        return None
    return delta, G


def most_valuable(values: np.ndarray, count: int) -> np.ndarray:
    """Indices of the ``count`` largest ``values``, largest first, ties in index order
    (as a stable sort of all of them would give). Selects before sorting: a heuristic
    labelling stopped by the clock can hold millions of route ends, and sorting them all
    ran past the time limit."""
    if len(values) <= count:
        return np.argsort(-values, kind="stable")
    kth = np.partition(values, len(values) - count)[len(values) - count]
    chosen = np.flatnonzero(values >= kth)  # in index order
    return chosen[np.argsort(-values[chosen], kind="stable")][:count]


def _halves(labels: Labels) -> tuple[np.ndarray, ...]:
    """The fields of a labelling :func:`_join` reads."""
    return labels.nodes, labels.lengths, labels.values, labels.memory, labels.parity, labels.extended


def _trace(label: int, parents: np.ndarray, nodes: np.ndarray) -> np.ndarray:
    """The KPOIs from the start to ``label``, in order."""
    out = []
    while parents[label] >= 0:
        out.append(int(nodes[label]))
        label = int(parents[label])
    return np.array(out[::-1], dtype=np.int64)


def read_clock() -> float:
    """The time the compiled loops compare with their end (``time.perf_counter()``), or
    ``inf`` once the thread was asked to stop (:func:`milp.core.timelimit.stop_requested`:
    a race's other entrant proved the answer), so that a pricing stops within one clock
    check of the request rather than at its end."""
    return math.inf if stop_requested() else time.perf_counter()


@njit(cache=True)
def clock_passed(ends_at):  # pragma: no cover - compiled
    """Whether :func:`read_clock` has reached ``ends_at``: the one clock check the compiled
    loops make (every :data:`CLOCK_EVERY` steps or so)."""
    with objmode(now="float64"):
        now = read_clock()
    return now >= ends_at


@njit(cache=True)
def completion_table(dd, back, prize, allowed, can_end, G, ends_at):  # pragma: no cover - compiled
    """``g(b, j)`` of the module docstring for ``b = 0..G`` (``-inf``: cannot end), over
    walks without 2-cycles, or None when the clock passes ``ends_at`` first (read every
    :data:`CLOCK_EVERY` steps).

    Each ``(b, j)`` keeps its best value, the KPOI that walk goes to next (0: it ends),
    and the best value through another next KPOI; a walk from ``j`` to ``k`` then uses
    ``k``'s best unless that returns to ``j`` at once, else ``k``'s second (Christofides,
    Mingozzi and Toth 1981)."""
    m1 = dd.shape[0]
    table = np.full((G + 1, m1), -np.inf)
    second = np.full((G + 1, m1), -np.inf)
    after = np.zeros((G + 1, m1), np.int64)  # next KPOI of the best walk (0: it ends)
    work = 0
    for b in range(G + 1):
        work += m1 * m1
        if work >= CLOCK_EVERY:
            work = 0
            if clock_passed(ends_at):
                return None
        for j in range(1, m1):
            best = 0.0 if (can_end[j] and back[j] <= b) else -np.inf
            nxt = 0
            other = -np.inf
            for k in range(1, m1):
                if k == j or not allowed[j, k]:
                    continue
                c = dd[j, k]
                if c <= b:
                    v = table[b - c, k] if after[b - c, k] != j else second[b - c, k]
                    if v == -np.inf:
                        continue
                    v += prize[k]
                    if v > best:
                        other, best, nxt = best, v, k
                    elif v > other:
                        other = v
            table[b, j], second[b, j], after[b, j] = best, other, nxt
    return table


class Arcs(NamedTuple):
    """What the labelling walks on (one pricing call)."""

    #: ``(m+1, m+1)`` distances, every off-diagonal one positive.
    D: np.ndarray
    #: ``(m+1,)`` :math:`r_j`: the way home from ``j`` (tours) or 0 (paths).
    back: np.ndarray
    #: ``(m+1, m+1)`` bool: the arcs branching leaves (row 0: the first arcs).
    allowed: np.ndarray
    #: ``(m+1,)`` bool: the KPOIs a route may end at.
    can_end: np.ndarray
    #: ``(m+1, words)`` ``uint64``: the part of each ng-neighbourhood the labels remember
    #: (:attr:`Pricing.remembered` or :attr:`Pricing.neighbourhoods`).
    neighbourhoods: np.ndarray


class Prizes(NamedTuple):
    """What a route collects: KPOI prizes less the penalties of subset-row cuts."""

    #: ``(m+1,)`` non-negative, ``prize[0] = 0``.
    prize: np.ndarray
    #: ``(m+1,)`` ``uint64``: bit ``t`` set when the KPOI is in cut ``t``'s triple.
    cut_bits: np.ndarray
    #: ``(m+1,)`` ``uint64``: bit ``t`` set when the KPOI is in cut ``t``'s memory.
    cut_memory: np.ndarray
    #: ``(MAX_CUTS,)`` non-negative: the prize a route loses each time cut ``t`` counts.
    penalties: np.ndarray


class Budget(NamedTuple):
    """The length budget and the completion bound over it (module docstring)."""

    #: Largest route length :math:`U`.
    U: float
    #: ``g(b, j)`` for ``b = 0..G`` (:func:`completion_table`); unused when ``G`` is 0.
    table: np.ndarray
    #: Grid step :math:`\delta`.
    delta: float
    #: Grid steps; 0: no completion bound.
    G: int
    #: Labels longer than this are not extended (bidirectional labelling: :math:`U/2`;
    #: :math:`U` otherwise), though they still end routes.
    half: float


class Labels(NamedTuple):
    """What one labelling (:func:`_label`) leaves: its routes and its labels."""

    #: The largest route prize found (at least the threshold).
    best: float
    #: Rows ``(label, prize)`` of the routes found above the threshold.
    ends: np.ndarray
    #: Per label: the label it extends (-1: the start's) and its node.
    parents: np.ndarray
    nodes: np.ndarray
    #: Per label: length, prize (less cut penalties), memory (``uint64`` words), cut parities.
    lengths: np.ndarray
    values: np.ndarray
    memory: np.ndarray
    parity: np.ndarray
    #: Per label: whether it left the heap undominated and was extended (labels longer
    #: than :attr:`Budget.half` never are); only these are joined.
    extended: np.ndarray
    #: Labels created, dominance tests made and extension candidates looked at.
    work: int
    #: False when the clock stopped it.
    complete: bool


@njit(cache=True)
def _subset(a, b):  # pragma: no cover - compiled
    """Whether bit set ``a`` is contained in ``b`` (arrays of uint64 words)."""
    for w in range(a.shape[0]):
        if a[w] & ~b[w]:
            return False
    return True


@njit(cache=True)
def _completion(table, delta, G, U, length, j):  # pragma: no cover - compiled
    """``g`` at the budget left after ``length`` (``-inf``: the route cannot end)."""
    if G == 0:
        return np.inf
    b = int(math.floor((U - length) / delta * (1.0 + BUDGET_ROUND))) + 1
    if b < 0:
        return -np.inf
    return table[min(b, G), j]


@njit(cache=True)
def _penalty(penalties, bits):  # pragma: no cover - compiled
    """Sum of ``penalties[t]`` over the set bits ``t`` of ``bits``."""
    total = 0.0
    t = 0
    while bits:
        if bits & np.uint64(1):
            total += penalties[t]
        bits >>= np.uint64(1)
        t += 1
    return total


@njit(cache=True)
def _dominated_on_arrival(vals, labs, filled, value, parity, bits, penalties):  # pragma: no cover - compiled
    """Whether a new label of prize ``value`` and parities ``bits`` is dominated, with
    the heuristic's dominance (memories ignored), by a label already extended at its
    node (``vals``, ``labs``: by decreasing prize; each is no longer than the new one, as
    labels leave the heap by increasing length). It would be dropped when it leaves the
    heap anyway; testing on arrival saves the heap its push and pop (measured on rat99
    with 7 tours: most heuristic labels are dominated, calls 15-35% faster). The exact
    dominance rarely holds this early (memories), so it is tested on leaving only. At most
    :data:`HEURISTIC_SCAN` labels are looked at: a label behind more is dropped."""
    k = 0
    while k < filled and vals[k] >= value:
        if k == HEURISTIC_SCAN:
            return True
        odd = parity[labs[k]] & ~bits
        if not odd or vals[k] - _penalty(penalties, odd) >= value:
            return True
        k += 1
    return False


@njit(cache=True)
def _insert(vals, labs, filled, k, value, label):  # pragma: no cover - compiled
    """Insert ``(value, label)`` at position ``k`` of the ``filled`` entries of ``vals``,
    ``labs`` (room for one more assumed), shifting those from ``k`` on by one; the new
    count. At ``k``, the first with a smaller prize, the prizes stay decreasing."""
    for q in range(filled, k, -1):
        vals[q], labs[q] = vals[q - 1], labs[q - 1]
    vals[k], labs[k] = value, label
    return filled + 1


@njit(cache=True)
def _heap_push(keys, labels, size, key, label):  # pragma: no cover - compiled
    """Push ``(key, label)`` on the binary min-heap held in ``keys[:size]``,
    ``labels[:size]`` (room for one more assumed); the new size."""
    pos = size
    while pos > 0:
        up = (pos - 1) // 2
        if keys[up] <= key:
            break
        keys[pos], labels[pos] = keys[up], labels[up]
        pos = up
    keys[pos], labels[pos] = key, label
    return size + 1


@njit(cache=True)
def _heap_pop(keys, labels, size):  # pragma: no cover - compiled
    """Pop the label of the least key from the heap of :func:`_heap_push` (``size > 0``):
    ``(label, new size)``; the last entry sifts down from the root."""
    top = labels[0]
    size -= 1
    if size > 0:
        key, label = keys[size], labels[size]
        pos = 0
        while True:
            child = 2 * pos + 1
            if child >= size:
                break
            if child + 1 < size and keys[child + 1] < keys[child]:
                child += 1
            if keys[child] >= key:
                break
            keys[pos], labels[pos] = keys[child], labels[child]
            pos = child
        keys[pos], labels[pos] = key, label
    return top, size


@njit(cache=True)
def _label(arcs, prizes, budget, threshold, exact, ends_at):  # pragma: no cover - compiled
    """Labelling from the start of ``arcs`` (module docstring; backward: on the reversed
    arcs), extending labels no longer than ``budget.half``. Returns the fields of
    :class:`Labels`: the best prize, route ends above ``threshold``, and every label kept
    (parent, node, length, prize, memory, parities, whether it was extended), for
    :func:`_join`.

    The arguments are grouped (:class:`Arcs`, :class:`Prizes`, :class:`Budget`) and unpacked
    here; the heap is :func:`_heap_push` and :func:`_heap_pop`, the insertion of an
    extended label :func:`_insert`; the extension loop and the dominance scan stay in this
    function (``milp/README.md``: as functions they cost more).

    Labels are created on extension and tested for dominance when they leave the heap:
    every label at the same node with a smaller length has left it before, so the test
    runs against those already extended only, kept per node by decreasing prize (only a
    prefix can dominate). ``work`` counts labels, dominance tests and the candidates of
    each extension; every :data:`CLOCK_EVERY` of them the clock is read, and at
    ``ends_at`` the labelling stops (``complete`` False).
    """
    D, back, allowed, can_end, neighbourhoods = arcs
    prize, cut_bits, cut_memory, penalties = prizes
    U, table, delta, G, half = budget
    m1 = D.shape[0]
    W = neighbourhoods.shape[1]
    cap = 1024
    node = np.empty(cap, np.int64)
    length = np.empty(cap)
    value = np.empty(cap)
    memory = np.zeros((cap, W), np.uint64)
    parity = np.zeros(cap, np.uint64)  # bit t: an odd number of visits to cut t's triple
    parent = np.empty(cap, np.int64)
    extended = np.zeros(cap, np.bool_)
    # labels already extended, per node, by decreasing prize
    done = [np.empty(8, np.int64) for _ in range(m1)]
    done_value = [np.empty(8) for _ in range(m1)]
    fill = np.zeros(m1, np.int64)
    # binary heap of (length, label)
    hkey = np.empty(cap)
    hval = np.empty(cap, np.int64)
    ends_label = np.empty(64, np.int64)
    ends_value = np.empty(64)
    nends = 0

    node[0], length[0], value[0], parent[0] = 0, 0.0, 0.0, -1
    count = 1
    hkey[0], hval[0], hsize = 0.0, 0, 1
    best = threshold
    work = 0
    clock = CLOCK_EVERY
    complete = True

    while hsize > 0:
        if work >= clock:
            clock = work + CLOCK_EVERY
            if clock_passed(ends_at):
                complete = False
                break
        lab, hsize = _heap_pop(hkey, hval, hsize)
        i, li, vi = node[lab], length[lab], value[lab]
        if lab > 0:
            if vi + _completion(table, delta, G, U, li, i) <= best:
                continue  # cannot beat the best route any more
            # dominance: an extended label at i with prize >= vi and memory within ours
            dominated = False
            vals, labs = done_value[i], done[i]
            k = 0
            while k < fill[i] and vals[k] >= vi:
                if not exact and k == HEURISTIC_SCAN:
                    dominated = True
                    break
                work += 1
                e = labs[k]
                # e's odd parities that ours lacks may cost e a penalty ours does not pay
                odd = parity[e] & ~parity[lab]
                if (not odd or vals[k] - _penalty(penalties, odd) >= vi) and (
                        not exact or _subset(memory[e], memory[lab])):
                    dominated = True
                    break
                k += 1
            if dominated:
                continue
            if fill[i] == labs.shape[0]:
                done[i] = enlarged(labs, 2 * fill[i])
                done_value[i] = enlarged(vals, 2 * fill[i])
            fill[i] = _insert(done_value[i], done[i], fill[i], k, vi, lab)
            work += fill[i] - k
        extended[lab] = True
        work += m1  # the extension loop below looks at every node
        for j in range(1, m1):
            if j == i or not allowed[i, j]:
                continue
            word, bit = j // WORD, np.uint64(1) << np.uint64(j % WORD)
            if memory[lab, word] & bit:
                continue
            nl = li + D[i, j]
            if nl + back[j] > U:
                continue
            nv = vi + prize[j]
            kept = parity[lab] & cut_memory[j]
            hit = cut_bits[j] & kept
            if hit:
                nv -= _penalty(penalties, hit)
            rest = _completion(table, delta, G, U, nl, j)
            if rest == -np.inf:
                continue
            ends_here = can_end[j] and nv > threshold
            if nv + rest <= best and not ends_here:
                continue
            work += 1
            if count == cap:
                cap *= 2
                node, parent = enlarged(node, cap), enlarged(parent, cap)
                length, value = enlarged(length, cap), enlarged(value, cap)
                hkey, hval = enlarged(hkey, cap), enlarged(hval, cap)
                parity, extended = enlarged(parity, cap), enlarged(extended, cap)
                grown = np.empty((cap, W), np.uint64)  # rows below count are written on use
                grown[:count] = memory[:count]
                memory = grown
            new = count
            count += 1
            node[new], length[new], value[new], parent[new], extended[new] = j, nl, nv, lab, False
            parity[new] = kept ^ cut_bits[j]
            for w in range(W):
                memory[new, w] = memory[lab, w] & neighbourhoods[j, w]
            memory[new, word] |= bit
            if nl <= half and (exact or not _dominated_on_arrival(done_value[j], done[j], fill[j], nv, parity,
                                                                  parity[new], penalties)):
                hsize = _heap_push(hkey, hval, hsize, nl, new)
            elif not ends_here:
                count -= 1  # dropped before it is stored
                continue
            # (a dominated or too long label that ends a route is kept for that route, never extended)
            if ends_here:
                if nends == ends_label.shape[0]:
                    ends_label, ends_value = enlarged(ends_label, 2 * nends), enlarged(ends_value, 2 * nends)
                ends_label[nends], ends_value[nends] = new, nv
                nends += 1
                if nv > best:
                    best = nv
    ends = np.empty((nends, 2))
    for r in range(nends):
        ends[r, 0], ends[r, 1] = ends_label[r], ends_value[r]
    return (best, ends, parent[:count], node[:count], length[:count], value[:count], memory[:count], parity[:count],
            extended[:count], work, complete)


@njit(cache=True)
def _join(forward, backward, D, allowed, U, floor, keep, penalties, ends_at):  # pragma: no cover - compiled
    r"""The routes of the bidirectional labelling that cross the middle (module docstring):
    each extended forward label ``f`` at ``i`` joined over an allowed arc ``i -> j`` to an
    extended backward label ``b`` at ``j`` when :math:`l_f + d_{ij} + l_b \le U` and their
    memories are disjoint, with prize :math:`p_f + p_b` less the cuts whose parity is odd
    on both sides (the two halves of one memory segment: one more pair).

    ``forward``, ``backward``: ``(nodes, lengths, values, memory, parity, extended)`` of the
    two labellings. Returns ``(best, pairs, values, work, complete)``: ``best`` the largest prize
    above ``floor`` (else ``floor``), ``pairs`` rows ``(f, b)`` and ``values`` the prizes of the ``keep`` best joins
    above ``floor`` (at least; when more than :data:`JOINS_HELD` are held, the floor rises
    to the ``keep``-th best prize), ``complete`` False when the clock passed ``ends_at``.
    Backward labels are scanned per node by decreasing prize, so a scan stops at the first
    one whose prize with ``f``'s is at most the floor."""
    fnode, flength, fvalue, fmemory, fparity, fextended = forward
    bnode, blength, bvalue, bmemory, bparity, bextended = backward
    m1 = D.shape[0]
    W = fmemory.shape[1]
    # extended backward labels grouped by node (start[j]..start[j+1]), by decreasing prize
    kept = np.flatnonzero(bextended & (bnode > 0))
    kept = kept[np.argsort(-bvalue[kept], kind="mergesort")]
    start = np.zeros(m1 + 1, np.int64)
    for b in kept:
        start[bnode[b] + 1] += 1
    for j in range(m1):
        start[j + 1] += start[j]
    bucket = np.empty(kept.shape[0], np.int64)
    placed = start[:m1].copy()
    shortest = np.full(m1, np.inf)
    for b in kept:
        j = bnode[b]
        bucket[placed[j]] = b
        placed[j] += 1
        shortest[j] = min(shortest[j], blength[b])
    held_f = np.empty(JOINS_HELD, np.int64)
    held_b = np.empty(JOINS_HELD, np.int64)
    held_v = np.empty(JOINS_HELD)
    held = 0
    best = floor
    work = 0
    clock = CLOCK_EVERY
    complete = True
    for f in range(fnode.shape[0]):
        i = fnode[f]
        if i == 0 or not fextended[f]:
            continue
        if work >= clock:
            clock = work + CLOCK_EVERY
            if clock_passed(ends_at):
                complete = False
                break
        lf, vf = flength[f], fvalue[f]
        work += m1
        for j in range(1, m1):
            if j == i or start[j] == start[j + 1] or not allowed[i, j]:
                continue
            if fmemory[f, j // WORD] & (np.uint64(1) << np.uint64(j % WORD)):
                continue
            if vf + bvalue[bucket[start[j]]] <= floor:
                continue
            room = U - lf - D[i, j]
            if room < shortest[j]:
                continue
            for q in range(start[j], start[j + 1]):
                b = bucket[q]
                if vf + bvalue[b] <= floor:
                    break
                work += 1
                if blength[b] > room:
                    continue
                disjoint = True
                for w in range(W):
                    if fmemory[f, w] & bmemory[b, w]:
                        disjoint = False
                        break
                if not disjoint:
                    continue
                v = vf + bvalue[b] - _penalty(penalties, fparity[f] & bparity[b])
                if v <= floor:
                    continue
                if v > best:
                    best = v
                if held == JOINS_HELD:  # keep the best ``keep``: raise the floor to the keep-th
                    floor = max(floor, np.sort(held_v)[JOINS_HELD - keep])
                    held = 0
                    for r in range(JOINS_HELD):
                        if held_v[r] > floor:
                            held_f[held], held_b[held], held_v[held] = held_f[r], held_b[r], held_v[r]
                            held += 1
                    if v <= floor:
                        continue
                held_f[held], held_b[held], held_v[held] = f, b, v
                held += 1
    pairs = np.empty((held, 2), np.int64)
    for r in range(held):
        pairs[r, 0], pairs[r, 1] = held_f[r], held_b[r]
    return best, pairs, held_v[:held].copy(), work, complete


def cut_coefficients(orders: list[np.ndarray], cut_bits: np.ndarray, cut_memory: np.ndarray,
                     count: int) -> np.ndarray:
    r"""Coefficients of limited-memory subset-row cuts, ``(count, len(orders))``.

    Cut ``t`` has a triple :math:`S_t` (bit ``t`` of ``cut_bits[j]`` for ``j`` in it) and a
    memory :math:`M_t \supseteq S_t` (bit ``t`` of ``cut_memory[j]``). Along a route, a
    parity bit flips at each visit to :math:`S_t` and is forgotten on a visit outside
    :math:`M_t`; each visit to :math:`S_t` with the bit set counts one. The count is at
    most :math:`\lfloor |r \cap S_t| / 2 \rfloor`, so :math:`\sum_r \alpha_{tr}
    \lambda_r \le 1` holds for every partition into elementary routes (Jepsen,
    Petersen, Spoorendonk and Pisinger 2008, Oper. Res. 56; limited memory: Pecin, Pessoa,
    Poggi and Uchoa 2017, Math. Prog. Comp. 9). The labelling applies the same rule.
    """
    flat = np.concatenate(orders) if orders else np.zeros(0, dtype=np.int64)
    starts = np.concatenate(([0], np.cumsum([len(o) for o in orders]))).astype(np.int64)
    return _cut_counts(flat.astype(np.int64), starts, cut_bits, cut_memory, count)


@njit(cache=True)
def _cut_counts(flat, starts, cut_bits, cut_memory, count):  # pragma: no cover - compiled
    out = np.zeros((count, starts.shape[0] - 1))
    for r in range(starts.shape[0] - 1):
        parity = np.uint64(0)
        for p in range(starts[r], starts[r + 1]):
            j = flat[p]
            parity &= cut_memory[j]
            hit = cut_bits[j] & parity
            t = 0
            while hit:
                if hit & np.uint64(1):
                    out[t, r] += 1.0
                hit >>= np.uint64(1)
                t += 1
            parity ^= cut_bits[j]
    return out


@njit(cache=True)
def enlarged(a, size):  # pragma: no cover - compiled
    """``a`` copied into a larger array of ``size`` entries."""
    out = np.empty(size, a.dtype)
    out[: a.shape[0]] = a
    return out


#: The compiled functions only :func:`cut_coefficients` calls: a search without cuts never compiles them.
CUT_KERNELS = (_cut_counts,)
#: Every compiled (numba) function of this module, for :mod:`milp.branchprice.compiling` to check and compile.
KERNELS = (clock_passed, completion_table, _subset, _completion, _penalty, _dominated_on_arrival, _insert, _heap_push,
           _heap_pop, _label, _join, enlarged, *CUT_KERNELS)
