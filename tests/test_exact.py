"""The exact methods through parcover: five methods agree, exports reproduce the optimum."""

from __future__ import annotations

import time

import highspy
import pytest

from milp.core.routes import makespan
from parcover import InputError, Status, frontier, generate, solve

CASES = [generate.random_points(7, 11), generate.random_graph(6, 5, virtual=8)]


@pytest.mark.parametrize("instance", CASES, ids=["euclid7", "graph6"])
@pytest.mark.parametrize("routes", ["paths", "tours"])
@pytest.mark.parametrize("question", [{"robots": 2}, {}])
def test_exact_methods_agree(instance, routes, question):
    methods = ("exact", "compact", "branchprice", "setpart", "cvxpy")
    values = []
    for method in methods:
        result = solve(instance, routes, method=method, **question)
        assert result.status is Status.OPTIMAL, method
        values.append(result.value)
    assert values == pytest.approx([values[0]] * len(methods), rel=1e-6)


def test_fig1_grid_optimal_makespans_8_4_4(fig1_grid):
    # Fig. 1: one robot walks a Hamiltonian path of the 8 cells (8 unit moves; no
    # shorter walk visits 8 cells); with 2 or 3 robots the far corner bounds it at c_max = 4.
    makespans = [solve(fig1_grid, robots=k).makespan for k in (1, 2, 3)]
    assert makespans == [8, 4, 4]


def test_exported_model_gives_the_same_optimum(tmp_path):
    instance = CASES[0]
    path = tmp_path / "model.mps"
    result = solve(instance, robots=2, export_model=str(path))
    highs = highspy.Highs()
    highs.setOptionValue("output_flag", False)
    highs.readModel(str(path))
    highs.setOptionValue("mip_rel_gap", 1e-9)
    highs.run()
    assert highs.getInfo().objective_function_value == pytest.approx(result.makespan, rel=1e-7)


def test_exact_frontier_is_non_increasing_and_ends_at_least_makespan():
    instance = generate.random_points(6, 2)
    for routes, least in (("paths", instance.c_max), ("tours", 2 * instance.c_max)):
        points = frontier(instance, routes).points
        makespans = [p.makespan for p in points]
        assert all(p.status is Status.OPTIMAL for p in points)
        assert makespans == sorted(makespans, reverse=True)
        assert makespans[-1] == pytest.approx(least)


def test_compact_keeps_to_its_time_limit_warm_start_included():
    # 40 KPOIs, k = 3 paths: not proven in 3 s, so the whole limit is used; the warm
    # start's search counts against it (it used to come on top).
    instance = generate.random_points(40, 2)
    started = time.perf_counter()
    result = solve(instance, "paths", robots=3, method="compact", time_limit=3)
    assert time.perf_counter() - started < 3.3
    assert result.status is Status.FEASIBLE and result.bound < result.value


def test_branchprice_keeps_to_its_time_limit_warm_start_included():
    # 60 KPOIs, 2 tours: routes of 30 KPOIs, far from proven in 3 s.
    instance = generate.random_points(60, 3)
    started = time.perf_counter()
    result = solve(instance, "tours", robots=2, method="branchprice", time_limit=3)
    assert time.perf_counter() - started < 3.3 + 0.5
    assert result.status in (Status.FEASIBLE, Status.OPTIMAL)


def test_ready_within_needs_the_compiled_pricing_or_room_to_compile(monkeypatch):
    from milp import branchprice
    from milp.branchprice import compiling

    branchprice.compile_pricing()  # compiles (a fresh installation) or loads the cache
    assert branchprice.ready_within(0.1)
    monkeypatch.setattr(compiling, "compiled", lambda function: False)  # a fresh installation
    assert not branchprice.ready_within(branchprice.COMPILE_SECONDS - 1)
    assert branchprice.ready_within(branchprice.COMPILE_SECONDS) and branchprice.ready_within(None)


