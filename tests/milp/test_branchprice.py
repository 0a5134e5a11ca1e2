"""Branch-and-price (milp.branchprice) and its ng-route pricing (milp.branchprice.ngroute).

The cross-check against arcflow, setpart and cvxpy on seeded instances is in
test_crosscheck.py; here: the pricing against brute force, clustered and coincident
instances against setpart, and the time limit.
"""

from __future__ import annotations

import itertools
import logging
import math
import re
import time

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from milp_helpers import TOL, check_solution, euclidean, graph_metric

from milp import setpart
from milp.bounds import robots_lower_bound
from milp.branchprice import colgen, ngroute, tree
from milp.branchprice.columns import Node, Pool
from milp.branchprice import makespan as makespan_search
from milp.branchprice import search as branchprice
from milp.branchprice.ngroute import MAX_CUTS, Pricing
from milp.core import progress
from milp.core.routes import least_makespan, route_cost


def open_arcs(m: int) -> tuple[np.ndarray, np.ndarray]:
    """No branching decision: every arc allowed, every KPOI may end a route."""
    allowed = np.ones((m + 1, m + 1), dtype=bool)
    np.fill_diagonal(allowed, False)
    can_end = np.ones(m + 1, dtype=bool)
    can_end[0] = False
    return allowed, can_end


def brute_force_best(D: np.ndarray, prize: np.ndarray, budget: float, tours: bool) -> float:
    """Largest prize of an elementary route within ``budget``, by enumerating permutations."""
    m, best = len(D) - 1, 0.0
    for size in range(1, m + 1):
        for order in itertools.permutations(range(1, m + 1), size):
            stops = [0, *order, *([0] if tours else [])]
            if D[stops[:-1], stops[1:]].sum() <= budget:
                best = max(best, float(prize[list(order)].sum()))
    return best


@pytest.mark.parametrize("tours", [False, True], ids=["paths", "tours"])
@pytest.mark.parametrize("seed", range(6))
def test_pricing_with_full_memory_is_the_elementary_optimum(seed, tours):
    """With ng-neighbourhoods holding every KPOI, ng-routes are elementary routes, so the
    exact pricing must find the brute-force optimum."""
    m = 6
    D = euclidean(m, seed)
    rng = np.random.default_rng(seed)
    prize = np.concatenate(([0.0], rng.uniform(0.0, 1.0, m)))
    budget = (2.0 if tours else 1.0) * D[0, 1:].max() * rng.uniform(1.2, 2.5)
    allowed, can_end = open_arcs(m)
    found = Pricing(D, tours=tours, ng_size=m).price(prize, budget, allowed=allowed,
                                                      can_end=can_end, exact=True, threshold=0.0)
    assert found.exact
    assert found.best == pytest.approx(brute_force_best(D, prize, budget, tours), abs=1e-9)
    for route in found.routes:  # every returned route is within the budget
        stops = [0, *route.tolist(), *([0] if tours else [])]
        assert D[stops[:-1], stops[1:]].sum() <= budget + 1e-9


@pytest.mark.parametrize("seed", range(4))
def test_ng_pricing_bounds_the_elementary_optimum(seed):
    """Small neighbourhoods relax the routes: the ng optimum is at least the elementary one."""
    m = 7
    D = euclidean(m, 10 + seed)
    prize = np.concatenate(([0.0], np.random.default_rng(seed).uniform(0.0, 1.0, m)))
    budget = 1.8 * D[0, 1:].max()
    allowed, can_end = open_arcs(m)
    found = Pricing(D, tours=False, ng_size=2).price(prize, budget, allowed=allowed,
                                                      can_end=can_end, exact=True, threshold=0.0)
    assert found.best >= brute_force_best(D, prize, budget, False) - 1e-9


def test_a_cycle_the_neighbourhoods_forbid_is_remembered_from_then_on():
    # four KPOIs on a line, every neighbourhood holds all of them (ng_size = m)
    D = euclidean(4, 0)
    pricing = Pricing(D, tours=False, ng_size=4)
    assert not pricing.remembered[2, 0] & np.uint64(1 << 1)  # starts from {i} alone
    assert pricing._forbid(np.array([1, 2, 1]))  # 1 is in N_2: the cycle 1-2-1 is forbidden
    assert pricing.remembered[2, 0] & np.uint64(1 << 1)  # now KPOI 2 remembers 1
    assert not pricing._forbid(np.array([1, 2, 3]))
    small = Pricing(D, tours=False, ng_size=1)  # neighbourhoods {i}: cycles allowed
    assert not small._forbid(np.array([1, 2, 1]))


@pytest.mark.parametrize("tours", [False, True], ids=["paths", "tours"])
@pytest.mark.parametrize("seed", range(5))
def test_growing_the_neighbourhoods_finds_the_ng_optimum(seed, tours):
    """The exact pricing from {i} (growing) and from the full neighbourhoods give the same
    best prize, and every route it returns is an ng-route."""
    m = 9
    D = euclidean(m, 20 + seed)
    rng = np.random.default_rng(seed)
    allowed, can_end = open_arcs(m)
    growing, full = Pricing(D, tours=tours, ng_size=4), Pricing(D, tours=tours, ng_size=4)
    full.remembered = full.neighbourhoods.copy()
    for _ in range(3):  # the neighbourhoods grown by one call serve the next
        prize = np.concatenate(([0.0], rng.uniform(0.0, 1.0, m)))
        budget = (2.0 if tours else 1.0) * D[0, 1:].max() * rng.uniform(1.5, 3.0)
        ours, theirs = (p.price(prize, budget, allowed=allowed, can_end=can_end, exact=True,
                                threshold=0.5) for p in (growing, full))
        assert ours.exact and theirs.exact
        assert ours.best == pytest.approx(theirs.best, abs=1e-9)
        checker = Pricing(D, tours=tours, ng_size=4)
        assert not any(checker._forbid(r) for r in ours.routes)


