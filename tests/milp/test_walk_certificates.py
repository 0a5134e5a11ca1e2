"""Certified bounds from heuristic pricings (milp.branchprice.ngroute.walk_bound).

The completion table's bound on every elementary route's prize must hold against brute
force (random prizes, paths and tours, branching masks), and branch-and-price with the
heuristic pricings certifying Farley's bound must agree with set partitioning, with the
certificates actually closing nodes or raising the bound (counted).
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from milp_helpers import check_solution, euclidean, graph_metric
from test_branchprice import clustered

from milp import setpart
from milp.branchprice import makespan as makespan_search
from milp.branchprice import ngroute
from milp.branchprice import search as branchprice
from milp.branchprice.ngroute import Pricing
from milp.core.routes import least_makespan


def elementary_best(D, prize, budget, tours, allowed, can_end):
    """Largest prize of an elementary route within ``budget`` using only allowed arcs."""
    m, best = len(D) - 1, 0.0
    for size in range(1, m + 1):
        for order in itertools.permutations(range(1, m + 1), size):
            stops = [0, *order]
            if not all(allowed[a, b] for a, b in zip(stops[:-1], stops[1:])) or not can_end[order[-1]]:
                continue
            length = D[stops[:-1], stops[1:]].sum() + (D[order[-1], 0] if tours else 0.0)
            if length <= budget:
                best = max(best, float(prize[list(order)].sum()))
    return best


@pytest.mark.parametrize("tours", [False, True], ids=["paths", "tours"])
@pytest.mark.parametrize("seed", range(8))
def test_walk_bound_holds_for_every_elementary_route(seed, tours):
    m = 6
    D = (euclidean, clustered, graph_metric)[seed % 3](m, seed)
    rng = np.random.default_rng(seed)
    prize = np.concatenate(([0.0], rng.uniform(0.0, 1.0, m)))
    budget = (2.0 if tours else 1.0) * D[0, 1:].max() * rng.uniform(1.0, 2.5)
    allowed = rng.uniform(size=(m + 1, m + 1)) > 0.2
    np.fill_diagonal(allowed, False)
    can_end = rng.uniform(size=m + 1) > 0.2
    can_end[0] = False
    for exact in (False, True):
        found = Pricing(D, tours=tours).price(prize, budget, allowed=allowed, can_end=can_end, exact=exact)
        assert found.prize_bound >= elementary_best(D, prize, budget, tours, allowed, can_end) - 1e-9


def test_walk_bound_is_infinite_without_a_grid(monkeypatch):
    monkeypatch.setattr(ngroute, "MAX_GRID", 1)
    D = euclidean(5, 1)
    allowed = np.ones((6, 6), dtype=bool)
    np.fill_diagonal(allowed, False)
    found = Pricing(D, tours=False).price(np.full(6, 0.5), D[0].max() * 2, allowed=allowed,
                                          can_end=np.ones(6, dtype=bool), exact=False)
    assert found.prize_bound == np.inf


@pytest.mark.parametrize("tours", [False, True], ids=["paths", "tours"])
@pytest.mark.parametrize("make,n,seed", [(euclidean, 12, 3), (clustered, 11, 2), (graph_metric, 10, 3)])
def test_branch_and_price_with_walk_certificates_agrees_with_setpart(make, n, seed, tours, monkeypatch):
    """The answers match set partitioning, and the heuristic pricings' walk certificates
    do raise bounds on the way (counted on the searches)."""
    searches = []
    init = branchprice.BranchAndPrice.__init__

    def keeping(self, *args, **kwargs):
        init(self, *args, **kwargs)
        searches.append(self)

    monkeypatch.setattr(branchprice.BranchAndPrice, "__init__", keeping)
    D = make(n, seed)
    least = least_makespan(D, tours=tours)
    for deadline in (least, 1.3 * least):
        ours, ref = branchprice.min_robots(D, deadline, tours=tours), setpart.min_robots(D, deadline, tours=tours)
        assert ours.status == ref.status == "optimal"
        check_solution(D, ours, tours=tours, deadline=deadline)
        assert ours.objective == ref.objective
    for k in (2, 3):
        ours, ref = makespan_search.min_makespan(D, k, tours=tours), setpart.min_makespan(D, k, tours=tours)
        assert ours.status == "optimal"
        assert check_solution(D, ours, tours=tours, k=k) == pytest.approx(ref.objective, rel=1e-6)
    assert sum(search.prize_bound_raised for search in searches) > 0  # the certificates did act


def test_coincident_kpois_with_walk_certificates():
    points = np.array([[0, 0], [0, 0], [3, 0], [3, 0], [0, 4], [5, 5], [5, 5], [6, 1]], dtype=float)
    D = np.linalg.norm(points[:, None] - points[None], axis=2)
    for tours in (False, True):
        least = least_makespan(D, tours=tours)
        for deadline in (least, 1.5 * least):
            ours, ref = branchprice.min_robots(D, deadline, tours=tours), setpart.min_robots(D, deadline, tours=tours)
            assert ours.status == "optimal" and ours.objective == ref.objective
