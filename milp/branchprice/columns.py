"""The columns and the branching nodes of branch-and-price (:mod:`milp.branchprice`).

A :class:`Pool` keeps every route generated in one search, with its length and the arcs
it uses, and tells which of them a node allows; a :class:`Node` holds the branching
decisions on arc flows as the arcs routes may still use. Arc ``(i, j)`` of a route runs
from KPOI ``i`` to KPOI ``j`` (0 the start); ``(i, 0)`` is the route's end at ``i``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import sparse

from milp.core.routes import route_cost

__all__ = ["Pool", "Node", "Entries", "entries_split"]


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


@dataclass(frozen=True)
class Entries:
    """A branching row on the routes entering a KPOI set: ``sum_r e_r lambda_r >= rhs``
    (``at_least``) or ``<= rhs``, with ``e_r`` the arcs by which route ``r`` enters the
    set (from the start or a KPOI outside it). ``members``: ``(m+1,)`` bool, the set
    (``members[0]`` False)."""

    members: np.ndarray
    at_least: bool
    rhs: int

    def count(self, route: np.ndarray) -> int:
        """The arcs by which ``route`` (KPOIs in order) enters the set."""
        inside = self.members[route]
        return int(inside[0]) + int(np.count_nonzero(inside[1:] & ~inside[:-1]))

    def arc_prize(self, dual: float) -> np.ndarray:
        """``(m+1, m+1)``: ``dual`` on every arc from outside the set into it."""
        return np.outer(~self.members, self.members) * dual


def entries_split(members: np.ndarray, flow: float) -> tuple[Entries, Entries]:
    """``(at most floor, at least ceil)`` rows for a set entered ``flow`` times (fractional):
    every solution lies on one side, its entries being an integer."""
    return Entries(members, False, math.floor(flow)), Entries(members, True, math.ceil(flow))


@dataclass
class Node:
    """Branching decisions: ``allowed[i, j]`` for the arcs routes may use, row 0 the
    first arcs, column 0 the arcs to the end (``allowed[i, 0]``: a route may end at
    ``i``); ``entries``, rows on the routes entering KPOI sets (:class:`Entries`: they
    stay in the master, their duals arc prizes in the pricing); ``depth``, the branchings
    from the root."""

    allowed: np.ndarray
    depth: int = 0
    entries: tuple[Entries, ...] = ()

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
        one = Node(self.allowed.copy(), self.depth + 1, self.entries)
        zero = Node(self.allowed.copy(), self.depth + 1, self.entries)
        zero.allowed[i, j] = False
        if tours:
            zero.allowed[j, i] = False
        if j > 0:  # nothing but i may precede j
            one.allowed[:, j] = False
        if i > 0:  # i goes nowhere but j (j = 0: i ends its route)
            one.allowed[i, :] = False
        one.allowed[i, j] = True
        return one, zero

    def with_entries(self, row: Entries) -> Node:
        """The child with ``row`` added (a branching on the routes entering a set)."""
        return Node(self.allowed, self.depth + 1, (*self.entries, row))
