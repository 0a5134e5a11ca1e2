"""The compiled parts of the ng-route pricing (milp.branchprice.ngroute), each on tiny
inputs whose expected values are worked out by hand, and the whole pricing against brute
force.

The search-level checks of the pricing (ng-routes, cuts, growing neighbourhoods) are in
test_branchprice.py.
"""

from __future__ import annotations

import itertools
import threading
import time

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from milp.branchprice import ngroute
from milp.branchprice.ngroute import MAX_CUTS, Pricing
from milp.core.routes import least_makespan
from milp.core.timelimit import stopping
from milp_helpers import euclidean

U1 = np.uint64(1)


def bits(*positions: int) -> np.uint64:
    """A ``uint64`` with the given bits set."""
    out = np.uint64(0)
    for p in positions:
        out |= U1 << np.uint64(p)
    return out


def test_penalty_sums_the_penalties_of_the_set_bits():
    penalties = np.zeros(MAX_CUTS)
    penalties[[0, 1, 2, 63]] = 0.5, 0.25, 2.0, 4.0
    assert ngroute._penalty(penalties, bits(0, 2)) == 2.5
    assert ngroute._penalty(penalties, bits(1, 63)) == 4.25
    assert ngroute._penalty(penalties, np.uint64(0)) == 0.0


def test_completion_reads_the_table_at_the_budget_left():
    """delta 1, U 2.5: after length 0.4 the budget left is 2.1, b = floor(2.1) + 1 = 3,
    capped at G = 2; after 2.6, b = floor(-0.1) + 1 = 0; after 3.7, b = -1: the route
    cannot end; G = 0 means no bound."""
    table = np.array([[-np.inf, 0.0], [-np.inf, 1.0], [-np.inf, 2.0]])
    assert ngroute._completion(table, 1.0, 2, 2.5, 0.4, 1) == 2.0
    assert ngroute._completion(table, 1.0, 2, 2.5, 1.4, 1) == 2.0  # floor(1.1) + 1 = 2
    assert ngroute._completion(table, 1.0, 2, 2.5, 2.0, 1) == 1.0  # floor(0.5) + 1 = 1
    assert ngroute._completion(table, 1.0, 2, 2.5, 2.6, 1) == 0.0
    assert ngroute._completion(table, 1.0, 2, 2.5, 3.7, 1) == -np.inf
    assert ngroute._completion(table, 1.0, 0, 2.5, 0.4, 1) == np.inf


def test_completion_table_on_a_line():
    """KPOIs 1, 2 at grid distances 1 and 2 from the start, 1 apart, prizes 0.5 and 0.25,
    paths (no way home), every arc allowed, both may end. g(b, 1): at b = 0 end at 1 (0);
    from b = 1 go on to 2 (0.25). g(b, 2): 0 at b = 0; from b = 1 go to 1 (0.5) and end
    there (the walk may not come back to 2 at once: 2 -> 1 -> 2 is a 2-cycle), so 0.5 for
    every b >= 1."""
    dd = np.array([[0, 1, 2], [1, 0, 1], [2, 1, 0]], np.int64)
    allowed = ~np.eye(3, dtype=bool)
    table = ngroute.completion_table(dd, np.zeros(3, np.int64), np.array([0.0, 0.5, 0.25]), allowed,
                                      np.ones(3, bool), 3, np.inf)
    assert table[:, 1].tolist() == [0.0, 0.25, 0.25, 0.25]
    assert table[:, 2].tolist() == [0.0, 0.5, 0.5, 0.5]


def test_grid_step_is_just_below_the_shortest_distance():
    delta, G = ngroute.grid_step(10.0, 2.0)
    assert delta < 2.0 and np.floor(2.0 / delta) == 1 and G == 6  # floor(10 / delta) + 1
    assert ngroute.grid_step(10.0, 0.0) is None
    assert ngroute.grid_step(1e6, 1.0) is None  # more than MAX_GRID steps


def test_subset_of_bit_sets_over_words():
    a = np.array([bits(1, 5), bits(0)], np.uint64)
    b = np.array([bits(1, 5, 7), bits(0, 3)], np.uint64)
    assert ngroute._subset(a, b) and not ngroute._subset(b, a)
    assert ngroute._subset(np.zeros(2, np.uint64), a)