@pytest.mark.parametrize("n, model", [(18, "setpart"), (25, "compact")])
def test_exact_skips_branchprice_when_its_compilation_does_not_fit(monkeypatch, n, model):
    from milp import branchprice

    monkeypatch.setattr(branchprice, "ready_within", lambda seconds: seconds is None)
    instance = generate.random_points(n, 4)
    started = time.perf_counter()
    result = solve(instance, "paths", robots=5, time_limit=5)
    assert time.perf_counter() - started < 5.5
    assert result.info["model"] == model
    if result.status is not Status.OPTIMAL:  # an unproven answer says why and what to do
        assert "compiles once per installation" in result.info["message"]
        assert "compiles once per installation" in result.summary()


def test_an_unproven_fallback_says_branchprice_was_not_compiled():
    from parcover.exact import _noting_uncompiled
    from parcover.problem import Solution

    unproven = _noting_uncompiled(Solution(routes=[[1]], info={"message": "time limit"}))
    assert unproven.info["message"].startswith("time limit; branch-and-price not run")
    proven = _noting_uncompiled(Solution(routes=[[1]], status=Status.OPTIMAL, info={"message": "closed"}))
    assert proven.info["message"] == "closed"


def test_branchprice_without_time_to_compile_answers_best_routes_and_says_why(monkeypatch):
    from milp import branchprice

    monkeypatch.setattr(branchprice, "ready_within", lambda seconds: seconds is None)
    instance = generate.random_points(25, 4)
    result = solve(instance, "tours", robots=2, method="branchprice", time_limit=2)
    assert result.routes and result.status is Status.FEASIBLE
    assert "compiled on first use" in result.info["message"]


def test_warm_start_takes_a_results_routes_and_refuses_bad_ones():
    instance = generate.random_points(9, 2)
    earlier = solve(instance, "tours", robots=3, method="best")
    again = solve(instance, "tours", robots=3, method="compact", warm_start=earlier.routes)
    assert again.status is Status.OPTIMAL and again.value <= earlier.value * (1 + 1e-9)
    kpois = list(instance.kpois)
    for bad, why in [([kpois[:-1]], "every KPOI exactly once"), ([kpois + ["nowhere"]], "not a node"),
                     ([[k] for k in kpois], "allows 3"), ("abc", "list of routes")]:
        with pytest.raises(InputError, match=why):
            solve(instance, "tours", robots=3, method="compact", warm_start=bad)
    # within a deadline: a route above it is refused
    with pytest.raises(InputError, match="above the deadline"):
        solve(instance, "tours", deadline=2 * instance.c_max, method="compact", warm_start=[kpois])


def test_exact_races_branch_and_cut_for_two_long_tours():
    """22 KPOIs, 2 tours: branch-and-price alone took 2.5 s and more on this one in a
    loaded run (timing-dependent), so exact may race it against branch-and-cut (on two
    cores); the answer is proven, names its method, and equals both methods' optimum."""
    from milp import race

    instance = generate.random_points(22, 26)
    result = solve(instance, "tours", robots=2, time_limit=120)
    assert result.status is Status.OPTIMAL
    assert result.info["model"] in (("branchprice", "branchcut") if race.cores() >= 2 else ("branchprice",))
    for method in ("branchcut", "branchprice"):
        alone = solve(instance, "tours", robots=2, method=method, time_limit=120)
        assert alone.status is Status.OPTIMAL and result.value == pytest.approx(alone.value, rel=1e-6)
    assert alone.status is Status.OPTIMAL and result.value == pytest.approx(alone.value, rel=1e-6)



