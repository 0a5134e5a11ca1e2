r"""Certified lower bounds from a route-based LP solved by column generation.

A lower bound on the least makespan with at most ``k`` routes, and on the fewest routes
within a deadline, for paths and tours from the start 0 of a metric ``D``. The bound is
*certified*: it stays valid when column generation stops early (time limit), because
every number it rests on comes from an exact pricing over a relaxed route set.

Model
-----
For a trial makespan :math:`T` let :math:`\mathcal R(T)` be the routes of cost
:math:`\le T`, :math:`a_{ir}` the number of visits of KPOI :math:`i` by route :math:`r`,
and

.. math::
    (1)\quad z(T) = \min \sum_r \lambda_r \quad\text{s.t.}\quad
    (2)\ \sum_r a_{ir} \lambda_r \ge 1 \ (i = 1..n), \qquad (3)\ \lambda \ge 0,

the LP relaxation of set covering. Any solution with at most ``k`` routes within
:math:`T` is an integer point of (2)-(3) with objective :math:`\le k`, so
:math:`z(T) > k` proves the least makespan is above :math:`T`; and
:math:`\lceil z(U) \rceil` robots are needed to meet a deadline :math:`U`.

Relaxed routes (pricing)
------------------------
Routes are priced over a larger set :math:`\mathcal R'(T) \supseteq \mathcal R(T)` in
which the optimisation is exact: *q-routes* with 2-cycle elimination (Christofides,
Mingozzi and Toth 1981, "Exact algorithms for the vehicle routing problem, based on
spanning tree and shortest path relaxations", Math. Prog. 20): walks from 0 that may
revisit a KPOI, but never as ``i -> j -> i``. Lengths are discretised on a grid
:math:`\delta`: :math:`d'_{ij} = \lfloor d_{ij}/\delta \rfloor` (rounded *down*), budget
:math:`L = \lfloor T/\delta \rfloor`, return :math:`r'_j = d'_{j0}` (tours) or 0 (paths).
A walk is in :math:`\mathcal R'(T)` when every prefix ending at ``j`` with discretised
length :math:`\ell` has :math:`\ell + r'_j \le L`. A real route of cost :math:`\le T`
qualifies: by the triangle inequality each prefix plus the way back costs at most
:math:`T`, rounding down only shortens, and an integer at most :math:`T/\delta` is at
most :math:`L`. Using :math:`\mathcal R'` can only lower (1), so its LP value
:math:`z'(T) \le z(T)` is still a bound. The pricing is a dynamic programme over
(discretised length, last node) keeping the best and second-best predecessor (2-cycle
elimination), vectorised with numpy over whole blocks of lengths (ng-routes,
Baldacci, Mingozzi and Roberti 2011, "New route relaxation and pricing strategies for
the vehicle routing problem", Oper. Res. 59, would be tighter; not implemented).

Certificate (Farley's bound)
----------------------------
The dual of (1)-(3) is :math:`\max \sum_i \pi_i` s.t. :math:`\sum_i a_{ir}\pi_i \le 1`
for all :math:`r \in \mathcal R'`, :math:`\pi \ge 0`. For *any* :math:`\pi \ge 0`
(here: the restricted master's duals, clipped at 0) let
:math:`M = \max_{r \in \mathcal R'} \sum_i a_{ir}\pi_i`, computed exactly by the pricing.
Then :math:`\pi / M` is dual feasible, hence

.. math::
    (4)\quad z'(T) \ge \sum_i \pi_i / M,

whatever columns the restricted master holds (Farley 1990, "A note on bounding a class
of linear programming problems, including cutting stock problems", Oper. Res. 38;
equal to the Lagrangian bound LP value + k x most negative reduced cost at convergence).
Column generation adds the priced walks with :math:`\sum a_{ir}\pi_i > 1` and stops as
soon as (4) exceeds ``k`` (``T`` proven infeasible), the restricted master's value is
at most ``k`` (nothing can be proven at ``T``: the master's value is an upper bound on
:math:`z'`), or time runs out. The pricing duals are smoothed towards the best
certificate so far (Wentges 1997, "Weighted Dantzig-Wolfe decomposition for linear
mixed-integer programming", Int. Trans. Oper. Res. 4): fewer iterations, and (4) holds
for the smoothed duals too, since it holds for any :math:`\pi \ge 0`.

Min-max bound: bisection on :math:`T` between the known lower bound (``c_max`` /
``2 c_max`` and :func:`milp.bounds.makespan_lower_bound`) and the caller's upper bound;
a ``T`` proven infeasible becomes the new lower end. The grid is fixed for the whole
bisection (:math:`\delta` from the upper bound), so columns carry over between steps.

Pre-processing: KPOIs at distance 0 are merged and KPOIs at the start dropped
(:mod:`milp.core.merge`); shortcutting repeated classes turns any solution of the original
into one of the merged instance with no longer routes, so bounds carry back. The grid
is never coarser than the smallest positive distance, so every arc has
:math:`d' \ge 1` and the programme has no zero-length cycles; when that would need more
than ``MAX_CELLS`` grid cells the trivial bound is returned.
"""

