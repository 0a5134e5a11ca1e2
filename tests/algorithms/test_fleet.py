"""PyVRP's search for the fewest routes (parcover/algorithms/fleet.py) and its race beside
branch-and-price in ``exact`` (parcover/exact.py, ``_race_robots``)."""

from __future__ import annotations

import time

import numpy as np
import pytest

import parcover.exact as exact_module
from milp import race, setpart
from milp.core.result import MilpResult
from milp.core.routes import least_makespan, makespan, route_cost, within
from milp.core.timelimit import TimeLimit, stop_requested
from parcover import generate
from parcover.algorithms import fleet
from parcover.algorithms.fleet import fewest_routes, race_entrant, shorter_routes
from parcover.problem import Problem
from parcover.result import Status


def _covers(routes: list[list[int]], n: int) -> bool:
    return sorted(k for route in routes for k in route) == list(range(1, n + 1))


@pytest.mark.parametrize("tours", [False, True])
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_shorter_routes_descend_to_set_partitionings_least_makespan(seed, tours):
    """From two routes in index order on 9 KPOIs, PyVRP's searches for shorter routes
    reach setpart's proven least makespan (an independent exact method), given as the
    target, and stop there; each routes told are valid and shorter than the last."""
    D = generate.random_points(9, seed).distances
    optimum = setpart.min_makespan(D, 2, tours=tours)
    assert optimum.status == "optimal"
    start = [[1, 2, 3, 4], [5, 6, 7, 8, 9]]
    told: list[list[list[int]]] = []
    routes = shorter_routes(D, 2, start, tours=tours, seed=seed, stop=time.perf_counter() + 10.0,
                            target=optimum.objective, found=told.append)
    values = [makespan(D, r, tours=tours) for r in told]
    assert all(len(r) <= 2 and _covers(r, 9) for r in told)
    assert values == sorted(set(values), reverse=True) and values[0] < makespan(D, start, tours=tours)
    assert told[-1] == routes and makespan(D, routes, tours=tours) == pytest.approx(optimum.objective, rel=1e-9)


def test_shorter_routes_end_after_searches_in_a_row_that_find_none(monkeypatch):
    """Without a stop time, from routes already optimal (setpart's, not given as the target),
    the searches find nothing shorter: they end after ``SHORTER_MISSES`` of them, returning
    the routes given, and tell nothing."""
    monkeypatch.setattr(fleet, "SHORTER_SECONDS", 0.3)
    D = generate.random_points(8, 4).distances
    optimum = setpart.min_makespan(D, 3, tours=False)
    told: list = []
    began = time.perf_counter()
    routes = shorter_routes(D, 3, optimum.routes, tours=False, found=told.append)
    assert routes == optimum.routes and not told
    assert time.perf_counter() - began < fleet.SHORTER_MISSES * 0.3 + 3.0


@pytest.mark.parametrize("tours", [False, True])
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_the_fewest_routes_match_set_partitioning_on_small_instances(seed, tours):
    """On 9 KPOIs, 1.2 x the least makespan, PyVRP's count is setpart's proven optimum
    (an independent exact method), and every route meets the deadline in floats."""
    D = generate.random_points(9, seed).distances
    deadline = 1.2 * least_makespan(D, tours=tours)
    routes = fewest_routes(D, deadline, tours=tours, seconds=2.0, seed=seed)
    optimum = setpart.min_robots(D, deadline, tours=tours)
    assert optimum.status == "optimal"
    assert routes is not None and _covers(routes, 9)
    assert all(within(route_cost(D, route, tours=tours), deadline) for route in routes)
    assert len(routes) == optimum.objective