def test_strong_branching_reaches_setparts_optimum(monkeypatch):
    """Strong branching only changes which arc is branched on: the search still ends at
    the optimum, every arc picked is among the candidates (the most fractional), and the
    node's master is left as it was (its children are scored by fixing columns at 0 and
    restoring them: solved again, it has the node's LP value)."""
    candidates = branchprice.STRONG_CANDIDATES
    picked, restored = [], []
    choose = branchprice.BranchAndPrice.branching_arc

    def recording(search, node, outcome, target):
        arc = choose(search, node, outcome, target)
        picked.append(arc in search.fractional_arcs(node, outcome)[:candidates])
        outcome.master.run()
        restored.append(outcome.master.getInfo().objective_function_value - outcome.value)
        return arc

    monkeypatch.setattr(branchprice.BranchAndPrice, "branching_arc", recording)
    monkeypatch.setattr(branchprice, "ENUMERATION_ROUTES", (0, -1))  # enumeration would answer the root
    # seed 1 branches at both sizes (measured: with the most fractional arc instead, n = 16
    # is not proven in 60 s)
    for n, k in ((16, 4), (20, 5)):
        D = euclidean(n, 1)
        ours = makespan_search.min_makespan(D, k, tours=False, time_limit=60)
        assert ours.status == "optimal"
        assert ours.objective == pytest.approx(setpart.min_makespan(D, k, tours=False).objective, rel=1e-9)
    assert picked and all(picked)
    assert max(map(abs, restored)) < 1e-7


def crossing_routes() -> tuple[branchprice.BranchAndPrice, branchprice.LpOutcome]:
    """Two paths that cross at KPOI 3 with equal length whichever tails they take: from
    the start (0, 0) over 1 = (1, 1) or 2 = (1, -1) to 3 = (2, 0), then to 4 = (3, 1) or
    5 = (3, -1), each 3 sqrt 2 long. A master solution of 1/2 on each of the four pairings
    has flow 1 on every arc it uses (worked by hand: each arc is on two of the four), so
    its arc flows are integral and its lambda not."""
    points = np.array([[0, 0], [1, 1], [1, -1], [2, 0], [3, 1], [3, -1]], dtype=float)
    D = np.linalg.norm(points[:, None] - points[None, :], axis=2)
    search = branchprice.BranchAndPrice(D, tours=False, ends_at=None)
    columns = list(search.pool.add([np.array(r) for r in ([1, 3, 4], [2, 3, 5], [1, 3, 5], [2, 3, 4])]))
    outcome = branchprice.LpOutcome(2.0, 2.0, columns, np.full(4, 0.5), tree.Why.SOLVED)
    return search, outcome


def test_pricing_duals_are_smoothed_first_and_the_true_duals_priced_last():
    """The order of :meth:`BranchAndPrice._duals_to_try`, worked by hand: without a
    stability center, a heuristic pricing at the moving average first (Neame), none on the
    first round; with one, the Wentges point (half center, half duals) heuristically and
    exactly; in every case the true duals last, exactly (they decide that the LP is
    solved)."""
    search, _ = crossing_routes()
    duals, moving, center = np.array([1.0, 0.0]), np.array([0.0, 1.0]), np.array([0.0, 3.0])
    order = [(y.tolist(), exact) for y, exact in search._duals_to_try(duals, None, None)]
    assert order == [([1.0, 0.0], False), ([1.0, 0.0], True)]
    order = [(y.tolist(), exact) for y, exact in search._duals_to_try(duals, None, moving)]
    assert order == [([0.0, 1.0], False), ([1.0, 0.0], False), ([1.0, 0.0], True)]
    order = [(y.tolist(), exact) for y, exact in search._duals_to_try(duals, center, moving)]
    assert order == [([0.5, 1.5], False), ([0.5, 1.5], True), ([1.0, 0.0], False), ([1.0, 0.0], True)]


def test_crossing_routes_have_no_arc_to_branch_on_but_their_columns_cover():
    search, outcome = crossing_routes()
    assert search.fractional_arcs(Node.root(5), outcome) == []
    routes = search.support_covering(outcome)
    assert routes is not None and len(routes) == 2
    assert sorted(k for r in routes for k in r) == [1, 2, 3, 4, 5]