from __future__ import annotations

import enum
import math
import time
from dataclasses import dataclass, field
from typing import NamedTuple

import highspy
import numpy as np
from scipy import sparse

from milp.bounds import makespan_lower_bound as tree_lower_bound
from milp.core.timelimit import TimeLimit, TimeLimitLike, stop_requested
from milp.bounds import robots_lower_bound as tree_robots_bound
from milp.core.highs import LpSolve, make_lp, new_highs, solve_lp
from milp.core.merge import merge_zero_distances
from milp.core.routes import check_distance_matrix, first_visits, least_makespan, route_cost, within

#: Grid steps over the upper bound: :math:`\delta = \text{upper} / \text{GRID}`.
GRID = 1000
#: Largest ``(L + 1) x (n + 1)`` table of the pricing programme.
MAX_CELLS = 2_000_000
#: Relative tolerance of the certificate (float round-off in sums of duals).
CERT_TOL = 1e-9
#: Weight of the stability center in the pricing duals (0: plain column generation).
SMOOTHING = 0.5
#: Bisection stops when the interval is below this fraction of the upper end.
BISECTION_TOL = 1e-4
#: Seconds per cell ``(ell, i, j)`` of one pricing (about 25 ns measured at 200-400 KPOIs,
#: rounded up): under a time limit, column generation is skipped when one pricing,
#: which cannot be interrupted, would not fit in what is left.
PRICING_SECONDS_PER_CELL = 4e-8


class Stop(enum.StrEnum):
    """Why column generation at one length budget stopped (:func:`_fewest_routes_lp`). A
    :class:`enum.StrEnum`, so each member also equals its string, which is the text
    :attr:`BoundInfo.message` reports."""

    #: The certified bound exceeds the target: more routes than the target are needed.
    PROVEN = "proven"
    #: The master's value is at most the target: the target cannot be proven at this budget.
    MASTER_WITHIN_TARGET = "master within target"
    #: No target, and the bound and the master's value round up to the same count.
    ROUNDED_BOUND_CLOSED = "rounded bound closed"
    #: The bound reached the master's value: the LP is solved.
    LP_SOLVED = "LP solved"
    #: The pricing found no new column and did not raise the bound.
    NO_NEW_COLUMN = "no new column"
    #: The time ran out, or the next pricing would end after it, or a race's other entrant
    #: proved the answer (also :func:`makespan_bound`'s message when this stops its bisection).
    TIME_LIMIT = "time limit"
    #: HiGHS did not solve the master LP to optimality (the message adds its model status).
    MASTER_FAILED = "master LP"


class _Stopped(NamedTuple):
    """Where column generation at one budget stopped (:func:`_fewest_routes_lp`)."""

    farley: float
    master_value: float
    iterations: int
    why: Stop
    #: HiGHS's model status when ``why`` is :attr:`Stop.MASTER_FAILED`, else empty.
    status: str = ""

    @property
    def message(self) -> str:
        """Why it stopped, in words: ``why``'s text, and the model status after it when HiGHS failed."""
        return f"{self.why}: {self.status}" if self.why is Stop.MASTER_FAILED else self.why.value


