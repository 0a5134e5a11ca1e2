"""Merge KPOIs at distance 0 from each other or from the start before modelling.

In a metric, "at distance 0" is an equivalence relation, and members of one class are
interchangeable: visiting them consecutively costs nothing extra and every distance to
a third node is the same. A compact model over the classes (one representative each)
therefore has the same optimum, and no zero-length cycle ``i -> j -> i`` can satisfy
the distance-flow constraints without touching the start.

KPOIs at distance 0 from the start are removed from the model altogether: they can be
put at the front of any route at no cost (``0 -> s -> i`` costs ``D[s, i] = D[0, i]``).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import connected_components

from milp.core.result import MilpResult, relative_gap
from milp.core.routes import route_cost, within

#: Distances at most ``ZERO * max(1, D.max())`` are treated as 0.
ZERO = 1e-12


@dataclass(frozen=True)
class Merged:
    """A distance matrix over the start and one representative per class.

    Attributes
    ----------
    D : numpy.ndarray
        ``(m+1, m+1)`` matrix; index 0 is the start, ``1..m`` the classes.
    groups : list of list of int
        ``groups[c - 1]`` lists the original KPOIs of model node ``c``.
    at_start : list of int
        Original KPOIs at distance 0 from the start (not in the model).
    """

    D: np.ndarray
    groups: list[list[int]]
    at_start: list[int]

    @property
    def size(self) -> int:
        """Number of model KPOIs ``m``."""
        return len(self.groups)

    def expand(self, routes: list[list[int]]) -> list[list[int]]:
        """Original-index routes from model routes (classes split back, start KPOIs first)."""
        out = [[i for c in route for i in self.groups[c - 1]] for route in routes]
        if self.at_start:
            if out:
                out[0] = [*self.at_start, *out[0]]
            else:
                out = [list(self.at_start)]
        return out

    def reduce(self, routes: list[list[int]]) -> list[list[int]]:
        """Model routes from valid original routes (first visit of a class kept).

        By the triangle inequality no route gets longer.
        """
        node_of = {i: c + 1 for c, members in enumerate(self.groups) for i in members}
        seen: set[int] = set()
        out = []
        for route in routes:
            reduced = []
            for i in route:
                c = node_of.get(i)
                if c is not None and c not in seen:
                    seen.add(c)
                    reduced.append(c)
            if reduced:
                out.append(reduced)
        return out


def merge_zero_distances(D: np.ndarray) -> Merged:
    """Classes of KPOIs at distance 0 from each other; KPOIs at the start set apart.

    Parameters
    ----------
    D : numpy.ndarray
        ``(n+1, n+1)`` metric distance matrix, index 0 the start.

    Returns
    -------
    Merged
    """
    zero = D <= ZERO * max(1.0, float(D.max()))
    _, label = connected_components(csr_matrix(zero), directed=False)
    at_start = [i for i in range(1, len(D)) if label[i] == label[0]]
    groups: dict[int, list[int]] = {}
    for i in range(1, len(D)):
        if label[i] != label[0]:
            groups.setdefault(int(label[i]), []).append(i)
    members = list(groups.values())
    keep = [0] + [g[0] for g in members]
    # a copy either way; a plain one is 4x faster than indexing (measured at 3000 KPOIs)
    return Merged(D.copy() if len(keep) == len(D) else D[np.ix_(keep, keep)], members, at_start)


def checked_start(merged: Merged, D: np.ndarray, routes: list[list[int]] | None, *,
                   tours: bool, deadline: float | None, k: int | None) -> list[list[int]] | None:
    """The warm start in merged indices when it covers every KPOI (within ``deadline`` and
    with at most ``k`` routes, when given), else None."""
    if not routes:
        return None
    covered = sorted(i for r in routes for i in r)
    if covered != list(range(1, len(D))):
        return None
    reduced = merged.reduce(routes)
    if deadline is not None and not all(within(route_cost(merged.D, r, tours=tours), deadline)
                                        for r in reduced):
        return None
    if k is not None and len(reduced) > k:
        return None
    return reduced


def model_result(status: str, merged: Merged, D: np.ndarray, routes: list[list[int]] | None,
                 objective: float | None, bound: float | None, nodes: int, began: float,
                 message: str) -> MilpResult:
    """A model's answer over merged indices as a :class:`~milp.core.result.MilpResult` over the
    original KPOIs (an optimal answer's bound is its objective, its gap 0)."""
    expanded = merged.expand(routes) if routes is not None else []
    gap = relative_gap(objective, bound)
    if status == "optimal":
        bound, gap = objective, 0.0
    return MilpResult(status, expanded, objective, bound, gap, nodes,
                      time.perf_counter() - began, message)