def test_an_arc_fractional_only_by_covering_twice_is_not_branched_on():
    """Paths over KPOIs 1, 2, 3 with the master at 1 on [1, 2] and 1/2 on [1, 3] and [3]
    (KPOI 1 covered 1.5 times). Worked by hand: the first arc (0, 1) carries 1.5, but
    every route through 1 enters it from the start, so imposing it bans nothing; (0, 3)
    and (1, 3) carry 1/2 and each child of either bans a positive column ([3] or [1, 3];
    imposing (1, 3) also bans [1, 2]). The end arc (3, 0) carries 1 and is not listed for
    (0, 3), as it was when a path's arc was taken for an edge of a tour."""
    points = np.array([[0, 0], [1, 0], [2, 0], [1, 1]], dtype=float)
    D = np.linalg.norm(points[:, None] - points[None, :], axis=2)
    search = branchprice.BranchAndPrice(D, tours=False, ends_at=None)
    routes = ([1, 2], [1, 3], [3])
    search.pool.add([np.array(r) for r in routes])  # [3] is in the pool already (one column per KPOI)
    columns = [[o.tolist() for o in search.pool.orders].index(r) for r in routes]
    outcome = branchprice.LpOutcome(2.0, 2.0, columns, np.array([1.0, 0.5, 0.5]), tree.Why.SOLVED)
    assert search.fractional_arcs(Node.root(3), outcome) == [(0, 3), (1, 3)]


def test_a_node_without_an_arc_to_branch_on_is_answered_by_its_columns(monkeypatch):
    """The tree at a node whose LP (2 routes, target 2) is the crossing above: the covering
    by its columns answers it, so the search ends exhausted with 2 routes (before:
    unknown, nothing found)."""
    search, outcome = crossing_routes()
    monkeypatch.setattr(search, "solve_node", lambda node, budget, target: outcome)
    monkeypatch.setattr(search, "integer_master", lambda budget: None)  # no primal side first
    monkeypatch.setattr(search, "enumerate_node", lambda node, outcome, budget, target, shortest: (outcome, None))
    decision = tree.Decision(search, 3 * math.sqrt(2), None, 2, first=False, improve=None)
    assert decision.run() == tree.Ending.EXHAUSTED
    assert decision.best is not None and len(decision.best) == 2


def test_integer_master_below_the_root_keeps_the_optimum(monkeypatch):
    """With POOL_GROWTH = 1 the integer master runs before every node below the root (at
    most once per search at the root): its coverings, accepted as solutions, must leave
    both questions at setpart's optimum, and it must have run below the root."""
    calls: dict[str, list[int]] = {"fewest_routes": [], "integer_master": []}
    for name, made in calls.items():
        method = getattr(branchprice.BranchAndPrice, name)

        def counting(search, *args, _method=method, _made=made, **kwargs):
            _made.append(1)
            return _method(search, *args, **kwargs)

        monkeypatch.setattr(branchprice.BranchAndPrice, name, counting)
    searches, masters = calls["fewest_routes"], calls["integer_master"]
    monkeypatch.setattr(tree, "POOL_GROWTH", 1.0)
    monkeypatch.setattr(branchprice, "ENUMERATION_ROUTES", (0, -1))  # the tree, not enumeration
    D = euclidean(16, 1)  # branches (test_strong_branching_reaches_setparts_optimum)
    for tours in (False, True):
        ours = makespan_search.min_makespan(D, 4, tours=tours, time_limit=60)
        assert ours.status == "optimal"
        ref = setpart.min_makespan(D, 4, tours=tours)
        assert check_solution(D, ours, tours=tours, k=4) == pytest.approx(ref.objective, rel=TOL)
        deadline = max(1.05 * least_makespan(D, tours=tours), 0.9 * ref.objective)
        ours = branchprice.min_robots(D, deadline, tours=tours, time_limit=60)
        assert ours.status == "optimal"
        check_solution(D, ours, tours=tours, deadline=deadline)
        assert ours.objective == setpart.min_robots(D, deadline, tours=tours).objective
    assert len(masters) > len(searches)


def test_a_branching_tree_logs_its_progress(monkeypatch, caplog):
    """With logging on, the tree writes its root LP value and a line of nodes solved,
    closed and open every PROGRESS_SECONDS (0 here: after every node), and the depth of
    the deepest open node counts the branchings; column generation writes its master's
    value above its certified bound, and its pricing rounds; an exact pricing, its labellings."""
    monkeypatch.setattr(progress, "PROGRESS_SECONDS", 0.0)
    monkeypatch.setattr(branchprice, "ENUMERATION_ROUTES", (0, -1))  # the tree, not enumeration
    D = euclidean(16, 1)  # branches (test_strong_branching_reaches_setparts_optimum)
    with caplog.at_level(logging.INFO, logger="milp"):
        assert makespan_search.min_makespan(D, 4, tours=False, time_limit=60).status == "optimal"
    messages = [record.getMessage() for record in caplog.records]
    assert any(re.search(r"root LP needs at least \d+ routes \(\d+ allowed; LP bound [\d.]+, \w", m)
               for m in messages)
    nodes = [re.search(r"(\d+) nodes solved, (\d+) closed \(([\d.]+)% of the tree\), (\d+) open "
                       r"\(deepest (\d+) branchings\)", m) for m in messages]
    nodes = [tuple(map(float, p.groups())) for p in nodes if p]
    assert nodes and any(depth > 0 for *_, depth in nodes)
    assert all(closed <= solved and 0 <= share <= 100 for solved, closed, share, _, _ in nodes)
    assert any(0 < share < 100 for _, _, share, _, _ in nodes)  # part of a tree closed, part open
    generation = [re.search(r"column generation, node (\d+): LP ([\d.]+) routes, bound ([\d.]+), "
                            r"after (\d+) pricing rounds \((\d+) columns, (\d+) cuts\)", m) for m in messages]
    generation = [g.groups() for g in generation if g]
    assert {int(g[0]) for g in generation} >= {1, 2}  # the root and the nodes below
    assert all(float(bound) <= float(lp) * (1 + 1e-6) for _, lp, bound, *_ in generation)
    assert any(int(rounds) > 0 for _, _, _, rounds, _, _ in generation)
    assert any(re.search(r"exact pricing: \d+ labellings so far .* best route prize [\d.]+", m) for m in messages)
    root = Node.root(3)
    assert [child.depth for child in root.children((1, 2), tours=False)] == [1, 1]


