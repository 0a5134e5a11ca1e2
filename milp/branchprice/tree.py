"""The tree of one fewest-routes decision in :mod:`milp.branchprice`.

:class:`Decision` searches the branch-and-price tree of "at most ``target`` routes within
``budget``" depth first, imposing first, driving a :class:`Search` (the column generation
of :mod:`milp.branchprice` is one): each node is solved by column generation
(:meth:`Search.solve_node`), closed by its certified bound rounded up
(:func:`rounded_up`), answered by route enumeration (:class:`Settled`) or by an integral
master, or split on an arc flow (:meth:`milp.branchprice.columns.Node.children`). Its progress is
the share of the tree closed (:attr:`Decision.closed_share`). The primal side runs
here too: the integer master over the pool at the root and whenever the pool has grown
:data:`POOL_GROWTH` times, the caller's ``improve`` heuristic once at the root, and routes
another method hands over (:meth:`Search.routes_elsewhere`), taken before and after each
node and before the tree reports its end.
"""

from __future__ import annotations

import enum
import logging
import math
import time
from collections.abc import Callable, Sized
from dataclasses import dataclass
from typing import Protocol, TypeVar

from milp.branchprice.columns import Node
from milp.core.progress import Every

log = logging.getLogger(__name__)

__all__ = ["Decision", "Search", "NodeOutcome", "Why", "Ending", "Settled", "Improve", "rounded_up", "share_text", "ROUND",
           "POOL_GROWTH"]

#: A heuristic asked for routes (KPOIs ``1..n``) with at most the given number of routes
#: within the deadline, or ``None``; its second argument is the seconds the root took, a
#: measure of the effort the primal side may take in balance (the caller decides).
Improve = Callable[[int, float], "list[list[int]] | None"]
#: A bound within this of an integer counts as that integer (LP round-off): it proves
#: more than ``t`` routes are needed only when above ``t + ROUND`` (:func:`rounded_up`).
ROUND = 1e-6
#: Below the root, the integer master over the pool runs again whenever the pool has grown
#: this many times since it last ran (enumerated families add many routes within the
#: budget; a covering of them is a solution the tree may reach only much later).
POOL_GROWTH = 2.0


class Why(enum.StrEnum):
    """Why the column generation at a node stopped (:attr:`NodeOutcome.why`). A
    :class:`enum.StrEnum`, so each member also equals its string."""

    #: The master LP is solved: its value is certified (the bound reached it).
    SOLVED = "solved"
    #: The certified bound shows more routes than the target are needed.
    CLOSED = "closed"
    #: The time limit came first.
    TIME_LIMIT = "time limit"
    #: No column prices out, but the bound is not certified up to the LP value.
    STALLED = "pricing stalled"


class Ending(enum.StrEnum):
    """How the tree of one fewest-routes decision ended (:meth:`Decision.run`)."""

    #: A solution beat the target and the caller asked for the first one (``first``).
    FOUND = "found"
    #: ``first``, and enumeration at the root found the least makespan of every solution
    #: with at most the target routes.
    LEAST = "least"
    #: The tree is closed: no solution with at most the target routes remains.
    EXHAUSTED = "exhausted"
    #: The time limit, or a node left open (nothing to branch on, pricing stalled).
    UNKNOWN = "unknown"


@dataclass
class Settled:
    """A node answered by route enumeration: its fewest routes when at most the target,
    else None (the node holds no such solution). ``least``: the routes have the least
    makespan of any solution of at most the target routes at the node (answered by
    :meth:`milp.branchprice.search.BranchAndPrice.enumerate_node` with ``shortest``)."""

    routes: list[list[int]] | None
    least: bool = False


class NodeOutcome(Protocol):
    """What the tree reads of a node's column generation: its certified bound and why it
    stopped."""

    @property
    def bound(self) -> float: ...

    @property
    def why(self) -> Why: ...


Outcome = TypeVar("Outcome", bound=NodeOutcome)


