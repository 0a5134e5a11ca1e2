"""The columns and the branching nodes of branch-and-price (:mod:`milp.branchprice`).

A :class:`Pool` keeps every route generated in one search, with its length and the arcs
it uses, and tells which of them a node allows; a :class:`Node` holds the branching
decisions on arc flows as the arcs routes may still use. Arc ``(i, j)`` of a route runs
from KPOI ``i`` to KPOI ``j`` (0 the start); ``(i, 0)`` is the route's end at ``i``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import sparse

from milp.core.routes import route_cost

__all__ = ["Pool", "Node"]


class Pool:
    """Every column generated: KPOIs in visiting order, real length, arcs used.

    Arc ``(i, j)`` has id ``i (m+1) + j``; the arc from ``i`` to the end of a route (the
    sink of a path, the way home of a tour) is ``(i, 0)``. A sparse column-by-arc
    incidence matrix, rebuilt when the pool has grown, tells which columns a node allows.
    """

    def __init__(self, D: np.ndarray, *, tours: bool) -> None:
        self.D, self.tours, self.m = D, tours, len(D) - 1
        self.orders: list[np.ndarray] = []
        self.lengths = np.zeros(0)
        self.arcs: list[np.ndarray] = []
        self.seen: set[bytes] = set()
        self._incidence: sparse.csr_matrix | None = None

    def __len__(self) -> int:
        return len(self.orders)

    def add(self, routes: list[np.ndarray], lengths: np.ndarray | None = None) -> range:
        """Add the routes (their ``lengths`` when known) not in the pool yet; the indices
        of the new columns."""
        before, added = len(self.orders), []
        for r, route in enumerate(routes):
            key = route.astype(np.int16).tobytes()
            if key in self.seen:
                continue
            self.seen.add(key)
            self.orders.append(route)
            self.arcs.append(np.concatenate(([0], route)) * (self.m + 1) + np.concatenate((route, [0])))
            added.append(route_cost(self.D, route.tolist(), tours=self.tours) if lengths is None else lengths[r])
        if added:
            self.lengths = np.concatenate((self.lengths, added))
            self._incidence = None
        return range(before, len(self.orders))

    def allows(self, node: Node, columns: list[int]) -> np.ndarray:
        """Which of ``columns`` use only arcs ``node`` allows."""
        forbidden = (~node.allowed).ravel().astype(np.float64)
        return self._incidence_matrix()[columns] @ forbidden == 0

    def _incidence_matrix(self) -> sparse.csr_matrix:
        if self._incidence is None:
            rows = np.repeat(np.arange(len(self.arcs)), [len(a) for a in self.arcs])
            self._incidence = sparse.csr_matrix(
                (np.ones(len(rows)), (rows, np.concatenate(self.arcs))),
                shape=(len(self.arcs), (self.m + 1) ** 2))
        return self._incidence

    def fitting(self, budget: float, node: Node, among: range | None = None) -> list[int]:
        """Columns (of ``among``, default all) within ``budget`` using only arcs ``node``
        allows."""
        forbidden = (~node.allowed).ravel().astype(np.float64)
        among = range(len(self)) if among is None else among
        picked = slice(among.start, among.stop)
        ok = (self._incidence_matrix()[picked] @ forbidden == 0) & (self.lengths[picked] <= budget)
        return (np.flatnonzero(ok) + among.start).tolist()


@dataclass
class Node:
    """Branching decisions: ``allowed[i, j]`` for the arcs routes may use, row 0 the
    first arcs, column 0 the arcs to the end (``allowed[i, 0]``: a route may end at
    ``i``); ``depth``, the branchings from the root."""

    allowed: np.ndarray
    depth: int = 0

    @classmethod
    def root(cls, m: int) -> Node:
        allowed = np.ones((m + 1, m + 1), dtype=bool)
        np.fill_diagonal(allowed, False)
        return cls(allowed)

    def children(self, arc: tuple[int, int], *, tours: bool) -> tuple[Node, Node]:
        """``(imposed, forbidden)`` children for arc ``(i, j)``; ``j = 0`` is the end.

        For tours the forbidden child forbids the edge both ways (``(j, i)`` too): a tour
        reversed is the same tour, so forbidding one direction alone would let the LP
        use every forbidden tour backwards. Imposing one direction still leaves every
        solution that uses the edge in the imposed child (reverse its tour if needed).
        """
        i, j = arc
        one, zero = Node(self.allowed.copy(), self.depth + 1), Node(self.allowed.copy(), self.depth + 1)
        zero.allowed[i, j] = False
        if tours:
            zero.allowed[j, i] = False
        if j > 0:  # nothing but i may precede j
            one.allowed[:, j] = False
        if i > 0:  # i goes nowhere but j (j = 0: i ends its route)
            one.allowed[i, :] = False
        one.allowed[i, j] = True
        return one, zero