def test_an_exhausted_tree_has_closed_all_of_its_share(monkeypatch):
    """A decision proven infeasible by branching has closed shares 2^-depth summing to
    exactly 1 (a closing path left uncounted, or a node counted twice, would miss it).
    Paths: the tours decisions at the optimum of such small instances close at the root."""
    monkeypatch.setattr(branchprice, "ENUMERATION_ROUTES", (0, -1))  # the tree, not enumeration
    D = euclidean(16, 1)  # branches (test_a_branching_tree_logs_its_progress)
    optimum = setpart.min_makespan(D, 4, tours=False).objective
    search = branchprice.BranchAndPrice(branchprice.prepared(D)[1].D, tours=False, ends_at=None)
    found, _, ending = search.fewest_routes(optimum * (1 - 1e-6), None, 4, first=True)
    assert ending == tree.Ending.EXHAUSTED and found is None
    assert search.nodes > 1 and search.tree_closed == 1.0
    assert tree.share_text(1.0) == "100%" and tree.share_text(1 - 1e-9) == "99.9%"
    assert tree.share_text(0.25) == "25%" and tree.share_text(2.0 ** -20) == "9.54e-05%"


def test_a_tree_stopped_by_its_time_limit_resumes_where_it_stopped(monkeypatch):
    """The decision of test_an_exhausted_tree_has_closed_all_of_its_share, its clock run out
    after a few nodes (one of them cut short inside its column generation), then resumed:
    the same tree goes on and closes all of its share (a node dropped at the stop would
    leave its share missing; a new tree would leave the stopped one's share below 1)."""
    monkeypatch.setattr(branchprice, "ENUMERATION_ROUTES", (0, -1))  # the tree, not enumeration
    D = euclidean(16, 1)
    budget = setpart.min_makespan(D, 4, tours=False).objective * (1 - 1e-6)
    search = branchprice.BranchAndPrice(branchprice.prepared(D)[1].D, tours=False, ends_at=None)
    polls = iter(range(10 ** 9))
    monkeypatch.setattr(search, "out_of_time", lambda: search.nodes >= 4 and next(polls) >= 1)
    _, _, ending = search.fewest_routes(budget, None, 4, first=True)
    stopped = search.stopped
    assert ending == tree.Ending.UNKNOWN and stopped is not None and stopped.resumable
    assert 0 <= stopped.closed_share < 1 and search.tree_closed == stopped.closed_share
    monkeypatch.setattr(search, "out_of_time", lambda: False)
    found, _, ending = search.fewest_routes(budget, None, 4, first=True, resume=True)
    assert ending == tree.Ending.EXHAUSTED and found is None
    assert stopped.closed_share == 1.0 and search.tree_closed == 1.0 and search.stopped is None


def test_an_unproven_answer_says_how_much_of_its_tree_it_closed():
    """Stopped by its time limit, a fewest-robots and a makespan answer carry the share of
    their last tree closed in the message."""
    D = euclidean(60, 3)
    least = least_makespan(D, tours=True)
    robots = branchprice.min_robots(D, 1.2 * least, tours=True, time_limit=1.0)
    makespan = makespan_search.min_makespan(D, 5, tours=True, time_limit=1.0)
    for answer in (robots, makespan):
        assert answer.status == "feasible", answer.message
        assert re.fullmatch(r"time limit, [\d.e-]+% of the last tree closed.*", answer.message), answer.message


def clustered(n: int, seed: int) -> np.ndarray:
    """KPOIs in three tight clusters far apart (long inter-cluster arcs)."""
    rng = np.random.default_rng(seed)
    centres = rng.uniform(0.0, 100.0, size=(3, 2))
    points = centres[rng.integers(0, 3, n + 1)] + rng.normal(0.0, 3.0, size=(n + 1, 2))
    return np.linalg.norm(points[:, None, :] - points[None, :, :], axis=2)


@pytest.mark.parametrize("tours", [False, True], ids=["paths", "tours"])
@pytest.mark.parametrize("make,n,seed", [(clustered, 9, 1), (clustered, 11, 2), (graph_metric, 10, 3),
                                          (euclidean, 12, 4)])
def test_agrees_with_setpart(make, n, seed, tours):
    D = make(n, seed)
    least = (2.0 if tours else 1.0) * D[0, 1:].max()
    for k in (2, 4):
        ours, ref = makespan_search.min_makespan(D, k, tours=tours), setpart.min_makespan(D, k, tours=tours)
        assert ours.status == ref.status == "optimal"
        assert check_solution(D, ours, tours=tours, k=k) == pytest.approx(ref.objective, rel=TOL)
    for deadline in (least, 1.3 * least):
        ours, ref = branchprice.min_robots(D, deadline, tours=tours), setpart.min_robots(D, deadline, tours=tours)
        assert ours.status == ref.status == "optimal"
        check_solution(D, ours, tours=tours, deadline=deadline)
        assert ours.objective == ref.objective


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 10**6), n=st.integers(2, 9), k=st.integers(1, 4), tours=st.booleans(),
       share=st.floats(1.0, 2.0))
