"""Route enumeration (milp/branchprice/enumeration.py) against brute force, and branch-and-price
answering nodes with it against set partitioning."""

from __future__ import annotations

import bisect
import itertools
import threading
import time

import numpy as np
import pytest

from milp import setpart
from milp.branchprice import columns
from milp.branchprice import makespan as makespan_search
from milp.branchprice import search as branchprice
from milp.branchprice import enumeration
from milp.branchprice.enumeration import routes_within_gap
from milp.core.timelimit import stopping
from milp.core.routes import least_makespan


def _length(D: np.ndarray, back: np.ndarray, route: tuple[int, ...]) -> float:
    walk = (0, *route)
    return float(sum(D[a, b] for a, b in zip(walk, walk[1:])) + back[route[-1]])


def _brute_force_family(D, back, prize, budget, threshold, allowed, can_end) -> dict[frozenset, float]:
    """Every KPOI set with a route (all orders tried) within the budget, respecting the
    arcs and ends, whose prize reaches the threshold: its shortest such route's length."""
    n = len(D) - 1
    family: dict[frozenset, float] = {}
    for size in range(1, n + 1):
        for route in itertools.permutations(range(1, n + 1), size):
            walk = (0, *route)
            if not all(allowed[a, b] for a, b in zip(walk, walk[1:])) or not can_end[route[-1]]:
                continue
            length = _length(D, back, route)
            if length <= budget and prize[list(route)].sum() >= threshold:
                key = frozenset(route)
                family[key] = min(family.get(key, np.inf), length)
    return family


@pytest.mark.parametrize("seed", range(24))
def test_lists_every_set_and_the_maximal_ones_within_any_length(seed):
    rng = np.random.default_rng(seed)
    n, tours = int(rng.integers(3, 8)), bool(seed % 2)
    points = rng.uniform(0, 100, (n + 1, 2))
    D = np.linalg.norm(points[:, None] - points[None], axis=-1)
    back = D[:, 0].copy() if tours else np.zeros(n + 1)
    prize = np.concatenate(([0.0], rng.uniform(0, 0.5, n)))
    budget, threshold = float(rng.uniform(60, 250)), float(rng.uniform(0.2, 1.2))
    allowed = ~np.eye(n + 1, dtype=bool)
    can_end = np.ones(n + 1, dtype=bool)
    restricted = seed % 3 == 0
    if restricted:  # as branching leaves them: a forbidden arc, a KPOI that cannot end
        allowed[rng.integers(0, n + 1), rng.integers(1, n + 1)] = False
        can_end[rng.integers(1, n + 1)] = False
    family = _brute_force_family(D, back, prize, budget, threshold, allowed, can_end)
    listing = routes_within_gap(D, back, prize, budget, threshold, allowed, can_end, max_states=10**6)
    assert len(listing) == len(family)
    # every length of the family, and one between two of them, as the limit
    limits = sorted({np.inf, *family.values(), *(0.5 * (a + b) for a, b in zip(sorted(family.values()), [0.0, *sorted(family.values())]))})
    for within in limits:
        inside = {s for s, length in family.items() if length <= within}
        maximal = {s for s in inside if not any(s < t for t in inside)}
        listed, lengths = listing.maximal(within)
        assert listing.count_maximal(within) == len(listed)
        sets = [frozenset(r.tolist()) for r in listed]
        assert len(sets) == len(set(sets))
        assert set(sets) >= maximal
        assert set(sets) <= inside
        if not restricted:  # without restrictions the one-KPOI test finds every smaller set
            assert set(sets) == maximal
        for route, s, length in zip(listed, sets, lengths):
            assert _length(D, back, tuple(route.tolist())) == pytest.approx(family[s], abs=1e-9)
            assert length == pytest.approx(family[s], abs=1e-9)


def test_gives_up_past_its_state_limit():
    rng = np.random.default_rng(0)
    points = rng.uniform(0, 100, (13, 2))
    D = np.linalg.norm(points[:, None] - points[None], axis=-1)
    prize = np.concatenate(([0.0], np.full(12, 0.1)))
    allowed, can_end = ~np.eye(13, dtype=bool), np.ones(13, dtype=bool)
    args = (D, D[:, 0].copy(), prize, 400.0, 0.3, allowed, can_end)
    assert routes_within_gap(*args, max_states=50) is None
    assert routes_within_gap(*args, max_states=10**7, max_sets=5) is None
    assert len(routes_within_gap(*args, max_states=10**7))


