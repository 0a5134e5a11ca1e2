"""Tests of the paper's Algorithms 1, 1-1 and 2 (parcover/algorithms/paper.py)."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st
from strategies import instances

import parcover as pc
from parcover import Instance
from parcover.algorithms.paper import (
    LITERAL,
    METHODS,
    NEAREST_END,
    Reading,
    algorithm_1,
    algorithm_2,
    paper,
)
from parcover.problem import Problem
from parcover.solve import build_result
from parcover.verify import route_costs

VARIANTS = [info.name for info in METHODS]
READINGS = [LITERAL, Reading(grow_from_end=True), Reading(supplement_from_end=True), NEAREST_END]


@pytest.fixture(scope="module")
def line_graph() -> Instance:
    """s, a, b, c at 0, 1, 2, 3 as a complete graph with the line's distances.

    The metric is tiny_line's, but the shortest path found from s to c is the direct
    edge (Dijkstra keeps the first of tied paths), so P_1 = [c]; on the plane the
    segment s-c passes a and b, and P_1 would be [a, b, c].
    """
    pos = {"s": 0, "a": 1, "b": 2, "c": 3}
    edges = tuple((u, v, float(abs(pos[u] - pos[v]))) for u in pos for v in pos if pos[u] < pos[v])
    inst = Instance("s", ("a", "b", "c"), edges=edges, name="line-graph")
    assert inst.P_max == ("c",)
    return inst


def ids(instance: Instance, routes: list[list[int]]) -> list[list[str]]:
    return [[instance.ids[i] for i in route] for route in routes]


def kpois(result: pc.Result, tours: bool = False) -> list[list[str]]:
    """Routes of a result without the start (and without the return of tours)."""
    return [route[1:-1] if tours else route[1:] for route in result.routes]


# -- hand-made instances ---------------------------------------------------------------


@pytest.fixture(scope="module")
def hook() -> Instance:
    """F far east sets c_max = 70; A, B, Y north of the start and X south of it.

    s = (0, 0), F = (70, 0), A = (0, 10), B = (0, 30), Y = (0, 40), X = (0, -16).
    """
    points = [[0, 0], [70, 0], [0, 10], [0, 30], [0, 40], [0, -16]]
    return Instance.from_points(points, names=["s", "F", "A", "B", "Y", "X"], name="hook")


@pytest.fixture(scope="module")
def cross() -> Instance:
    """E and W at distance 10 east and west of the start, N at distance 1 north."""
    return Instance.from_points([[0, 0], [10, 0], [-10, 0], [0, 1]], names=["s", "E", "W", "N"])


@pytest.fixture(scope="module")
def branches() -> Instance:
    """A graph: s -1- a -1- b, and s -1.5- c -0.4- d (unique shortest paths)."""
    edges = (("s", "a", 1.0), ("a", "b", 1.0), ("s", "c", 1.5), ("c", "d", 0.4))
    return Instance("s", ("a", "b", "c", "d"), edges=edges, name="branches")


def test_literal_reading_and_repair_on_hook(hook: Instance) -> None:
    # c_max = 70, v_max = F, P_1 = [F] (steps 2-4). V = {A, B, Y, X}.
    # 5a: nearest to s is A (10); P_2 = [A], cost 10.
    # 5d (nearest to v_m = A): B (20): 10 + 20 = 30 <= 70, insert; cost 30, end B.
    #     next nearest to A: X (26, before Y at 30): printed 30 + 26 = 56 <= 70, but
    #     the path goes on from B: 30 + d(B, X) = 30 + 46 = 76 > 70 -> repair, break.
    # 5a: nearest to s of {Y, X}: X (16); 5d: nearest to X: Y (56): 16 + 56 > 70, break.
    # 5a: Y (40), V empty. Four paths.
    result = pc.solve(hook, method="paper")
    assert kpois(result) == [["F"], ["A", "B"], ["X"], ["Y"]]
    assert result.makespan == pytest.approx(70)


@pytest.mark.parametrize("method", ["paper-5d-end", "paper-nearest-end"])
def test_growth_from_the_end_differs_on_hook(hook: Instance, method: str) -> None:
    # Same steps 1-4. 5a: A (10). 5d from the current end: A -> B (20, cost 30),
    # B -> Y (10, cost 40), Y -> X (56): 40 + 56 = 96 > 70, break.
    # 5a: X (16); V empty. Three paths, one fewer than the literal reading.
    result = pc.solve(hook, method=method)
    assert kpois(result) == [["F"], ["A", "B", "Y"], ["X"]]
    # Algorithm 1-1 is not involved at c_max: its variant reads step 5d literally.
    assert kpois(pc.solve(hook, method="paper-1-1-end")) == [["F"], ["A", "B"], ["X"], ["Y"]]


def test_algorithm_1_follows_shortest_paths_in_a_graph(branches: Instance) -> None:
    # d(s, .) = a 1, b 2, c 1.5, d 1.9: c_max = 2, v_max = b; the shortest path
    # s -> b passes a, so P_1 = [a, b] (step 3). 5a: c (1.5); 5d: nearest to c is d
    # (0.4): 1.5 + 0.4 = 1.9 <= 2, insert. V empty: two paths.
    for method in VARIANTS:
        result = pc.solve(branches, method=method)
        assert kpois(result) == [["a", "b"], ["c", "d"]]
        assert result.route_costs == pytest.approx([2.0, 1.9])


def test_algorithm_1_1_readings_on_the_line(line_graph: Instance) -> None:
    # c_max = 3, P_1 = [c], deadline c_p = 5 > c_max: Algorithm 1-1.
    # Literal step 1 (nearest to the start): a: 3 + d(c, a) = 5 <= 5, add, v_d = a;
    #   b: 5 + 1 = 6 > 5, break. Step 5: path [b] (cost 2). Two paths.
    # Nearest to the end: b: 3 + 1 = 4, add; a: 4 + 1 = 5, add. One path.
    assert kpois(pc.solve(line_graph, deadline=5, method="paper")) == [["c", "a"], ["b"]]
    assert kpois(pc.solve(line_graph, deadline=5, method="paper-5d-end")) == [["c", "a"], ["b"]]
    for method in ("paper-1-1-end", "paper-nearest-end"):
        assert kpois(pc.solve(line_graph, deadline=5, method=method)) == [["c", "b", "a"]]


def test_robot_limit_scans_thresholds_on_the_line(line_graph: Instance) -> None:
    # K = 1. Literal: Alg 1 at 3 gives [c], [a, b]; Alg 1-1 just above 3 rejects
    # a at 5, still two paths; at 5 it adds a and rejects b at 6; at 6 it adds b:
    # one path c, a, b of cost 3 + 2 + 1 = 6.
    # Nearest end: Alg 1-1 just above 3 rejects b at 4; at 4: c, b, a costs 5.
    literal = pc.solve(line_graph, robots=1, method="paper")
    assert kpois(literal) == [["c", "a", "b"]] and literal.makespan == pytest.approx(6)
    assert literal.info["threshold"] == pytest.approx(6) and literal.info["search"]["exact"]
    end = pc.solve(line_graph, robots=1, method="paper-nearest-end")
    assert kpois(end) == [["c", "b", "a"]] and end.makespan == pytest.approx(5)
    # K = 2: Algorithm 1 at c_max = 3 already gives two paths.
    two = pc.solve(line_graph, robots=2, method="paper")
    assert kpois(two) == [["c"], ["a", "b"]] and two.info["threshold"] == 3


def test_bisection_when_the_scan_budget_is_used_up(line_graph: Instance) -> None:
    # One scan run (Algorithm 1 at 3: two paths) and K = 1. The one-route run (at
    # infinity) is c, a, b with largest test 6; bisection between 3 and 6: at 4.5
    # Alg 1-1 rejects a at 5 (two paths), so low = 5; at 5.5 it adds a and rejects b
    # at 6 (two paths), so low = 6 = high: threshold 6, one path c, a, b.
    problem = Problem("paths", robots=1)
    solution = paper(line_graph, problem, max_scan_runs=1)
    assert solution.routes == [[3, 1, 2]]
    assert solution.info["threshold"] == 6 and not solution.info["search"]["exact"]


def test_robot_count_is_not_monotone_in_the_deadline() -> None:
    # s = (12, 10); KPOIs 1 (7, 19), 2 (12, 14), 3 (8, 10), 4 (16, 9), 5 (13, 9), 6 (15, 13).
    # d(s, .) = sqrt(106) = 10.296 (c_max, v_max = 1), 4, 4, sqrt(17), sqrt(2), sqrt(18).
    # Alg 1-1 step 1: nearest to s is 5; 10.296 + d(1, 5) = 10.296 + sqrt(136) = 21.957.
    # c_p = 21.9: break. Path 2 from 5 (1.414), 5d nearest to 5: 4 (3) -> 4.414;
    #   6 (sqrt 20): from 4 costs 4.414 + sqrt(17) = 8.537; 2 and 3 tie at sqrt(26),
    #   2 first: 8.537 + d(6, 2) = sqrt(10) -> 11.700; 3: printed 11.700 + 5.099 =
    #   16.80, path 11.700 + d(2, 3) = sqrt(32) -> 17.357 <= 21.9. Two paths.
    # c_p = 22: path 1 takes 5 (21.957); next, 2: 21.957 + sqrt(26) > 22, break.
    #   Path 2 from 2 (4): nearest to 2: 6 (sqrt 10) -> 7.162; 3 (sqrt 32): printed
    #   12.82, path 7.162 + d(6, 3) = sqrt(58) -> 14.778; 4 (sqrt 41): printed
    #   21.18 <= 22 but the path from 3 costs 14.778 + sqrt(65) = 22.84: repair, break.
    #   Path 3: [4]. Three paths: more time, more robots.
    points = [[12, 10], [7, 19], [12, 14], [8, 10], [16, 9], [13, 9], [15, 13]]
    instance = Instance.from_points(points)
    assert kpois(pc.solve(instance, deadline=21.9, method="paper")) == [["1"], ["5", "4", "6", "2", "3"]]
    assert kpois(pc.solve(instance, deadline=22, method="paper")) == [["1", "5"], ["2", "6", "3"], ["4"]]
    # So a search over c_p for two robots must not stop at 22's "too many".
    two = pc.solve(instance, robots=2, method="paper")
    assert two.robots <= 2 and two.info["threshold"] <= 21.9


def test_algorithm_2_published_on_the_line(line_graph: Instance) -> None:
    # Alg 1: [c] (cost 3), then 5a a, 5d b: 1 + 1 = 2 <= 3 -> [a, b] (cost 2).
    # Alg 2: a = path 1 (end c); partner path 2 (end b): 3 + 1 + 2 = 6.
    # Tour s, c, b, a, s of cost 6; the deadline is dropped.
    result = pc.solve(line_graph, routes="tours", method="paper")
    assert kpois(result, tours=True) == [["c", "b", "a"]]
    assert result.makespan == pytest.approx(6) and result.deadline is None


def test_algorithm_2_pairs_only_within_a_deadline(cross: Instance) -> None:
    # c_max = 10 (E and W tie: E is listed first, v_max = E). Paths at c_p = 20 / 2:
    # [E] (10); 5a N (1), 5d W: 1 + sqrt(101) > 10, break; [N]; then [W] (10).
    # Published Alg 2: a = [E] (first of the ties), best partner [N]:
    # 10 + sqrt(101) + 1 = 21.05 -> tour E, N; then W alone (20).
    w = math.sqrt(101)
    published = pc.solve(cross, routes="tours", method="paper")
    assert kpois(published, tours=True) == [["E", "N"], ["W"]]
    assert published.makespan == pytest.approx(11 + w)
    # With deadline 20 the pair E + N (21.05) and W + N (21.05) do not fit: 3 tours.
    bounded = pc.solve(cross, routes="tours", deadline=20, method="paper")
    assert kpois(bounded, tours=True) == [["E"], ["W"], ["N"]]
    # With deadline 22 they do: E + N, then W alone.
    assert kpois(pc.solve(cross, routes="tours", deadline=22, method="paper"), tours=True) == [
        ["E", "N"],
        ["W"],
    ]


# -- the paper's figures ---------------------------------------------------------------


@pytest.mark.parametrize("method", VARIANTS)
@pytest.mark.parametrize("routes", ["paths", "tours"])
def test_figures_give_valid_solutions(fig1_grid: Instance, fig3_star: Instance, method: str, routes: str) -> None:
    for instance in (fig1_grid, fig3_star):
        pc.solve(instance, routes=routes, method=method)  # verified inside solve
        pc.solve(instance, routes=routes, robots=2, method=method)
        pc.solve(instance, routes=routes, deadline=3 * instance.c_max, method=method)


def test_fig3_counts(fig3_star: Instance) -> None:
    # Fig. 3: 6 equidistant KPOIs 1 apart (a hexagon): every path is one edge s -> v
    # of cost 1 = c_max, and any second KPOI costs 1 + 1 > c_max: 6 paths.
    paths = pc.solve(fig3_star, method="paper")
    assert paths.robots == 6 and paths.makespan == pytest.approx(1)
    # Algorithm 2 as published pairs them: 3 tours of two KPOIs each.
    tours = pc.solve(fig3_star, routes="tours", method="paper")
    assert tours.robots == 3 and all(len(t) == 4 for t in tours.routes)


def test_fig1_readings(fig1_grid: Instance) -> None:
    # c_max = 4 and P_1 holds the 4 KPOIs of a shortest path s -> r2c2 (step 3).
    literal = pc.solve(fig1_grid, method="paper")
    assert literal.route_costs[0] == pytest.approx(4) and len(literal.routes[0]) == 5
    assert literal.routes[0][-1] == "r2c2"
    # Nearest-end growth covers the other 4 cells with one more robot (Fig. 1: 2 robots
    # reach time 4); the literal reading needs 3 here.
    assert pc.solve(fig1_grid, method="paper-nearest-end").robots == 2
    assert literal.robots == 3


def test_trace_on_fig1(fig1_grid: Instance) -> None:
    result = pc.solve(fig1_grid, method="paper", trace=True)
    trace = result.info["trace"]
    for step in ("step 1", "step 2", "step 3", "step 4", "step 5a", "step 5d", "step 6"):
        assert any(step in line for line in trace), step
    assert any("v_max = r2c2" in line and "c_max = 4" in line for line in trace)
    assert any("budget left" in line for line in trace)
    assert trace[-1] == "Result: 3 robots (3 paths)"
    assert "trace" not in pc.solve(fig1_grid, method="paper").info


@pytest.mark.parametrize(("routes", "robots"), [("paths", None), ("paths", 2), ("tours", None), ("tours", 2)])
def test_trace_steps_record_each_line_with_its_state(fig1_grid: Instance, routes: str, robots: int | None) -> None:
    # info["steps"] holds one record per line of info["trace"], in order; the state it
    # carries agrees with the routes returned and with the budget the line prints.
    result = pc.solve(fig1_grid, routes, robots=robots, method="paper", trace=True)
    steps = result.info["steps"]
    assert [step.text for step in steps] == result.info["trace"]
    final = steps[-1].tours if routes == "tours" else steps[-1].paths
    start = fig1_grid.start
    assert [[start, *r, *([start] if routes == "tours" else [])] for r in final] == result.routes
    for step in steps:
        if step.budget_left is not None and "budget left" in step.text:
            assert f"budget left {step.budget_left:g}" in step.text
        if step.candidate is not None and step.current is not None and step.paths:
            # a candidate is in the path grown exactly when the step took it
            assert (step.candidate in step.paths[step.current]) == step.accepted
    pairing = [step for step in steps if step.text.startswith("Alg 2 steps")]
    assert len(pairing) == (len(result.routes) if routes == "tours" else 0)
    for step in pairing:  # each tour is its paths joined: P_a, then P_b reversed
        a, *b = step.joined
        assert step.tours[step.current] == step.paths[a] + (step.paths[b[0]][::-1] if b else ())


# -- properties ------------------------------------------------------------------------


@given(instances(1, 8))
def test_algorithm_1_makespan_is_c_max(instance: Instance) -> None:
    # Prop. 1: the first path is a shortest path to v_max, every other within c_max.
    for method in VARIANTS:
        result = pc.solve(instance, method=method)
        assert result.makespan == pytest.approx(instance.c_max, rel=1e-9, abs=1e-9)


@given(instances(1, 8), st.floats(1.0, 3.0))
def test_algorithm_1_1_meets_the_deadline(instance: Instance, factor: float) -> None:
    c_p = factor * instance.c_max
    for reading in READINGS:
        paths = algorithm_1(instance, c_p, reading=reading)
        covered = sorted(i for path in paths for i in path)
        assert covered == list(range(1, instance.n + 1))
        assert max(route_costs(instance, paths, tours=False)) <= c_p * (1 + 1e-9) + 1e-9
    for method in VARIANTS:
        pc.solve(instance, deadline=c_p, method=method)
        pc.solve(instance, routes="tours", deadline=2 * c_p, method=method)


@given(instances(1, 8), st.integers(1, 4))
def test_robot_limit_is_kept(instance: Instance, k: int) -> None:
    for method in VARIANTS:
        for routes in ("paths", "tours"):
            result = pc.solve(instance, routes=routes, robots=k, method=method)
            assert result.robots <= k
            assert result.info["search"]["exact"]


@given(instances(1, 7), st.integers(1, 3))
def test_robot_limit_threshold_is_the_least(instance: Instance, k: int) -> None:
    # Independent check of the scan: at every threshold on a fine grid below the one
    # found (and at c_max itself, Algorithm 1), Algorithm 1 / 1-1 needs more than K paths.
    result = pc.solve(instance, robots=k, method="paper")
    found = result.info["threshold"]
    c_max = instance.c_max
    assert len(algorithm_1(instance, c_max)) > k or found == c_max
    for step in range(1, 101):
        c_p = c_max + (found - c_max) * step / 101
        if c_p > c_max and c_p < found * (1 - 1e-6) - 1e-6:
            assert len(algorithm_1(instance, c_p)) > k, c_p


@given(instances(1, 8))
def test_published_tours_are_valid_pairings(instance: Instance) -> None:
    paths = algorithm_1(instance)
    tours = algorithm_2(instance, paths)
    assert len(tours) == math.ceil(len(paths) / 2)
    pc.solve(instance, routes="tours", method="paper")


@given(instances(2, 8), st.integers(1, 3))
def test_bisection_fallback_is_valid(instance: Instance, k: int) -> None:
    # One scan run only: the search must fall back to bisection and still keep K.
    problem = Problem("paths", robots=k)
    solution = paper(instance, problem, max_scan_runs=1)
    result = build_result(instance, problem, "paper", solution, 0.0)
    assert result.robots <= k


def test_same_answer_twice(fig1_grid: Instance) -> None:
    first = pc.solve(fig1_grid, robots=2, method="paper")
    assert pc.solve(fig1_grid, robots=2, method="paper").routes == first.routes