@dataclass
class BoundInfo:
    """What a bound computation did.

    Attributes
    ----------
    bound : float
        The certified bound (makespan) or its float value before rounding up (robots).
    trivial : float
        The bound it started from (``c_max`` / ``2 c_max``, the spanning-tree bound and,
        for :func:`makespan_bound`, the caller's ``lower``).
    steps : list of tuple
        ``(T, proven, farley_bound, master_value, iterations)`` per trial makespan.
    columns : int
        Columns generated in all.
    seconds : float
        Wall-clock time.
    message : str
        Why it stopped (after column generation in :func:`robots_bound`, the text of a
        :class:`Stop`, with HiGHS's model status after it when the master LP failed).
    routes : list of list of int
        :func:`robots_bound` with ``routes=True``: routes within the deadline from the
        generated columns (:func:`master_routes`), in the indices of the merged matrix
        (:func:`milp.core.merge.merge_zero_distances`); else empty.
    """

    bound: float
    trivial: float
    steps: list[tuple[float, bool, float, float, int]] = field(default_factory=list)
    columns: int = 0
    seconds: float = 0.0
    message: str = ""
    routes: list[list[int]] = field(default_factory=list)

    def robots(self) -> int:
        """The robot count this bound proves: ``bound`` rounded up (1e-6 tolerance for
        round-off), never below ``trivial``."""
        return max(int(self.trivial), math.ceil(self.bound - 1e-6))


class _Pricer:
    """Exact pricing over discretised q-routes with 2-cycle elimination (see module doc).

    Parameters
    ----------
    D : numpy.ndarray
        Merged distance matrix (no zero off-diagonal distance).
    tours : bool
        Route kind.
    delta : float
        Grid step, at most the smallest positive distance / (1 + 1e-6).
    """

    def __init__(self, D: np.ndarray, *, tours: bool, delta: float) -> None:
        self.n = len(D) - 1
        self.dd = np.maximum(np.floor(D / delta - 1e-9), 0).astype(np.int64)
        np.fill_diagonal(self.dd, 0)
        self.back = self.dd[:, 0].copy() if tours else np.zeros(self.n + 1, dtype=np.int64)
        self.step = int(self.dd[:, 1:][~np.eye(self.n + 1, self.n, -1, dtype=bool)].min())
        assert self.step >= 1, "zero-length arc in the pricing grid"

    def pricing_seconds(self, L: int) -> float:
        """Expected seconds of one :meth:`price` at budget ``L`` (O(L n^2) work)."""
        return L * (self.n + 1) * self.n * PRICING_SECONDS_PER_CELL

    def budget(self, T: float, delta: float) -> int:
        """``L``: the discretised length budget of makespan ``T``."""
        return int(math.floor(T / delta + 1e-9))

    def price(self, prize: np.ndarray, L: int) -> tuple[float, list[np.ndarray], list[int]]:
        """Best walk value ``M`` and the best walk ending at each KPOI (if positive).

        Parameters
        ----------
        prize : numpy.ndarray
            ``pi_1..pi_n`` (non-negative).
        L : int
            Length budget.

        Returns
        -------
        tuple
            ``(M, walks, needs)``: ``walks`` as arrays of KPOIs ``1..n`` (visits in
            order), best first, ``needs[w]`` = the walk's largest ``ell + r'_j``.
        """
        n, dd, back = self.n, self.dd, self.back
        arcs = np.minimum(dd[:, 1:], L + 1)  # (n+1, n) lengths i -> j (j = 1..n)
        arcs[np.eye(n + 1, n, -1, dtype=bool)] = L + 1  # no i -> i
        pad = int(arcs.max())  # rows 0..pad-1: lengths below 0, never reachable
        F1 = np.full((pad + L + 1, n + 1), -np.inf)
        F2 = np.full((pad + L + 1, n + 1), -np.inf)
        P1 = np.full((pad + L + 1, n + 1), -1, dtype=np.int64)
        P2 = np.full((pad + L + 1, n + 1), -1, dtype=np.int64)
        F1[pad, 0] = 0.0
        cols = np.arange(1, n + 1)
        offset = (arcs - pad) * (n + 1) - np.arange(n + 1)[:, None]  # flat = row*(n+1) - offset
        f1, f2, p1s = F1.ravel(), F2.ravel(), P1.ravel()
        cutoff = L - back[1:]
        block = max(1, min(self.step, 64))
        for start in range(1, L + 1, block):
            ells = np.arange(start, min(start + block, L + 1))
            flat = ells[:, None, None] * (n + 1) - offset[None, :, :]
            value = np.where(p1s.take(flat) == cols, f2.take(flat), f1.take(flat))
            best = np.argmax(value, axis=1)[:, None, :]  # (B, 1, n)
            v1 = np.take_along_axis(value, best, axis=1)[:, 0, :]
            np.put_along_axis(value, best, -np.inf, axis=1)
            second = np.argmax(value, axis=1)[:, None, :]
            v2 = np.take_along_axis(value, second, axis=1)[:, 0, :]
            late = ells[:, None] > cutoff[None, :]
            F1[pad + ells, 1:] = np.where(late, -np.inf, v1 + prize)
            F2[pad + ells, 1:] = np.where(late, -np.inf, v2 + prize)
            P1[pad + ells, 1:], P2[pad + ells, 1:] = best[:, 0, :], second[:, 0, :]
        F1, P1, P2 = F1[pad:], P1[pad:], P2[pad:]
        end = F1[:, 1:]
        ell = np.argmax(end, axis=0)
        value = end[ell, np.arange(n)]
        M = float(value.max()) if n else 0.0
        walks, needs = [], []
        for j in np.argsort(-value, kind="stable"):
            if not np.isfinite(value[j]):
                break
            walk, need = self._walk(int(ell[j]), int(j) + 1, P1, P2)
            walks.append(walk)
            needs.append(need)
        return M, walks, needs

    def _walk(self, ell: int, j: int, P1: np.ndarray, P2: np.ndarray) -> tuple[np.ndarray, int]:
        """Trace the best walk ending at ``(ell, j)`` back to the start."""
        order, need, rank = [], 0, 1
        while j != 0:
            order.append(j)
            need = max(need, ell + int(self.back[j]))
            i = int((P1 if rank == 1 else P2)[ell, j])
            ell -= int(self.dd[i, j])
            rank = 2 if i != 0 and P1[ell, i] == j else 1
            j = i
        return np.array(order[::-1], dtype=np.int64), need


