"""Tests of the search inside ``best``: annealing acceptance, string-removal ruin, the
local search restricted to changed routes and fewer_robots
(parcover.algorithms.local_search)."""

from __future__ import annotations

import itertools
import random

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from parcover import generate
from milp import setpart
from parcover.algorithms.local_search import _accepts, best, fewer_robots, improve
from parcover.algorithms.moves import Search
from parcover.problem import Problem, meets_deadline
from parcover.verify import route_costs
from strategies import instances, least_makespan_or_robots


def _least_makespan_by_brute_force(instance, tours, robots):
    """Every split of the KPOIs into at most ``robots`` routes, each route in its best
    order (all permutations): the optimum, independent of the heuristic."""
    d = instance.distances
    kpois = range(1, instance.n + 1)

    def route(order):
        stops = (0, *order, 0) if tours else (0, *order)
        return sum(d[a][b] for a, b in zip(stops, stops[1:]))

    best_cost = {
        subset: min(route(p) for p in itertools.permutations(subset))
        for size in range(1, instance.n + 1)
        for subset in itertools.combinations(kpois, size)
    }
    least = float("inf")
    for labels in itertools.product(range(robots), repeat=instance.n):
        if labels[0] != 0:  # robots are interchangeable: KPOI 1 goes to robot 0
            continue
        groups = [tuple(v for v, r in zip(kpois, labels) if r == g) for g in range(robots)]
        least = min(least, max(best_cost[g] for g in groups if g))
    return least


@pytest.mark.parametrize("routes", ["paths", "tours"])
@pytest.mark.parametrize("points_seed", [0, 1, 2])
def test_reaches_the_brute_force_optimum_on_seven_points(routes, points_seed):
    instance = generate.random_points(7, points_seed)
    optimum = _least_makespan_by_brute_force(instance, routes == "tours", 2)
    result = best(instance, Problem(routes, robots=2), seed=0, iterations=20)
    costs = route_costs(instance, result.routes, tours=routes == "tours")
    assert max(costs) == pytest.approx(optimum)


def test_accepts_better_keys_and_never_more_robots():
    rng = random.Random(0)
    assert _accepts((10.0, 30.0), (11.0, 20.0), 0.0, rng)  # lower makespan
    assert _accepts((10.0, 19.0), (10.0, 20.0), 0.0, rng)  # same makespan, shorter
    assert not _accepts((10.5, 20.0), (10.0, 20.0), 0.0, rng)  # worse, frozen
    # the robots objective keys start with the robots: one more is never taken
    assert not _accepts((4.0, 1.0, 4.0), (3.0, 10.0, 30.0), 1e9, rng)
    # a hot search takes a slightly worse makespan (energy +0.1 at temperature 1e6:
    # refused only when -ln(1 - u) < 1e-7, i.e. practically never)
    assert all(_accepts((10.1, 20.0), (10.0, 20.0), 1e6, rng) for _ in range(100))


def test_same_seed_gives_identical_tours():
    instance = generate.random_points(30, 4)
    problem = Problem("tours", robots=3)
    first = best(instance, problem, seed=3, iterations=15)
    second = best(instance, problem, seed=3, iterations=15)
    assert first.routes == second.routes
    assert first.info["value"] == second.info["value"]


def _partition(seqs, n):
    return sorted(v for s in seqs for v in s[1:-1]) == list(range(1, n + 1))


def _poor_start(n, robots):
    """A valid but poor start: one route in KPOI order, or (robots objective) one KPOI
    per route, which meets the least-makespan deadline (c_max or 2 c_max)."""
    return [list(range(1, n + 1))] if robots is not None else [[v] for v in range(1, n + 1)]


@settings(max_examples=20, deadline=None)
@given(instance=instances(2, 12), problem=least_makespan_or_robots(4), seed=st.integers(0, 5))
def test_ruin_and_recreate_keeps_a_valid_solution(instance, problem, seed):
    robots = problem.robots
    search = Search(instance, problem)
    seqs = search.sequences(_poor_start(instance.n, robots))
    rng = random.Random(seed)
    for _ in range(5):
        search.ruin_and_recreate(seqs, rng)
        assert _partition(seqs, instance.n)
        used = [s for s in seqs if len(s) > 2]
        assert robots is None or len(used) <= robots
        deadline = problem.effective_deadline(instance)
        if deadline is not None:
            assert all(meets_deadline(search.cost(s), deadline) for s in used)