def test_exact_hands_the_searched_routes_over_where_branch_and_cut_races(monkeypatch):
    """3 tours on 22 KPOIs: the rival is branch-and-cut after ``best``'s local search
    (``searched_branchcut``), which hands each better routes to branch-and-price as it
    finds them. With a branch-and-price here that proves nothing and a poor warm start,
    the routes handed over improve on it, and the answer, proven by branch-and-cut, is no
    longer than the last of them and equals branch-and-price's optimum (a second exact
    method)."""
    from milp import branchprice, race
    import parcover.exact as exact_module
    from parcover.problem import Problem

    if race.cores() < 2:
        pytest.skip("the race needs two cores")
    handed = []

    def nothing_proven(D, k, *, tours, time_limit, warm_start=None, elsewhere=None):
        from milp.core.result import MilpResult
        from milp.core.timelimit import TimeLimit, stop_requested

        clock = TimeLimit(time_limit)
        while not clock.expired() and not stop_requested():
            routes = elsewhere()  # as branch-and-price polls between pricing rounds
            if routes is not None:
                handed.append(routes)
            time.sleep(0.02)
        return MilpResult("unknown", [], None, None, None, 0, 0.0, "time limit")

    instance = generate.random_points(22, 8)
    reference = branchprice.min_makespan(instance.distances, 3, tours=True, time_limit=60.0)
    monkeypatch.setattr(branchprice, "min_makespan", nothing_proven)
    poor = [list(range(1, 9)), list(range(9, 16)), list(range(16, 23))]
    answer = exact_module.exact(instance, Problem("tours", robots=3), time_limit=40.0, warm_start=poor)
    assert handed, "no routes reached branch-and-price"
    values = [makespan(instance.distances, routes, tours=True) for routes in handed]
    assert values == sorted(values, reverse=True) and values[0] < makespan(instance.distances, poor, tours=True)
    assert reference.status == "optimal" and answer.info["model"] == "branchcut"
    assert makespan(instance.distances, answer.routes, tours=True) == pytest.approx(reference.objective, rel=1e-6)
    assert makespan(instance.distances, answer.routes, tours=True) <= values[-1] * (1 + 1e-9)


def test_the_makespan_race_picks_its_rival_by_robots_and_size():
    """Branch-and-cut alone with 1 robot, and with 2 below 60 KPOIs; after the local search
    with 3 robots, and with 2 from 60 KPOIs; the local search alone with more robots or KPOIs than
    branch-and-cut races for (``parcover.exact``'s constants)."""
    from parcover.exact import RACE_MAX_KPOIS, makespan_rival

    alone, searched = ("branchcut", "milp.branchcut:min_makespan"), (
        "branchcut", "parcover.algorithms.local_search:searched_branchcut")
    local_search = ("best", "parcover.algorithms.local_search:race_entrant")
    assert makespan_rival(40, 2) == makespan_rival(59, 2) == makespan_rival(98, 1) == alone
    assert makespan_rival(60, 2) == makespan_rival(98, 2) == makespan_rival(22, 3) == searched
    assert makespan_rival(22, 4) == makespan_rival(RACE_MAX_KPOIS + 1, 2) == local_search


def test_exact_races_within_its_time_limit():
    # 60 KPOIs, 2 tours: unproven in 6 s; the race and the first branch-and-price share it
    instance = generate.random_points(60, 3)
    started = time.perf_counter()
    result = solve(instance, "tours", robots=2, time_limit=6)
    assert time.perf_counter() - started < 6 * 1.1
    assert result.status is Status.FEASIBLE and result.bound < result.value