class _Master:
    """Restricted master LP (1)-(3) in HiGHS over a growing pool of walks."""

    def __init__(self, n: int) -> None:
        self.n = n
        self.pool: list[np.ndarray] = []  # visit counts per walk
        self.orders: list[np.ndarray] = []  # each walk's KPOIs in order of first visit
        self.need: list[int] = []
        self.seen: set[bytes] = set()

    def add(self, walks: list[np.ndarray], needs: list[int]) -> list[int]:
        """Add new walks to the pool; indices of those actually new."""
        fresh = []
        for walk, need in zip(walks, needs):
            counts = np.bincount(walk - 1, minlength=self.n).astype(np.float64)
            key = counts.tobytes() + need.to_bytes(8, "little")
            if key not in self.seen:
                self.seen.add(key)
                self.pool.append(counts)
                self.orders.append(walk[np.sort(np.unique(walk, return_index=True)[1])])
                self.need.append(need)
                fresh.append(len(self.pool) - 1)
        return fresh

    def open(self, L: int) -> highspy.Highs:
        """A HiGHS LP over the pool's walks that fit budget ``L``."""
        h = new_highs(None)  # the project's thread count: HiGHS' scheduler is process-wide
        h.addRows(self.n, np.ones(self.n), np.full(self.n, highspy.kHighsInf), 0,
                  np.zeros(0, dtype=np.int32), np.zeros(0, dtype=np.int32), np.zeros(0))
        self.extend(h, [c for c in range(len(self.pool)) if self.need[c] <= L])
        h.changeObjectiveSense(highspy.ObjSense.kMinimize)
        return h

    def extend(self, h: highspy.Highs, columns: list[int]) -> None:
        """Append pool columns to the LP ``h``."""
        if not columns:
            return
        matrix = np.array([self.pool[c] for c in columns])
        rows, which = np.nonzero(matrix.T)
        order = np.lexsort((rows, which))
        rows, which = rows[order], which[order]
        starts = np.searchsorted(which, np.arange(len(columns))).astype(np.int32)
        values = matrix[which, rows]
        h.addCols(len(columns), np.ones(len(columns)), np.zeros(len(columns)),
                  np.full(len(columns), highspy.kHighsInf), len(rows), starts,
                  rows.astype(np.int32), values)


