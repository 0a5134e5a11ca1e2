"""setpart's inclusion-exclusion counting against brute force and against the HiGHS model."""

from __future__ import annotations

import functools
import itertools
import operator

import numpy as np
import pytest

import parcover
from milp import branchprice, setpart
from milp.core.routes import route_cost

from milp_helpers import euclidean


def brute_counts(family: np.ndarray, j: int) -> int:
    """j-tuples of family members whose union is every element (plain enumeration)."""
    members = np.flatnonzero(family)
    full = len(family) - 1
    return sum(1 for tup in itertools.product(members, repeat=j)
               if functools.reduce(operator.or_, map(int, tup), 0) == full)


def test_counts_match_enumeration_on_a_hand_family():
    # 3 elements; the family: empty, each single, {1,2} (mask 3). Downward closed.
    family = np.zeros(8, dtype=bool)
    family[[0, 1, 2, 4, 3]] = True
    assert setpart.downward_closed(family)
    counter = setpart.RouteCounter(family)
    # by hand: 2-tuples covering {1,2,3} must contain {3} (mask 4) and {1,2} (mask 3): 2 orders
    assert brute_counts(family, 2) == 2
    p = setpart.PRIMES[0]
    assert counter.partitions(2, p)[7] == 2 and counter.covers(2)
    assert not counter.covers(1)
    assert counter.fewest() == 2
    assert sorted(counter.split(2)) == [3, 4]
    for j in range(4):
        assert counter.partitions(j, p)[7] == brute_counts(family, j)


def test_a_count_that_vanishes_modulo_a_prime_is_decided_by_the_next():
    # the hand family above: N_2 = 2 (a cover exists) vanishes mod 2, not mod 3; N_1 = 0
    # is proven zero once the primes' product exceeds z(full)^1 = 5 (2 x 3 = 6)
    family = np.zeros(8, dtype=bool)
    family[[0, 1, 2, 4, 3]] = True
    counter = setpart.RouteCounter(family, primes=(2, 3, 5))
    assert list(counter._residues(2)) == [0, 2]
    assert counter.covers(2) and sorted(counter.split(2)) == [3, 4]
    assert list(counter._residues(1)) == [0, 0] and not counter.covers(1)
    with pytest.raises(ArithmeticError):
        setpart.RouteCounter(family, primes=(2,)).covers(1)  # 2 < 5: zero is not proven


def test_the_primes_are_primes_below_2_to_the_31():
    primes = setpart.PRIMES
    assert len(set(primes)) == len(primes) and all(p < 2**31 for p in primes)
    for p in primes:  # trial division by every odd number up to the square root
        assert p % 2 and all(p % d for d in range(3, int(p**0.5) + 1, 2))
    assert sum(np.log2(primes)) > 20 * 20  # (2^20)^20 tuples at most


def test_a_family_missing_a_subset_is_not_downward_closed():
    family = np.zeros(8, dtype=bool)
    family[[0, 1, 2, 3, 7]] = True  # {1,2,3} in, {3} out
    assert not setpart.downward_closed(family)


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("tours", [False, True])
def test_counting_and_milp_give_the_same_fewest_routes(seed, tours):
    D = euclidean(9, seed)
    table = setpart.RouteTable(D)
    costs = table.costs(tours=tours)
    least = (2 if tours else 1) * D[0, 1:].max()
    for factor in (1.0, 1.3, 2.0):
        counter = setpart.RouteCounter(setpart.route_family(costs, factor * least))
        solve, _ = setpart._fewest_routes(table, costs, factor * least, None)
        assert counter.fewest() == round(solve.objective)
        masks = counter.split(counter.fewest())
        assert sorted(i for m in masks for i in range(9) if m >> i & 1) == list(range(9))
        assert all(route_cost(D, table.route(m, tours=tours), tours=tours) <= factor * least + 1e-9
                   for m in masks)


def test_a_family_that_is_not_downward_closed_is_solved_by_the_milp():
    # Out of the metric contract (D[1, 3] = 10 > D[1, 2] + D[2, 3]): route 0-1-2-3 costs 3
    # while KPOIs {1, 3} alone cost 11, so within 3 the family holds {1, 2, 3} but not
    # {1, 3}. By hand: one robot suffices within 3; with 2 robots {1, 2} + {3} give 2.
    D = np.array([[0, 1, 1, 1], [1, 0, 1, 10], [1, 1, 0, 1], [1, 10, 1, 0]], dtype=float)
    table = setpart.RouteTable(D)
    assert not setpart.downward_closed(setpart.route_family(table.costs(tours=False), 3.0))
    result = setpart.min_robots(D, 3.0, tours=False)
    assert result.status == "optimal" and result.objective == 1
    assert result.message != "inclusion-exclusion count"
    assert setpart.min_makespan(D, 2, tours=False).objective == pytest.approx(2.0)