def test_random_instances_agree_with_setpart(seed, n, k, tours, share):
    D = euclidean(n, seed)
    ours, ref = makespan_search.min_makespan(D, k, tours=tours), setpart.min_makespan(D, k, tours=tours)
    assert ours.status == "optimal"
    assert check_solution(D, ours, tours=tours, k=k) == pytest.approx(ref.objective, rel=TOL)
    deadline = share * ref.objective
    ours, ref = branchprice.min_robots(D, deadline, tours=tours), setpart.min_robots(D, deadline, tours=tours)
    assert ours.status == "optimal" and ours.objective == ref.objective


@pytest.mark.parametrize("tours", [False, True], ids=["paths", "tours"])
def test_improve_is_asked_once_with_the_root_bound_and_its_routes_are_checked(tours):
    D = euclidean(12, 6)
    deadline = 1.2 * least_makespan(D, tours=tours)
    ref = setpart.min_robots(D, deadline, tours=tours)
    singletons = [[j] for j in range(1, 13)]
    asked = []

    def improve(floor: int, root_seconds: float) -> list[list[int]]:
        asked.append((floor, root_seconds))
        return ref.routes

    began = time.perf_counter()
    ours = branchprice.min_robots(D, deadline, tours=tours, warm_start=singletons, improve=improve)
    assert ours.status == "optimal" and ours.objective == ref.objective
    assert len(asked) == 1 and 1 <= asked[0][0] <= ref.objective  # the root bound, rounded up
    assert 0 < asked[0][1] <= time.perf_counter() - began  # the root's seconds
    too_long = branchprice.min_robots(D, deadline, tours=tours, warm_start=singletons,
                                      improve=lambda floor, _: [list(range(1, 13))])  # one route, too long
    assert too_long.status == "optimal" and too_long.objective == ref.objective
    check_solution(D, too_long, tours=tours, deadline=deadline)


@pytest.mark.parametrize("seed, tours", [(1, False), (1, True), (4, False), (5, False)])
def test_the_root_tells_each_larger_bound_its_certificates_prove(seed, tours):
    """Instances (14 KPOIs, within the least makespan) whose root proves more routes than
    the spanning-tree / clique bound: ``proven`` hears bounds above that one, each larger
    than the last, none above setpart's optimum (a second exact method)."""
    D = euclidean(14, seed)
    deadline = least_makespan(D, tours=tours)
    told: list[int] = []
    ours = branchprice.min_robots(D, deadline, tours=tours, proven=told.append)
    ref = setpart.min_robots(D, deadline, tours=tours)
    trivial = robots_lower_bound(D, deadline, tours=tours)
    assert ours.status == "optimal" and ours.objective == ref.objective
    assert told and told == sorted(set(told)) and trivial < told[0] and told[-1] <= ref.objective


@pytest.mark.parametrize("tours", [False, True])
@pytest.mark.parametrize("seed", [1, 4])
def test_routes_from_elsewhere_become_the_incumbent_while_the_root_is_solved(seed, tours):
    """From a route per KPOI, ``elsewhere`` hands over setpart's optimum (a second exact
    method) at its fourth poll, while the root LP is being solved: the tree takes it, looks
    for one route fewer, and proves it optimal; the message says whose routes they are.
    Routes that do not cover every KPOI, or break the deadline, are not taken."""
    D = euclidean(14, seed)
    deadline = least_makespan(D, tours=tours)
    ref = setpart.min_robots(D, deadline, tours=tours)
    polls = {"count": 0}

    def elsewhere():
        polls["count"] += 1
        return ref.routes if polls["count"] == 4 else None

    ours = branchprice.min_robots(D, deadline, tours=tours, warm_start=[[j] for j in range(1, 15)],
                                  elsewhere=elsewhere)
    assert polls["count"] > 4 and ours.status == "optimal" and ours.objective == ref.objective
    check_solution(D, ours, tours=tours, deadline=deadline)
    assert "routes from another method" in ours.message
    whole = [list(range(1, 15))]  # one route through every KPOI: far over the least makespan
    assert route_cost(D, whole[0], tours=tours) > deadline
    wrong = itertools.cycle([whole, ref.routes[1:]])  # over the deadline, or not covering
    ignored = branchprice.min_robots(D, deadline, tours=tours, elsewhere=lambda: next(wrong))
    assert ignored.status == "optimal" and ignored.objective == ref.objective
    assert "another method" not in ignored.message


