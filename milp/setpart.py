r"""Set partitioning over every subset's cheapest route (Held-Karp), solved by counting.

An exact method independent of :mod:`milp.compact.arcflow` (it shares only the HiGHS plumbing
and input checks).

1. Held-Karp dynamic programme, vectorised over subsets: for each subset :math:`S` of
   KPOIs and each :math:`j \in S`, :math:`f(S, j)` is the cheapest open path from 0
   through exactly :math:`S` ending at :math:`j`:

   .. math::
       f(\{j\}, j) = d_{0j}, \qquad
       f(S, j) = \min_{i \in S \setminus \{j\}} f(S \setminus \{j\}, i) + d_{ij}.

   Path cost :math:`c(S) = \min_j f(S, j)`; tour cost :math:`c(S) = \min_j f(S, j) + d_{j0}`.
   Time :math:`O(2^n n^2)`, memory :math:`O(2^n n)`: ``n <= 20`` (21 M states, 190 MB,
   about 2 s).

2. ``min_robots(U)``: the family :math:`F = \{S : c(S) \le U\}` of routes within the
   deadline. With a metric :math:`D` it is *downward closed* (dropping a KPOI from a
   route never makes it longer: shortcut, triangle inequality), and then ``S`` can be
   split into at most :math:`j` routes of :math:`F` iff :math:`j` members of
   :math:`F` (the empty set included) have union ``S``. Their number is an
   inclusion-exclusion sum over the zeta transform
   :math:`z(R) = |\{T \in F : T \subseteq R\}|` (Bjoerklund, Husfeldt and Koivisto,
   "Set partitioning via inclusion-exclusion", SIAM J. Comput. 39, 2009):

   .. math::
       N_j(S) = \sum_{R \subseteq S} (-1)^{|S \setminus R|} z(R)^j ,

   computed in :math:`O(2^n n)` modulo primes below :math:`2^{31}` (the products fit
   in 64 bits): a nonzero residue proves :math:`N_j > 0`; zero residues modulo primes
   whose product exceeds :math:`z(\{1..n\})^j \ge N_j` prove :math:`N_j = 0`
   (Chinese remainder theorem), so every answer is exact. The fewest robots is the
   least :math:`j` with :math:`N_j(\{1..n\}) > 0`; the routes are recovered one at a
   time (the route through the lowest remaining KPOI whose complement still has
   :math:`N_{j-1} > 0`). When rounding makes :math:`F` not downward closed (a
   non-metric matrix), the set-partitioning MILP decides instead, in HiGHS:

   .. math::
       \min \sum_S y_S \quad \text{s.t.} \quad \sum_{S \ni i} y_S = 1 \quad (i = 1..n).

3. ``min_makespan(k)``: the optimal makespan is one of the distinct route costs
   :math:`c(S)`. Bisection over them, sorted: a value :math:`T` is achievable iff
   ``min_robots(T) <= k`` (:math:`N_k > 0`). The smallest achievable value is the optimum.

Zero distances need no special care here: the dynamic programme enumerates routes
explicitly, so no zero-length cycle can stand in for a route.
"""

from __future__ import annotations

import logging
import math
import time

import highspy
import numpy as np
from scipy import sparse

from milp.core.highs import LpSolve, make_lp, solve_lp
from milp.core.result import MilpResult, relative_gap
from milp.core.routes import check_distance_matrix, check_routes, within
from milp.core.sizes import SETPART_MAX_KPOIS

log = logging.getLogger(__name__)

#: Largest number of KPOIs (:data:`milp.core.sizes.SETPART_MAX_KPOIS`, which says why).
MAX_KPOIS = SETPART_MAX_KPOIS


def expected_seconds(n: int) -> float:
    """About how long a solve takes at ``n`` KPOIs, table and search, on a 2-core shared
    machine: :math:`10^{-8} \\cdot 2^n n^2` s, above the measured 1-4 s at n = 20 and
    0.1-0.25 s at n = 17 (callers with a time limit skip it when less is left)."""
    return 1e-8 * 2**n * n**2


