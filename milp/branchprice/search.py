r"""Branch-and-price over ng-routes: fewest routes within a deadline (the least makespan with
k routes is a sequence of such decisions, :mod:`milp.branchprice.makespan`).

Model
-----
For a length budget :math:`U` let :math:`\mathcal R(U)` be the ng-routes
(:mod:`milp.branchprice.ngroute`) of length at most :math:`U` from the start 0 (paths, or tours back
to 0), :math:`a_{ir}` the visits of KPOI :math:`i` by route :math:`r`:

.. math::
    (1)\quad \min \sum_r \lambda_r \quad\text{s.t.}\quad
    (2)\ \sum_r a_{ir}\lambda_r \ge 1 \ (i \in N), \qquad
    (3)\ \lambda_r \in \{0, 1\}.

Every solution of the coverage problem with routes within :math:`U` is a solution of
(1)-(3), and every solution of (1)-(3) shortcuts (first visits only; by the triangle
inequality no route gets longer) to a coverage solution with no more routes. So the
optimum of (1)-(3) is the fewest robots within :math:`U` (Ghannam, Mexi, Lam and Gleixner
2024, arXiv:2401.17937, solve the depot-free relative of this problem this way).

Column generation
-----------------
The LP relaxation of (1)-(3) over a restricted set of columns (the master, HiGHS) gives
duals :math:`\pi \ge 0`; the pricing (:class:`milp.branchprice.ngroute.Pricing`) returns routes with
:math:`\sum_i a_{ir}\pi_i > 1` and the largest such prize :math:`M`. Farley's bound
:math:`\sum_i \pi_i / \max(M, 1)` is a lower bound on the LP for *any* :math:`\pi \ge 0`
(Farley 1990, Oper. Res. 38; see :mod:`milp.branchprice.colgen`), so each exact pricing certifies a
bound, and the node is closed as soon as its rounded-up bound exceeds the target. Columns
are kept in one pool for the whole search (:class:`milp.branchprice.columns.Pool`; every node and
every budget reuses those that fit). Pricing is heuristic first (fast dominance) and
exact only when the heuristic finds nothing, and the duals are smoothed towards the best
certificate so far (Wentges 1997, Int. Trans. Oper. Res. 4), and before any certificate
exists towards their own moving average (Neame's smoothing, :data:`NEAME_SMOOTHING`); a
smoothed round that prices out nothing for the true duals is repeated with the true duals.
A master with no solution (a KPOI no column at the node covers, or the subset-row cuts of
an ancestor against the columns the branching left) goes through phase one first: the
duals of the LP with an artificial column per KPOI price in the routes it lacks (Farkas
pricing), and when an exact pricing finds none the node's LP has no solution and it closes
(:meth:`BranchAndPrice._phase_one`).
A heuristic pricing certifies a (weaker) bound too: the pricing's completion table bounds
every elementary route's prize (:func:`milp.branchprice.ngroute.walk_bound`), and Farley's
bound with that maximum is valid (:data:`PRIZE_BOUND_CERTIFICATES`; so is an exact pricing's
stopped by the clock, with the least best prize of its complete labellings); such a bound closes nodes and
is reported, but only exact certificates decide that an LP is solved and serve as the
stability center. At the root of the fewest-robots search every certificate that proves
more routes than the last is told at once to the caller (:func:`min_robots`' ``proven``),
each complete labelling of a long exact pricing included, so that a race's other entrant
whose routes meet it need not wait for the root LP to be solved.

Subset-row cuts
---------------
A solved fractional LP is strengthened by subset-row cuts on triples :math:`S` of KPOIs,

.. math::
    (5)\quad \sum_r \alpha_{Sr} \lambda_r \le 1,

valid for every partition into elementary routes (at most one route can visit two of
three KPOIs; Jepsen, Petersen, Spoorendonk and Pisinger 2008, Oper. Res. 56(2)), with the
limited-memory coefficients of :func:`milp.branchprice.ngroute.cut_coefficients` (Pecin, Pessoa,
Poggi and Uchoa 2017): the memory of a cut is its triple and the KPOIs the current
solution's routes visit between two of its KPOIs (separation: :mod:`milp.branchprice.cuts`). The
pricing carries one parity bit per cut; the cut duals :math:`\sigma \le 0` enter Farley's
bound as :math:`(\sum_i \pi_i + \sum_S \sigma_S) / \max(M, 1)`. At most :data:`milp.branchprice.ngroute.MAX_CUTS`
cuts in all and :data:`CUTS_PER_KPOI` per KPOI, and only for LP solutions of at least
:data:`CUT_MIN_ROUTES` routes: each parity bit splits the labels a dominance test can
compare (measured: unlimited cuts made a 12-KPOI, 2-path search 200x slower, while the
fewest-robots cells at n = 50 closed at the root).

Branching
---------
On arc flows :math:`x_{ij} = \sum_r \lambda_r [r \text{ uses } (i, j)]`, arcs from the
start and arcs to the end of a route included (for tours on edge flows
:math:`x_{ij} + x_{ji}`, a tour and its reverse being one tour): the most fractional arc
is forbidden in one child (``x = 0``; for tours both directions) and imposed in the other
(``x = 1``: ``i`` is followed by ``j`` in every route through ``i`` and ``j`` preceded by
``i``), both enforced in the pricing by removing arcs, so that the pricing keeps its
structure (:class:`milp.branchprice.columns.Node`). Every coverage solution (elementary routes, one
visit per KPOI) lies in one child. Only arcs whose two children both exclude part of the
master's solution are branched on: the master covers (a KPOI may be covered twice), and an
arc into a KPOI carrying 1.5 with no other arc into it keeps the whole solution in the
imposed child (seen: 20 KPOIs, 5 paths, a chain of 970 such nodes). Depth first, imposing first (finds solutions early). A
node whose arc flows are integral but whose :math:`\lambda` is not cannot be branched on.
Such a master mixes routes that share their arcs: a tour and its reverse, or two routes
through a KPOI at no extra length (on the segment between its neighbours) in both pairings
of their tails. Then a few of its positive columns usually cover every KPOI with the
node's LP value, so the fewest that do (:meth:`BranchAndPrice.support_covering`) answer
the node when they meet its bound; otherwise the node is left open and the search ends
unproven (status ``feasible``), never with a wrong claim.

Route enumeration
-----------------
A node whose LP bound ``z`` leaves a gap ``k - z`` below 1 route can be answered without
branching: only routes of reduced cost at most the gap can be in a solution of at most
``k`` routes, so :mod:`milp.branchprice.enumeration` lists their KPOI sets (when there are not too
many) and a set-covering MIP over them (HiGHS) finds the node's fewest routes (Baldacci,
Christofides and Mingozzi 2008; Baldacci, Mingozzi and Roberti 2011). Tried from the
root down, for targets in :data:`ENUMERATION_ROUTES`, after the root's primal side (a
decision that the integer master answers needs no listing; the listing, largest while
the budget is far above the optimum, is kept for the decisions that need a proof). In a
makespan decision the listed sets also hold every route of any better solution, so
covering MIPs over the sets within shorter and shorter lengths find the node's least
makespan; at the root that ends the search (:mod:`milp.branchprice.makespan`).

Primal side: the incumbent comes from the caller (``warm_start``, e.g. parcover's
``best``), from integral master solutions, and from the master solved as an integer
program over the pool (price-and-branch) at the root, and again below it whenever the
pool has grown :data:`milp.branchprice.tree.POOL_GROWTH` times.
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass

import highspy
import numpy as np
from scipy import sparse

from milp.bounds import robots_lower_bound as tree_robots_bound
from milp.branchprice import colgen, enumeration, ngroute
from milp.branchprice.columns import Node, Pool
from milp.branchprice.compiling import (
    COMPILE_SECONDS,
    announce_compiling,
    compile_rarely_used,
    ready_within,
)
from milp.branchprice.cuts import cut_memory, popcount, violated_triples
from milp.branchprice.tree import (
    ROUND,
    Decision,
    Ending,
    Improve,
    Settled,
    Why,
    rounded_up,
    share_text,
)
from milp.core.highs import make_lp, new_highs
from milp.core.merge import Merged, checked_start, merge_zero_distances, model_result
from milp.core.progress import Every
from milp.core.result import MilpResult
from milp.core.routes import (
    ABS_TOL,
    REL_TOL,
    check_distance_matrix,
    first_visits,
    least_makespan,
    makespan,
)
from milp.core.sizes import BRANCHPRICE_MAX_KPOIS
from milp.core.timelimit import stop_requested

log = logging.getLogger(__name__)

__all__ = ["min_robots", "prepared", "BranchAndPrice", "LpOutcome", "ready_within", "compile_pricing",
           "MAX_KPOIS", "COMPILE_SECONDS"]

#: Largest number of (merged) KPOIs (:data:`milp.core.sizes.BRANCHPRICE_MAX_KPOIS`).
MAX_KPOIS = BRANCHPRICE_MAX_KPOIS
#: Relative tolerance of certificates (round-off in sums of duals).
CERT_TOL = 1e-9
#: Weight of the stability center in the pricing duals.
SMOOTHING = 0.5
#: Before any exact pricing has certified a bound (no stability center), the pricing duals
#: are smoothed toward the previous round's smoothed duals with this weight (Neame's
#: smoothing, a dual point moving average; Pessoa, Sadykov, Uchoa and Vanderbeck 2018,
#: "Automation and combination of linear-programming based stabilization techniques in
#: column generation", INFORMS J. Comput. 30). Measured on 100-KPOI roots (milp/README.md).
NEAME_SMOOTHING = 0.8
#: Pricings that are not exact certify Farley's bound too, with their certified bound on
#: every elementary route's prize (:attr:`milp.branchprice.ngroute.PricingResult.prize_bound`:
#: the completion table's walk bound, or a complete DSSR labelling's best when the clock
#: stopped a later one): a node can close, and an unproven root reports a bound, before
#: any exact pricing finishes. Only
#: exact certificates tell when the LP is solved (stopping column generation at such a
#: bound's ceiling leaves worse LPs to branch on), and only they become the smoothing's
#: stability center: measured on 100-KPOI roots (milp/README.md), a center from the
#: weaker certificates made the heuristic column generation tail off (clustered
#: tours within 2 c_max: not converged after 179 pricings in 60 s, against 133 without).
PRIZE_BOUND_CERTIFICATES = True
#: A makespan decision asks for routes within ``Z * (1 - STRICT)``; a makespan within
#: ``1 + STRICT`` of a lower bound counts as proven (the relative tolerance of every exact
#: method here).
STRICT = 1e-9
#: The LP counts as solved when the certified bound is within this relative distance of its
#: value: Farley's bound reaches the LP value only in the limit, and HiGHS' duals are exact
#: only to its own tolerances.
LP_SOLVED = 1e-7
#: A priced route enters the master only when its prize exceeds 1 by this much (reduced
#: cost below ``-PRICES_OUT``): a route that prices out by round-off would be added again
#: and again.
PRICES_OUT = 1e-9
#: The phase-one LP's value at which the master counts as feasible (HiGHS' primal
#: feasibility tolerance, 1e-7, is on each row; this is their sum's scale)
PHASE_ONE_FEASIBLE = 1e-6
#: Statuses of a master with no solution: infeasible (presolve may not tell it from
#: unbounded), or "empty" when no column fits the node (its rows still ask for a cover)
INFEASIBLE = (highspy.HighsModelStatus.kInfeasible, highspy.HighsModelStatus.kUnboundedOrInfeasible,
              highspy.HighsModelStatus.kModelEmpty)
#: Strong branching counts a child's gain as at least this, so that the product of the two
#: gains still ranks the arcs when one child does not raise the LP value.
LEAST_GAIN = 1e-6
#: Share of the time left (and a cap in seconds) for each run of the integer master.
MASTER_IP_SHARE, MASTER_IP_CAP = 0.1, 5.0
#: Subset-row cuts added per round (at most :data:`milp.branchprice.ngroute.MAX_CUTS` in all: the
#: pricing's parity bits), and the least violation that counts.
CUTS_PER_ROUND, CUT_VIOLATION = 8, 0.05
#: A KPOI belongs to at most this many cuts' triples.
CUTS_PER_KPOI = 4
#: Cuts only for LP solutions with at least this many routes: with few long routes the
#: parity bits cost the labelling more than the cuts gain (measured on the n = 30-50
#: grid: k = 3-5 makespan cells 2-10x slower with cuts, tours within 1.2 x 2 c_max
#: (4 routes) unproven in 10 s; fewest robots with 6-12 routes closed at the root).
CUT_MIN_ROUTES = 6
#: Strong branching scores this many of the most fractional arcs (1: no scoring).
STRONG_CANDIDATES = 8
#: A lambda or an arc flow within this of an integer counts as integral.
INTEGRAL = 1e-6
#: Route enumeration (:mod:`milp.branchprice.enumeration`) at a node whose LP leaves a gap below
#: this many routes ...
ENUMERATION_GAP = 1.0
#: ... for targets in this range of routes: with 2 the covering MIPs over long routes are
#: slow (n = 20, k = 2 paths, tests/milp/test_counting.py: 34.9 s with enumeration,
#: against 2.5 s without); with 6 or more (fewest robots at n = 50, where the subset-row
#: cuts work) it lost 4 of 36 questions proven within 10 s and won 3.
ENUMERATION_ROUTES = (3, CUT_MIN_ROUTES - 1)
#: It gives up past this many partial routes (memory: a listing that gave up at 20 M
#: peaked at 6.1 GB), or this many (set, last KPOI) states at the threshold (the
#: maximal-set filter grows with them) ...
ENUMERATION_STATES, ENUMERATION_SETS = 8_000_000, 2_500_000
#: ... or when more than this many of its sets are maximal (the covering MIP's columns):
#: the Necula cell eil51 m = 5 (tours) listed 790,093 sets at the root, 74,132 maximal,
#: whose MIP ran 78 s and settled nothing (the root's children, at smaller gaps, were then
#: answered in 3 s each), while the MIPs that answered nodes on the n = 30-40 grid had at
#: most about 7,000 ...
ENUMERATION_MAXIMAL = 20_000
#: ... or when its share of the time is spent: the share of the time left that a node's
#: listing and its covering MIPs may take (whether a listing pays depends on the MIPs
#: after it more than on its size).
ENUMERATION_SHARE = 0.25
#: ... and is then tried again only where the gap is below this times the gap it gave up at,
#: in this search's later decisions too (a least makespan's decisions have budgets within a
#: fraction of a percent of each other: n = 40 k = 5 tours, `parcover generate random --n 40
#: --seed 163`, gave up at gaps 0.50, 0.36, 0.35 and 0.25 in four decisions, 28 s in all).
ENUMERATION_RETRY = 0.5
#: Prize slack of the enumeration threshold (round-off in sums of duals).
ENUMERATION_SLACK = 1e-9


@dataclass
class LpOutcome:
    """Column generation at one node: the certified bound, the master's value and
    solution over ``columns`` (pool indices), and why it stopped."""

    bound: float
    value: float
    columns: list[int]
    x: np.ndarray
    why: Why
    master: highspy.Highs | None = None  # the master LP just solved (set when why is Why.SOLVED)
    duals: np.ndarray | None = None  # (pi, sigma) certifying ``bound`` (scaled by Farley's M)


class BranchAndPrice:
    """Column generation and branching over one pool (merged matrix, route kind): the
    :class:`milp.branchprice.tree.Search` that :class:`milp.branchprice.tree.Decision` drives.
    ``ends_at``: a ``time.perf_counter()`` value at which every phase stops (None: no
    limit); :meth:`until` gives one phase an earlier end."""

    def __init__(self, D: np.ndarray, *, tours: bool, ends_at: float | None) -> None:
        announce_compiling()
        self.m = len(D) - 1
        self.tours = tours
        self.pricing = ngroute.Pricing(D, tours=tours, ng_size=ngroute.NG_SIZE)
        self.pool = Pool(D, tours=tours)
        self.pool.add([np.array([j]) for j in range(1, self.m + 1)])
        self.ends_at = ends_at
        self.nodes = 0
        compile_rarely_used()
        self.cuts: list[tuple[int, int, int]] = []
        self.cut_bits = np.zeros(self.m + 1, dtype=np.uint64)  # bit t: in cut t's triple
        self.cut_memory = np.zeros(self.m + 1, dtype=np.uint64)  # bit t: in cut t's memory
        self.enumeration_gap = ENUMERATION_GAP  # enumerate at nodes with a smaller LP gap (all decisions)
        self.makespan_bound = 0.0  # a lower bound on the least makespan (for min_makespan)
        self.prize_bound_raised = 0  # bounds raised by certificates of pricings not exact
        #: Called with the fewest routes each certificate at the root proves, as soon as one
        #: proves more than the last (:meth:`_root_certified`); None: nobody listens.
        self.root_bound_listener: Callable[[int], None] | None = None
        self.root_bound_told = 0
        #: Polled between pricing rounds and nodes for routes another method found that
        #: answer the tree's question (merged indices: fewer routes than the tree's best,
        #: within the deadline; for a makespan decision, at most ``k`` routes within its
        #: budget), or None; None: nobody hands any (:meth:`routes_elsewhere`).
        self.elsewhere: Callable[[], list[list[int]] | None] | None = None
        self.handed: list[list[int]] | None = None  # polled, not yet taken by the tree
        self.taken: list[list[int]] | None = None  # the last routes the tree took
        #: The share of the last decision's tree closed (tree.Decision.closed_share); None
        #: before the first decision
        self.tree_closed: float | None = None
        #: The last decision's tree when the time limit stopped it short of an ending
        #: (:attr:`tree.Decision.resumable`), for :meth:`fewest_routes` to resume; else None
        self.stopped: Decision | None = None
        self.progress = Every(log)  # column generation's progress lines (--log)

    @contextmanager
    def until(self, ends_at: float | None) -> Iterator[None]:
        """Within the ``with`` block the search stops at ``ends_at`` (a ``time.perf_counter()``
        value; None: no limit) instead of its own end, which holds again after it."""
        own, self.ends_at = self.ends_at, ends_at
        try:
            yield
        finally:
            self.ends_at = own

    def _poll_elsewhere(self) -> list[list[int]] | None:
        """The latest routes :attr:`elsewhere` handed over that the tree has not taken."""
        if self.elsewhere is not None and (routes := self.elsewhere()) is not None:
            log.info("branch-and-price: %d routes from another method", len(routes))
            self.handed = routes
        return self.handed

    def routes_elsewhere(self) -> list[list[int]] | None:
        """Routes another method found (:attr:`elsewhere`) not taken yet, taken now: the
        tree makes them its incumbent (None: none new)."""
        routes, self.handed = self._poll_elsewhere(), None
        if routes is not None:
            self.taken = routes
        return routes

    def whose(self, routes: list[list[int]] | None) -> str:
        """What an answer's message adds when ``routes`` are the last the tree took from
        another method."""
        return " (routes from another method)" if routes is not None and routes is self.taken else ""

    def unproven(self, routes: list[list[int]] | None) -> str:
        """The message of an answer left unproven with ``routes``: why the search stopped
        and how much of its last tree it had closed (:attr:`tree_closed`), when one ran."""
        why = "time limit" if self.out_of_time() else "a node could not be branched on"
        closed = "" if self.tree_closed is None else f", {share_text(self.tree_closed)} of the last tree closed"
        return f"{why}{closed}{self.whose(routes)}"

    @contextmanager
    def handing(self, elsewhere: Callable[[], list[list[int]] | None]) -> Iterator[None]:
        """Within the ``with`` block the search polls ``elsewhere`` (:attr:`elsewhere`)."""
        self.elsewhere, self.handed = elsewhere, None
        try:
            yield
        finally:
            self.elsewhere, self.handed = None, None

    def out_of_time(self) -> bool:
        # stop_requested: a race's other entrant proved the answer (milp.race.race_here)
        return stop_requested() or (self.ends_at is not None and time.perf_counter() >= self.ends_at)

    def left(self) -> float | None:
        if stop_requested():  # as out_of_time
            return 0.0
        return None if self.ends_at is None else max(self.ends_at - time.perf_counter(), 0.0)

    def price(self, prize: np.ndarray, budget: float, node: Node, *, exact: bool,
              threshold: float = 1.0, cut_bits: np.ndarray | None = None,
              cut_memory: np.ndarray | None = None,
              penalties: np.ndarray | None = None,
              on_prize_bound: Callable[[float], None] | None = None) -> ngroute.PricingResult:
        """One pricing at ``node``, stopped by the search's time limit (``on_prize_bound``: as
        :meth:`milp.branchprice.ngroute.Pricing.price`)."""
        return self.pricing.price(prize, budget, allowed=node.allowed, can_end=node.allowed[:, 0],
                                  exact=exact, threshold=threshold,
                                  ends_at=math.inf if self.ends_at is None else self.ends_at,
                                  cut_bits=cut_bits, cut_memory=cut_memory, penalties=penalties,
                                  on_prize_bound=on_prize_bound)

    def _master(self, columns: list[int], *, phase_one: bool = False) -> highspy.Highs:
        """The LP (1)-(2) over ``columns`` of the pool, with the subset-row cuts (5). With
        ``phase_one``, the LP of phase one instead: the columns cost 0, and each KPOI
        has an artificial column of cost 1 that covers it, so the LP is feasible and its
        value is 0 exactly when the master is."""
        h = new_highs(None)
        rows, n = self.m + len(self.cuts), len(columns)
        matrix, cost = self._matrix(columns), np.ones(n)
        if phase_one:
            matrix = sparse.hstack([matrix, sparse.eye(rows, self.m)]).tocsc()
            cost = np.concatenate((np.zeros(n), np.ones(self.m)))
        lp = make_lp(cost, (np.zeros(len(cost)), np.full(len(cost), np.inf)), matrix,
                     (np.concatenate((np.ones(self.m), np.full(len(self.cuts), -np.inf))),
                      np.concatenate((np.full(self.m, np.inf), np.ones(len(self.cuts))))),
                     np.zeros(len(cost), dtype=bool))
        h.passModel(lp)
        return h

    def _duals(self, h: highspy.Highs) -> np.ndarray:
        """``(pi, sigma) >= 0`` of a solved master ``h``: the covering duals, and the cut
        duals with their sign turned."""
        row_dual = np.asarray(h.getSolution().row_dual, dtype=np.float64)
        return np.concatenate((np.maximum(row_dual[:self.m], 0.0), np.maximum(-row_dual[self.m:], 0.0)))

    def _coverage(self, columns: list[int]) -> sparse.csc_matrix:
        """Visit counts ``a_ir`` of ``columns`` (rows KPOIs ``1..m``)."""
        orders = [self.pool.orders[c] for c in columns]
        rows = np.concatenate(orders) - 1 if orders else np.zeros(0, dtype=np.int64)
        cols = np.repeat(np.arange(len(orders)), [len(o) for o in orders])
        return sparse.csc_matrix((np.ones(len(rows)), (rows, cols)), shape=(self.m, len(orders)))

    def _matrix(self, columns: list[int]) -> sparse.csc_matrix:
        """Rows of the master: visit counts (2), then each cut's coefficients (5)."""
        coverage = self._coverage(columns)
        if not self.cuts:
            return coverage
        rows = ngroute.cut_coefficients([self.pool.orders[c] for c in columns], self.cut_bits,
                                        self.cut_memory, len(self.cuts))
        return sparse.vstack([coverage, sparse.csr_matrix(rows)]).tocsc()

    def solve_node(self, node: Node, budget: float, target: float) -> LpOutcome:
        """Column generation at ``node`` until its bound exceeds ``target`` (closed), the
        LP is solved, or time runs out; a solved fractional LP is strengthened by
        subset-row cuts and solved again while new violated cuts are found."""
        self.nodes += 1
        columns = self.pool.fitting(budget, node)
        outcome = LpOutcome(0.0, math.inf, columns, np.zeros(0), Why.STALLED)  # nothing solved yet
        while True:
            outcome = self._column_generation(node, budget, target, columns, outcome)
            if (outcome.why != Why.SOLVED or rounded_up(outcome.bound) > target
                    or self.integral_routes(outcome) is not None or not self._separate(outcome)):
                return outcome

    def _column_generation(self, node: Node, budget: float, target: float, columns: list[int],
                           known: LpOutcome, *, converge: bool = False) -> LpOutcome:
        """Column generation over the master with the current cuts (``known``: a bound
        already certified at this node, with its duals). It stops when the certified
        bound rounds up to the LP value's integer or, with ``converge``, when it reaches
        the LP value (the duals then price out exactly). Past the time limit it solves no
        master LP: it returns ``known`` (on entry) or the last master's outcome (after a
        pricing), so that a call ends at its limit and not one master solve later. With
        logging on, a line every :data:`milp.core.progress.PROGRESS_SECONDS`: the master's
        value and the certified bound, the pricing rounds, the columns and cuts."""
        if self.out_of_time():
            return LpOutcome(known.bound, known.value, columns, known.x, Why.TIME_LIMIT, None, known.duals)
        h = self._master(columns)
        bound, center, certificate = known.bound, None, known.duals
        if certificate is not None:  # cuts added since: their duals 0 certify the same bound
            certificate = np.concatenate((certificate, np.zeros(self.m + len(self.cuts) - len(certificate))))
        # the best certificate from a pricing not exact (PRIZE_BOUND_CERTIFICATES): it closes
        # the node and is reported when above ``bound``, but only exact certificates tell
        # when the LP is solved
        weak, weak_duals = -math.inf, None
        rounds, smoothed = 0, None

        def outcome(why: Why, master: highspy.Highs | None = None) -> LpOutcome:
            if weak > bound:
                return LpOutcome(weak, value, columns, x, why, master, weak_duals)
            return LpOutcome(bound, value, columns, x, why, master, certificate)

        while True:
            h.run()
            if h.getModelStatus() in INFEASIBLE:
                stopped = self._phase_one(h, node, budget, columns)
                if stopped == Why.CLOSED:
                    return LpOutcome(math.inf, math.inf, columns, np.zeros(0), Why.CLOSED)
                if stopped is not None:
                    return LpOutcome(known.bound, known.value, columns, known.x, stopped, None, known.duals)
                continue
            assert h.getModelStatus() == highspy.HighsModelStatus.kOptimal, "master LP not solved"
            value = float(h.getInfo().objective_function_value)
            duals = self._duals(h)
            x = np.asarray(h.getSolution().col_value, dtype=np.float64)
            if self.progress.due():
                log.info("column generation, node %d: LP %.6g routes, bound %.6g, after %d pricing rounds "
                         "(%d columns, %d cuts)", self.nodes, value, max(bound, weak, 0.0), rounds,
                         len(columns), len(self.cuts))
            rounds += 1
            if (handed := self._poll_elsewhere()) is not None:  # the tree takes them (tree.Decision)
                target = min(target, len(handed) - 1)
            if ((rounded_up(bound) >= rounded_up(value) and not converge)
                    or bound >= value * (1 - LP_SOLVED)):
                return outcome(Why.SOLVED, h)
            if self.out_of_time():
                return outcome(Why.TIME_LIMIT)
            found, previous = 0, smoothed
            smoothed = duals if previous is None else NEAME_SMOOTHING * previous + (1 - NEAME_SMOOTHING) * duals
            for y, exact in self._duals_to_try(duals, center, None if previous is None else smoothed):
                res = self._price_duals(y, budget, node, exact=exact,
                                        threshold=self._closing_prize(y, target) if exact else 1.0,
                                        on_prize_bound=self._root_listener(node, y))
                if res.exact:
                    certified = self._farley(y, res.best)
                    if certified > bound:
                        bound, center = certified, y / max(res.best, 1.0)
                        certificate = center
                elif PRIZE_BOUND_CERTIFICATES and math.isfinite(res.prize_bound):
                    certified = self._farley(y, res.prize_bound)
                    if certified > max(weak, bound):
                        weak, weak_duals = certified, y / max(res.prize_bound, 1.0)
                        self.prize_bound_raised += 1
                if node.depth == 0:
                    self._root_certified(max(bound, weak))
                if rounded_up(max(bound, weak)) > target:
                    return outcome(Why.CLOSED)
                useful = [r for r in res.routes if self._route_value(r, duals) > 1 + PRICES_OUT]
                found = self._append(h, columns, useful, budget, node)
                if found:
                    break
            if found and self.out_of_time():
                return outcome(Why.TIME_LIMIT)
            if not found:
                # the true duals priced out exactly: bound = the dual value = value, unless
                # the clock stopped the exact pricing
                why = (Why.SOLVED if bound >= value * (1 - LP_SOLVED)
                       else Why.TIME_LIMIT if self.out_of_time() else Why.STALLED)
                return outcome(why, h)

    def _root_listener(self, node: Node, y: np.ndarray) -> Callable[[float], None] | None:
        """For a pricing at the root with duals ``y``, when someone listens
        (:attr:`root_bound_listener`): what tells them Farley's bound (4) of each prize
        bound the pricing certifies on its way."""
        if self.root_bound_listener is None or node.depth != 0:
            return None
        return lambda prize_bound: self._root_certified(self._farley(y, prize_bound))

    def _root_certified(self, bound: float) -> None:
        """Tell :attr:`root_bound_listener` the routes a certified bound of the root LP
        proves, when more than it was told before."""
        rounded = rounded_up(bound)
        if self.root_bound_listener is not None and math.isfinite(rounded) and rounded > self.root_bound_told:
            self.root_bound_told = int(rounded)
            log.info("branch-and-price: the root's certificates prove at least %d routes", self.root_bound_told)
            self.root_bound_listener(self.root_bound_told)

    def _farley(self, y: np.ndarray, best: float) -> float:
        """Farley's bound (4) for duals ``y = (pi, sigma)`` whose best route prize is ``best``:
        the dual objective ``sum(pi) - sum(sigma)`` over ``max(best, 1)``."""
        return float(y[:self.m].sum() - y[self.m:].sum()) / (max(best, 1.0) * (1 + CERT_TOL))

    def _closing_prize(self, y: np.ndarray, target: float) -> float:
        """The prize a route must beat for duals ``y`` to leave the node open: when no
        route's prize exceeds it, Farley's bound (4) is above ``target`` and the node
        closes. At least 1 (a column must price out). Pricing with it as threshold prunes
        every label that could only reach prizes between 1 and it (early termination of
        column generation by the Lagrangian bound, Desaulniers, Desrosiers and Solomon,
        "Column Generation", 2005, ch. 1)."""
        dual_objective = float(y[:self.m].sum() - y[self.m:].sum())
        closing = dual_objective / ((1 + CERT_TOL) * (target + 2 * ROUND))
        return max(1.0, closing)

    def _price_duals(self, y: np.ndarray, budget: float, node: Node, *, exact: bool,
                     threshold: float = 1.0,
                     on_prize_bound: Callable[[float], None] | None = None) -> ngroute.PricingResult:
        """Pricing for duals ``y = (pi, sigma)``: prizes ``pi``, cut penalties ``sigma``;
        routes whose prize exceeds ``threshold``."""
        penalties = np.zeros(ngroute.MAX_CUTS)
        penalties[:len(self.cuts)] = y[self.m:]
        return self.price(np.concatenate(([0.0], y[:self.m])), budget, node, exact=exact,
                          threshold=threshold, cut_bits=self.cut_bits, cut_memory=self.cut_memory,
                          penalties=penalties, on_prize_bound=on_prize_bound)

    def _route_value(self, route: np.ndarray, y: np.ndarray) -> float:
        """A route's prize under duals ``y``: its visits' ``pi`` minus its cuts' ``sigma``
        (times the cut's coefficient)."""
        value = float(y[route - 1].sum())
        if self.cuts:
            alpha = ngroute.cut_coefficients([route], self.cut_bits, self.cut_memory, len(self.cuts))
            value -= float(y[self.m:] @ alpha[:, 0])
        return value

    def _separate(self, outcome: LpOutcome) -> bool:
        """Add the subset-row cuts (5) most violated by the master's solution; whether
        any was added."""
        room = ngroute.MAX_CUTS - len(self.cuts)
        if room <= 0 or outcome.value < CUT_MIN_ROUTES:
            return False
        support = np.flatnonzero(outcome.x > INTEGRAL)
        counts = self._coverage([outcome.columns[i] for i in support]).T.toarray()
        found = violated_triples(counts, outcome.x[support], CUT_VIOLATION)
        known = set(self.cuts)
        fresh = [t for t in (tuple(int(v) + 1 for v in row) for row in found) if t not in known]
        routes = [self.pool.orders[outcome.columns[i]] for i in support]
        added = 0
        for triple in fresh:
            if added == min(room, CUTS_PER_ROUND):
                break
            if any(popcount(self.cut_bits[j]) >= CUTS_PER_KPOI for j in triple):
                continue  # more cuts on a KPOI multiply the labels its parities tell apart
            added += 1
            bit = np.uint64(1) << np.uint64(len(self.cuts))
            self.cuts.append(triple)
            for kpoi in cut_memory(triple, routes):
                self.cut_memory[kpoi] |= bit
            for kpoi in triple:
                self.cut_bits[kpoi] |= bit
        return added > 0

    def _phase_one(self, h: highspy.Highs, node: Node, budget: float, columns: list[int]) -> Why | None:
        """Make the infeasible master ``h`` feasible: phase one of column generation. Its
        columns at ``node`` (there may be none) may leave a KPOI uncovered, or cover them only against
        the subset-row cuts (5) (cuts found at an ancestor, with the columns the
        branching left). The duals ``(pi, sigma)`` of the phase-one LP (:meth:`_master`)
        price in the routes whose prize under them is positive (Farkas pricing), added to
        ``h``, until that LP's value is 0. None when ``h`` is feasible again; otherwise
        why not: :attr:`Why.CLOSED` when an exact pricing finds no such route (by Farkas'
        lemma the node's LP has no solution), :attr:`Why.TIME_LIMIT` when the pricing
        was cut short, :attr:`Why.STALLED` when it found only routes already held."""
        added = 0
        while True:
            phase = self._master(columns, phase_one=True)
            phase.run()
            assert phase.getModelStatus() == highspy.HighsModelStatus.kOptimal, "phase-one LP not solved"
            if phase.getInfo().objective_function_value <= PHASE_ONE_FEASIBLE:
                return None if added else Why.STALLED  # stalled: feasible here, not in h
            y = self._duals(phase)
            res = self._price_duals(y, budget, node, exact=True, threshold=PRICES_OUT)
            useful = [r for r in res.routes if self._route_value(r, y) > PRICES_OUT]
            if not useful:
                return Why.CLOSED if res.exact else Why.TIME_LIMIT
            found = self._append(h, columns, useful, budget, node)
            if not found:
                return Why.STALLED
            added += found

    def _duals_to_try(self, duals: np.ndarray, center: np.ndarray | None, moving: np.ndarray | None):
        """Heuristic then exact pricing, at smoothed duals first, then at the true duals
        (which decide whether the LP is solved). With a stability ``center`` (an exact
        certificate) the duals are smoothed toward it (Wentges); before one exists, a
        heuristic pricing at the ``moving`` average of the past duals comes first (Neame,
        :data:`NEAME_SMOOTHING`)."""
        if center is not None:
            smooth = SMOOTHING * center + (1 - SMOOTHING) * duals
            yield smooth, False
            yield smooth, True
        elif moving is not None:
            yield moving, False
        yield duals, False
        yield duals, True

    def _append(self, h: highspy.Highs, columns: list[int], routes: list[np.ndarray],
                budget: float, node: Node) -> int:
        """Add ``routes`` to the pool and, when they fit, to the master ``h``."""
        fresh = self.pool.fitting(budget, node, self.pool.add(routes))
        if fresh:
            matrix = self._matrix(fresh).tocsc()
            h.addCols(len(fresh), np.ones(len(fresh)), np.zeros(len(fresh)),
                      np.full(len(fresh), highspy.kHighsInf), matrix.nnz,
                      matrix.indptr[:-1].astype(np.int32), matrix.indices.astype(np.int32),
                      matrix.data)
            columns.extend(fresh)
        return len(fresh)

    def integral_routes(self, outcome: LpOutcome) -> list[list[int]] | None:
        """The master's solution as routes when every lambda is 0 or 1."""
        chosen = [c for c, v in zip(outcome.columns, outcome.x) if v > INTEGRAL]
        if any(abs(outcome.x[i] - 1) > INTEGRAL for i, v in enumerate(outcome.x) if v > INTEGRAL):
            return None
        return first_visits([self.pool.orders[c] for c in chosen])

    def branching_arc(self, node: Node, outcome: LpOutcome, target: int) -> tuple[int, int] | None:
        """The arc to branch on: among the :data:`STRONG_CANDIDATES` most fractional, the
        one whose two children raise the node's master LP value most (product of the
        gains, each child's value capped at ``target + 1``, where it closes). A child's
        value is the node's master with the columns it forbids fixed at 0, re-solved from
        the node's optimal basis (:meth:`_child_value`; no pricing in the children).
        Strong branching: Achterberg, Koch and Martin, "Branching rules revisited", Oper.
        Res. Letters 33 (2005)."""
        candidates = self.fractional_arcs(node, outcome)[:STRONG_CANDIDATES]
        if len(candidates) <= 1:
            return candidates[0] if candidates else None
        best, chosen = -math.inf, candidates[0]
        for arc in candidates:
            if self.out_of_time():
                break
            values = [self._child_value(outcome, child) for child in node.children(arc, tours=self.tours)]
            gains = [max(min(v, target + 1.0) - outcome.value, LEAST_GAIN) for v in values]
            if gains[0] * gains[1] > best:
                best, chosen = gains[0] * gains[1], arc
        return chosen

    def _child_value(self, outcome: LpOutcome, child: Node) -> float:
        """The node's master LP value with the columns ``child`` forbids fixed at 0,
        re-solved from the node's optimal basis (inf when infeasible); the bounds are
        restored after."""
        banned = np.flatnonzero(~self.pool.allows(child, outcome.columns)).astype(np.int32)
        if len(banned) == 0:
            return outcome.value
        h = outcome.master
        assert h is not None, "branching on a node whose master LP was not solved"
        h.changeColsBounds(len(banned), banned, np.zeros(len(banned)), np.zeros(len(banned)))
        h.run()
        solved = h.getModelStatus() == highspy.HighsModelStatus.kOptimal
        value = float(h.getInfo().objective_function_value) if solved else math.inf
        h.changeColsBounds(len(banned), banned, np.zeros(len(banned)), np.full(len(banned), highspy.kHighsInf))
        return value

    def fractional_arcs(self, node: Node, outcome: LpOutcome) -> list[tuple[int, int]]:
        """The arcs with fractional flow whose two children both exclude part of the
        master's solution, closest to 1/2 first (``(i, 0)``: ending at ``i``).

        For tours the flow of an edge is that of both its directions (the arc returned is
        the direction carrying more of it; for paths each arc is its own). In the covering master a KPOI may be covered
        more than once, and a flow fractional only by that (1.5 on the first arc to a KPOI
        at which two positive routes start) leaves the imposed child with the node's own
        solution: branching on it would repeat forever (module docstring, Branching)."""
        support = [c for c, v in zip(outcome.columns, outcome.x) if v > INTEGRAL]
        flow: dict[tuple[int, int], float] = {}
        for c, v in zip(outcome.columns, outcome.x):
            if v <= INTEGRAL:
                continue
            route = self.pool.orders[c].tolist()
            for arc in zip([0, *route], [*route, 0]):
                flow[arc] = flow.get(arc, 0.0) + v
        edges: dict[tuple[int, int], float] = {}
        for (i, j), f in flow.items():
            key = (min(i, j), max(i, j)) if self.tours else (i, j)
            edges[key] = edges.get(key, 0.0) + f
        fractional = []
        for (i, j), f in edges.items():
            if f - math.floor(f) > INTEGRAL and math.ceil(f) - f > INTEGRAL:
                forward, backward = flow.get((i, j), 0.0), flow.get((j, i), 0.0) if self.tours else 0.0
                fractional.append((abs(f - math.floor(f) - 0.5), (i, j) if forward >= backward else (j, i)))
        return [arc for _, arc in sorted(fractional)
                if not any(self.pool.allows(child, support).all() for child in node.children(arc, tours=self.tours))]

    def support_covering(self, outcome: LpOutcome) -> list[list[int]] | None:
        r"""The fewest of the master's columns with positive :math:`\lambda` that cover
        every KPOI (set covering (1)-(3) over them, HiGHS MIP, with the integer master's
        time), or None: the answer to a node that cannot be branched on (module
        docstring, Branching)."""
        orders = [self.pool.orders[c] for c, v in zip(outcome.columns, outcome.x) if v > INTEGRAL]
        return colgen.fewest_covering(orders, self.m, self._integer_master_seconds())

    def _integer_master_seconds(self) -> float:
        """:data:`MASTER_IP_SHARE` of the time left, at most :data:`MASTER_IP_CAP` seconds."""
        left = self.left()
        return MASTER_IP_CAP if left is None else max(min(MASTER_IP_CAP, MASTER_IP_SHARE * left), 0.01)

    def integer_master(self, budget: float) -> list[list[int]] | None:
        """Set covering (1)-(3) over every pooled column within ``budget`` (HiGHS MIP), for
        :data:`MASTER_IP_SHARE` of the time left (at most :data:`MASTER_IP_CAP` seconds)."""
        orders = [self.pool.orders[c] for c in np.flatnonzero(self.pool.lengths <= budget)]
        return colgen.fewest_covering(orders, self.m, self._integer_master_seconds())

    def fewest_routes(self, budget: float, incumbent: list[list[int]] | None, target: int,
                      *, first: bool, improve: Improve | None = None, floor: int = 1, resume: bool = False,
                      ) -> tuple[list[list[int]] | None, int | None, Ending]:
        """Branch-and-price for the fewest routes within ``budget``.

        Searches for routes within ``budget``, at most ``target`` of them (fewer than
        ``incumbent`` when it is given: ``target`` moves down with every better solution).
        With ``first``, returns at the first solution found; it also returns at a solution
        of ``floor`` routes (a bound the caller proved). ``improve``, when the root
        does not prove the incumbent, is asked once for routes meeting the root's bound.
        The integer master over the pool runs at the root and again below it whenever the
        pool has grown :data:`milp.branchprice.tree.POOL_GROWTH` times. With ``resume``, a
        tree the time limit stopped (:attr:`stopped`) at the same ``budget`` and ``target``
        goes on instead of a new one (a bound resumed between two runs of the makespan
        search: :func:`milp.branchprice.makespan.min_makespan`).

        Returns
        -------
        tuple
            ``(routes, root_bound, outcome)``: the best routes (``incumbent`` when none
            better), the root's certified bound rounded up, and how the tree ended
            (:class:`milp.branchprice.tree.Ending`; with :attr:`~Ending.EXHAUSTED`,
            ``target`` is one below the returned routes' count when any were found).
        """
        tree = self.stopped
        if not (resume and tree is not None and tree.budget == budget and tree.target == target):
            tree = Decision(self, budget, incumbent, target, first=first, improve=improve, floor=floor)
        outcome = tree.run()
        self.stopped = tree if outcome == Ending.UNKNOWN and tree.resumable else None
        self.tree_closed = tree.closed_share
        return tree.best, tree.root_bound, outcome

    def enumerate_node(self, node: Node, outcome: LpOutcome, budget: float, target: int, *,
                   shortest: bool) -> tuple[LpOutcome, Settled | None]:
        """Answer ``node`` by route enumeration when its LP gap allows (:mod:`milp.branchprice.enumeration`).

        The LP is first solved to the end (its duals then give the smallest gap
        ``target - z``); the sets whose route can be in a solution of at most ``target``
        routes are listed and a set-covering MIP over them finds the node's fewest routes.
        Returns the (re-solved) outcome and, when the node is answered, its best routes
        (None: none with at most ``target``; with ``shortest``, those with the least
        makespan, :meth:`_least_makespan_covering`). Gives up (None) when the listing grows past
        :data:`ENUMERATION_STATES` or holds more than :data:`ENUMERATION_MAXIMAL` maximal sets
        (the gap it gave up at then bars nodes with gaps not below :data:`ENUMERATION_RETRY`
        x it, in later decisions too) or the MIP is not solved in
        time: the listing and its MIPs get :data:`ENUMERATION_SHARE` of the time left. The
        listed sets join the pool only when the MIP answered the node: every pooled column
        within the budget enters each later master, and an undecided family of 31,764
        maximal sets (n = 40 k = 5 tours, `parcover generate random --n 40 --seed 51`) made
        the later masters and integer masters cost 9 s more."""
        low, high = ENUMERATION_ROUTES
        if not low <= target <= high or target - outcome.value >= self.enumeration_gap:
            return outcome, None
        outcome = self._column_generation(node, budget, target, outcome.columns, outcome, converge=True)
        if outcome.why not in (Why.SOLVED, Why.CLOSED) or outcome.duals is None:
            return outcome, None
        if rounded_up(outcome.bound) > target:
            return outcome, Settled(None)
        y = outcome.duals / (1 + CERT_TOL)
        gap = target - float(y[:self.m].sum() - y[self.m:].sum())
        if gap >= self.enumeration_gap:
            return outcome, None
        left = self.left()
        ends_at = math.inf if left is None else time.perf_counter() + ENUMERATION_SHARE * left
        family = enumeration.routes_within_gap(
            self.pricing.D, self.pricing.back, np.concatenate(([0.0], y[:self.m])), budget,
            1.0 - gap - ENUMERATION_SLACK, node.allowed, node.allowed[:, 0],
            max_states=ENUMERATION_STATES, max_sets=ENUMERATION_SETS, ends_at=ends_at)
        if family is None or family.count_maximal() > ENUMERATION_MAXIMAL:  # gave up, or too large a MIP
            self.enumeration_gap = ENUMERATION_RETRY * gap
            return outcome, None
        orders, lengths = family.maximal()
        decided, routes = self._covering(orders, target, ends_at)
        if not decided:
            return outcome, None
        self.pool.add(orders, lengths)
        if routes is None or not shortest:
            return outcome, Settled(routes)
        routes, least = self._least_makespan_covering(family, routes, target, ends_at)
        return outcome, Settled(routes, least)

    def _covering(self, orders: list[np.ndarray], target: int,
                  ends_at: float) -> tuple[bool, list[list[int]] | None]:
        """Set-covering MIP over ``orders``: ``(True, routes)`` with the fewest covering
        routes when at most ``target``, ``(True, None)`` when proven that none are,
        ``(False, None)`` when HiGHS settled neither by ``ends_at`` (a ``time.perf_counter()``
        value; inf: no limit)."""
        seconds = None if math.isinf(ends_at) else max(ends_at - time.perf_counter(), 0.01)
        solve, routes = colgen.covering_solve(orders, self.m, seconds)
        if solve.status == "infeasible" or (solve.bound is not None and solve.bound > target + ROUND):
            return True, None
        if solve.status != "optimal" or solve.objective is None or routes is None:
            return False, None
        return True, (routes if solve.objective <= target + ROUND else None)

    def _least_makespan_covering(self, family: enumeration.Family, routes: list[list[int]],
                                 target: int, ends_at: float) -> tuple[list[list[int]], bool]:
        """From a covering of at most ``target`` sets of ``family``, one with the least
        makespan: bisection over the family's route lengths ``T``, each step the covering
        MIP over the sets maximal within ``T`` (:meth:`enumeration.Family.maximal`). Every
        route of a solution of at most ``target`` routes at the node has its KPOI set in
        the family, no longer, so a step finding no covering proves that none has a
        makespan within ``T``. One listing thus ends a least-makespan search, where
        returning the first covering made the search take one decision per slightly
        shorter covering (measured: ten on n = 40 k = 5 paths, seed 1 of the benchmark
        grid). The first step probes just below the covering found, since it is often the
        least already: then one MIP proves it (n = 30 k = 3 tours, `parcover generate random
        --n 30 --seed 121`: one MIP, where bisecting from the bound took seven infeasible
        MIPs of 1-2 s and ran out of its time share). Returns the routes and whether they
        are proven least (False: the time ran out or a MIP was not settled)."""
        lengths = np.unique(family.lengths)
        value = makespan(self.pricing.D, routes, tours=self.tours)
        low = int(np.searchsorted(lengths, self.makespan_bound))  # lengths[:low] are too short
        probe_below = True
        while (high := int(np.searchsorted(lengths, value * (1 - STRICT)))) > low:
            if time.perf_counter() >= ends_at:
                return routes, False
            middle = high - 1 if probe_below else (low + high) // 2
            probe_below = False
            decided, better = self._covering(family.maximal(lengths[middle])[0], target, ends_at)
            if not decided:
                return routes, False
            if better is None:
                low = middle + 1
            else:
                routes, value = better, makespan(self.pricing.D, better, tours=self.tours)
        return routes, True