def test_gives_up_before_sorting_a_level_past_its_state_limit(monkeypatch):
    """A level that extends to more states than are left of the limit ends the listing
    before the shortest of each set and last KPOI are picked (a sort of 8.7 million
    states took 7 s past the listing's time): that filter never sees more states than
    the limit."""
    sorted_sizes = []
    shortest_per_end = enumeration._shortest_per_end

    def recording(sets, *args):
        sorted_sizes.append(len(sets))
        return shortest_per_end(sets, *args)

    monkeypatch.setattr(enumeration, "_shortest_per_end", recording)
    for limit in (50, 500, 5000):
        sorted_sizes[:] = []
        assert routes_within_gap(*_many_states(12), max_states=limit) is None
        assert sorted_sizes and max(sorted_sizes) <= limit


@pytest.mark.parametrize("seed", range(6))
def test_keeps_the_first_shortest_state_of_each_set_and_last_kpoi(seed):
    """Against a dictionary: per (set, last KPOI) pair the shortest state, the first of
    equally short ones (lengths drawn from a few values, so ties occur), pairs in the order
    they first occur."""
    rng = np.random.default_rng(seed)
    n, words = int(rng.integers(1, 400)), int(rng.integers(1, 3))
    sets = rng.integers(0, 4, (n, words)).astype(np.uint64)
    last = rng.integers(1, 4, n).astype(np.int64)
    length = rng.integers(0, 5, n).astype(np.float64)
    best: dict[tuple, int] = {}
    for s in range(n):
        key = (*sets[s].tolist(), int(last[s]))
        if key not in best or length[s] < length[best[key]]:
            best[key] = s
    assert enumeration._first_shortest(sets, last, length).tolist() == list(best.values())


def _many_states(n: int) -> tuple:
    """A listing of many states: ``n`` KPOIs, small prizes, a long budget."""
    rng = np.random.default_rng(0)
    points = rng.uniform(0, 100, (n + 1, 2))
    D = np.linalg.norm(points[:, None] - points[None], axis=-1)
    prize = np.concatenate(([0.0], np.full(n, 0.1)))
    return D, D[:, 0].copy(), prize, 1000.0, 0.3, ~np.eye(n + 1, dtype=bool), np.ones(n + 1, dtype=bool)


def test_a_listing_stops_at_its_clock_and_at_a_stop_request():
    """Within a level too (the clock is read every EXTENSIONS_PER_CLOCK extensions): a
    listing of billions of states ends within a fraction of a second of its end, or of
    the thread's stop request (a race's other entrant proved the answer)."""
    args = _many_states(40)
    routes_within_gap(*_many_states(5), max_states=10)  # compiled before the clock starts
    began = time.perf_counter()
    assert routes_within_gap(*args, max_states=10**12, ends_at=began + 0.3) is None
    assert time.perf_counter() - began < 1.5
    stop = threading.Event()
    stop.set()
    with stopping(stop):
        began = time.perf_counter()
        assert routes_within_gap(*args, max_states=10**12) is None
        assert time.perf_counter() - began < 1.5


def _euclidean(n: int, seed: int) -> np.ndarray:
    points = np.random.default_rng(seed).uniform(0, 100, (n + 1, 2))
    return np.linalg.norm(points[:, None] - points[None], axis=-1)


def _least_makespan_as_setpart(D: np.ndarray, k: int, tours: bool):
    """Branch-and-price's least makespan, asserted proven and equal to set partitioning's."""
    ours = makespan_search.min_makespan(D, k, tours=tours, time_limit=60)
    theirs = setpart.min_makespan(D, k, tours=tours)
    assert ours.status == theirs.status == "optimal"
    assert ours.objective == pytest.approx(theirs.objective, rel=1e-9)
    return ours


def _recorded_listings(monkeypatch) -> list[tuple[float, object]]:
    """Every listing branch-and-price asks for from now on: its gap and its family (None:
    it gave up)."""
    listings = []
    list_routes = branchprice.enumeration.routes_within_gap

    def recording(*args, **kwargs):
        family = list_routes(*args, **kwargs)
        listings.append((1.0 - args[4] - branchprice.ENUMERATION_SLACK, family))
        return family

    monkeypatch.setattr(branchprice.enumeration, "routes_within_gap", recording)
    return listings


