"""Spanning-tree lower bounds on the makespan and on the number of routes.

Cheap bounds every exact model starts from: :mod:`milp.arcflow` uses them as ``L`` of its
constraint (8) and ``Q`` of (1), :mod:`milp.colgen` bisects upwards from them, and
:mod:`parcover.bounds` reports them beside every method's answer.
"""

from __future__ import annotations

import numpy as np

from milp.routes import least_makespan, within

__all__ = ["spanning_tree_length", "makespan_lower_bound", "robots_lower_bound"]


def spanning_tree_length(D: np.ndarray) -> float:
    """Length of a minimum spanning tree of the complete graph on ``D``.

    Prim's algorithm on the dense matrix, O(n^2) time and O(n) extra memory; zero
    distances (coincident points) are ordinary edges.
    """
    n = len(D)
    in_tree = np.zeros(n, dtype=bool)
    in_tree[0] = True
    nearest = np.array(D[0], dtype=float)
    total = 0.0
    for _ in range(n - 1):
        candidates = np.where(in_tree, np.inf, nearest)
        j = int(np.argmin(candidates))
        total += float(candidates[j])
        in_tree[j] = True
        np.minimum(nearest, D[j], out=nearest)
    return total


def makespan_lower_bound(D: np.ndarray, k: int, *, tours: bool) -> float:
    """``L`` of arcflow's (8): the larger of ``c_max`` (``2 c_max``) and a tree bound.

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
    return max(least_makespan(D, tours=tours), float(np.min((tree + closing) / q)))

def robots_lower_bound(D: np.ndarray, deadline: float, *, tours: bool) -> int:
    """``Q`` of arcflow's (1): the least route count the spanning-tree argument allows.

    ``q`` routes within ``U`` have total length ``<= q U``; that total is at least the
    MST (paths), or the MST plus the ``q`` smallest ``d_i0`` (tours), see
    :func:`makespan_lower_bound`.

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
    return int(q[np.argmax(fits)])