@pytest.mark.parametrize("tours", [False, True])
def test_the_squeeze_goes_down_from_the_start_to_the_floor(tours):
    """From a route per KPOI (each within the deadline, since it is at least ``c_max``),
    the squeeze reaches setpart's proven optimum; with the optimum as the floor it ends
    there; with the start's own count as the floor it returns the start untouched."""
    D = generate.random_points(10, 4).distances
    deadline = 1.2 * least_makespan(D, tours=tours)
    optimum = setpart.min_robots(D, deadline, tours=tours)
    assert optimum.status == "optimal"
    singles = [[k] for k in range(1, 11)]
    routes = fewest_routes(D, deadline, tours=tours, seconds=3.0, start=singles)
    assert routes is not None and _covers(routes, 10) and len(routes) == optimum.objective
    assert all(within(route_cost(D, route, tours=tours), deadline) for route in routes)
    floored = fewest_routes(D, deadline, tours=tours, seconds=60.0, start=singles, floor=int(optimum.objective))
    assert floored is not None and len(floored) == optimum.objective
    began = time.perf_counter()
    assert fewest_routes(D, deadline, tours=tours, seconds=60.0, start=singles, floor=10) is singles
    assert time.perf_counter() - began < 5


def test_a_squeeze_that_finds_nothing_tries_the_next_seeds(monkeypatch):
    """The first search at each fleet size finds nothing (as PyVRP from an unlucky seed):
    the squeeze tries that fleet again with the next seed, so it still reaches setpart's
    optimum; one vehicle fewer than that (no routes exist) it gives up after
    :data:`SQUEEZE_SEARCHES` searches, seeds 0, 1, 2, ..., and the search over the whole
    fleet has the time left."""
    from parcover.algorithms import fleet

    D = generate.random_points(10, 4).distances
    deadline = 1.2 * least_makespan(D, tours=False)
    optimum = int(setpart.min_robots(D, deadline, tours=False).objective)
    solve, searches = fleet._solve, []

    def unlucky_first(data, seconds, seed, *, first, done):
        size = data.vehicle_type(0).num_available
        searches.append((size, seed, first))
        found = solve(data, seconds, seed, first=first, done=done)
        return found if not first or [s for s, _, _ in searches].count(size) > 1 else _Nothing()

    monkeypatch.setattr(fleet, "_solve", unlucky_first)
    monkeypatch.setattr(fleet, "SQUEEZE_SECONDS", 0.2)
    routes = fewest_routes(D, deadline, tours=False, seconds=8.0, start=[[k] for k in range(1, 11)])
    assert routes is not None and _covers(routes, 10) and len(routes) == optimum
    assert searches[:2] == [(9, 0, True), (9, 1, True)]  # the fleet of 9 again, with the next seed
    assert [seed for size, seed, _ in searches if size == optimum - 1] == list(range(fleet.SQUEEZE_SEARCHES))
    assert searches[-1][2] is False  # then the whole fleet


class _Nothing:
    """A PyVRP result without routes within the deadline."""

    def is_feasible(self) -> bool:
        return False


def test_a_route_exactly_as_long_as_the_deadline_is_kept():
    """KPOIs on a line at 0.1, 0.3 and 0.7 from the start: one path of length 0.7 (as
    0.1 + 0.2 + 0.4 in floats) at the deadline 0.7 = c_max. Scaled lengths rounded up
    must not push it over the deadline (the module docstring's argument)."""
    xs = np.array([0.0, 0.1, 0.3, 0.7])
    D = np.abs(xs[:, None] - xs[None, :])
    routes = fewest_routes(D, 0.7, tours=False, seconds=1.0)
    assert routes == [[1, 2, 3]]


@pytest.mark.parametrize("tours", [False, True])
def test_each_routes_found_are_told_fewer_than_the_last(tours):
    """``found`` hears every routes fewer than before as they are found, from a route per
    KPOI down to the routes returned (setpart's proven optimum here), each covering every
    KPOI within the deadline."""
    D = generate.random_points(10, 4).distances
    deadline = 1.2 * least_makespan(D, tours=tours)
    heard: list[list[list[int]]] = []
    routes = fewest_routes(D, deadline, tours=tours, seconds=3.0, start=[[k] for k in range(1, 11)],
                           found=heard.append)
    counts = [len(r) for r in heard]
    assert heard and heard[-1] == routes and counts == sorted(set(counts), reverse=True) and counts[0] < 10
    assert len(routes) == setpart.min_robots(D, deadline, tours=tours).objective
    for told in heard:
        assert _covers(told, 10) and all(within(route_cost(D, r, tours=tours), deadline) for r in told)