def _primes_below(limit: int, count: int) -> tuple[int, ...]:
    """The ``count`` largest primes below ``limit`` (trial division by the primes up to
    its square root)."""
    root = math.isqrt(limit) + 1
    sieve = np.ones(root + 1, dtype=bool)
    sieve[:2] = False
    for i in range(2, math.isqrt(root) + 1):
        if sieve[i]:
            sieve[i * i::i] = False
    small = np.flatnonzero(sieve)
    found: list[int] = []
    candidate = limit - 1
    while len(found) < count:
        if np.all(candidate % small[small < candidate] != 0):
            found.append(candidate)
        candidate -= 1
    return tuple(found)


#: Moduli of the route counts: residues multiply below 2^62. 32 of them hold counts up to
#: 2^990, above the largest possible, (2^20)^20 (all 20-tuples of subsets of 20 KPOIs).
PRIMES = _primes_below(1 << 31, 32)


class RouteTable:
    """Cheapest path and tour of every non-empty subset of KPOIs (Held-Karp).

    Parameters
    ----------
    D : numpy.ndarray
        ``(n+1, n+1)`` distance matrix, index 0 the start, ``n <= 20``.
    ends_at : float
        A ``time.perf_counter()`` value: :class:`OutOfTime` is raised when the table is
        not done by then (checked at every layer and end KPOI, a few ms apart at n = 20).

    Attributes
    ----------
    n : int
        Number of KPOIs; subset ``S`` is a bit mask, bit ``i - 1`` for KPOI ``i``.
    last : numpy.ndarray
        ``last[S, j]``: cheapest open path from 0 through ``S`` ending at KPOI ``j + 1``
        (``inf`` when ``j + 1`` is not in ``S``).
    parent : numpy.ndarray
        The KPOI index (0-based) before ``j`` on that path, ``-1`` at the first.
    """

    def __init__(self, D: np.ndarray, ends_at: float = math.inf) -> None:
        n = len(D) - 1
        if n > MAX_KPOIS:
            raise ValueError(
                f"set partitioning enumerates all 2^n subsets: n={n} > {MAX_KPOIS} would need "
                f"{2 ** n * n:,} DP states and {2 ** n - 1:,} columns"
            )
        self.D, self.n = D, n
        self.last, self.parent = _held_karp(D[1:, 1:], D[0, 1:], ends_at)

    def costs(self, *, tours: bool) -> np.ndarray:
        """Cost of the cheapest route over each subset (index = mask; ``[0]`` unused)."""
        back = self.D[1:, 0] if tours else np.zeros(self.n)
        return (self.last + back[None, :]).min(axis=1)

    def route(self, mask: int, *, tours: bool) -> list[int]:
        """The cheapest route over subset ``mask`` as KPOI indices ``1..n``."""
        back = self.D[1:, 0] if tours else np.zeros(self.n)
        j = int(np.argmin(self.last[mask] + back))
        order = []
        while j >= 0:
            order.append(j + 1)
            previous = int(self.parent[mask, j])
            mask ^= 1 << j
            j = previous
        return order[::-1]


class OutOfTime(Exception):
    """The Held-Karp table was not finished within the time limit."""


def _held_karp(between: np.ndarray, first: np.ndarray, ends_at: float) -> tuple[np.ndarray, np.ndarray]:
    """Held-Karp tables ``(last, parent)`` layer by layer of subset size."""
    if time.perf_counter() >= ends_at:  # before allocating 2^n x n entries
        raise OutOfTime
    n = len(first)
    masks = np.arange(1 << n)
    size = _popcount(masks)
    last = np.full((1 << n, n), np.inf)
    parent = np.full((1 << n, n), -1, dtype=np.int8)
    singles = 1 << np.arange(n)
    last[singles, np.arange(n)] = first
    for s in range(2, n + 1):
        layer = masks[size == s]
        for j in range(n):
            if time.perf_counter() >= ends_at:
                raise OutOfTime
            with_j = layer[(layer >> j) & 1 == 1]
            before = last[with_j ^ (1 << j)] + between[:, j][None, :]
            best = np.argmin(before, axis=1)
            last[with_j, j] = before[np.arange(len(with_j)), best]
            parent[with_j, j] = best
    return last, parent


def _popcount(masks: np.ndarray) -> np.ndarray:
    """Number of set bits of each mask (vectorised)."""
    bits = np.zeros_like(masks)
    for b in range(int(masks.max()).bit_length()):
        bits += (masks >> b) & 1
    return bits