class Search(Protocol[Outcome]):
    """What :class:`Decision` needs of the search it drives over one pool of columns.

    ``m`` KPOIs, ``tours`` or paths, ``nodes`` solved so far, the ``pool`` of columns
    (its size tells when the integer master runs again).
    """

    @property
    def m(self) -> int: ...

    @property
    def tours(self) -> bool: ...

    @property
    def nodes(self) -> int: ...

    @property
    def pool(self) -> Sized: ...

    def out_of_time(self) -> bool:
        """Whether the time limit is reached."""

    def solve_node(self, node: Node, budget: float, target: float) -> Outcome:
        """Column generation at ``node`` for routes within ``budget``, stopped once its
        bound shows more than ``target`` routes are needed."""

    def integral_routes(self, outcome: Outcome) -> list[list[int]] | None:
        """The master's solution as routes when integral, else None."""

    def enumerate_node(self, node: Node, outcome: Outcome, budget: float, target: int, *,
                       shortest: bool) -> tuple[Outcome, Settled | None]:
        """Answer ``node`` by route enumeration when its LP gap allows: the (re-solved)
        outcome and, when answered, the node's fewest routes (those of least makespan
        with ``shortest``)."""

    def branching_arc(self, node: Node, outcome: Outcome, target: int) -> tuple[int, int] | None:
        """The arc to branch on, or None when there is none."""

    def support_covering(self, outcome: Outcome) -> list[list[int]] | None:
        """A covering by the fewest of the master's positive columns, or None (for a
        node whose arc flows are integral but whose solution is not)."""

    def integer_master(self, budget: float) -> list[list[int]] | None:
        """A covering by the fewest pooled columns within ``budget``, or None."""

    def routes_elsewhere(self) -> list[list[int]] | None:
        """Routes another method found that answer this tree's question (fewer routes
        than its best, within the budget), taken now, or None. ``solve_node`` may close a
        node against one route fewer than routes it has seen and not handed over yet:
        the tree takes them as soon as the node returns."""