@pytest.mark.parametrize("routes, robots", [("paths", 3), ("tours", 4), ("tours", None)])
def test_local_search_from_changed_routes_reaches_a_full_local_optimum(routes, robots):
    # Moves between two routes untouched since the last pass cannot improve, so the
    # search restricted to the changed routes must end where a full search has nothing
    # left to do.
    instance = generate.random_points(40, 6)
    problem = Problem(routes, robots=robots)
    search = Search(instance, problem)
    seqs = search.polish(search.sequences(_poor_start(40, robots)))
    rng = random.Random(1)
    for _ in range(5):
        before = {tuple(s) for s in seqs}
        search.ruin_and_recreate(seqs, rng)
        search.polish(seqs, {r for r, s in enumerate(seqs) if tuple(s) not in before})
        polished = [list(s) for s in seqs]
        search.local_search(seqs)
        assert seqs == polished


@settings(max_examples=15, deadline=None)
@given(instance=instances(1, 10), problem=least_makespan_or_robots(3), seed=st.integers(0, 3))
def test_improve_never_returns_worse_than_its_start(instance, problem, seed):
    robots = problem.robots
    n = instance.n
    start = _poor_start(n, robots)
    found, info = improve(instance, problem, start, seed=seed, iterations=10)
    assert sorted(v for r in found for v in r) == list(range(1, n + 1))
    tours = problem.tours
    key = lambda rs: (max(route_costs(instance, rs, tours=tours)),)  # noqa: E731
    if robots is None:
        assert len(found) <= len(start)
        if len(found) == len(start):
            assert key(found)[0] <= key(start)[0] + 1e-9
    else:
        assert key(found)[0] <= key(start)[0] + 1e-9


@pytest.mark.parametrize("routes", ["paths", "tours"])
def test_rounds_escape_the_first_local_optimum(routes):
    # On 40 random points the local search alone stops at a local optimum; 40 rounds
    # of ruin, recreate and annealed acceptance must find a strictly lower makespan.
    instance = generate.random_points(40, 1)
    problem = Problem(routes, robots=3)
    start = [list(range(1, 41))]
    _, polished = improve(instance, problem, start, seed=0, iterations=0)
    _, searched = improve(instance, problem, start, seed=0, iterations=40)
    assert searched["value"][0] < polished["value"][0] - 1e-6


@settings(max_examples=20, deadline=None)
@given(instance=instances(2, 10), tours=st.booleans(), stretch=st.sampled_from([1.0, 1.3]))
def test_fewer_robots_keeps_every_route_within_the_deadline(instance, tours, stretch):
    kind = "tours" if tours else "paths"
    deadline = stretch * (2 if tours else 1) * instance.c_max
    problem = Problem(kind, deadline=deadline)
    start = [[v] for v in range(1, instance.n + 1)]  # one robot per KPOI always fits
    found, _ = fewer_robots(instance, problem, start, seed=0, iterations=5)
    assert _partition([[0, *r, 0] for r in found], instance.n)
    assert len(found) <= len(start)
    assert all(meets_deadline(c, deadline) for c in route_costs(instance, found, tours=tours))


@pytest.mark.parametrize("routes", ["paths", "tours"])
def test_fewer_robots_packs_one_robot_per_kpoi_down_towards_the_optimum(routes):
    instance = generate.random_points(12, 5)
    problem = Problem(routes, deadline=1.2 * (2 if routes == "tours" else 1) * instance.c_max)
    fewest = setpart.min_robots(instance.distances, problem.deadline, tours=routes == "tours")
    found, rounds = fewer_robots(instance, problem, [[v] for v in range(1, 13)], iterations=20)
    assert fewest.objective <= len(found) < 12 and rounds > 0


@pytest.mark.parametrize("routes", ["paths", "tours"])
def test_fewer_robots_stops_at_its_target(routes):
    """With a target of 10 robots (a bound a caller proved) it stops there: from 12
    singletons within 1.2 x the least makespan (2-4 robots suffice, setpart), 10 exactly."""
    instance = generate.random_points(12, 5)
    problem = Problem(routes, deadline=1.2 * (2 if routes == "tours" else 1) * instance.c_max)
    found, _ = fewer_robots(instance, problem, [[v] for v in range(1, 13)], iterations=20, target=10)
    assert len(found) == 10