def _cover_model(table: RouteTable, masks: np.ndarray) -> highspy.HighsLp:
    """Set-partitioning model: one binary column per subset in ``masks``, minimise count."""
    n = table.n
    member = (masks[:, None] >> np.arange(n)[None, :]) & 1
    cols, rows = np.nonzero(member)
    matrix = sparse.csc_matrix((np.ones(len(rows)), (rows, cols)), shape=(n, len(masks)))
    return make_lp(np.ones(len(masks)), (np.zeros(len(masks)), np.ones(len(masks))), matrix,
                   (np.ones(n), np.ones(n)), np.ones(len(masks), dtype=bool))


def _fewest_routes(table: RouteTable, costs: np.ndarray, deadline: float,
                   time_limit: float | None) -> tuple[LpSolve, np.ndarray]:
    """Solve the set-partitioning MILP over subsets within ``deadline`` (HiGHS)."""
    masks = np.flatnonzero(within(costs, deadline))
    masks = masks[masks > 0]
    singles = 1 << np.arange(table.n)
    if not np.all(within(costs[singles], deadline)):
        alone = "a KPOI alone exceeds the deadline"
        return LpSolve("infeasible", None, None, None, 0, alone), masks
    return solve_lp(_cover_model(table, masks), time_limit=time_limit), masks


def _chosen_routes(
    table: RouteTable, solve: LpSolve, masks: np.ndarray, tours: bool
) -> list[list[int]]:
    """Routes of the subsets selected in a set-partitioning solution."""
    picked = masks[solve.values > 0.5]
    return [table.route(int(mask), tours=tours) for mask in picked]


class RouteCounter:
    """Route sets within a deadline, counted by inclusion-exclusion (module docstring, 2).

    Parameters
    ----------
    family : numpy.ndarray
        Boolean, indexed by subset mask: whether the subset's cheapest route meets the
        deadline. ``family[0]`` (the empty route) must be True and the family downward
        closed (:func:`downward_closed`).
    primes : tuple of int
        Moduli of the counts, each below :math:`2^{31}` (tests pass small ones).
    """

    def __init__(self, family: np.ndarray, primes: tuple[int, ...] = PRIMES) -> None:
        self.n = int(len(family)).bit_length() - 1
        self.family = family
        self.primes = primes
        self.z = _subset_sums(family.astype(np.int64), +1)  # z(R) <= 2^n: exact in int64
        self.full = len(family) - 1
        self.odd = (self.n - _popcount(np.arange(len(family)))) % 2 == 1  # sign (-1)^(n-|R|)

    def covers(self, j: int) -> bool:
        """Whether the KPOIs split into at most ``j`` routes of the family: N_j(full) > 0,
        decided exactly from its residues (module docstring, 2)."""
        return any(residue != 0 for residue in self._residues(j))

    def _residues(self, j: int):
        """``N_j(full)`` modulo one prime after another, until one is nonzero or the
        primes so far prove it zero; raises when the primes run out first."""
        ceiling = j * math.log2(max(int(self.z[self.full]), 1))  # N_j <= z(full)^j
        proven = 0.0  # log2 of the product of the primes used
        for p in self.primes:
            terms = _power_mod(self.z % p, j, p)  # each < 2^31: sums of 2^20 fit in 64 bits
            residue = int(terms[~self.odd].sum() - terms[self.odd].sum()) % p
            yield residue
            proven += math.log2(p)
            if residue != 0 or proven > ceiling:
                return
        raise ArithmeticError(f"{len(self.primes)} primes cannot decide counts up to 2^{ceiling:.0f}")

    def partitions(self, j: int, p: int) -> np.ndarray:
        """``N_j(S) mod p`` for every subset ``S`` (``j``-tuples of family members with
        union ``S``)."""
        return _partitions_mod(self.z, j, p)

    def fewest(self) -> int | None:
        """The fewest routes of the family covering every KPOI, None if no number does."""
        return next((j for j in range(1, self.n + 1) if self.covers(j)), None)

    def split(self, j: int) -> list[int]:
        """Masks of at most ``j`` disjoint family members covering every KPOI.

        Requires :meth:`covers` ``(j)``. Each step takes, among the members holding the
        lowest uncovered KPOI whose complement provably still splits into the routes left
        (a nonzero residue of its count, for the first prime giving one), the largest,
        then the smallest mask.
        """
        masks = np.arange(len(self.family))
        left, chosen = self.full, []
        for rest in range(j - 1, -1, -1):
            if left == 0:
                break
            lowest = left & -left
            fits = self.family & ((masks & ~left) == 0) & ((masks & lowest) != 0)
            candidates = masks[fits]
            for p in self.primes:
                proven = candidates[self.partitions(rest, p)[left ^ candidates] != 0]
                if len(proven):
                    break
            else:
                raise ArithmeticError("no prime proves a split; covers(j) was not true")
            pick = proven[np.lexsort((proven, -_popcount(proven)))[0]]
            chosen.append(int(pick))
            left ^= int(pick)
        return chosen


