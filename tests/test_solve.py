"""The dispatcher: verification of every method's answer and honest statuses."""

from __future__ import annotations

import pytest

from parcover import InputError, MethodInfo, Problem, Solution, SolverError, Status, solve
from parcover.solve import METHODS, available_methods, register_method


@pytest.fixture
def broken_method():
    """Registers a method returning the routes given, then removes it."""

    def install(routes):
        register_method(MethodInfo("broken", lambda *a, **k: Solution(routes=routes), "test only"))

    available_methods()
    yield install
    METHODS.pop("broken", None)


def test_trivial_proves_the_star_needs_6_paths(fig3_star):
    # Fig. 3: 6 KPOIs at distance 1, neighbours 1 apart. The spanning tree of s and the
    # hexagon weighs 6, so 6 paths within c_max = 1 are needed (bound ceil(6 / 1) = 6):
    # one robot per KPOI is then proven optimal.
    result = solve(fig3_star, method="trivial")
    assert result.status is Status.OPTIMAL and result.robots == 6 and result.bound == 6


def test_heuristic_value_above_bound_is_only_feasible(fig1_grid):
    result = solve(fig1_grid, robots=2, method="trivial")
    assert result.status is Status.FEASIBLE and result.bound == 4 and result.gap == pytest.approx(0.5)


def test_a_deadline_below_c_max_is_infeasible_without_running_the_method(fig1_grid, broken_method):
    broken_method([[1, 1]])  # would fail verification if it ran
    result = solve(fig1_grid, deadline=3.99, method="broken")
    assert result.status is Status.INFEASIBLE and result.routes == []


@pytest.mark.parametrize(
    "routes",
    [
        [[1, 2, 3]],  # KPOIs 4..8 uncovered
        [[1, 2, 3, 4, 5, 6, 7, 8, 8]],  # KPOI 8 twice
    ],
)
def test_invalid_routes_from_a_method_are_a_solver_error(fig1_grid, broken_method, routes):
    broken_method(routes)
    with pytest.raises(SolverError, match="invalid routes"):
        solve(fig1_grid, robots=1, method="broken")


def test_breaking_the_deadline_is_a_solver_error(fig1_grid, broken_method):
    broken_method([[1, 2, 3, 4, 5, 6, 7, 8]])
    with pytest.raises(SolverError, match="deadline 4 is missed"):
        solve(fig1_grid, method="broken")


def test_problem_validation():
    with pytest.raises(InputError, match="not both"):
        Problem("paths", robots=2, deadline=3.0)
    with pytest.raises(InputError, match="route kind"):
        Problem("circles")  # type: ignore[arg-type]
    assert Problem("tours").objective == "robots" and Problem(robots=3).objective == "makespan"


def test_a_problem_is_the_whole_question(fig1_grid):
    asked = solve(fig1_grid, Problem("tours", robots=2), method="best")
    assert (asked.routes_kind, asked.robots_limit) == ("tours", 2)
    assert asked.makespan == solve(fig1_grid, "tours", robots=2, method="best").makespan
    with pytest.raises(InputError, match="not both"):
        solve(fig1_grid, Problem("tours"), robots=2)


def test_unknown_option_is_refused(fig1_grid):
    with pytest.raises(InputError, match="takes no option 'colour'"):
        solve(fig1_grid, method="trivial", colour="red")