def _single_kpoi_master(pricer: _Pricer) -> _Master:
    """A restricted master holding the route ``0 -> j`` (``-> 0``) of every KPOI ``j``,
    so that (2) is feasible from the first iteration."""
    master = _Master(pricer.n)
    master.add([np.array([j]) for j in range(1, pricer.n + 1)],
               [int(pricer.dd[0, j] + pricer.back[j]) for j in range(1, pricer.n + 1)])
    return master


def _fewest_routes_lp(
    master: _Master, pricer: _Pricer, L: int, target: float | None, ends_at: float | None,
) -> _Stopped:
    """Column generation at budget ``L``: ``(farley, master_value, iterations, why, status)``.

    ``farley`` is a certified lower bound (4) on :math:`z'`. Stops when it exceeds
    ``target``, when the master's value is at most ``target`` (a target cannot be
    proven), when the LP is solved (bound meets the master's value), or at ``ends_at``
    (``time.perf_counter()`` value; also before a pricing that would end after it). Duals are smoothed (Wentges 1997): the pricing uses
    ``SMOOTHING * center + (1 - SMOOTHING) * master duals``, the center being the scaled
    duals of the best bound so far; (4) holds for any non-negative duals, so the bound
    stays certified.
    """
    h = master.open(L)
    farley, value, iterations = 0.0, math.inf, 0
    center = None
    while True:
        h.run()
        if h.getModelStatus() != highspy.HighsModelStatus.kOptimal:
            status = h.modelStatusToString(h.getModelStatus())
            return _Stopped(farley, value, iterations, Stop.MASTER_FAILED, status)
        value = float(h.getInfo().objective_function_value)
        duals = np.maximum(np.asarray(h.getSolution().row_dual, dtype=np.float64), 0.0)
        pi = duals if center is None else SMOOTHING * center + (1 - SMOOTHING) * duals
        if stop_requested() or (ends_at is not None and time.perf_counter() + pricer.pricing_seconds(L) > ends_at):
            # stop_requested: a race's other entrant proved it
            return _Stopped(farley, value, iterations, Stop.TIME_LIMIT)
        M, walks, needs = pricer.price(pi, L)
        iterations += 1
        improved = M > 0 and float(pi.sum()) / (M * (1 + CERT_TOL)) > farley
        if improved:
            farley, center = float(pi.sum()) / (M * (1 + CERT_TOL)), pi / M
        if target is not None and farley > target * (1 + CERT_TOL) + CERT_TOL:
            return _Stopped(farley, value, iterations, Stop.PROVEN)
        if target is not None and value <= target * (1 + CERT_TOL) + CERT_TOL:
            return _Stopped(farley, value, iterations, Stop.MASTER_WITHIN_TARGET)
        if target is None and math.ceil(farley - 1e-6) >= math.ceil(value - 1e-6):
            return _Stopped(farley, value, iterations, Stop.ROUNDED_BOUND_CLOSED)
        if farley >= value * (1 - 1e-7):
            return _Stopped(farley, value, iterations, Stop.LP_SOLVED)
        if ends_at is not None and time.perf_counter() >= ends_at:
            return _Stopped(farley, value, iterations, Stop.TIME_LIMIT)
        counts = [np.bincount(w - 1, minlength=master.n) for w in walks]
        keep = [i for i, c in enumerate(counts) if float(c @ duals) > 1 + 1e-9]
        fresh = master.add([walks[i] for i in keep], [needs[i] for i in keep])
        if fresh:
            master.extend(h, fresh)
        elif not improved:
            return _Stopped(farley, value, iterations, Stop.NO_NEW_COLUMN)


def _pricing_fits(pricer: _Pricer, L: int, time_limit: TimeLimit) -> bool:
    """Whether one pricing at budget ``L`` fits in what is left of ``clock``."""
    left = time_limit.remaining()
    return left is None or pricer.pricing_seconds(L) <= left


def _setup(merged: np.ndarray, top: float, *, tours: bool) -> tuple[float, _Pricer] | None:
    """Grid step and pricer over a merged matrix (:func:`milp.core.merge.merge_zero_distances`),
    or None when the grid would be too large."""
    n = len(merged) - 1
    if n == 0 or (GRID + 2) * (n + 1) > MAX_CELLS:
        # the grid has at least GRID steps (delta <= top / GRID): too large from 1996 KPOIs,
        # known before the 0.6 s of building the pricer (measured at 3000 KPOIs)
        return None
    positive = merged[~np.eye(n + 1, dtype=bool)]
    delta = min(top / GRID, float(positive.min()) / (1 + 1e-6))
    if delta <= 0 or (top / delta + 2) * (n + 1) > MAX_CELLS:
        return None
    return delta, _Pricer(merged, tours=tours, delta=delta)