def _power_mod(base: np.ndarray, exponent: int, p: int) -> np.ndarray:
    """``base ** exponent mod p`` elementwise, by squaring (``0 <= base < p < 2^31``, so
    every product fits in 64 bits)."""
    result = np.ones_like(base)
    while exponent:
        if exponent & 1:
            result = result * base % p
        base = base * base % p
        exponent >>= 1
    return result


def _partitions_mod(z: np.ndarray, j: int, p: int) -> np.ndarray:
    """``N_j(S) mod p`` for every ``S``: the Moebius transform of ``z^j`` modulo ``p``."""
    out = _power_mod(z % p, j, p)
    n = int(len(out)).bit_length() - 1
    for b in range(n):
        pairs = out.reshape(-1, 2, 1 << b)
        pairs[:, 1, :] -= pairs[:, 0, :]
        pairs[:, 1, :] %= p
    return out


def route_family(costs: np.ndarray, deadline: float) -> np.ndarray:
    """Which subsets' cheapest routes meet ``deadline`` (the empty one always does)."""
    family = within(costs, deadline)
    family[0] = True
    return family


def downward_closed(family: np.ndarray) -> bool:
    """Whether every subset of a member of ``family`` is a member too."""
    has_member_above = _subset_sums(family.astype(np.int64), +1, supersets=True) > 0
    return bool(np.all(family | ~has_member_above))


def _subset_sums(values: np.ndarray, sign: int, *, supersets: bool = False) -> np.ndarray:
    """Zeta (``sign=+1``) or Moebius (``-1``) transform over subsets, or over supersets.

    Zeta: ``out[S] = sum of values[R] for R subset of S`` (superset: ``R`` superset of
    ``S``); Moebius inverts it. One pass per bit, ``O(2^n n)``.
    """
    out = values.copy()
    n = int(len(out)).bit_length() - 1
    for b in range(n):
        pairs = out.reshape(-1, 2, 1 << b)
        if supersets:
            pairs[:, 0, :] += sign * pairs[:, 1, :]
        else:
            pairs[:, 1, :] += sign * pairs[:, 0, :]
    return out


def _counter(costs: np.ndarray, deadline: float) -> RouteCounter | None:
    """The counter of the routes within ``deadline``, None when they are not downward closed."""
    family = route_family(costs, deadline)
    return RouteCounter(family) if downward_closed(family) else None


def _table(D: np.ndarray, began: float, time_limit: float | None) -> RouteTable | None:
    """The route table, or None when ``time_limit`` (from ``began``) ends first."""
    try:
        return RouteTable(D, math.inf if time_limit is None else began + time_limit)
    except OutOfTime:
        return None


def _unfinished(began: float) -> MilpResult:
    """The answer when the time limit ends before the route table is done."""
    return MilpResult("unknown", seconds=time.perf_counter() - began,
                      message="time limit (the Held-Karp table was not finished)")