def test_dominated_on_arrival_needs_the_prize_after_penalties():
    """Extended labels 0 (prize 2, parities {0}) and 1 (prize 1.2, none), by decreasing
    prize. A new label of prize 1.8 without parities: label 0's odd parity 0 may cost it
    0.5 later, which the new one would not pay: 2 - 0.5 < 1.8, not dominated by it, and
    label 1's prize is smaller: not dominated. With penalty 0.1: 2 - 0.1 >= 1.8,
    dominated. A new label sharing parity 0 is dominated by label 0 at any penalty."""
    parity = np.array([bits(0), 0], np.uint64)
    vals, labs = np.array([2.0, 1.2]), np.array([0, 1], np.int64)
    big, small = np.zeros(MAX_CUTS), np.zeros(MAX_CUTS)
    big[0], small[0] = 0.5, 0.1
    assert not ngroute._dominated_on_arrival(vals, labs, 2, 1.8, parity, np.uint64(0), big)
    assert ngroute._dominated_on_arrival(vals, labs, 2, 1.8, parity, np.uint64(0), small)
    assert ngroute._dominated_on_arrival(vals, labs, 2, 1.8, parity, bits(0), big)
    assert ngroute._dominated_on_arrival(vals, labs, 2, 1.0, parity, np.uint64(0), big)  # label 1: 1.2 >= 1
    assert not ngroute._dominated_on_arrival(vals, labs, 0, 1.0, parity, np.uint64(0), big)  # none extended


def test_heuristic_dominance_drops_a_label_behind_heuristic_scan_labels():
    """Extended labels each of prize 2 and odd parity 0 (penalty 0.5): none dominates a new
    label of prize 1.8 without parities (2 - 0.5 < 1.8). With HEURISTIC_SCAN of them it
    is kept; with one more it is dropped after looking at HEURISTIC_SCAN."""
    scan = ngroute.HEURISTIC_SCAN
    big = np.zeros(MAX_CUTS)
    big[0] = 0.5
    for extended, dropped in ((scan, False), (scan + 1, True)):
        parity = np.full(extended, bits(0), np.uint64)
        vals, labs = np.full(extended, 2.0), np.arange(extended, dtype=np.int64)
        assert ngroute._dominated_on_arrival(vals, labs, extended, 1.8, parity, np.uint64(0), big) is dropped


def test_cut_coefficients_count_visits_with_the_parity_set():
    """Cut 0 on the triple {1, 2, 3} with memory {1, 2, 3, 4}, cut 1 on {1, 2, 5} with
    memory {1, 2, 5}. Route 1, 4, 2, 3: cut 0 parity set at 1, kept at 4, counts at 2
    (then clear), set at 3: 1; cut 1 set at 1, forgotten at 4: 0. Route 1, 2, 5: cut 0
    counts at 2: 1; cut 1 counts at 2, then set again at 5: 1."""
    cut_bits = np.array([0, bits(0, 1), bits(0, 1), bits(0), 0, bits(1)], np.uint64)
    cut_memory = np.array([0, bits(0, 1), bits(0, 1), bits(0), bits(0), bits(1)], np.uint64)
    alpha = ngroute.cut_coefficients([np.array([1, 4, 2, 3]), np.array([1, 2, 5])], cut_bits, cut_memory, 2)
    assert alpha.tolist() == [[1.0, 1.0], [0.0, 1.0]]


def test_ng_neighbourhoods_hold_each_kpoi_and_its_nearest():
    """Points on a line at 0 (start), 1, 2, 4, 8: with size 2 each KPOI's neighbourhood is
    itself and its nearest KPOI (ties to the lower index)."""
    x = np.array([0.0, 1.0, 2.0, 4.0, 8.0])
    masks = ngroute.ng_neighbourhoods(np.abs(x[:, None] - x[None]), 2)
    assert masks[:, 0].tolist() == [0, bits(1, 2), bits(1, 2), bits(2, 3), bits(3, 4)]


@given(st.lists(st.integers(0, 5), max_size=40), st.integers(1, 12))
def test_most_valuable_is_the_head_of_a_stable_sort(values, count):
    # few distinct values: ties at the cut-off are the common case
    values = np.array(values, dtype=np.float64)
    expected = np.argsort(-values, kind="stable")[:count]
    assert np.array_equal(ngroute.most_valuable(values, count), expected)


@given(st.lists(st.tuples(st.booleans(), st.floats(0, 100)), max_size=60))
def test_heap_pops_labels_by_increasing_key(steps):
    """Pushes (True) and pops (False) in any order: each pop returns a label of the least
    key pushed and not yet popped (ties in any order), as a sorted list would."""
    keys, labels = np.empty(len(steps)), np.empty(len(steps), np.int64)
    size, waiting = 0, []
    for label, (push, key) in enumerate(steps):
        if push:
            size = ngroute._heap_push(keys, labels, size, key, label)
            waiting.append((key, label))
        elif size:
            popped, size = ngroute._heap_pop(keys, labels, size)
            least = min(k for k, _ in waiting)
            assert (least, popped) in waiting
            waiting.remove((least, popped))
        assert size == len(waiting)


