"""Tests of the baseline constructions (parcover.algorithms.baselines).

Every method goes through :func:`parcover.solve`, which verifies the routes; the
tests add their own checks (each KPOI once, robot limit, deadline) so that they can
fail independently of the verifier. Expected routes of tiny instances are derived
by hand in the comments.
"""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st
from strategies import instances

from parcover import Instance, solve
from parcover.algorithms.baselines import METHODS
from parcover.problem import meets_deadline

NAMES = ("mst", "nn", "knn", "kni", "split")
KINDS = ("paths", "tours")


def least_makespan(instance: Instance, routes: str) -> float:
    return 2 * instance.c_max if routes == "tours" else instance.c_max


def check(instance: Instance, routes: str, method: str, robots: int | None = None,
          deadline: float | None = None) -> None:
    """Solve and check validity, the robot limit and the deadline independently."""
    result = solve(instance, routes=routes, robots=robots, deadline=deadline, method=method)
    visited = [node for route in result.routes for node in route if node in instance.kpois]
    assert sorted(visited) == sorted(instance.kpois)
    assert result.robots == len(result.routes) >= 1
    if robots is not None:
        assert result.robots <= robots
    else:
        limit = least_makespan(instance, routes) if deadline is None else deadline
        assert all(meets_deadline(cost, limit) for cost in result.route_costs)


def ids(instance: Instance, routes: list[list[str]]) -> list[list[str]]:
    """Result routes without the start (and the return of tours)."""
    return [[node for node in route if node != instance.start] for route in routes]


def test_methods_listed() -> None:
    assert tuple(info.name for info in METHODS) == NAMES
    assert all(info.description for info in METHODS)


@pytest.mark.parametrize("method", NAMES)
@pytest.mark.parametrize("routes", KINDS)
@pytest.mark.parametrize("fixture", ["fig1_grid", "fig3_star"])
def test_paper_figures(request: pytest.FixtureRequest, fixture: str, routes: str, method: str) -> None:
    instance = request.getfixturevalue(fixture)
    least = least_makespan(instance, routes)
    for robots in (1, 2, 3, instance.n + 2):
        check(instance, routes, method, robots=robots)
    for deadline in (None, least, 1.5 * least, 4 * least):
        check(instance, routes, method, deadline=deadline)


@given(instance=instances(1, 9), data=st.data())
def test_every_method_answers_validly(instance: Instance, data: st.DataObject) -> None:
    robots = data.draw(st.integers(1, instance.n + 1), label="robots")
    factor = data.draw(st.floats(1.0, 3.0), label="deadline factor")
    for method in NAMES:
        for routes in KINDS:
            check(instance, routes, method, robots=robots)
            check(instance, routes, method, deadline=factor * least_makespan(instance, routes))


# Hand-derived answers. tiny_line: s=0, a=1, b=2, c=3 on a line (c_max = 3).


def test_nn_tiny_line(tiny_line: Instance) -> None:
    # Paths, deadline c_max = 3: s->a (1), a->b (2), b->c (3 <= 3): one robot.
    result = solve(tiny_line, "paths", method="nn")
    assert ids(tiny_line, result.routes) == [["a", "b", "c"]]
    # Robot limit 2: both robots cost 0, robot 1 (lower number) takes a (cost 1);
    # robot 2 (cost 0) takes b, nearest uncovered to s (cost 2); robot 1 (1 < 2)
    # takes c, nearest uncovered to a (cost 1 + 2 = 3). Makespan 3.
    result = solve(tiny_line, "paths", robots=2, method="nn")
    assert ids(tiny_line, result.routes) == [["a", "c"], ["b"]]
    assert result.makespan == pytest.approx(3.0)


def test_knn_kni_tiny_line_tours(tiny_line: Instance) -> None:
    # kNN, 2 tours: robot 1 takes a (tour 2), robot 2 takes b (tour 4), robot 1
    # (2 < 4) takes c, nearest to a: tour s-a-c-s = 1 + 2 + 3 = 6.
    result = solve(tiny_line, "tours", robots=2, method="knn")
    assert ids(tiny_line, result.routes) == [["a", "c"], ["b"]]
    assert result.makespan == pytest.approx(6.0)
    # kNI, 2 tours: robot 1 takes a (nearest to {s}), robot 2 takes b (nearest
    # uncovered to {s}); robot 1 takes c (nearest to {s, a}): inserting it between
    # s and a grows 3 + 2 - 1 = 4, between a and s 2 + 3 - 1 = 4: the tie goes to
    # the earlier position, tour s-c-a-s = 6.
    result = solve(tiny_line, "tours", robots=2, method="kni")
    assert ids(tiny_line, result.routes) == [["c", "a"], ["b"]]
    assert result.makespan == pytest.approx(6.0)


