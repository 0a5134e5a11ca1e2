r"""Least makespan with k routes by branch-and-price: a sequence of fewest-routes decisions.

The optimum is the least :math:`U` whose fewest routes is at most :math:`k`. Starting
from the incumbent's makespan :math:`Z`, the search decides :math:`U = Z (1 - 10^{-9})`:
a solution with at most :math:`k` routes within it improves :math:`Z` (and the search
repeats); a proof that none exists proves :math:`Z` optimal (to the 1e-9 relative
tolerance of every exact method here), and so does a root answered by enumeration
(its least makespan is the optimum). A lower bound for an unproven answer comes from
bisection on the root LP bound (:math:`\lceil z(U) \rceil > k` proves :math:`U` too
small), computed first with a share of the time limit.

The decisions are those of :class:`milp.branchprice.search.BranchAndPrice` (one search, so
its column pool, cuts and grown ng-memories serve every decision).
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable

import numpy as np

from milp.bounds import makespan_lower_bound as tree_makespan_bound
from milp.branchprice import colgen
from milp.branchprice.columns import Node
from milp.branchprice.search import STRICT, BranchAndPrice, prepared
from milp.branchprice.tree import Ending, Why
from milp.core.merge import checked_start, model_result
from milp.core.result import MilpResult
from milp.core.routes import least_makespan, makespan
from milp.core.timelimit import stop_requested
from milp.warmstart import nearest_neighbour_order, split_min_makespan

log = logging.getLogger(__name__)

__all__ = ["min_makespan", "BISECTION_SHARE", "BISECTION_SECONDS", "LP_BOUND_TOL", "NG_BISECTION_FIRST"]

#: Share of a makespan time limit for the LP bisection (the bound reported if unproven),
#: and the relative width at which the bisection stops.
BISECTION_SHARE, LP_BOUND_TOL = 0.25, 1e-4
#: ... at most this many seconds: a share without a cap gave an unconverged bisection more
#: time under a longer limit and the proof after it came later (n = 40, 3 tours,
#: `parcover generate random --n 40 --seed 7`, on a loaded machine: proven at 77 s with
#: --time-limit 120, at 126 s with 300, the bisection taking 20 s and 57 s).
BISECTION_SECONDS = 30.0
#: Share of the bisection's time for the ng-route LP alone (:func:`_makespan_lp_bound`).
NG_BISECTION_FIRST = 0.25


def min_makespan(
    D: np.ndarray, k: int, *, tours: bool, time_limit: float | None = None,
    warm_start: list[list[int]] | None = None,
    elsewhere: Callable[[], list[list[int]] | None] | None = None,
) -> MilpResult:
    """Least makespan with at most ``k`` routes: a sequence of fewest-routes decisions.

    Parameters are those of :func:`min_robots` with ``k`` (routes available) in place of
    the deadline; ``warm_start`` should hold at most ``k`` routes. ``elsewhere``, polled
    between pricing rounds and nodes while the decisions run, returns routes another
    method found (KPOIs ``1..n``), or None: at most ``k`` routes with a smaller makespan
    than the best so far end the decision under way, and the next decides below them.

    Returns
    -------
    MilpResult
        ``objective`` = makespan; ``optimal`` when the decision just below it is proven
        infeasible, else ``feasible`` with the LP-bisection bound.
    """
    began = time.perf_counter()
    if k < 1:
        raise ValueError("k must be at least 1")
    D, merged = prepared(D)
    if merged.size == 0:
        return model_result("optimal", merged, D, [], 0.0, 0.0, 0, began, "every KPOI at the start")
    ends_at = None if time_limit is None else began + time_limit
    lower = max(least_makespan(D, tours=tours), tree_makespan_bound(merged.D, k, tours=tours, time_limit=time_limit))
    routes = checked_start(merged, D, warm_start, tours=tours, deadline=None, k=k)
    if routes is None:
        routes = split_min_makespan(merged.D, nearest_neighbour_order(merged.D), k, tours=tours)
    value = makespan(merged.D, routes, tours=tours)
    search = BranchAndPrice(merged.D, tours=tours, ends_at=ends_at)
    if value <= lower * (1 + STRICT):
        return model_result("optimal", merged, D, routes, value, value, 0, began,
                       "warm start meets the lower bound")
    log.info("branch-and-price: makespan %.6g from the warm start, bound %.6g (gap %s)", value, lower,
             _gap(value, lower))
    lower, cut_short = _makespan_lp_bound(
        search, k, lower, value,
        None if time_limit is None else began + min(BISECTION_SHARE * time_limit, BISECTION_SECONDS))
    search.makespan_bound = lower
    log.info("branch-and-price: root LP bound %.6g (gap %s)", lower, _gap(value, lower))
    # a bisection cut short by its cap gets the last share of the limit back after the
    # decisions (only the bound is left to gain there), so a long limit still buys the
    # bound while the decisions run the same whatever the limit; what the resumed
    # bisection leaves goes back to the decisions (the tree the stop left open goes on:
    # restarted, a tree 87.5% closed at the stop was 45% closed at the limit, uniform
    # 60 KPOIs k = 4 tours seed 1, 600 s)
    resume = cut_short and ends_at is not None
    decisions = _MakespanDecisions(search, k, routes, value)

    def better() -> list[list[int]] | None:  # routes from elsewhere that answer the decision under way
        found = None if elsewhere is None else checked_start(merged, D, elsewhere(), tours=tours, deadline=None, k=k)
        if found is None or makespan(merged.D, found, tours=tours) >= decisions.value * (1 - STRICT):
            return None
        return found

    with search.until(ends_at - BISECTION_SHARE * time_limit if resume else ends_at), search.handing(better):
        proof = decisions.run(lower)
    if proof is None and resume and decisions.timed_out and not search.out_of_time():
        # the bisection polls nothing: a node it solves must not close against handed routes
        lower = search.makespan_bound = max(lower, _makespan_lp_bound(search, k, lower, decisions.value, ends_at)[0])
        log.info("branch-and-price: root LP bound resumed: %.6g (gap %s)", lower, _gap(decisions.value, lower))
        with search.handing(better):
            proof = decisions.run(lower)
    routes, value = decisions.routes, decisions.value
    if proof is not None:
        found, bound, message = proof
        return model_result("optimal", merged, D, found, makespan(merged.D, found, tours=tours), bound,
                            search.nodes, began, message + search.whose(found))
    return model_result("feasible", merged, D, routes, value, lower, search.nodes, began, search.unproven(routes))


class _MakespanDecisions:
    """The fewest-routes decisions of :func:`min_makespan`, each below the best makespan
    found (``routes``, ``value``), while the search's time lasts."""

    def __init__(self, search: BranchAndPrice, k: int, routes: list[list[int]], value: float) -> None:
        self.search, self.k, self.routes, self.value = search, k, routes, value
        self.timed_out = False  # whether the last run stopped for the time, not at a node

    def run(self, lower: float) -> tuple[list[list[int]], float, str] | None:
        """Decide until a proof, the time limit or a node that cannot be branched on: the
        proof as (routes, bound, message), or None."""
        search = self.search
        while not search.out_of_time():
            if self.value <= lower * (1 + STRICT):
                return self.routes, self.value, "lower bound reached"
            found, _, outcome = search.fewest_routes(self.value * (1 - STRICT), None, self.k, first=True,
                                                     resume=True)
            if outcome == Ending.LEAST:
                return found, lower, "least makespan over the routes enumerated at the root"
            if outcome == Ending.FOUND:
                self.routes, self.value = found, makespan(search.pricing.D, found, tours=search.tours)
                log.info("branch-and-price: makespan %.6g, bound %.6g (gap %s), %d nodes", self.value, lower,
                         _gap(self.value, lower), search.nodes)
                continue
            if outcome == Ending.EXHAUSTED:
                return self.routes, self.value, "no solution within (1 - 1e-9) x the makespan"
            self.timed_out = search.out_of_time()
            return None
        self.timed_out = True
        return None