def test_the_entrant_stops_at_the_bound_it_is_handed(tmp_path):
    """With branch-and-price's bound in the file, the entrant answers optimal as soon as
    its routes meet it, long before its time limit; without one (no file) it uses the
    spanning-tree / clique bound, and answers feasible at its limit when that is lower."""
    D = generate.random_points(25, 4).distances
    deadline = 1.2 * least_makespan(D, tours=True)
    optimum = len(fewest_routes(D, deadline, tours=True, seconds=3.0, seed=1))
    bound_file = tmp_path / "bound"
    race.hand_over(bound_file, optimum)
    began = time.perf_counter()
    answer = race_entrant(D, deadline, tours=True, bound_file=str(bound_file), seed=1, time_limit=30.0)
    assert time.perf_counter() - began < 10
    assert answer.status == "optimal" and answer.objective == answer.bound == optimum
    assert _covers(answer.routes, 25)
    unproven = race_entrant(D, deadline, tours=True, bound_file=str(tmp_path / "none"), seed=1, time_limit=1.0)
    assert unproven.status in ("feasible", "optimal") and unproven.bound >= 1
    assert unproven.status == "optimal" or unproven.bound < unproven.objective


def _root_then_wait(D, deadline, *, tours, time_limit, warm_start, improve, proven, elsewhere):
    """A stand-in for branch-and-price whose root certifies 2 routes while its LP is not
    solved yet (``proven``, not ``improve``: the bound is told as soon as a pricing
    certifies it), then waits for the stop (as the real one reads it at its clock checks)."""
    proven(2)
    clock = TimeLimit(time_limit)
    while not clock.expired() and not stop_requested():
        time.sleep(0.02)
    return MilpResult("feasible", warm_start, float(len(warm_start)), 2.0, None, 0, 0.0,
                      "stopped" if stop_requested() else "time limit")


def test_exact_takes_pyvrps_routes_when_they_meet_branch_and_prices_bound(monkeypatch):
    """``exact`` for the fewest robots above ROOT_FIRST_MAX KPOIs: branch-and-price (here
    a stand-in whose root certifies 2 routes) hands its bound to PyVRP, whose routes
    meeting it end the race early: optimal, proven by branch-and-price's bound, routes
    verified. Two tours cover these 35 KPOIs within 2.5 x the least makespan."""
    from milp import branchprice

    if race.cores() < 2:
        pytest.skip("the race needs two cores")
    monkeypatch.setattr(branchprice, "min_robots", _root_then_wait)
    instance = generate.random_points(35, 5)
    problem = Problem("tours", deadline=2.5 * least_makespan(instance.distances, tours=True))
    start = [[k] for k in range(1, 36)]
    began = time.perf_counter()
    solution = exact_module.exact(instance, problem, time_limit=60.0, warm_start=start)
    assert time.perf_counter() - began < 30
    assert solution.status == Status.OPTIMAL and len(solution.routes) == 2 and solution.bound == 2
    assert solution.info["model"] == "branchprice" and "PyVRP" in solution.info["message"]
    D = instance.distances
    assert _covers(solution.routes, 35)
    assert all(within(route_cost(D, route, tours=True), problem.deadline) for route in solution.routes)


def _uniform_35_tours() -> tuple[np.ndarray, float]:
    """35 uniform KPOIs, tours within 1.2 x the least makespan: the spanning-tree / clique
    bound is 3, the q-route LP bound 4 (3.07 rounded up), and 4 is the optimum
    (branch-and-price proves it in the test below)."""
    D = generate.random_points(35, 7).distances
    return D, 1.2 * least_makespan(D, tours=True)


def test_the_entrant_proves_the_q_route_bound_before_its_search(tmp_path):
    """Without a bound from branch-and-price (no file) the entrant's routes meet the
    q-route LP bound: optimal; and a warm start that meets it is the answer at once."""
    from milp import branchprice
    from milp.bounds import robots_lower_bound

    D, deadline = _uniform_35_tours()
    assert robots_lower_bound(D, deadline, tours=True) == 3
    reference = branchprice.min_robots(D, deadline, tours=True, time_limit=120.0)
    assert reference.status == "optimal" and reference.objective == 4
    bound_file = tmp_path / "bound"  # never written: branch-and-price proves nothing here
    answer = race_entrant(D, deadline, tours=True, bound_file=str(bound_file), seed=1, time_limit=60.0)
    assert answer.status == "optimal" and answer.objective == answer.bound == 4
    assert "q-route LP bound 4" in answer.message and _covers(answer.routes, 35)
    began = time.perf_counter()
    warm = race_entrant(D, deadline, tours=True, bound_file=str(bound_file), time_limit=60.0,
                        warm_start=answer.routes)
    assert time.perf_counter() - began < 10
    assert warm.status == "optimal" and warm.routes == answer.routes
    assert warm.message.endswith("meets the warm start's routes")