def test_exact_races_best_where_branch_and_cut_does_not_reach(monkeypatch):
    """5 tours on 25 KPOIs (more robots than branch-and-cut races for): the rival is
    ``best``'s local search in another process. With a branch-and-price here that proves
    nothing, the answer is the rival's: verified routes no worse than the warm start, the
    trivial bound, the message saying whose routes they are; it hands each better routes to
    branch-and-price as it finds them."""
    from milp import branchprice, race

    if race.cores() < 2:
        pytest.skip("the race needs two cores")
    asked, handed = [], []

    def nothing_proven(D, k, *, tours, time_limit, warm_start=None, elsewhere=None):
        from milp.core.result import MilpResult
        from milp.core.timelimit import TimeLimit

        asked.append(warm_start)
        clock = TimeLimit(time_limit)
        while True:
            routes = elsewhere()  # as branch-and-price polls between pricing rounds
            if routes is not None:
                handed.append(routes)
            if clock.expired():
                break
            time.sleep(0.02)
        return MilpResult("unknown", [], None, None, None, 0, 0.0, "time limit")

    monkeypatch.setattr(branchprice, "min_makespan", nothing_proven)
    instance = generate.random_points(25, 8)
    result = solve(instance, "tours", robots=5, time_limit=8)
    assert asked and result.routes and "routes by best's local search and PyVRP" in result.info["message"]
    assert result.model in ("branchprice", "bounds")
    assert result.value <= makespan(instance.distances, asked[0], tours=True) * (1 + 1e-9)
    assert 2 * instance.c_max <= result.bound <= result.value
    # from a poor warm start the rival finds better routes, and hands each over as it does
    import parcover.exact as exact_module
    from parcover.problem import Problem

    poor = [list(range(1, 6)), list(range(6, 11)), list(range(11, 16)), list(range(16, 21)), list(range(21, 26))]
    asked.clear()
    answer = exact_module.exact(instance, Problem("tours", robots=5), time_limit=8.0, warm_start=poor)
    assert asked == [poor] and handed, "no routes reached branch-and-price"
    values = [makespan(instance.distances, routes, tours=True) for routes in handed]
    assert all(len(r) <= 5 and sorted(j for route in r for j in route) == list(range(1, 26)) for r in handed)
    assert values == sorted(values, reverse=True) and values[0] < makespan(instance.distances, poor, tours=True)
    assert makespan(instance.distances, answer.routes, tours=True) == pytest.approx(values[-1])


def test_branchcut_answers_the_least_makespan_only():
    with pytest.raises(InputError, match="least makespan only"):
        solve(generate.random_points(8, 1), "tours", deadline=500, method="branchcut")


def test_branchcut_refuses_more_than_its_kpois():
    from milp import branchcut

    instance = generate.random_points(branchcut.MAX_KPOIS + 1, 1)
    with pytest.raises(InputError, match="at most 100 KPOIs"):
        solve(instance, "tours", robots=2, method="branchcut", time_limit=5)


@pytest.mark.parametrize("limit,method_seconds", [(5.0, 4.5), (120.0, 118.0), (300.0, 298.0)])
def test_a_long_limit_keeps_back_seconds_not_a_share(monkeypatch, limit, method_seconds):
    """The method gets the limit less 10% for checking, but never less than all but 2 s:
    a share without a cap made a proof at 110 s need --time-limit 300 (the method had
    108 s of 120)."""
    import sys

    from parcover.problem import MethodInfo, Solution

    solve_module = sys.modules["parcover.solve"]  # parcover.solve is also the function

    given = []

    def record(instance, problem, *, time_limit=None, seed=0):
        given.append(time_limit)
        return Solution(routes=[list(range(1, instance.n + 1))])

    monkeypatch.setitem(solve_module.METHODS, "recorder", MethodInfo("recorder", record, "records its time limit"))
    solve(generate.random_points(5, 1), robots=2, method="recorder", time_limit=limit)
    assert given and given[0] == pytest.approx(method_seconds, abs=0.05)


def test_balanced_search_takes_the_roots_seconds_beyond_the_warm_start():
    """The root took no longer than the warm start: no search. Given a second: routes
    meeting the bound when the heuristic finds them (12 KPOIs, paths within 1.2 c_max:
    setpart's optimum is the bound asked for)."""
    from milp import setpart
    from milp.core.timelimit import TimeLimit
    from parcover.exact import balanced_search
    from parcover.problem import Problem

    instance = generate.random_points(12, 5)
    problem = Problem("paths", deadline=1.2 * instance.c_max)
    fewest = int(setpart.min_robots(instance.distances, problem.deadline, tours=False).objective)
    assert balanced_search(instance, problem, TimeLimit(None), 0, fewest, 0.0) is None
    routes = balanced_search(instance, problem, TimeLimit(None), 0, fewest, 1.0)
    assert routes is not None and len(routes) == fewest
