"""The independent verifier: valid solutions pass, every corruption is caught."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from parcover import Instance, InvalidSolution, verify
from strategies import instances


def _cost(instance: Instance, route: list[str]) -> float:
    """A route's cost summed pair by pair: a second computation, independent of the verifier's."""
    return sum(instance.distance(u, v) for u, v in zip(route, route[1:]))


@st.composite
def solutions(draw: st.DrawFn) -> tuple[Instance, list[list[str]], str]:
    """A random instance and a random valid solution of it: a shuffled partition of the KPOIs."""
    instance = draw(instances(1, 8))
    kpois = draw(st.permutations(instance.kpois))
    robots = draw(st.integers(1, len(kpois)))
    cuts = sorted(draw(st.sets(st.integers(1, len(kpois) - 1), min_size=robots - 1, max_size=robots - 1))) if robots > 1 else []
    bounds = [0, *cuts, len(kpois)]
    kind = draw(st.sampled_from(["paths", "tours"]))
    tail = [instance.start] if kind == "tours" else []
    routes = [[instance.start, *kpois[a:b], *tail] for a, b in zip(bounds, bounds[1:])]
    return instance, routes, kind


@given(solutions())
def test_valid_solutions_pass_with_the_right_makespan(case):
    instance, routes, kind = case
    verdict = verify(instance, {"routes": routes, "routes_kind": kind})
    assert verdict.robots == len(routes) and verdict.feasible
    assert verdict.makespan == pytest.approx(max(_cost(instance, r) for r in routes), rel=1e-12, abs=1e-12)


def _drop(routes, instance):
    victim = max(routes, key=len)
    victim.pop(1)
    return [r for r in routes if len(r) > (2 if r[-1] == instance.start and len(r) > 1 else 1)] or routes


def _duplicate(routes, instance):
    routes[0].insert(1, routes[-1][1])
    return routes


def _unknown(routes, instance):
    routes[0][1] = "no-such-kpoi"
    return routes


def _break_start(routes, instance):
    routes[-1][0] = routes[-1][1]
    return routes


@given(solutions(), st.sampled_from([_drop, _duplicate, _unknown, _break_start]))
def test_every_single_corruption_is_rejected(case, corrupt):
    instance, routes, kind = case
    routes = corrupt([list(r) for r in routes], instance)
    with pytest.raises(InvalidSolution):
        verify(instance, {"routes": routes, "routes_kind": kind})


def test_a_missed_deadline_is_a_quantity(tiny_line):
    verdict = verify(tiny_line, [["s", "a", "b", "c"]], deadline=2)
    assert verdict.makespan == 3 and verdict.deadline_excess == 1 and verdict.late_routes == [1]
    assert not verdict.feasible and "missed by 1" in verdict.violations()[0]


def test_too_many_robots_is_a_quantity(tiny_line):
    verdict = verify(tiny_line, {"routes": [["s", "a"], ["s", "b"], ["s", "c"]], "robots_limit": 2})
    assert verdict.robots_excess == 1 and not verdict.feasible


def test_tours_are_inferred_and_costed_home(tiny_line):
    verdict = verify(tiny_line, [["s", "a", "b", "c", "s"]])
    assert verdict.routes_kind == "tours" and verdict.makespan == 6


@pytest.mark.parametrize(
    ("routes", "message"),
    [
        ([["a", "b", "c"]], "does not begin at the start"),  # routes begin at s
        ([["s", "a"], ["s", "b"]], "not covered: 'c'"),  # c is missed
        ([["s", "a", "b", "c", "a"]], "covered twice in route 1"),  # a twice
        ([["s", "a", "b"], ["s", "b", "c"]], "in routes 1 and 2"),  # b by two robots
        ([["s", "a", "x", "b", "c"]], "unknown id 'x'"),  # x is not on the map
        ([["s", "a", "s", "b", "c"]], "lists the start"),  # the start is no stop
        ([["s"], ["s", "a", "b", "c"]], "covers no KPOI"),  # an empty route
        ([["s", "a", 3]], "non-string id 3"),  # ids are strings
        ([], "there are no routes"),  # nothing covers anything
    ],
)
def test_broken_structure_names_the_problem(tiny_line, routes, message):
    with pytest.raises(InvalidSolution, match=message):
        verify(tiny_line, {"routes": routes, "routes_kind": "paths"})


def test_a_tour_must_come_home(tiny_line):
    with pytest.raises(InvalidSolution, match="does not return"):
        verify(tiny_line, [["s", "a", "b", "c"]], routes_kind="tours")


def test_virtual_nodes_are_named_as_such():
    inst = Instance("s", ("a",), edges=(("s", "v", 1), ("v", "a", 1)))
    with pytest.raises(InvalidSolution, match="'v', a virtual node"):
        verify(inst, [["s", "v", "a"]])