@given(st.lists(st.floats(0, 10), max_size=40))
def test_insert_keeps_the_labels_by_decreasing_prize(prizes):
    """Each label goes in before the first with a smaller prize (as the labelling inserts
    an extended label after those it was compared with): the prizes stay decreasing, ties
    in arrival order, as a stable sort by decreasing prize."""
    vals, labs = np.empty(len(prizes) + 1), np.empty(len(prizes) + 1, np.int64)
    filled = 0
    for label, prize in enumerate(prizes):
        k = int(np.sum(vals[:filled] >= prize))
        filled = ngroute._insert(vals, labs, filled, k, prize, label)
    expected = np.argsort(-np.array(prizes), kind="stable")
    assert filled == len(prizes)
    assert labs[:filled].tolist() == expected.tolist()


def test_forbid_remembers_the_kpoi_of_a_forbidden_cycle():
    """Neighbourhoods of size 2 on the line above, remembered from {i} (DSSR): route 1, 2, 1
    revisits 1 while 1 is in 2's neighbourhood (a cycle the ng-relaxation forbids), so 2
    now remembers 1; route 1, 3, 1 is an ng-route (1 is not in 3's neighbourhood)."""
    x = np.array([0.0, 1.0, 2.0, 4.0, 8.0])
    pricing = Pricing(np.abs(x[:, None] - x[None]), tours=False, ng_size=2)
    assert pricing.remembered[:, 0].tolist() == [0, bits(1), bits(2), bits(3), bits(4)]
    assert pricing._forbid(np.array([1, 2, 1]))
    assert pricing.remembered[2, 0] == bits(1, 2)
    assert not pricing._forbid(np.array([1, 3, 1]))  # 1 is not in 3's neighbourhood: an ng-route
    assert pricing.remembered[3, 0] == bits(3)


def test_a_stopped_exact_pricing_certifies_its_last_complete_labelling(monkeypatch):
    """The line above, neighbourhoods of size 2 remembered from {i}, prizes 0.6 on KPOIs 1
    and 2, paths within 3.5, no completion bound (so no walk bound): the first labelling's
    best is route 1, 2, 1 (length 3, prize 1.8; 1 is forgotten at 2), a forbidden cycle, so
    a second labelling runs; the clock stops it. The result is not exact, but 1.8 still
    bounds every elementary route's prize (the best, 1, 2, is 1.2): it is the certificate
    (``prize_bound``), and the stopped labelling's best is not."""
    x = np.array([0.0, 1.0, 2.0, 4.0, 8.0])
    D = np.abs(x[:, None] - x[None])
    prize = np.array([0.0, 0.6, 0.6, 0.0, 0.0])
    label, bests = Pricing._label_both_ways, []

    def second_stopped(*args):
        best, routes, work, complete = label(*args)
        bests.append(best)
        return best, routes, work, complete and len(bests) == 1

    monkeypatch.setattr(ngroute, "MAX_GRID", 0)
    monkeypatch.setattr(Pricing, "_label_both_ways", second_stopped)
    result = Pricing(D, tours=False, ng_size=2).price(prize, 3.5, allowed=np.ones((5, 5), bool),
                                                      can_end=np.ones(5, bool), exact=True)
    assert bests == pytest.approx([1.8, 1.2])
    assert not result.exact and result.prize_bound == pytest.approx(1.8)


def test_an_exact_pricing_tells_each_complete_labellings_certificate(monkeypatch):
    """The line of the test above: the first labelling (best 1.8, a forbidden cycle)
    certifies 1.8 and the second (best 1.2, the elementary route 1, 2) 1.2, each told as
    soon as its labelling ends; a labelling stopped by the clock tells nothing."""
    x = np.array([0.0, 1.0, 2.0, 4.0, 8.0])
    D = np.abs(x[:, None] - x[None])
    prize = np.array([0.0, 0.6, 0.6, 0.0, 0.0])
    monkeypatch.setattr(ngroute, "MAX_GRID", 0)
    told = []
    result = Pricing(D, tours=False, ng_size=2).price(prize, 3.5, allowed=np.ones((5, 5), bool),
                                                      can_end=np.ones(5, bool), exact=True, on_prize_bound=told.append)
    assert result.exact and told == pytest.approx([1.8, 1.2])
    label, labellings = Pricing._label_both_ways, []

    def second_stopped(*args):
        best, routes, work, complete = label(*args)
        labellings.append(best)
        return best, routes, work, complete and len(labellings) == 1

    monkeypatch.setattr(Pricing, "_label_both_ways", second_stopped)
    told.clear()
    Pricing(D, tours=False, ng_size=2).price(prize, 3.5, allowed=np.ones((5, 5), bool), can_end=np.ones(5, bool),
                                             exact=True, on_prize_bound=told.append)
    assert told == pytest.approx([1.8])