def makespan_bound(
    D: np.ndarray, k: int, *, tours: bool, upper: float, time_limit: TimeLimitLike = None,
    lower: float = 0.0,
) -> BoundInfo:
    """Certified lower bound on the least makespan with at most ``k`` routes, with details.

    Parameters
    ----------
    D : numpy.ndarray
        ``(n+1, n+1)`` metric distance matrix, index 0 the start.
    k : int
        Routes available (at least 1).
    tours : bool
        Tours (return to 0) or open paths.
    upper : float
        A makespan known to be achievable (e.g. a heuristic's); the bisection's upper end.
    time_limit : float or milp.core.timelimit.TimeLimit, optional
        Seconds, or a deadline shared with the caller; the bound found so far is
        returned when they run out, and the spanning-tree bound at once when one
        pricing would not fit (:meth:`_Pricer.pricing_seconds`).
    lower : float, optional
        A lower bound certified elsewhere (e.g. by branch-and-price's route LP): the
        bisection starts from the larger of it and the spanning-tree bound, so the bound
        returned is never below it.

    Returns
    -------
    BoundInfo
        ``bound`` never exceeds the optimum (module docstring).
    """
    began = time.perf_counter()
    time_limit = TimeLimit.of(time_limit)
    ends_at = time_limit.ends_at
    if k < 1:
        raise ValueError("k must be at least 1")
    D = check_distance_matrix(D)
    merged = merge_zero_distances(D).D
    floor = max(least_makespan(D, tours=tours), lower,
                tree_lower_bound(merged, k, tours=tours, time_limit=time_limit.remaining()))
    info = BoundInfo(floor, floor)
    ready = _setup(merged, max(upper, floor), tours=tours)
    if ready is None or upper <= floor:
        info.message = "starting bound (nothing to bisect or grid too large)"
        info.seconds = time.perf_counter() - began
        return info
    delta, pricer = ready
    if not _pricing_fits(pricer, pricer.budget(upper, delta), time_limit):
        info.message = "starting bound (no time for one pricing)"
        info.seconds = time.perf_counter() - began
        return info
    master = _single_kpoi_master(pricer)
    lo, hi = floor, upper
    info.message = "converged"
    while hi - lo > BISECTION_TOL * hi:
        if time_limit.expired():  # its clock, or a race's other entrant proved it (milp.core.timelimit.stopping)
            info.message = Stop.TIME_LIMIT.value
            break
        T = 0.5 * (lo + hi)
        farley, value, its, why, _ = _fewest_routes_lp(master, pricer, pricer.budget(T, delta), k, ends_at)
        proven = why is Stop.PROVEN
        info.steps.append((T, proven, farley, value, its))
        if proven:
            lo = T
        else:
            hi = T
    info.bound, info.columns = lo, len(master.pool)
    info.seconds = time.perf_counter() - began
    return info


def makespan_lower_bound(
    D: np.ndarray, k: int, *, tours: bool, upper: float, time_limit: TimeLimitLike = None,
    lower: float = 0.0,
) -> float:
    """Certified lower bound on the least makespan with at most ``k`` routes.

    See :func:`makespan_bound` (same parameters); this returns its ``bound`` only.
    """
    return makespan_bound(D, k, tours=tours, upper=upper, time_limit=time_limit, lower=lower).bound