@pytest.mark.parametrize("tours", [False, True])
def test_a_shorter_makespan_from_elsewhere_ends_the_decision_under_way(tours):
    """The least makespan from a poor warm start (one route through every KPOI), and
    ``elsewhere`` handing setpart's optimum (a second exact method) at its third poll,
    after the bisection: the decision under way takes it, and the next proves it optimal.
    Routes no shorter than the best so far are not taken."""
    D, k = euclidean(12, 2), 3
    ref = setpart.min_makespan(D, k, tours=tours)
    polls = {"count": 0}

    def elsewhere():
        polls["count"] += 1
        return ref.routes if polls["count"] == 3 else None

    poor = [list(range(1, 13))]
    ours = makespan_search.min_makespan(D, k, tours=tours, warm_start=poor, elsewhere=elsewhere)
    assert polls["count"] > 3 and ours.status == "optimal" and "routes from another method" in ours.message
    assert check_solution(D, ours, tours=tours, k=k) == pytest.approx(ref.objective, abs=TOL)
    same = makespan_search.min_makespan(D, k, tours=tours, warm_start=ref.routes, elsewhere=lambda: poor)
    assert same.status == "optimal" and same.objective == pytest.approx(ref.objective, abs=TOL)
    assert "another method" not in same.message


def test_coincident_kpois_and_kpois_at_the_start():
    """Zero distances are merged before pricing (no zero-length cycles)."""
    points = np.array([[0, 0], [0, 0], [3, 0], [3, 0], [0, 4], [5, 5], [5, 5]], dtype=float)
    D = np.linalg.norm(points[:, None] - points[None], axis=2)
    for tours in (False, True):
        for k in (1, 2, 3):
            ours, ref = makespan_search.min_makespan(D, k, tours=tours), setpart.min_makespan(D, k, tours=tours)
            assert ours.status == "optimal"
            assert check_solution(D, ours, tours=tours, k=k) == pytest.approx(ref.objective, abs=TOL)


def test_time_limit_is_held_and_the_answer_is_honest():
    """30 KPOIs, 3 tours, 1 s: whatever the status, the routes are valid and the bound holds."""
    D = euclidean(30, 5)
    began = time.perf_counter()
    answer = makespan_search.min_makespan(D, 3, tours=True, time_limit=1.0)
    assert time.perf_counter() - began <= 1.1 + 0.5  # 10% plus one pricing round
    check_solution(D, answer, tours=True, k=3)


def test_column_generation_solves_no_master_lp_past_the_limit(monkeypatch):
    """The clock runs out during a pricing round that found columns: the call returns the
    last master's outcome without solving the master again, and a later call returns at
    once. (A master solve takes 0.35 s at 100 KPOIs; two of them ran past a 120 s limit.)"""
    D = euclidean(12, 3)
    search = branchprice.BranchAndPrice(D, tours=True, ends_at=None)
    root, budget = branchprice.Node.root(search.m), 1.2 * least_makespan(D, tours=True)
    runs = []
    master = search._master

    def counted_master(columns, **kind):
        h = master(columns, **kind)
        run = h.run
        h.run = lambda: runs.append(1) or run()
        return h

    append = search._append

    def append_then_stop(*args):
        found = append(*args)
        search.ends_at = time.perf_counter()  # the clock runs out during this round
        return found

    monkeypatch.setattr(search, "_master", counted_master)
    monkeypatch.setattr(search, "_append", append_then_stop)
    columns = search.pool.fitting(budget, root)
    nothing = branchprice.LpOutcome(0.0, math.inf, columns, np.zeros(0), branchprice.Why.STALLED)
    outcome = search._column_generation(root, budget, 3, columns, nothing)
    assert outcome.why == branchprice.Why.TIME_LIMIT
    assert len(runs) == 1
    again = search._column_generation(root, budget, 3, columns, outcome)
    assert again.why == branchprice.Why.TIME_LIMIT and again.bound == outcome.bound
    assert len(runs) == 1


#: Three KPOIs. Tours: the shortest of all three ([1, 3, 2]) 6.47, [1, 3] 6.47, [1, 2] 5.24,
#: [1] 4.47, [2, 3] 4. Paths: [1, 2, 3] 5.24, [1, 2] 4.24, [2, 3] 2.
PHASE_ONE_POINTS = np.array([[0, 0], [2, 1], [0, 1], [0, 2]], dtype=float)


def search_with_cut(tours: bool, pooled: tuple[list[int], ...] = ([1, 2], [2, 3])
                    ) -> tuple[branchprice.BranchAndPrice, list[int]]:
    """A search on :data:`PHASE_ONE_POINTS` holding the subset-row cut on (1, 2, 3), and
    a pool of the ``pooled`` routes alone (their columns). By default [1, 2] and [2, 3]:
    each visits two of the triple, so with the cut (at most one such route) they cannot
    cover the three KPOIs: the master is infeasible."""
    D = np.linalg.norm(PHASE_ONE_POINTS[:, None] - PHASE_ONE_POINTS[None], axis=2)
    search = branchprice.BranchAndPrice(D, tours=tours, ends_at=None)
    search.cuts = [(1, 2, 3)]
    search.cut_bits, search.cut_memory = cut_masks(3, search.cuts, [set()])
    search.pool = Pool(D, tours=tours)
    return search, list(search.pool.add([np.array(route) for route in pooled]))