def _gap(value: float, bound: float) -> str:
    """The relative gap in percent, for the log."""
    return f"{100 * (value - bound) / value:.2f}%" if value > 0 else "0%"


def _makespan_lp_bound(search: BranchAndPrice, k: int, lower: float, upper: float,
                       ends_at: float | None) -> tuple[float, bool]:
    """A certified lower bound on the least makespan by ``ends_at`` (a ``time.perf_counter()``
    value; None: no limit), from ``lower`` (known too small) and ``upper`` (achievable), and
    whether the time ran out before the bisection's tolerance :data:`LP_BOUND_TOL`.

    Bisection on the root LP over ng-routes (:func:`_bisect_lp_bound`) for
    :data:`NG_BISECTION_FIRST` of the time; when that has not converged (long routes, where
    each LP takes many pricings), the bisection of :mod:`milp.branchprice.colgen` over q-routes (its
    pricing a dynamic programme over discretised lengths) from that bound for half of what
    is left, then the ng-route bisection again from the larger bound. Each relaxation's
    bound is certified; neither contains the other: the q-route bound helps where long
    routes keep the ng-route bisection from converging, and is never run where it
    converges (measurements: the decisions table of ``milp/README.md``)."""
    now = time.perf_counter()
    with search.until(None if ends_at is None else now + NG_BISECTION_FIRST * (ends_at - now)):
        lower = _bisect_lp_bound(search, k, lower, upper)
        converged = not search.out_of_time()
    if converged or ends_at is None or stop_requested():  # stop_requested: as BranchAndPrice.out_of_time
        return lower, not converged
    now = time.perf_counter()
    lower = colgen.makespan_lower_bound(search.pricing.D, k, tours=search.tours, upper=upper,
                                        time_limit=0.5 * (ends_at - now), lower=lower)
    with search.until(ends_at):
        lower = _bisect_lp_bound(search, k, lower, upper)
        return lower, search.out_of_time()


def _bisect_lp_bound(search: BranchAndPrice, k: int, lower: float, upper: float) -> float:
    """Largest makespan proven too small by the root LP (bound above ``k``), by bisection
    between ``lower`` (known too small or trivial) and ``upper`` (achievable)."""
    root = Node.root(search.m)
    while upper - lower > LP_BOUND_TOL * upper and not search.out_of_time():
        mid = 0.5 * (lower + upper)
        outcome = search.solve_node(root, mid, k)
        if outcome.why == Why.CLOSED:
            lower = mid
        elif outcome.why == Why.TIME_LIMIT:
            break
        else:
            upper = mid
    return lower