#: What the stand-in below was handed by ``elsewhere``, as it polled.
HANDED: list[list[list[int]]] = []


def _polls_for_routes_elsewhere(D, deadline, *, tours, time_limit, warm_start, improve, proven, elsewhere):
    """A stand-in for branch-and-price that proves nothing and polls ``elsewhere`` (as the
    real one does between pricing rounds) until the stop or its limit and once after,
    keeping each routes handed to it."""
    clock = TimeLimit(time_limit)
    while True:
        routes = elsewhere()  # once more after the stop, as the real tree takes them before it ends
        if routes is not None:
            HANDED.append(routes)
        if clock.expired() or stop_requested():
            break
        time.sleep(0.02)
    return MilpResult("feasible", warm_start, float(len(warm_start)), 1.0, None, 0, 0.0, "time limit")


def test_pyvrps_routes_reach_branch_and_price_while_it_runs(monkeypatch):
    """``exact``'s race hands each routes PyVRP finds, fewer than before, to branch-and-price
    as they are found (a file it polls): from a route per KPOI, the stand-in is handed
    routes covering every KPOI within the deadline, each fewer than the last, down to the 4
    that meet the q-route bound (PyVRP's proof, which ends the race long before the limit)."""
    from milp import branchprice

    if race.cores() < 2:
        pytest.skip("the race needs two cores")
    HANDED.clear()
    monkeypatch.setattr(branchprice, "min_robots", _polls_for_routes_elsewhere)
    D, deadline = _uniform_35_tours()
    instance = generate.random_points(35, 7)
    start = [[k] for k in range(1, 36)]
    began = time.perf_counter()
    solution = exact_module.exact(instance, Problem("tours", deadline=deadline), time_limit=90.0, warm_start=start)
    assert time.perf_counter() - began < 60
    assert solution.status == Status.OPTIMAL and len(solution.routes) == 4
    assert HANDED, "no routes reached branch-and-price"
    counts = [len(routes) for routes in HANDED]
    assert counts == sorted(set(counts), reverse=True) and counts[0] < 35 and counts[-1] == 4
    for routes in HANDED:
        assert _covers(routes, 35) and all(within(route_cost(D, route, tours=True), deadline) for route in routes)


def _root_proves_three(D, deadline, *, tours, time_limit, warm_start, improve, proven, elsewhere):
    """A stand-in for branch-and-price whose solved root proves only 3 routes."""
    improve(3, 0.0)
    clock = TimeLimit(time_limit)
    while not clock.expired() and not stop_requested():
        time.sleep(0.02)
    return MilpResult("feasible", warm_start, float(len(warm_start)), 3.0, None, 0, 0.0, "stopped")


def test_exact_names_the_q_route_bound_when_it_proves_the_answer(monkeypatch):
    """Branch-and-price's bound (3, a stand-in) is below the 4 routes; the entrant's
    q-route bound proves them: ``model`` is ``colgen``, and ``verify --certify`` would
    re-prove with branch-and-price."""
    from milp import branchprice
    from parcover.certify import certifier_for

    if race.cores() < 2:
        pytest.skip("the race needs two cores")
    monkeypatch.setattr(branchprice, "min_robots", _root_proves_three)
    D, deadline = _uniform_35_tours()
    instance = generate.random_points(35, 7)
    solution = exact_module.exact(instance, Problem("tours", deadline=deadline), time_limit=60.0)
    assert solution.status == Status.OPTIMAL and len(solution.routes) == 4 and solution.bound == 4
    assert solution.info["model"] == "colgen"
    assert all(within(route_cost(D, route, tours=True), deadline) for route in solution.routes)
    assert certifier_for(instance, "exact", "robots", model="colgen") == "branchprice"
