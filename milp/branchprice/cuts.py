"""Separation of the subset-row cuts (5) of :mod:`milp.branchprice`.

A cut on a triple :math:`S` of KPOIs says that at most one route visits two of them
(Jepsen, Petersen, Spoorendonk and Pisinger 2008); the coefficients a route gets, with a
cut's limited memory, are :func:`milp.branchprice.ngroute.cut_coefficients`.
"""

from __future__ import annotations

import numpy as np

from milp.core.jit import njit
from milp.branchprice.ngroute import MAX_CUTS

__all__ = ["violated_triples", "popcount", "cut_memory", "KERNELS"]


@njit(cache=True)
def violated_triples(counts, x, least):  # pragma: no cover - compiled
    """Triples ``(a, b, c)`` (0-based KPOIs) whose subset-row cut (5) is violated by more
    than ``least``: ``sum_r x_r floor((counts_ra + counts_rb + counts_rc) / 2) > 1``,
    most violated first, at most :data:`milp.branchprice.ngroute.MAX_CUTS` (all the pricing can carry)."""
    m = counts.shape[1]
    found = np.zeros((0, 4))
    rows = []
    for a in range(m):
        for b in range(a + 1, m):
            for c in range(b + 1, m):
                total = 0.0
                for r in range(counts.shape[0]):
                    total += x[r] * ((counts[r, a] + counts[r, b] + counts[r, c]) // 2)
                if total > 1.0 + least:
                    rows.append((float(a), float(b), float(c), total))
    if rows:
        found = np.array(rows)
        found = found[np.argsort(-found[:, 3])][:MAX_CUTS]
    return found[:, :3].astype(np.int64)


def popcount(bits: np.uint64) -> int:
    """How many bits of ``bits`` are set (the cuts whose triple holds a KPOI)."""
    return bin(int(bits)).count("1")


def cut_memory(triple: tuple[int, int, int], routes: list[np.ndarray]) -> set[int]:
    """The memory of a new cut: its triple and every KPOI that a route of the current
    solution visits between two of the triple's KPOIs (so the cut keeps its violation)."""
    memory = set(triple)
    for route in routes:
        where = np.flatnonzero(np.isin(route, triple))
        if len(where) >= 2:
            memory.update(int(j) for j in route[where[0]:where[-1] + 1])
    return memory


#: Every compiled (numba) function of this module, for :mod:`milp.branchprice.compiling` to check and compile.
KERNELS = (violated_triples,)
