"""Spanning-tree and Held-Karp lower bounds on the makespan, and on the number of routes
(with the conflict-clique bound: KPOIs no two of which fit on one route).

Cheap bounds every exact model starts from: :mod:`milp.compact.arcflow` uses them as ``L`` of its
constraint (8) and ``Q`` of (1), :mod:`milp.branchprice.colgen` bisects upwards from them, and
:mod:`parcover.bounds` reports them beside every method's answer.
"""

from __future__ import annotations

import functools

import numpy as np

from milp.core.routes import least_makespan, within

__all__ = ["spanning_tree_length", "held_karp_makespan_bound", "makespan_lower_bound", "robots_lower_bound",
           "conflict_clique"]

#: The Held-Karp bound joins :func:`makespan_lower_bound` from this many KPOIs (below,
#: set partitioning proves optima within a second and the bound's 15-30 ms would be most
#: of a solve) up to this many (each subgradient step is a spanning tree, O(n^2): about
#: 0.6-0.75 s in all for 200 KPOIs, 3 paths; :data:`HELD_KARP_SHARE` keeps it to its part of a
#: time limit) ...
HELD_KARP_KPOIS = (21, 200)
#: ... with at most this many subgradient steps; the step length is halved after this
#: many steps without a better bound, starting from this factor, and aims at this much
#: above the best bound so far.
HELD_KARP_STEPS, HELD_KARP_PATIENCE, HELD_KARP_START, HELD_KARP_AIM = 300, 10, 2.0, 1.02
#: :func:`robots_lower_bound` tries at most this many route counts with it.
HELD_KARP_ROBOT_STEPS = 3
#: Seconds per distance-matrix entry of one Held-Karp bound (measured 2.3e-5 to 4.5e-5 s at
#: 30-200 KPOIs on a 2-core EPYC), rounded up: :func:`held_karp_seconds`.
HELD_KARP_SECONDS_PER_ENTRY = 5e-5
#: Most of a caller's time limit the Held-Karp part of a bound may take (expected).
HELD_KARP_SHARE = 0.25
#: :func:`conflict_clique` grows a clique from this many KPOIs (the most conflicting), up
#: to this many KPOIs (at the least makespan, uniform points, a loaded 2-core EPYC: 0.01 s
#: at 400 KPOIs, 0.04-0.06 s at 1000, 0.2-0.3 s at 2000, 1.2-1.3 s at 3000).
CLIQUE_STARTS, CLIQUE_MAX_KPOIS = 16, 2000


def spanning_tree_length(D: np.ndarray) -> float:
    """Length of a minimum spanning tree of the complete graph on ``D``
    (:func:`_spanning_tree`)."""
    return _spanning_tree(D)[0]


def _spanning_tree(C: np.ndarray) -> tuple[float, np.ndarray]:
    """Length and node degrees of a minimum spanning tree of the complete graph on ``C``.

    Prim's algorithm on the dense matrix, O(n^2) time and O(n) extra memory; zero
    distances (coincident points) are ordinary edges.
    """
    n = len(C)
    in_tree = np.zeros(n, dtype=bool)
    in_tree[0] = True
    nearest = np.array(C[0], dtype=float)
    parent = np.zeros(n, dtype=np.int64)
    total = 0.0
    for _ in range(n - 1):
        candidates = np.where(in_tree, np.inf, nearest)
        j = int(np.argmin(candidates))
        total += float(candidates[j])
        in_tree[j] = True
        closer = (C[j] < nearest) & ~in_tree
        parent[closer] = j
        np.minimum(nearest, C[j], out=nearest)
    degrees = np.bincount(parent[1:], minlength=n) + 1
    degrees[0] -= 1
    return total, degrees