def test_mst_branches() -> None:
    # s=(0,0), a=(1,0), b=(2,0), c=(1,1). Prim from s: a (1); then b and c both at 1
    # from a, the tie to b (lower index), then c: the tree is s-a, a-b, a-c. Preorder
    # a, b, c with leaves b and c: branches [a, b] (cost 2) and [c] (sqrt 2, reached
    # from s through the closure). c_max = 2, so both meet the default deadline.
    instance = Instance.from_points([[0, 0], [1, 0], [2, 0], [1, 1]], names=["s", "a", "b", "c"])
    result = solve(instance, "paths", method="mst")
    assert ids(instance, result.routes) == [["a", "b"], ["c"]]
    # One robot, two leaves: the preorder a, b, c as one piece, 1 + 1 + sqrt 2.
    result = solve(instance, "paths", robots=1, method="mst")
    assert ids(instance, result.routes) == [["a", "b", "c"]]
    assert result.makespan == pytest.approx(2 + math.sqrt(2))


def test_mst_branch_cut_at_deadline() -> None:
    # s=(0,0), a=(1,0), b=(1,1): the MST is the chain s-a-b (a-b = 1 < s-b = sqrt 2),
    # one leaf. Its branch costs 2 > c_max = sqrt 2, so it is cut: [a] (1), then
    # b would make 2 > sqrt 2 and starts its own route (sqrt 2).
    instance = Instance.from_points([[0, 0], [1, 0], [1, 1]], names=["s", "a", "b"])
    result = solve(instance, "paths", method="mst")
    assert ids(instance, result.routes) == [["a"], ["b"]]


def test_split_two_sided_line() -> None:
    # s=0, a=1, b=2, c=-1, e=-2 on a line; c_max = 2. Nearest neighbour from s: a
    # (tie with c, lower index), b, then c (3), e: tour s-a-b-c-e-s of length
    # 1+1+3+1+2 = 8, optimal, so 2-opt changes nothing. k = 2: the cut threshold
    # (1/2)(8 - 2*2) + 2 = 4; prefixes a 1, b 2, c 5, e 6: cut after b. Tours
    # s-a-b-s and s-c-e-s, both 4.
    instance = Instance.from_points(
        [[0, 0], [1, 0], [2, 0], [-1, 0], [-2, 0]], names=["s", "a", "b", "c", "e"]
    )
    result = solve(instance, "tours", robots=2, method="split")
    assert ids(instance, result.routes) == [["a", "b"], ["c", "e"]]
    assert result.makespan == pytest.approx(4.0)
    # k = 3: thresholds (j/3)(8 - 4) + 2 = 3.33 and 4.67 both cut after b (prefix 2;
    # c has 5): the middle piece is empty and dropped, the same two tours. (Equal
    # thirds of L, 2.67 and 5.33, would give three.)
    result = solve(instance, "tours", robots=3, method="split")
    assert ids(instance, result.routes) == [["a", "b"], ["c", "e"]]
    # Deadline 2 c_max = 4: k = 1 gives one tour of 8 > 4, k = 2 the two tours above.
    result = solve(instance, "tours", method="split")
    assert ids(instance, result.routes) == [["a", "b"], ["c", "e"]]
    # Paths: the path s-a-b-c-e has length 6; threshold 2 + (1/2)(6 - 2) = 4, cut
    # after b again: paths of 2 and 1 + 1 = 2 = c_max.
    result = solve(instance, "paths", robots=2, method="split")
    assert ids(instance, result.routes) == [["a", "b"], ["c", "e"]]
    assert result.makespan == pytest.approx(2.0)


@pytest.mark.parametrize("method", NAMES)
def test_same_answer_twice(fig3_star: Instance, method: str) -> None:
    first = solve(fig3_star, "tours", robots=2, method=method)
    assert solve(fig3_star, "tours", robots=2, method=method).routes == first.routes
