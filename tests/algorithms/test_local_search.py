"""Tests of ``best`` (parcover.algorithms.local_search)."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from parcover import Instance, generate, solve
from parcover.algorithms.local_search import best, improve, min_max_insertion, race_entrant, searched_branchcut
from parcover.problem import MethodInfo, Problem, Solution, meets_deadline
from parcover.solve import METHODS, available_methods
from parcover.verify import route_costs
from strategies import instances, least_makespan_or_robots

QUESTIONS = [
    ("paths", 2, None),
    ("tours", 2, None),
    ("paths", None, None),
    ("tours", None, None),
]


def _value(instance, problem, routes):
    """The objective key recomputed by the project's verifier."""
    costs = route_costs(instance, routes, tours=problem.tours)
    value = (max(costs), sum(costs))
    return value if problem.objective == "makespan" else (len(routes), *value)


@pytest.mark.parametrize("routes, robots, deadline", QUESTIONS)
@pytest.mark.parametrize("fixture", ["fig1_grid", "fig3_star"])
def test_best_is_valid_on_the_paper_figures(request, fixture, routes, robots, deadline):
    instance = request.getfixturevalue(fixture)
    result = solve(instance, routes, robots=robots, deadline=deadline, method="best")
    # solve() raises SolverError on invalid routes; the makespan objective uses <= k robots
    assert result.routes
    if robots is not None:
        assert result.robots <= robots


def test_fig1_grid_two_paths_reach_the_optimum_four(fig1_grid):
    # c_max = 4 (cell r2c2 is 4 steps from the start r0c0) is a lower bound on the
    # makespan: some robot must reach r2c2. Two paths of cost 4 cover the 8 cells:
    # r0c1 r0c2 r1c2 r2c2 and r1c0 r2c0 r2c1 r1c1 (one step each). So 4 is optimal.
    result = solve(fig1_grid, "paths", robots=2, method="best")
    assert result.makespan == pytest.approx(4.0)


def test_tiny_line_tours_one_robot(tiny_line):
    # One tour must go out to c (distance 3) and back: cost 6, reached by s a b c s.
    result = solve(tiny_line, "tours", robots=1, method="best")
    assert result.makespan == pytest.approx(6.0)


def test_own_construction_is_valid_under_a_deadline(fig3_star):
    problem = Problem("tours")  # deadline 2 c_max = 2: one KPOI per tour on the star
    routes = min_max_insertion(fig3_star, problem)
    assert sorted(v for r in routes for v in r) == list(range(1, 7))
    assert all(meets_deadline(c, 2.0) for c in route_costs(fig3_star, routes, tours=True))


def _raises(instance, problem, **_):
    raise RuntimeError("a broken construction")


def _misses_a_kpoi(instance, problem, **_):
    return Solution(routes=[[1]])  # KPOIs 2..n uncovered: invalid, must be skipped


def test_broken_constructions_are_skipped(monkeypatch, fig1_grid):
    available_methods()  # load the registry before patching it
    monkeypatch.setitem(METHODS, "broken", MethodInfo("broken", _raises, "raises"))
    monkeypatch.setitem(METHODS, "partial", MethodInfo("partial", _misses_a_kpoi, "invalid"))
    result = solve(fig1_grid, "paths", robots=2, method="best", iterations=2)
    assert result.makespan == pytest.approx(4.0)
    assert result.info["start"] not in ("broken", "partial")


def test_same_seed_gives_identical_routes():
    instance = generate.random_points(25, 3)
    first = solve(instance, "paths", robots=3, method="best", seed=7, iterations=5)
    second = solve(instance, "paths", robots=3, method="best", seed=7, iterations=5)
    assert first.routes == second.routes


def test_improves_a_poor_start_on_random_points():
    # The trivial start deals KPOIs out in list order: far from optimal on random points.
    instance = generate.random_points(30, 5)
    problem = Problem("paths", robots=3)
    start = [list(range(1, 11)), list(range(11, 21)), list(range(21, 31))]
    routes, info = improve(instance, problem, start, seed=0, iterations=5)
    assert _value(instance, problem, routes)[0] < _value(instance, problem, start)[0]
    assert info["value"][0] == pytest.approx(_value(instance, problem, routes)[0])


def test_the_search_stops_once_the_target_is_met_and_not_before():
    # The same poor start as above: 3 paths of 10 KPOIs in list order. A target at the
    # start's own makespan is met before the first round; one below every makespan (0)
    # never is, so all rounds run.
    instance = generate.random_points(30, 5)
    problem = Problem("paths", robots=3)
    start = [list(range(1, 11)), list(range(11, 21)), list(range(21, 31))]
    start_value = _value(instance, problem, start)[0]
    _, met = improve(instance, problem, start, seed=0, iterations=5, target=start_value)
    _, unmet = improve(instance, problem, start, seed=0, iterations=5, target=0.0)
    assert met["iterations"] == 0 and unmet["iterations"] == 5


def test_robots_target_counts_routes(fig3_star):
    # Robots objective: a target of as many robots as the start has stops at once; the
    # answer is never worse than the start.
    problem = Problem("paths", deadline=fig3_star.c_max * 3)
    start = [[j] for j in range(1, fig3_star.n + 1)]
    routes, met = improve(fig3_star, problem, start, seed=0, iterations=5, target=len(start))
    _, unmet = improve(fig3_star, problem, start, seed=0, iterations=5, target=0)
    assert met["iterations"] == 0 and len(routes) <= len(start)
    assert unmet["iterations"] == 5