def held_karp_makespan_bound(D: np.ndarray, k: int, *, tours: bool) -> float:
    r"""A Lagrangian (Held and Karp 1970, 1971) lower bound on the least makespan.

    With ``n >= k`` KPOIs some optimal solution has exactly ``k`` non-empty routes
    (splitting a route in two leaves each part no longer, by the triangle inequality), so
    the makespan is at least the least total length of ``k`` routes over ``k``. Their
    edges form a graph ``G`` in which every KPOI has degree 2 (tours; at most 2 for
    paths) and the start degree ``2k`` (tours; ``k`` for paths). For paths ``G`` is a
    spanning tree of ``{0..n}``; for tours, dropping one start edge per tour leaves one,
    and the dropped edges lead to ``k`` distinct KPOIs. With multipliers :math:`\pi_i`
    on the KPOIs' degrees (:math:`\pi \ge 0` for paths) and :math:`\lambda` on the
    start's, and costs :math:`c'_{ij} = d_{ij} + \pi_i + \pi_j` (:math:`\pi_0 = \lambda`),

    .. math::
        \text{length}(G) \ge \text{MST}(c') + \sum_{k \text{ smallest}} c'_{0i}
        - 2 \sum_i \pi_i - 2k\lambda \quad\text{(tours)}, \qquad
        \text{length}(G) \ge \text{MST}(c') - 2 \sum_i \pi_i - k\lambda \quad\text{(paths)}.

    Every right-hand side is a bound; subgradient steps on the degrees' excess
    (:data:`HELD_KARP_STEPS` of them, a Polyak step towards :data:`HELD_KARP_AIM` x the
    best bound so far, halved after :data:`HELD_KARP_PATIENCE` steps without progress)
    raise it. On TSPLIB tours with 1 route it comes within 0.3% of the optimal tour
    (eil76 543.25 against 544.37); Necula's eil76 with 2 tours: 275.77 (spanning-tree
    bound 242.21), ch150 with 3 tours 2177.2 (1979.7). Returns 0 when there are fewer
    KPOIs than routes (the other bounds are then exact)."""
    n = len(D) - 1
    if n < max(k, 1):
        return 0.0
    pi = np.zeros(n + 1)  # pi[0] is lambda
    best, step, stalled = -np.inf, HELD_KARP_START, 0
    for _ in range(HELD_KARP_STEPS):
        C = D + pi[:, None] + pi[None, :]
        np.fill_diagonal(C, np.inf)
        tree, degrees = _spanning_tree(C)
        excess = degrees.astype(float)
        if tours:
            closing = np.argpartition(C[0, 1:], k - 1)[:k] if k < n else np.arange(n)
            value = tree + float(C[0, 1 + closing].sum()) - 2.0 * pi[1:].sum() - 2.0 * k * pi[0]
            excess[0] += k
            excess[1 + closing] += 1
            excess[1:] -= 2.0
            excess[0] -= 2.0 * k
        else:
            value = tree - 2.0 * pi[1:].sum() - k * pi[0]
            excess[1:] -= 2.0
            excess[0] -= k
            excess[1:][(pi[1:] <= 0.0) & (excess[1:] < 0.0)] = 0.0  # pi stays >= 0
        if value > best:
            best, stalled = value, 0
        else:
            stalled += 1
            if stalled >= HELD_KARP_PATIENCE:
                step, stalled = step / 2.0, 0
        norm = float(excess @ excess)
        if norm == 0.0 or best <= 0.0:  # degrees all met: the bound is a solution's length
            break
        pi += step * (HELD_KARP_AIM * best - value) / norm * excess
        if not tours:
            np.maximum(pi[1:], 0.0, out=pi[1:])
    return max(best, 0.0) / k


def held_karp_seconds(D: np.ndarray, *, robots: bool) -> float:
    """About how long the Held-Karp part of :func:`makespan_lower_bound` (one bound) or
    :func:`robots_lower_bound` (up to :data:`HELD_KARP_ROBOT_STEPS`) takes on ``D``; 0
    outside :data:`HELD_KARP_KPOIS`, and once a bound of ``D`` was computed (they are
    remembered, and a solve asks for the same ones again)."""
    low, high = HELD_KARP_KPOIS
    if not low <= len(D) - 1 <= high or _matrix_key(D) in _HELD_KARP_MATRICES:
        return 0.0
    return HELD_KARP_SECONDS_PER_ENTRY * len(D) ** 2 * (HELD_KARP_ROBOT_STEPS if robots else 1)