def robots_bound(
    D: np.ndarray, deadline: float, *, tours: bool, time_limit: TimeLimitLike = None,
    routes: bool = False,
) -> BoundInfo:
    """Certified lower bound (float) on the fewest routes within ``deadline``, with details.

    ``bound`` is the LP bound (4) at ``T = deadline``; round it up for a robot count
    (:meth:`BoundInfo.robots`). ``trivial`` is the spanning-tree count of
    :func:`milp.bounds.robots_lower_bound`. With ``routes``, ``info.routes`` also holds a
    solution from the generated columns (:func:`master_routes`, within ``time_limit``:
    seconds or a shared :class:`~milp.core.timelimit.TimeLimit`; the trivial bound at once when
    one pricing would not fit). Raises ValueError when ``deadline`` is below ``c_max`` / ``2 c_max`` (no solution).
    """
    began = time.perf_counter()
    time_limit = TimeLimit.of(time_limit)
    D = check_distance_matrix(D)
    if deadline < least_makespan(D, tours=tours) * (1 - 1e-9) - 1e-9:
        raise ValueError("deadline below the least makespan: no solution")
    merged = merge_zero_distances(D).D
    trivial = float(tree_robots_bound(merged, deadline, tours=tours, time_limit=time_limit.remaining()))
    info = BoundInfo(trivial, trivial)
    ready = _setup(merged, deadline, tours=tours)
    if ready is None:
        info.message = "trivial bound (grid too large)"
        info.seconds = time.perf_counter() - began
        return info
    delta, pricer = ready
    L = pricer.budget(deadline, delta)
    if not _pricing_fits(pricer, L, time_limit):
        info.message = "trivial bound (no time for one pricing)"
        info.seconds = time.perf_counter() - began
        return info
    master = _single_kpoi_master(pricer)
    stopped = _fewest_routes_lp(master, pricer, L, None, time_limit.ends_at)
    info.steps.append((deadline, False, stopped.farley, stopped.master_value, stopped.iterations))
    info.bound, info.columns, info.message = max(stopped.farley, trivial), len(master.pool), stopped.message
    if routes:
        left = time_limit.remaining()
        info.routes = master_routes(master, merged, deadline, tours=tours,
                                    time_limit=None if left is None else max(left, 0.05))
    info.seconds = time.perf_counter() - began
    return info


def master_routes(master: _Master, D: np.ndarray, deadline: float, *, tours: bool,
                  time_limit: float | None) -> list[list[int]]:
    r"""Fewest routes from the generated columns: the restricted master as an integer program.

    Each walk of the pool becomes the route through its KPOIs in order of first visit
    (no longer than the walk, by the triangle inequality); those whose real cost meets
    ``deadline`` are the columns of the set-covering integer program (1)-(3) with
    :math:`\lambda` binary, solved by HiGHS within ``time_limit`` (a "price-and-branch"
    heuristic: it proves nothing, the caller's model does). A KPOI covered twice stays
    on the first chosen route only, which again shortens the others. Empty when no
    integer solution was found in time.
    """
    orders = [o for o in master.orders if within(route_cost(D, list(o), tours=tours), deadline)]
    return fewest_covering(orders, master.n, time_limit) or []


def fewest_covering(orders: list[np.ndarray], n: int, time_limit: float | None) -> list[list[int]] | None:
    """The fewest of ``orders`` (KPOI sequences over ``1..n``) covering every KPOI: the
    set-covering integer program in HiGHS within ``time_limit``, the chosen routes made a
    partition by :func:`milp.core.routes.first_visits`. None when no covering was found in time."""
    return covering_solve(orders, n, time_limit)[1]


def covering_solve(orders: list[np.ndarray], n: int, time_limit: float | None,
                   ) -> tuple[LpSolve, list[list[int]] | None]:
    """:func:`fewest_covering` with what HiGHS established (status, count, bound)."""
    if not orders:
        return LpSolve("infeasible", None, None, None, 0, "no routes"), None
    rows = np.concatenate(orders) - 1
    cols = np.repeat(np.arange(len(orders)), [len(o) for o in orders])
    matrix = sparse.csc_matrix((np.ones(len(rows)), (rows, cols)), shape=(n, len(orders)))
    ones = np.ones(len(orders))
    lp = make_lp(ones, (np.zeros(len(orders)), ones), matrix, (np.ones(n), np.full(n, np.inf)),
                 np.ones(len(orders), dtype=bool))
    solve = solve_lp(lp, time_limit=time_limit)
    if solve.values is None:
        return solve, None
    return solve, first_visits([orders[c] for c in np.flatnonzero(solve.values > 0.5)])


def robots_lower_bound(
    D: np.ndarray, deadline: float, *, tours: bool, time_limit: TimeLimitLike = None,
) -> int:
    """Certified lower bound on the fewest robots whose routes all meet ``deadline``.

    The LP bound of :func:`robots_bound` rounded up (with a 1e-6 tolerance for float
    round-off), never below the spanning-tree count.
    """
    return robots_bound(D, deadline, tours=tours, time_limit=time_limit).robots()