class Decision:
    """The tree of one fewest-routes search (:meth:`milp.branchprice.search.BranchAndPrice.fewest_routes`): depth first
    from the root, the best routes found so far and the target they leave (one route
    fewer), the root's bound."""

    def __init__(self, search: Search[NodeOutcome], budget: float, incumbent: list[list[int]] | None,
                 target: int, *, first: bool, improve: Improve | None, floor: int = 1) -> None:
        self.search, self.budget, self.first, self.improve = search, budget, first, improve
        self.best, self.target = incumbent, target
        self.floor = floor  # a bound the caller proved: routes meeting it end the search
        self.root_bound: int | None = None  # set when the root is solved (None: still at it)
        self.unresolved = False  # a node was left open (pricing stalled, nothing to branch on)
        self.pool_tried = 0  # the pool's size when the integer master last ran
        self.began = time.perf_counter()  # the root's seconds, for improve, count from here
        self.progress = Every(log)
        #: The nodes left to search, the next one last; a run stopped by the time limit leaves
        #: them here (with a node whose column generation it cut short), for :meth:`run` to resume.
        self.stack = [Node.root(search.m)]
        self.closed = 0  # nodes closed: by their bound, answered by enumeration, or integral
        #: The share of the tree closed: the sum of ``2 ** -depth`` over the closed nodes
        #: (each branching halves a node's share between its children; Knuth, "Estimating the
        #: efficiency of backtrack programs", Math. Comp. 29, 1975). 1 when the tree is exhausted;
        #: how much of the tree is settled, not how much time is left (depth first leaves
        #: the deep parts of the imposed side for last).
        self.closed_share = 0.0

    def run(self) -> Ending:
        """Search the tree; how it ended. With logging on, a line every
        :data:`milp.core.progress.PROGRESS_SECONDS`: nodes solved and closed, nodes open, the
        deepest open one. Stopped by the time limit (:attr:`resumable`), a second run goes on
        from the nodes left open, its closed nodes and share kept: a closed node stays proven
        whatever the search learned since (its pool and ng-memories only add columns and
        strengthen the relaxation)."""
        ending = self._search()
        if ending in (Ending.EXHAUSTED, Ending.UNKNOWN) and self._accept(self.search.routes_elsewhere()):
            return Ending.FOUND  # the last nodes may have closed against them
        return ending

    @property
    def resumable(self) -> bool:
        """Whether another :meth:`run` could still close the tree: nodes are left and none
        was left open for good."""
        return bool(self.stack) and not self.unresolved

    def _search(self) -> Ending:
        """The depth-first search of :meth:`run`, until an ending."""
        stack = self.stack
        while stack:
            if self.search.out_of_time():
                return Ending.UNKNOWN
            ended, children = self._visit(stack.pop())
            stack.extend(children)
            if ended is not None:
                return ended
            self._report(stack)
        return Ending.UNKNOWN if self.unresolved else Ending.EXHAUSTED

    def _report(self, stack: list[Node]) -> None:
        """The progress line, when one is due."""
        if not self.progress.due():
            return
        depth = max((node.depth for node in stack), default=0)
        log.info("branch-and-price: %d nodes solved, %d closed (%s of the tree), %d open (deepest %d "
                 "branchings), looking for %d routes", self.search.nodes, self.closed, share_text(self.closed_share),
                 len(stack), depth, self.target)

    def _visit(self, node: Node) -> tuple[Ending | None, list[Node]]:
        """Solve ``node``: how the search ends there (:attr:`Ending.FOUND`, :attr:`Ending.LEAST`,
        :attr:`Ending.UNKNOWN`), or None; and the nodes to search next: its children (none when
        it is closed by its bound, answered by enumeration, or integral), or the node itself
        when the time limit cut its column generation short."""
        search, budget = self.search, self.budget
        at_root = node.depth == 0
        if self._accept(search.routes_elsewhere()):
            return Ending.FOUND, []
        if not at_root and len(search.pool) >= POOL_GROWTH * self.pool_tried and self._accept(self._pool_covering()):
            return Ending.FOUND, []
        outcome = search.solve_node(node, budget, self.target)
        rounded = rounded_up(outcome.bound)
        if at_root:
            self.root_bound = max(1, rounded, self.root_bound or 1) if math.isfinite(rounded) else None
            log.info("branch-and-price: the root LP needs at least %s routes (%d allowed; LP bound %.6g, %s)",
                     self.root_bound, self.target, outcome.bound, outcome.why)
        if self._accept(search.routes_elsewhere()):  # the node may have closed against them
            return Ending.FOUND, []
        if at_root and any(self._accept(routes) for routes in self._root_candidates(rounded)):
            return Ending.FOUND, []
        settled = None
        if outcome.why == Why.SOLVED and rounded <= self.target and search.integral_routes(outcome) is None:
            outcome, settled = search.enumerate_node(node, outcome, budget, self.target, shortest=self.first)
            rounded = rounded_up(outcome.bound)
            if at_root and self.root_bound is not None and math.isfinite(rounded):
                self.root_bound = max(self.root_bound, rounded)
            if settled is not None and settled.routes is not None:
                if self.first and at_root and settled.least:
                    self.best = settled.routes
                    return Ending.LEAST, []
                if self._accept(settled.routes):
                    return Ending.FOUND, []
        # the master's solution when integral (that of the LP re-solved for a listing too)
        if outcome.why == Why.SOLVED and rounded <= self.target and self._accept(search.integral_routes(outcome)):
            return Ending.FOUND, []
        if outcome.why == Why.TIME_LIMIT:
            return Ending.UNKNOWN, [node]  # solved again if the tree is resumed
        if rounded > self.target or settled is not None:
            return self._closed(node)  # by its bound, or answered by enumeration
        if outcome.why != Why.SOLVED:
            self.unresolved = True
            return None, []
        if search.integral_routes(outcome) is not None:
            return self._closed(node)  # an integral LP optimum: nothing better below this node
        arc = search.branching_arc(node, outcome, self.target)
        if arc is None:  # integral arc flows, fractional lambda: crossing routes
            routes = search.support_covering(outcome)
            if self._accept(routes):
                return Ending.FOUND, []
            if routes is None or len(routes) > rounded:
                self.unresolved = True
                return None, []
            return self._closed(node)  # its covering meets its bound
        one, zero = node.children(arc, tours=search.tours)
        return None, [zero, one]  # imposing first

    def _closed(self, node: Node) -> tuple[None, list[Node]]:
        """Count ``node`` closed (:attr:`closed_share`): nothing below it to search."""
        self.closed += 1
        self.closed_share += 2.0 ** -node.depth
        return None, []

    def _root_candidates(self, rounded: float) -> list[list[list[int]] | None]:
        """At the root, routes that may beat the target: the integer master over the pool
        and ``improve`` (the cheap primal side first: enumeration then proves against
        them)."""
        if rounded > self.target:
            return []
        candidates = [self._pool_covering()]
        if self.improve is not None:
            candidates.append(self.improve(max(1, int(rounded)), time.perf_counter() - self.began))
        return candidates

    def _pool_covering(self) -> list[list[int]] | None:
        """The integer master over the pool now, its size noted."""
        self.pool_tried = len(self.search.pool)
        return self.search.integer_master(self.budget)

    def _accept(self, routes: list[list[int]] | None) -> bool:
        """Keep ``routes`` when they beat the target; True when the search should stop (the
        caller asked for the first, or they meet the caller's bound)."""
        if routes is None or len(routes) > self.target:
            return False
        self.best, self.target = routes, len(routes) - 1
        log.info("branch-and-price: %d routes found, %d nodes", len(routes), self.search.nodes)
        return self.first or len(routes) <= self.floor


def share_text(share: float) -> str:
    """A share of a tree (:attr:`Decision.closed_share`) in percent, for messages: three
    significant digits, and never 100% short of 1 (a deep tree leaves shares of 1e-6)."""
    percent = 100 * share
    return "100%" if share >= 1 else f"{min(float(f'{percent:.3g}'), 99.9):g}%"


def rounded_up(bound: float) -> float:
    """The least number of routes a certified LP bound proves (inf stays inf)."""
    return math.ceil(bound - ROUND) if math.isfinite(bound) else bound