def makespan_lower_bound(D: np.ndarray, k: int, *, tours: bool, time_limit: float | None = None) -> float:
    """``L`` of arcflow's (8): the largest of ``c_max`` (``2 c_max``), a tree bound and,
    for :data:`HELD_KARP_KPOIS` KPOIs, :func:`held_karp_makespan_bound` when it is expected
    to take at most :data:`HELD_KARP_SHARE` of ``time_limit`` (None: always).

    The routes of a solution all contain the start, so for paths their ``n`` arcs form
    a spanning tree of ``{0..n}``: total length >= MST, and with ``q <= k`` routes the
    makespan is >= MST / q >= MST / k. For tours, dropping each tour's closing arc leaves
    such a tree, and the ``q`` closing arcs return from ``q`` distinct KPOIs: makespan
    >= min over q <= k of (MST + sum of the q smallest ``d_i0``) / q.

    Parameters
    ----------
    D : numpy.ndarray
        ``(n+1, n+1)`` metric distance matrix, index 0 the start.
    k : int
        Robots available.
    tours : bool
        Route kind.

    Returns
    -------
    float
    """
    if len(D) == 1:
        return 0.0
    tree = spanning_tree_length(D)
    q = np.arange(1, min(k, len(D) - 1) + 1)
    closing = np.cumsum(np.sort(D[0, 1:]))[: len(q)] if tours else np.zeros(len(q))
    bound = max(least_makespan(D, tours=tours), float(np.min((tree + closing) / q)))
    low, high = HELD_KARP_KPOIS
    if low <= len(D) - 1 <= high and _held_karp_fits(D, time_limit, robots=False):
        bound = max(bound, _held_karp(D, k, tours))
    return bound


def _held_karp_fits(D: np.ndarray, time_limit: float | None, *, robots: bool) -> bool:
    """Whether the Held-Karp part fits in :data:`HELD_KARP_SHARE` of ``time_limit``."""
    return time_limit is None or held_karp_seconds(D, robots=robots) <= HELD_KARP_SHARE * time_limit


def _held_karp(D: np.ndarray, k: int, tours: bool) -> float:
    """:func:`held_karp_makespan_bound`, less round-off, once per matrix and ``k`` (a solve
    asks for it several times)."""
    matrix = np.ascontiguousarray(D, dtype=np.float64).tobytes()
    _HELD_KARP_MATRICES.add(hash(matrix))
    return _remembered_held_karp(matrix, len(D), k, tours) * (1 - 1e-12)


#: Hashes of the matrices :func:`_held_karp` has bounded (:func:`held_karp_seconds`).
_HELD_KARP_MATRICES: set[int] = set()


def _matrix_key(D: np.ndarray) -> int:
    return hash(np.ascontiguousarray(D, dtype=np.float64).tobytes())


@functools.lru_cache(maxsize=16)
def _remembered_held_karp(matrix: bytes, size: int, k: int, tours: bool) -> float:
    """:func:`held_karp_makespan_bound` of the matrix held in ``matrix``."""
    D = np.frombuffer(matrix, dtype=np.float64).reshape(size, size)
    return held_karp_makespan_bound(D, k, tours=tours)