def min_robots(
    D: np.ndarray,
    deadline: float,
    *,
    tours: bool,
    time_limit: float | None = None,
    warm_start: list[list[int]] | None = None,
) -> MilpResult:
    """Fewest robots whose routes all meet ``deadline`` (counting, else set partitioning).

    Parameters and return value as :func:`milp.compact.arcflow.min_robots`; ``warm_start`` is
    only checked (the model is solved from scratch). Raises ValueError for ``n > 20``.
    """
    began = time.perf_counter()
    D = check_distance_matrix(D)
    if warm_start is not None:
        check_routes(warm_start, len(D) - 1)
    table = _table(D, began, time_limit)
    if table is None:
        return _unfinished(began)
    costs = table.costs(tours=tours)
    counter = _counter(costs, deadline)
    if counter is not None:
        fewest = counter.fewest()
        if fewest is None:
            return MilpResult("infeasible", seconds=time.perf_counter() - began,
                              message="a KPOI alone exceeds the deadline")
        routes = [table.route(mask, tours=tours) for mask in counter.split(fewest)]
        count = float(len(routes))
        return MilpResult("optimal", routes, count, count, 0.0, 0, time.perf_counter() - began,
                          "inclusion-exclusion count")
    solve, masks = _fewest_routes(table, costs, deadline, time_limit)
    if solve.status == "infeasible":
        return MilpResult("infeasible", seconds=time.perf_counter() - began, message=solve.message)
    if solve.values is None:
        return MilpResult("unknown", bound=solve.bound, nodes=solve.nodes,
                          seconds=time.perf_counter() - began, message=solve.message)
    routes = _chosen_routes(table, solve, masks, tours)
    count = float(len(routes))
    bound = count if solve.status == "optimal" else float(np.ceil((solve.bound or 1.0) - 1e-6))
    return MilpResult(solve.status, routes, count, bound, relative_gap(count, bound), solve.nodes,
                      time.perf_counter() - began, solve.message)


def min_makespan(
    D: np.ndarray,
    k: int,
    *,
    tours: bool,
    time_limit: float | None = None,
    warm_start: list[list[int]] | None = None,
) -> MilpResult:
    """Least makespan with at most ``k`` robots (bisection over route costs).

    Parameters and return value as :func:`milp.compact.arcflow.min_makespan`; ``warm_start`` is
    only checked. Raises ValueError for ``n > 20``. With a time limit, an unresolved
    bisection step ends the search with the best achievable value found as ``feasible``
    and the smallest value not yet ruled out as bound.
    """
    began = time.perf_counter()
    D = check_distance_matrix(D)
    if k < 1:
        raise ValueError("k must be at least 1")
    if warm_start is not None:
        check_routes(warm_start, len(D) - 1)
    table = _table(D, began, time_limit)
    if table is None:
        return _unfinished(began)
    costs = table.costs(tours=tours)
    values = np.unique(costs[1:])
    floor = costs[1 << np.arange(table.n)].max()  # no route set beats its costliest single
    values = values[values >= floor]
    lo, hi = 0, int(np.searchsorted(values, costs[-1]))  # values[hi]: everything in one route
    best: list[list[int]] | RouteCounter = [table.route(len(costs) - 1, tours=tours)]
    most = min(k, table.n)
    nodes, message = 0, "bisection over route costs"
    log.info("setpart: %d subsets' cheapest routes, bisection over %d route costs", len(costs) - 1, hi - lo + 1)
    while lo < hi:
        mid = (lo + hi) // 2
        remaining = None if time_limit is None else time_limit - (time.perf_counter() - began)
        if remaining is not None and remaining <= 0:
            message = "time limit"
            break
        counter = _counter(costs, values[mid])
        if counter is not None:  # exact count; the routes are recovered once, at the end
            if counter.covers(most):
                hi, best = mid, counter
            else:
                lo = mid + 1
            continue
        solve, masks = _fewest_routes(table, costs, values[mid], remaining)
        nodes += solve.nodes
        if solve.status == "optimal" and solve.objective <= k + 0.5:
            hi, best = mid, _chosen_routes(table, solve, masks, tours)
        elif solve.status == "optimal" or solve.status == "infeasible":
            lo = mid + 1
        elif solve.values is not None and np.sum(solve.values > 0.5) <= k:
            hi, best = mid, _chosen_routes(table, solve, masks, tours)
        else:
            message = solve.message
            break
    if isinstance(best, RouteCounter):
        best = [table.route(mask, tours=tours) for mask in best.split(most)]
    value = max(costs[_mask(r)] for r in best)
    status = "optimal" if lo == hi else "feasible"
    bound = float(value) if status == "optimal" else float(values[lo])
    return MilpResult(status, best, float(value), bound, relative_gap(float(value), bound), nodes,
                      time.perf_counter() - began, message)


def _mask(route: list[int]) -> int:
    """Bit mask of the KPOIs on a route."""
    return sum(1 << (i - 1) for i in route)