@pytest.mark.parametrize("tours", [False, True])
def test_nodes_answered_by_enumeration_agree_with_setpart(tours, monkeypatch):
    """Both questions, k = 3-4 (enumeration's range), on instances where it answers
    nodes (and proves least makespans at the root): the same optima as set partitioning."""
    answered, least = [], []
    enumerate_node = branchprice.BranchAndPrice.enumerate_node

    def recording(search, *args, **kwargs):
        outcome, settled = enumerate_node(search, *args, **kwargs)
        answered.append(settled is not None)
        return outcome, settled

    monkeypatch.setattr(branchprice.BranchAndPrice, "enumerate_node", recording)
    # without the root's integer master the decisions reach enumeration (it runs first)
    monkeypatch.setattr(branchprice.BranchAndPrice, "integer_master", lambda *args: None)
    for seed in range(4):
        D = _euclidean(11, 100 + seed)
        for k in (3, 4):
            ours = _least_makespan_as_setpart(D, k, tours)
            least.append(ours.message.startswith("least makespan over the routes enumerated"))
            # more than k routes, every KPOI reachable
            deadline = max(0.98 * ours.objective, 1.0001 * least_makespan(D, tours=tours))
            fewest = branchprice.min_robots(D, deadline, tours=tours, time_limit=60)
            assert fewest.status == "optimal"
            assert fewest.objective == setpart.min_robots(D, deadline, tours=tours).objective
    assert any(answered) and any(least)


@pytest.mark.parametrize("tours", [False, True])
def test_enumeration_out_of_its_time_share_leaves_the_tree_to_decide(tours, monkeypatch):
    """With a negligible share of the time for listing and covering MIPs, every node's
    enumeration stops undecided; the branching tree must then reach set partitioning's
    optima (an undecided listing or MIP is never taken as "no solution")."""
    listings = _recorded_listings(monkeypatch)
    monkeypatch.setattr(branchprice, "ENUMERATION_SHARE", 1e-9)
    monkeypatch.setattr(branchprice.BranchAndPrice, "integer_master", lambda *args: None)
    for seed in range(2):
        D = _euclidean(11, 100 + seed)
        for k in (3, 4):
            _least_makespan_as_setpart(D, k, tours)
    assert listings and all(family is None for _, family in listings)


@pytest.mark.parametrize("tours", [False, True])
def test_a_listing_that_gave_up_bars_larger_gaps_in_later_decisions(tours, monkeypatch):
    """A least makespan takes one decision per better makespan; once a listing has given
    up at gap ``g``, no later listing (later decisions included) is tried at a gap of
    ``ENUMERATION_RETRY * g`` or more, and the optima stay set partitioning's."""
    listings, decisions = _recorded_listings(monkeypatch), []  # decisions: listings before each
    fewest_routes = branchprice.BranchAndPrice.fewest_routes

    def counting(search, *args, **kwargs):
        decisions.append(len(listings))
        return fewest_routes(search, *args, **kwargs)

    monkeypatch.setattr(branchprice.BranchAndPrice, "fewest_routes", counting)
    monkeypatch.setattr(branchprice, "ENUMERATION_STATES", 30)  # every listing gives up
    monkeypatch.setattr(branchprice.BranchAndPrice, "integer_master", lambda *args: None)
    later = 0
    for seed in range(3):
        D = _euclidean(11, 100 + seed)
        for k in (3, 4):
            decisions[:], listings[:] = [], []
            _least_makespan_as_setpart(D, k, tours)
            decided_in = [bisect.bisect_right(decisions, i) for i in range(len(listings))]
            for i, (gap, _) in enumerate(listings):
                barred = [g for g, family in listings[:i] if family is None]
                assert all(gap < branchprice.ENUMERATION_RETRY * g for g in barred)
                later += any(d < decided_in[i] for d in decided_in[:i])
            assert all(family is None for _, family in listings)
    assert later  # some listings came in a later decision than an earlier give-up