def conflict_clique(D: np.ndarray, deadline: float, *, tours: bool) -> list[int]:
    """KPOIs (``1..n``) no two of which one route within ``deadline`` can visit: each needs
    a route of its own, so their number bounds the fewest routes.

    A route visiting ``i`` and then ``j`` costs at least ``d_0i + d_ij`` (and ``+ d_j0`` for
    a tour) by the triangle inequality; two KPOIs conflict when that exceeds the deadline
    in both orders. Any clique of this conflict graph is a bound; it is found greedily
    from each of the :data:`CLIQUE_STARTS` most conflicting KPOIs (add the candidate with
    the most conflicts among the candidates left), which matched the maximum clique of
    networkx's exact search on all 108 graphs measured (100 KPOIs of uniform, clustered
    and map instances and 50-200 uniform ones, deadlines 1.0-1.2 x the least makespan;
    8 starts did too). With deadlines near the least makespan, where the farthest KPOIs
    leave a route little slack, it is the strongest cheap bound: 7 routes where the
    spanning-tree and Held-Karp bounds give 4 (tours within ``2 c_max``, 100 KPOIs in
    clustered rooms). Above :data:`CLIQUE_MAX_KPOIS` KPOIs it is not computed (empty).
    """
    m = len(D) - 1
    if m > CLIQUE_MAX_KPOIS:
        return []
    if m <= 1:
        return list(range(1, m + 1))
    d0, M = D[0, 1:], D[1:, 1:]
    if tours:
        there = d0[:, None] + M + D[1:, 0][None, :]  # 0 -> i -> j -> 0
        need = np.minimum(there, there.T)
    else:
        need = np.minimum(d0[:, None] + M, (d0[:, None] + M).T)  # 0 -> i -> j or 0 -> j -> i
    conflict = ~within(need, deadline)
    np.fill_diagonal(conflict, False)
    best: list[int] = []
    for start in np.argsort(-conflict.sum(axis=1), kind="stable")[:CLIQUE_STARTS]:
        clique, candidates = [int(start)], conflict[start].copy()
        inner = conflict[:, candidates].sum(axis=1)  # each KPOI's conflicts among the candidates
        while candidates.any():
            inside = np.flatnonzero(candidates)
            chosen = int(inside[np.argmax(inner[inside])])
            clique.append(chosen)
            leaving = candidates & ~conflict[chosen]
            candidates &= conflict[chosen]
            inner -= conflict[:, leaving].sum(axis=1)
        if len(clique) > len(best):
            best = clique
    return sorted(i + 1 for i in best)


def robots_lower_bound(D: np.ndarray, deadline: float, *, tours: bool, time_limit: float | None = None) -> int:
    """``Q`` of arcflow's (1): the least route count the spanning-tree argument allows,
    raised by the Held-Karp bound for :data:`HELD_KARP_KPOIS` KPOIs when it fits in
    ``time_limit`` (as :func:`makespan_lower_bound`), and by the conflict clique
    (:func:`conflict_clique`).

    ``q`` routes within ``U`` have total length ``<= q U``; that total is at least the
    MST (paths), or the MST plus the ``q`` smallest ``d_i0`` (tours), see
    :func:`makespan_lower_bound`. Then, while :func:`held_karp_makespan_bound` with ``q``
    routes exceeds ``U`` (at most :data:`HELD_KARP_ROBOT_STEPS` times), ``q`` routes
    cannot meet the deadline, nor can fewer: ``q + 1``. (At a deadline of the makespan of
    a nearest-neighbour split into 3 or 6 routes, n = 50-150, it raised ``Q`` by one on 9
    of 24 instances and never by more.)

    Parameters
    ----------
    D : numpy.ndarray
        ``(n+1, n+1)`` metric distance matrix, index 0 the start.
    deadline : float
        ``U``, at least ``c_max`` (paths) / ``2 c_max`` (tours).
    tours : bool
        Route kind.

    Returns
    -------
    int
        At least 1.
    """
    if len(D) == 1:
        return 1
    tree = spanning_tree_length(D)
    q = np.arange(1, len(D))
    closing = np.cumsum(np.sort(D[0, 1:])) if tours else np.zeros(len(q))
    with np.errstate(over="ignore"):  # q x a deadline near 1e308 is inf: every q fits
        fits = within(tree + closing, q * deadline)
    fewest = int(q[np.argmax(fits)])
    low, high = HELD_KARP_KPOIS
    if low <= len(D) - 1 <= high and _held_karp_fits(D, time_limit, robots=True):
        for _ in range(HELD_KARP_ROBOT_STEPS):
            if fewest >= len(D) - 1 or within(_held_karp(D, fewest, tours), deadline):
                break
            fewest += 1
    return max(fewest, len(conflict_clique(D, deadline, tours=tours)))