def compile_pricing() -> None:
    """Compile every numba function now (or load it from numba's on-disk cache) by
    solving a toy instance: for callers that time solves and should not count the
    one-off compilation (:data:`COMPILE_SECONDS`), such as the benchmarks. Afterwards
    :func:`ready_within` holds for any limit."""
    points = np.array([[0.0, 0.0], [3.0, 1.0], [1.0, 4.0], [5.0, 5.0], [6.0, 2.0]])
    D = np.linalg.norm(points[:, None] - points[None], axis=-1)
    min_robots(D, 0.6 * float(D.sum(axis=1).max()), tours=False)


def prepared(D: np.ndarray) -> tuple[np.ndarray, Merged]:
    """``D`` checked, and merged where KPOIs are at distance 0 (what both searches work on);
    ValueError above :data:`MAX_KPOIS` merged KPOIs."""
    D = check_distance_matrix(D)
    merged = merge_zero_distances(D)
    if merged.size > MAX_KPOIS:
        raise ValueError(f"branch-and-price handles at most {MAX_KPOIS} KPOIs")
    return D, merged


def min_robots(
    D: np.ndarray, deadline: float, *, tours: bool, time_limit: float | None = None,
    warm_start: list[list[int]] | None = None, improve: Improve | None = None,
    proven: Callable[[int], None] | None = None,
    elsewhere: Callable[[], list[list[int]] | None] | None = None,
) -> MilpResult:
    """Fewest routes whose costs all meet ``deadline``, by branch-and-price.

    Parameters
    ----------
    D : numpy.ndarray
        ``(n+1, n+1)`` metric distance matrix, index 0 the start.
    deadline : float
        The largest route cost allowed (shared tolerance of :func:`milp.core.routes.within`).
    tours : bool
        Tours (return to 0) or open paths.
    time_limit : float, optional
        Seconds for the whole call.
    warm_start : list of list of int, optional
        Routes (KPOIs ``1..n``) within the deadline: the first incumbent.
    improve : callable, optional
        When the root's bound does not prove the incumbent, called once with that bound
        (rounded up) and the seconds the root took: routes within the deadline that meet
        the bound, if it finds some (a heuristic that only runs when the bound leaves
        room: the warm start can be cheap).
    proven : callable, optional
        Called with the fewest routes the root's certificates prove, each time they prove
        more, as soon as a pricing certifies it (during a long exact pricing too: each of
        its complete labellings certifies a bound): a race's other entrant, whose routes
        may already meet it, need not wait for the root LP to be solved.
    elsewhere : callable, optional
        Polled between pricing rounds and nodes for routes (KPOIs ``1..n``) another method
        found, or None: routes within the deadline and fewer than the tree's best become
        its incumbent, so the tree looks for one route fewer than them from then on (a
        race's other entrant finds such routes while the root LP is being solved; with the
        lower target its pricings may stop sooner, at the prize that closes the node).

    Returns
    -------
    MilpResult
        ``objective`` = number of routes; ``optimal`` when the branch-and-price tree is
        closed, else ``feasible`` with the root's certified bound.
    """
    began = time.perf_counter()
    D, merged = prepared(D)
    if deadline < least_makespan(D, tours=tours) * (1 - REL_TOL) - ABS_TOL:
        return MilpResult("infeasible", seconds=time.perf_counter() - began,
                          message="deadline below the least makespan")
    if merged.size == 0:
        return model_result("optimal", merged, D, [], 1.0, 1.0, 0, began, "every KPOI at the start")
    budget = deadline * (1 + REL_TOL) + ABS_TOL  # milp.core.routes.within
    ends_at = None if time_limit is None else began + time_limit
    search = BranchAndPrice(merged.D, tours=tours, ends_at=ends_at)
    start = checked_start(merged, D, warm_start, tours=tours, deadline=deadline, k=None)
    if start is None:
        start = [[j] for j in range(1, merged.size + 1)]
    trivial = tree_robots_bound(merged.D, deadline, tours=tours, time_limit=time_limit)
    search.root_bound_listener, search.root_bound_told = proven, trivial  # told: only what beats it
    if len(start) <= trivial:
        return model_result("optimal", merged, D, start, len(start), len(start), 0, began,
                       "warm start meets the spanning-tree / conflict-clique bound")
    log.info("branch-and-price: %d routes from the warm start, bound %d", len(start), trivial)
    handed = (lambda: None) if elsewhere is None else (
        lambda: checked_start(merged, D, elsewhere(), tours=tours, deadline=deadline, k=None))
    better = None if improve is None else (
        lambda floor, seconds: checked_start(merged, D, improve(floor, seconds), tours=tours, deadline=deadline,
                                             k=None))
    with search.handing(handed):
        routes, root, outcome = search.fewest_routes(budget, start, len(start) - 1, first=False, improve=better,
                                                     floor=trivial)
    bound = max(trivial, root or 1)
    if outcome == Ending.EXHAUSTED or len(routes) <= bound:
        return model_result("optimal", merged, D, routes, len(routes), len(routes), search.nodes, began,
                       ("branch-and-price tree closed" if outcome == Ending.EXHAUSTED else "routes meet the bound")
                       + search.whose(routes))
    return model_result("feasible", merged, D, routes, len(routes), bound, search.nodes, began,
                        search.unproven(routes))