def brute_force(D, prize, budget, tours, allowed, can_end):
    """Every elementary route on allowed arcs within ``budget`` ending where allowed:
    ``{route: prize}``."""
    m = len(D) - 1
    routes = {}
    for size in range(1, m + 1):
        for order in itertools.permutations(range(1, m + 1), size):
            stops = [0, *order]
            if not all(allowed[a, b] for a, b in zip(stops, stops[1:])) or not can_end[order[-1]]:
                continue
            if D[stops[:-1], stops[1:]].sum() + (D[order[-1], 0] if tours else 0.0) <= budget:
                routes[order] = float(prize[list(order)].sum())
    return routes


@pytest.mark.parametrize("tours", [False, True], ids=["paths", "tours"])
@pytest.mark.parametrize("seed", range(8))
def test_pricing_matches_brute_force_under_branching(seed, tours):
    """Random tiny instances with forbidden arcs and ends: with full neighbourhoods the
    exact pricing's best is the brute-force best elementary route; every route it returns
    is elementary, allowed, within the budget, above the threshold, with its stated order;
    the heuristic finds no more than it."""
    m = 6
    D = euclidean(m, 100 + seed)
    rng = np.random.default_rng(seed)
    prize = np.concatenate(([0.0], rng.uniform(0.0, 0.6, m)))
    budget = (2.0 if tours else 1.0) * D[0, 1:].max() * rng.uniform(1.0, 2.0)
    allowed = (rng.uniform(size=(m + 1, m + 1)) > 0.2) & ~np.eye(m + 1, dtype=bool)
    can_end = rng.uniform(size=m + 1) > 0.2
    can_end[0] = False
    expected = brute_force(D, prize, budget, tours, allowed, can_end)
    threshold = 0.5
    best = max([threshold, *expected.values()])
    exact = Pricing(D, tours=tours, ng_size=m).price(prize, budget, allowed=allowed, can_end=can_end,
                                                     exact=True, threshold=threshold)
    heuristic = Pricing(D, tours=tours, ng_size=m).price(prize, budget, allowed=allowed, can_end=can_end,
                                                         exact=False, threshold=threshold)
    assert exact.exact and exact.best == pytest.approx(best, abs=1e-12)
    assert heuristic.best <= exact.best + 1e-12
    for found in (exact, heuristic):
        values = [expected[tuple(r.tolist())] for r in found.routes]  # KeyError: not a brute-force route
        assert all(v > threshold for v in values)
        assert all(a >= b - 1e-12 for a, b in zip(values, values[1:]))  # joins sum in another order
    if best > threshold:
        assert expected[tuple(exact.routes[0].tolist())] == pytest.approx(best, abs=1e-12)


def test_a_stop_request_ends_the_labelling_at_its_next_clock_check():
    """A race's other entrant proves the answer while this process prices: the exact
    labelling (60 KPOIs in three rooms, every prize 0.15, tours within 2 c_max: it runs
    past 20 s when left alone) returns uncertified soon after the request, not at its
    30 s end."""
    from parcover.generate import random_points

    D = random_points(60, 1, layout="clustered").distances
    m = len(D) - 1
    prize = np.concatenate(([0.0], np.full(m, 0.15)))
    pricing = Pricing(D, tours=True, ng_size=16)
    small = Pricing(D[:8, :8], tours=True, ng_size=16)  # compiled or loaded before the clock starts
    small.price(prize[:8], 2 * least_makespan(D[:8, :8], tours=True), allowed=np.ones((8, 8), bool),
                can_end=np.ones(8, bool), exact=True)
    request = threading.Event()
    with stopping(request):
        threading.Timer(0.3, request.set).start()
        began = time.perf_counter()
        result = pricing.price(prize, 2 * least_makespan(D, tours=True), allowed=np.ones((m + 1, m + 1), bool),
                               can_end=np.ones(m + 1, bool), exact=True, ends_at=began + 30)
        took = time.perf_counter() - began
    assert not result.exact
    assert took < 5.0