def test_phase_one_prices_in_the_columns_an_infeasible_master_needs():
    """Cuts found at an ancestor, with the columns a branching left, can make a child's
    master infeasible (100 uniform KPOIs, seed 38, tours: an AssertionError). Phase one
    prices in the missing columns, and column generation then reaches the LP value over
    every route within the budget, 6: 2 by hand (no route within it visits both 1 and
    3), and by scipy's LP over all routes listed."""
    from scipy.optimize import linprog

    search, columns = search_with_cut(tours=True)
    budget, root = 6.0, Node.root(3)
    master = search._master(columns)
    master.run()
    assert master.getModelStatus() in branchprice.INFEASIBLE
    nothing = branchprice.LpOutcome(0.0, math.inf, columns, np.zeros(0), branchprice.Why.STALLED)
    outcome = search._column_generation(root, budget, math.inf, columns, nothing, converge=True)
    routes = [list(p) for r in (1, 2, 3) for p in itertools.permutations((1, 2, 3), r)
              if route_cost(search.pool.D, list(p), tours=True) <= budget]
    coverage = np.array([[j in route for route in routes] for j in (1, 2, 3)], dtype=float)
    cut = np.array([[len(route) // 2 for route in routes]], dtype=float)
    listed = linprog(np.ones(len(routes)), A_ub=np.vstack([-coverage, cut]), b_ub=[-1, -1, -1, 1])
    assert listed.status == 0 and listed.fun == pytest.approx(2.0)
    assert outcome.why == branchprice.Why.SOLVED and outcome.value == pytest.approx(listed.fun)


def test_phase_one_closes_a_node_whose_lp_has_no_solution():
    """Paths at a node that lets KPOI 1 only start a route and go on to 2, and KPOI 3
    only follow 2: within 4.5 the routes holding 1 or 3 are [1, 2] and [2, 3] ([1, 2, 3]
    costs 5.24), which the cut on (1, 2, 3) lets the LP take once in all. No LP solution
    (Farkas): the node closes."""
    search, _ = search_with_cut(tours=False)
    allowed = Node.root(3).allowed.copy()
    allowed[1, 0] = allowed[1, 3] = allowed[3, 1] = allowed[2, 1] = allowed[0, 3] = False
    node = Node(allowed, depth=1)
    outcome = search.solve_node(node, 4.5, math.inf)
    assert outcome.why == branchprice.Why.CLOSED and outcome.bound == math.inf
    opened = Node.root(3)  # without the branching, [1] and [3] alone fit: the LP is feasible
    assert search.solve_node(opened, 4.5, math.inf).why == branchprice.Why.SOLVED


def test_phase_one_starts_from_no_column():
    """A node where no pooled column fits (a pool of the tour [1, 3, 2] alone, 6.47):
    within 5 the LP value is 2 by hand (1 fits only alone, [1] 4.47; [2, 3] 4), within 3
    no tour reaches KPOI 1 and the node closes."""
    search, _ = search_with_cut(tours=True, pooled=([1, 3, 2],))
    solved = search.solve_node(Node.root(3), 5.0, math.inf)
    assert solved.why == branchprice.Why.SOLVED and solved.value == pytest.approx(2.0)
    closed = search.solve_node(Node.root(3), 3.0, math.inf)
    assert closed.why == branchprice.Why.CLOSED and closed.bound == math.inf


def cut_masks(m: int, triples: list[tuple[int, ...]], memories: list[set[int]]) -> tuple[np.ndarray, np.ndarray]:
    """Bit masks of cut triples and memories per KPOI (bit t for cut t)."""
    cuts, mems = np.zeros(m + 1, dtype=np.uint64), np.zeros(m + 1, dtype=np.uint64)
    for t, (triple, memory) in enumerate(zip(triples, memories)):
        for j in triple:
            cuts[j] |= np.uint64(1 << t)
        for j in memory | set(triple):
            mems[j] |= np.uint64(1 << t)
    return cuts, mems


@settings(max_examples=50, deadline=None)
@given(seed=st.integers(0, 10**6))
def test_cut_coefficients_are_valid_for_every_partition(seed):
    """A limited-memory subset-row cut counts at most floor(|r & S| / 2) on a route, so
    a partition into elementary routes never has more than 1 in all."""
    rng = np.random.default_rng(seed)
    m = 8
    triple = tuple(int(j) for j in rng.choice(np.arange(1, m + 1), 3, replace=False))
    memory = {int(j) for j in rng.choice(np.arange(1, m + 1), int(rng.integers(0, m)), replace=False)}
    cuts, mems = cut_masks(m, [triple], [memory])
    order = rng.permutation(np.arange(1, m + 1))
    cutpoints = sorted(rng.choice(np.arange(1, m), int(rng.integers(0, m - 1)), replace=False))
    routes = [r for r in np.split(order, cutpoints) if len(r)]
    alpha = ngroute.cut_coefficients(routes, cuts, mems, 1)[0]
    for route, a in zip(routes, alpha):
        assert a <= np.isin(route, triple).sum() // 2
    assert alpha.sum() <= 1


@pytest.mark.parametrize("limited", [False, True], ids=["full-memory", "limited-memory"])
@pytest.mark.parametrize("tours", [False, True], ids=["paths", "tours"])
@pytest.mark.parametrize("seed", range(4))
def test_pricing_with_cuts_is_the_elementary_optimum(seed, tours, limited):
    """With full ng-memory and two cuts, the exact pricing must find the brute-force best
    of prize minus penalty[t] x the cut's count on the route (:func:`ngroute.cut_coefficients`:
    floor(|r & S_t| / 2) with full cut memory). The best route is often found by joining a
    forward and a backward label, whose parities meet in the middle."""
    m = 6
    D = euclidean(m, 30 + seed)
    rng = np.random.default_rng(seed)
    prize = np.concatenate(([0.0], rng.uniform(0.0, 1.0, m)))
    triples = [(1, 2, 3), (2, 4, 6)]
    memories = [set(rng.choice(np.arange(1, m + 1), 2, replace=False).tolist()) if limited else set(range(1, m + 1))
                for _ in triples]
    cuts, mems = cut_masks(m, triples, memories)
    penalties = np.zeros(MAX_CUTS)
    penalties[:2] = rng.uniform(0.0, 0.8, 2)
    budget = (2.0 if tours else 1.0) * D[0, 1:].max() * rng.uniform(1.2, 2.0)
    allowed, can_end = open_arcs(m)
    found = Pricing(D, tours=tours, ng_size=m).price(
        prize, budget, allowed=allowed, can_end=can_end, exact=True, threshold=0.0,
        cut_bits=cuts, cut_memory=mems, penalties=penalties)
    orders = [np.array(order) for size in range(1, m + 1) for order in itertools.permutations(range(1, m + 1), size)
              if route_cost(D, list(order), tours=tours) <= budget]
    counts = ngroute.cut_coefficients(orders, cuts, mems, 2)
    values = [prize[order].sum() - penalties[:2] @ counts[:, r] for r, order in enumerate(orders)]
    assert found.exact and found.best == pytest.approx(max(values), abs=1e-9)


@pytest.mark.parametrize("tours", [False, True], ids=["paths", "tours"])
def test_makespan_bound_takes_the_q_route_bound_when_the_ng_route_bisection_runs_out(tours, monkeypatch):
    """When the ng-route LP bisection has not converged in its half of the time, the
    q-route bound of milp.branchprice.colgen continues from it, then the ng-route bisection again; the
    bound stays at or below setpart's optimum. With time to converge, colgen is not run."""
    D = euclidean(10, 3)
    k, optimum = 3, setpart.min_makespan(D, 3, tours=tours).objective
    upper = 1.2 * optimum
    lower = least_makespan(D, tours=tours)
    asked: list[float] = []
    q_bound = colgen.makespan_lower_bound

    def recording(*args, lower: float = 0.0, **kwargs) -> float:
        asked.append(lower)
        return q_bound(*args, lower=lower, **kwargs)

    monkeypatch.setattr(branchprice.colgen, "makespan_lower_bound", recording)
    search = branchprice.BranchAndPrice(D, tours=tours, ends_at=None)
    converged, cut_short = makespan_search._makespan_lp_bound(search, k, lower, upper, time.perf_counter() + 60)
    assert not asked and not cut_short and lower < converged <= optimum * (1 + TOL)

    bisect = makespan_search._bisect_lp_bound
    halves: list[float] = []

    def out_of_time_at_first(search, k, low, high):
        halves.append(low)
        if len(halves) == 1:  # the first half ends before any step: as with long routes
            search.ends_at = time.perf_counter()
        return bisect(search, k, low, high)

    monkeypatch.setattr(makespan_search, "_bisect_lp_bound", out_of_time_at_first)
    search = branchprice.BranchAndPrice(D, tours=tours, ends_at=None)
    bound, cut_short = makespan_search._makespan_lp_bound(search, k, lower, upper, time.perf_counter() + 60)
    assert asked == [lower] and len(halves) == 2 and halves[1] >= lower and not cut_short
    assert bound == pytest.approx(converged, rel=1e-3) and bound <= optimum * (1 + TOL)


def test_a_makespan_bisection_cut_short_resumes_after_the_decisions(monkeypatch):
    """With its cap at (almost) 0 s the root LP bisection is cut short at once; the
    decisions (here: waiting out their time, as hard ones do) then stop a quarter of the
    limit early, and the bisection resumes in that quarter: the bound reported is the
    bisection's converged bound, not the trivial one it started from. The time the
    resumed bisection leaves goes back to the decisions, which ask for their tree to resume."""
    D = euclidean(12, 3)
    k, tours = 3, False
    start = [[1, 2, 3, 4], [5, 6, 7, 8], [9, 10, 11, 12]]
    value = float(max(D[[0, *r[:-1]], r].sum() for r in start))
    lower = least_makespan(D, tours=tours)
    full, _ = makespan_search._makespan_lp_bound(branchprice.BranchAndPrice(D, tours=tours, ends_at=None), k,
                                             lower, value, None)
    stopped: list[float] = []
    resumes: list[bool] = []

    def undecided(self, budget, incumbent, target, *, first, improve=None, floor=1, resume=False):
        while not self.out_of_time():
            time.sleep(0.01)
        stopped.append(time.perf_counter())
        resumes.append(resume)
        return None, None, tree.Ending.UNKNOWN

    monkeypatch.setattr(makespan_search, "BISECTION_SECONDS", 1e-6)
    monkeypatch.setattr(branchprice.BranchAndPrice, "fewest_routes", undecided)
    began = time.perf_counter()
    result = makespan_search.min_makespan(D, k, tours=tours, time_limit=4.0, warm_start=start)
    assert result.status == "feasible" and result.objective == pytest.approx(value)
    assert stopped and stopped[0] - began == pytest.approx(3.0, abs=0.5)  # 4 s less a quarter
    assert len(stopped) == 2 and stopped[1] - began == pytest.approx(4.0, abs=0.5)  # and the rest
    assert resumes == [True, True]
    assert full > 1.01 * lower  # the bisection has something to gain here
    assert result.bound >= full * (1 - 1e-3)