@pytest.mark.parametrize("tours", [False, True])
def test_an_undecided_family_does_not_join_the_pool(tours, monkeypatch):
    """When the covering MIP over a listing settles nothing, the listed sets are not
    pooled (every pooled column within the budget would enter each later master), and the
    tree still reaches set partitioning's optima."""
    listings, pooled_while_listed = _recorded_listings(monkeypatch), []
    answered = [0]  # listings made before enumerate_node last returned
    add, enumerate_node = columns.Pool.add, branchprice.BranchAndPrice.enumerate_node

    def adding(pool, routes, *args, **kwargs):
        pooled_while_listed.append(any(family is not None for _, family in listings[answered[0]:]))
        return add(pool, routes, *args, **kwargs)

    def enumerating(*args, **kwargs):
        result = enumerate_node(*args, **kwargs)
        answered[0] = len(listings)
        return result

    monkeypatch.setattr(columns.Pool, "add", adding)
    monkeypatch.setattr(branchprice.BranchAndPrice, "enumerate_node", enumerating)
    monkeypatch.setattr(branchprice.BranchAndPrice, "_covering", lambda *args: (False, None))
    monkeypatch.setattr(branchprice.BranchAndPrice, "integer_master", lambda *args: None)
    for seed in range(2):
        _least_makespan_as_setpart(_euclidean(11, 100 + seed), 3, tours)
    assert pooled_while_listed and not any(pooled_while_listed)


def test_least_makespan_covering_probes_just_below_the_covering_first(monkeypatch):
    """The bisection over a family's lengths first asks for a covering with every route
    shorter than the one found (often the least already: then one MIP proves it)."""
    probes, calls = [], []
    maximal = branchprice.enumeration.Family.maximal
    least = branchprice.BranchAndPrice._least_makespan_covering

    def recording_maximal(family, within=np.inf):
        probes.append(within)
        return maximal(family, within)

    def recording_least(search, family, routes, *args, **kwargs):
        lengths = np.unique(family.lengths)
        value = branchprice.makespan(search.pricing.D, routes, tours=search.tours)
        below = lengths[lengths < value * (1 - branchprice.STRICT)]
        probes[:] = []
        result = least(search, family, routes, *args, **kwargs)
        if len(below) and below[-1] >= search.makespan_bound and probes:
            calls.append(probes[0] == below[-1])
        return result

    monkeypatch.setattr(branchprice.enumeration.Family, "maximal", recording_maximal)
    monkeypatch.setattr(branchprice.BranchAndPrice, "_least_makespan_covering", recording_least)
    monkeypatch.setattr(branchprice.BranchAndPrice, "integer_master", lambda *args: None)
    for seed in range(4):
        for tours in (False, True):
            _least_makespan_as_setpart(_euclidean(11, 100 + seed), 3, tours)
    assert calls and all(calls)


@pytest.mark.parametrize("tours", [False, True])
def test_a_family_of_too_many_maximal_sets_counts_as_given_up(tours, monkeypatch):
    """A listing whose maximal sets outnumber ``ENUMERATION_MAXIMAL`` gets no covering MIP
    (its MIP would be slow and settle nothing) and bars larger gaps, like a listing that
    gave up; the tree still reaches set partitioning's optima."""
    monkeypatch.setattr(branchprice, "ENUMERATION_MAXIMAL", 4)
    listings, events = _recorded_listings(monkeypatch), []  # events: listings then MIPs
    covering = branchprice.BranchAndPrice._covering

    def recording(search, *args, **kwargs):
        events.append(("MIP", len(listings)))
        return covering(search, *args, **kwargs)

    monkeypatch.setattr(branchprice.BranchAndPrice, "_covering", recording)
    monkeypatch.setattr(branchprice.BranchAndPrice, "integer_master", lambda *args: None)
    too_many = 0
    for seed in range(3):
        listings[:], events[:] = [], []
        _least_makespan_as_setpart(_euclidean(11, 100 + seed), 3, tours)
        for i, (gap, family) in enumerate(listings):
            barred = [g for g, f in listings[:i] if f is None or len(f.maximal()[0]) > 4]
            assert all(gap < branchprice.ENUMERATION_RETRY * g for g in barred)
            if family is not None and len(family.maximal()[0]) > 4:
                too_many += 1
                assert ("MIP", i + 1) not in events  # no covering MIP after this listing
    assert too_many