def test_exact_uses_setpart_up_to_16_kpois_and_branchprice_above():
    small = parcover.generate.random_points(8, 3)
    assert parcover.solve(small, robots=2).info["model"] == "setpart"
    line = parcover.Instance.from_points([(i, 0) for i in range(18)])  # 17 KPOIs on a line
    result = parcover.solve(line, robots=2, time_limit=60)
    assert result.info["model"] == "branchprice"
    # by hand: one robot walks to the far end (17), the other one idles
    assert result.makespan == pytest.approx(17) and result.status is parcover.Status.OPTIMAL


def test_exact_asks_branchprice_for_the_fewest_robots_from_15_kpois():
    instance = parcover.generate.random_points(15, 3)
    deadline = 1.1 * parcover.solve(instance, robots=4).makespan
    makespan = parcover.solve(instance, robots=4)
    assert makespan.info["model"] in ("setpart", "bounds")
    robots = parcover.solve(instance, deadline=deadline, time_limit=60)
    assert robots.info["model"] == "branchprice" and robots.status is parcover.Status.OPTIMAL
    by_setpart = parcover.solve(instance, deadline=deadline, method="setpart")
    assert robots.robots == by_setpart.robots <= 4


@pytest.mark.parametrize("routes", ["paths", "tours"])
@pytest.mark.parametrize("make", [
    lambda: parcover.generate.random_points(16, 7, layout="clustered"),
    lambda: parcover.generate.random_graph(15, 8),
    lambda: parcover.Instance.from_points([(x % 4, x // 4 % 3) for x in range(17)]),  # coincident KPOIs
], ids=["clustered", "graph", "coincident"])
def test_exact_fewest_robots_from_the_root_agrees_with_setpart(make, routes):
    # exact answers by branchprice started from best's construction (the root first)
    instance = make()
    least = parcover.solve(instance, routes, robots=instance.n, method="setpart").makespan
    for factor in (1.0, 1.3):
        ours = parcover.solve(instance, routes, deadline=factor * least, time_limit=60)
        ref = parcover.solve(instance, routes, deadline=factor * least, method="setpart")
        assert ours.info["model"] == "branchprice" and ours.status is parcover.Status.OPTIMAL
        assert ours.robots == ref.robots


def test_exact_settles_by_the_trivial_bound_when_a_construction_meets_it():
    # 15 KPOIs, 5 tours: some tour reaches the farthest KPOI, so 2 c_max is a lower bound
    # (Prop. 1); when best's construction meets it no model runs, and setpart agrees.
    instance = parcover.generate.random_points(15, 2)
    result = parcover.solve(instance, "tours", robots=5)
    assert result.info["model"] == "bounds" and result.status is parcover.Status.OPTIMAL
    assert result.makespan == pytest.approx(2 * instance.c_max, rel=1e-9)
    by_setpart = parcover.solve(instance, "tours", robots=5, method="setpart")
    assert by_setpart.makespan == pytest.approx(result.makespan, rel=1e-9)
    # two paths cannot meet c_max here: setpart answers, above the trivial bound
    two = parcover.solve(instance, robots=2)
    assert two.info["model"] == "setpart" and two.makespan > instance.c_max * (1 + 1e-6)


def test_exact_falls_back_to_setpart_when_branchprice_runs_out_of_its_share(monkeypatch):
    from parcover import exact

    instance = parcover.generate.random_points(18, 4)
    by_branchprice = parcover.solve(instance, robots=3, method="branchprice", time_limit=60)
    monkeypatch.setattr(exact, "BRANCHPRICE_FIRST", 1e-6)
    result = parcover.solve(instance, robots=3, time_limit=60)
    assert result.info["model"] == "setpart" and result.status is parcover.Status.OPTIMAL
    assert by_branchprice.status is parcover.Status.OPTIMAL
    assert result.makespan == pytest.approx(by_branchprice.makespan, rel=1e-9)


@pytest.mark.parametrize("tours", [False, True])
def test_setpart_agrees_with_branchprice_at_20_kpois(tours):
    D = euclidean(20, 7)
    for k in (2, 4):
        ours = setpart.min_makespan(D, k, tours=tours)
        theirs = branchprice.min_makespan(D, k, tours=tours, time_limit=120)
        assert ours.status == theirs.status == "optimal"
        assert ours.objective == pytest.approx(theirs.objective, rel=1e-9)