@settings(max_examples=25)
@given(instance=instances(1, 9), problem=least_makespan_or_robots(4), seed=st.integers(0, 3))
def test_best_is_valid_and_never_worse_than_its_start(instance, problem, seed):
    robots = problem.robots
    solution = best(instance, problem, seed=seed, iterations=3)
    found = solution.routes
    assert sorted(v for r in found for v in r) == list(range(1, instance.n + 1))
    if robots is not None:
        assert len(found) <= robots
    deadline = problem.effective_deadline(instance)
    costs = route_costs(instance, found, tours=problem.tours)
    if deadline is not None:
        assert all(meets_deadline(c, deadline) for c in costs)
    value = _value(instance, problem, found)
    start = solution.info["start_value"]
    assert value[0] <= start[0] + 1e-9
    if problem.objective == "robots" and value[0] == start[0]:
        assert value[1] <= start[1] * (1 + 1e-9) + 1e-9


def test_local_search_keeps_the_names_of_its_split_parts():
    from parcover.algorithms import local_search, moves, starts

    assert local_search.min_max_insertion is starts.min_max_insertion
    assert local_search.best_construction is starts.best_construction
    assert set(local_search.__all__) <= set(dir(local_search)) and local_search.Search is moves.Search


@pytest.mark.parametrize("tours", [False, True])
def test_race_entrant_answers_with_valid_routes_and_the_trivial_bound(tours):
    """The local search as branch-and-price's rival: every KPOI once in at most k routes,
    the objective their makespan, the bound the trivial one (not above it), never worse
    than its warm start."""
    from milp import bounds
    from milp.core.routes import makespan

    D = generate.random_points(18, 4).distances
    start = [list(range(1, 10)), list(range(10, 19))]
    answer = race_entrant(D, 3, tours=tours, warm_start=start, seed=2, time_limit=1.0)
    assert answer.status in ("optimal", "feasible") and len(answer.routes) <= 3
    assert sorted(j for r in answer.routes for j in r) == list(range(1, 19))
    assert answer.objective == pytest.approx(makespan(D, answer.routes, tours=tours))
    assert answer.objective <= makespan(D, start, tours=tours) + 1e-9
    assert answer.bound == bounds.makespan_lower_bound(D, 3, tours=tours, time_limit=0.2)
    assert answer.bound <= answer.objective * (1 + 1e-9)


def test_race_entrant_writes_each_better_routes_as_it_finds_them(tmp_path):
    """``improve`` tells each better solution's routes as it finds them (makespans never
    rising); with a routes file, the entrant writes them there, where the race's reader
    finds the last, its answer (every KPOI once in at most k routes), once."""
    from milp import race
    from milp.core.routes import makespan

    D = generate.random_points(18, 4).distances
    start = [list(range(1, 10)), list(range(10, 19))]
    path = tmp_path / "routes"
    read, seen = race.handed_reader(path), []
    assert read() is None  # nothing written yet
    heard = []
    _, info = improve(Instance.from_matrix(D), Problem("tours", robots=3), start, seed=2, iterations=200,
                      found=heard.append)
    assert heard and info["value"][0] == pytest.approx(makespan(D, heard[-1], tours=True))
    answer = race_entrant(D, 3, tours=True, warm_start=start, seed=2, time_limit=1.0, routes_file=str(path))
    seen.append(read())
    assert read() is None  # the same routes again: nothing new
    assert seen[0] is not None and len(seen[0]) <= 3 and sorted(j for r in seen[0] for j in r) == list(range(1, 19))
    assert makespan(D, seen[0], tours=True) == pytest.approx(answer.objective)
    values = [makespan(D, r, tours=True) for r in heard]  # better: a smaller makespan or total length
    assert values == sorted(values, reverse=True)


def test_race_entrant_proves_what_meets_the_trivial_bound():
    """As many robots as KPOIs: one KPOI a route, the makespan is the farthest KPOI's
    distance, which is the trivial bound: optimal."""
    D = generate.random_points(6, 1).distances
    answer = race_entrant(D, 6, tours=False, seed=0, time_limit=2.0)
    assert answer.status == "optimal"
    assert answer.objective == pytest.approx(D[0].max())


@pytest.mark.parametrize("tours", [False, True])
def test_searched_branchcut_proves_set_partitionings_optimum_from_the_searched_routes(tmp_path, tours):
    """The rival with few long routes: the local search from a poor start hands its routes
    over (shorter than the start), then branch-and-cut proves the least makespan, equal to
    set partitioning's over every route (a second exact method), with routes no longer
    than the ones handed over."""
    from milp import race, setpart
    from milp.core.routes import makespan

    D = generate.random_points(12, 7).distances
    start = [list(range(1, 7)), list(range(7, 13))]
    path = tmp_path / "routes"
    answer = searched_branchcut(D, 2, tours=tours, warm_start=start, seed=3, time_limit=8.0,
                                routes_file=str(path))
    handed = race.handed_reader(path)()
    reference = setpart.min_makespan(D, 2, tours=tours, time_limit=60.0)
    assert reference.status == "optimal"
    assert handed is not None and makespan(D, handed, tours=tours) < makespan(D, start, tours=tours)
    assert answer.status == "optimal" and answer.objective == pytest.approx(reference.objective, rel=1e-6)
    assert sorted(j for r in answer.routes for j in r) == list(range(1, 13)) and len(answer.routes) <= 2
    assert makespan(D, answer.routes, tours=tours) <= makespan(D, handed, tours=tours) + 1e-9
    assert answer.message.startswith("from best's local search")
