"""Spanning-tree, Held-Karp and conflict-clique bounds (milp/bounds.py): the tree by a
second algorithm, the clique's conflicts by route costs, the bounds never above the
optimum, zero distances included."""

from __future__ import annotations

import networkx as nx
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from milp import bounds, branchprice, setpart
from milp.core.routes import route_cost
from milp_helpers import euclidean
from strategies import euclidean_instances


@settings(max_examples=40, deadline=None)
@given(instance=euclidean_instances(1, 12))
def test_spanning_tree_length_matches_networkx(instance):
    D = instance.distances
    graph = nx.complete_graph(len(D))
    for u, v in graph.edges:
        graph[u][v]["weight"] = D[u, v]  # zero weights stay edges
    expected = nx.minimum_spanning_tree(graph).size(weight="weight")
    assert bounds.spanning_tree_length(D) == pytest.approx(expected, abs=1e-9)


def test_bounds_by_hand_on_a_line():
    # start at 0 and KPOIs at 1, 2, 3 on a line: the tree has length 3, c_max = 3.
    points = np.array([0.0, 1.0, 2.0, 3.0])
    D = np.abs(points[:, None] - points[None, :])
    assert bounds.spanning_tree_length(D) == 3.0
    assert bounds.makespan_lower_bound(D, 2, tours=False) == 3.0  # c_max beats 3 / 2
    # deadline 1.5 (paths): q routes of total <= 1.5 q must reach the tree's 3, so q >= 2;
    # no path within 1.5 visits two of the KPOIs (it would be at least 1 + 1 long), so
    # the conflict clique {1, 2, 3} raises it to 3
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(bounds, "conflict_clique", lambda *args, **kwargs: [])
        assert bounds.robots_lower_bound(D, 1.5, tours=False) == 2
    assert bounds.conflict_clique(D, 1.5, tours=False) == [1, 2, 3]
    assert bounds.robots_lower_bound(D, 1.5, tours=False) == 3
    # tours within 6: tree 3 plus the smallest closing arc 1 is 4 <= 6, one route
    assert bounds.robots_lower_bound(D, 6.0, tours=True) == 1


def test_conflict_clique_by_hand_on_a_circle():
    """12 KPOIs evenly on the unit circle around the start, paths within c_max = 1: a path
    visiting two of them is at least 1 + their chord (>= 0.52) long, so each needs a robot
    of its own: 12. The spanning-tree bound gives 7 (tree: one spoke and 11 chords of
    2 sin 15 deg = 0.518, 6.69 in all, over routes of at most 1); Held-Karp joins only
    from 21 KPOIs. Tours within 2: every pair conflicts too (2 + chord > 2)."""
    angles = np.arange(12) * np.pi / 6
    points = np.vstack(([0.0, 0.0], np.column_stack((np.cos(angles), np.sin(angles)))))
    D = np.linalg.norm(points[:, None] - points[None, :], axis=2)
    assert bounds.conflict_clique(D, 1.0, tours=False) == list(range(1, 13))
    assert bounds.conflict_clique(D, 2.0, tours=True) == list(range(1, 13))
    assert bounds.robots_lower_bound(D, 1.0, tours=False) == 12
    # with a deadline that lets neighbours share a path (1 + chord 0.518 <= 1.6), every
    # second KPOI still conflicts with every other: 6
    assert len(bounds.conflict_clique(D, 1.6, tours=False)) == 6


@settings(max_examples=40, deadline=None)
@given(instance=euclidean_instances(2, 12), tours=st.booleans(), stretch=st.sampled_from([1.0, 1.1, 1.5]))
def test_conflict_clique_members_fit_on_no_route_together(instance, tours, stretch):
    """Every two KPOIs of the clique: the route visiting just them, in either order, is
    over the deadline (checked by route costs, not the bound's own formula)."""
    D = instance.distances
    deadline = stretch * (2 if tours else 1) * float(D[0].max())
    clique = bounds.conflict_clique(D, deadline, tours=tours)
    assert clique and len(set(clique)) == len(clique)
    for a, i in enumerate(clique):
        for j in clique[a + 1:]:
            for pair in ([i, j], [j, i]):
                assert route_cost(D, pair, tours=tours) > deadline * (1 + 1e-9) + 1e-9


@settings(max_examples=25, deadline=None)
@given(
    instance=euclidean_instances(1, 8),
    tours=st.booleans(),
    k=st.integers(1, 4),
    stretch=st.sampled_from([1.0, 1.3, 2.0]),
)
def test_bounds_never_exceed_the_set_partitioning_optimum(instance, tours, k, stretch):
    D = instance.distances
    least = setpart.min_makespan(D, k, tours=tours)
    assert bounds.makespan_lower_bound(D, k, tours=tours) <= least.objective * (1 + 1e-9) + 1e-9
    deadline = stretch * (2 if tours else 1) * float(D[0].max())
    fewest = setpart.min_robots(D, deadline, tours=tours)
    assert 1 <= bounds.robots_lower_bound(D, deadline, tours=tours) <= fewest.objective


def test_held_karp_by_hand_on_a_line():
    """Start at 0, KPOIs at 1, 2, 3 on a line. One tour must reach 3 and come back: 6,
    where the tree bound gives 3 + 1 = 4; the Lagrangian bound comes within 0.01% of it
    (subgradient steps approach the dual optimum). Two tours (exactly two: {1} and
    {2, 3}, or {1, 2} and {3}) total at least 2 + 6 = 8, so the bound is at most 4,
    under 2 c_max = 6."""
    points = np.array([0.0, 1.0, 2.0, 3.0])
    D = np.abs(points[:, None] - points[None, :])
    assert 6.0 * (1 - 1e-4) <= bounds.held_karp_makespan_bound(D, 1, tours=True) <= 6.0 + 1e-9
    assert bounds.held_karp_makespan_bound(D, 2, tours=True) <= 4.0 + 1e-9


@settings(max_examples=40, deadline=None)
@given(instance=euclidean_instances(1, 11), tours=st.booleans(), k=st.integers(1, 4),
       stretch=st.sampled_from([1.0, 1.1, 1.3]))
def test_held_karp_never_exceeds_the_set_partitioning_optimum(instance, tours, k, stretch):
    """The Lagrangian bound alone, and both bounds with it at any size, against setpart's
    optima: the least makespan, and the fewest robots within a stretch of it."""
    D = instance.distances
    least = setpart.min_makespan(D, k, tours=tours)
    assert bounds.held_karp_makespan_bound(D, k, tours=tours) <= least.objective * (1 + 1e-9) + 1e-9
    deadline = stretch * least.objective
    fewest = setpart.min_robots(D, deadline, tours=tours)
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(bounds, "HELD_KARP_KPOIS", (1, 200))
        assert bounds.makespan_lower_bound(D, k, tours=tours) <= least.objective * (1 + 1e-9) + 1e-9
        assert 1 <= bounds.robots_lower_bound(D, deadline, tours=tours) <= fewest.objective


@pytest.mark.parametrize("tours", [False, True], ids=["paths", "tours"])
def test_held_karp_joins_the_makespan_bound_at_30_kpois(tours, monkeypatch):
    """Random 30 KPOIs, 3 routes: the Lagrangian bound stays below the optimum that
    branch-and-price proves, and makespan_lower_bound takes it; for paths it is above
    the bound without it (123.5 against c_max 117.8 when written)."""
    D = euclidean(30, 1)
    held_karp = bounds.held_karp_makespan_bound(D, 3, tours=tours)
    optimum = branchprice.min_makespan(D, 3, tours=tours, time_limit=60)
    assert optimum.status == "optimal"
    assert held_karp <= optimum.objective * (1 + 1e-9)
    assert bounds.makespan_lower_bound(D, 3, tours=tours) >= held_karp * (1 - 1e-9)
    if not tours:
        monkeypatch.setattr(bounds, "HELD_KARP_KPOIS", (0, -1))
        assert held_karp > 1.03 * bounds.makespan_lower_bound(D, 3, tours=tours)


def test_a_short_time_skips_the_held_karp_part_until_it_is_remembered():
    # At 120 KPOIs one Held-Karp bound takes most of a second: a caller with a short time
    # left gets the spanning-tree bound at once; once computed, the bound is free.
    import time

    from parcover import generate
    from parcover.bounds import lower_bound
    from parcover.problem import Problem

    instance = generate.random_points(120, 9)
    problem = Problem("tours", robots=3)
    began = time.perf_counter()
    quick = lower_bound(instance, problem, seconds=0.0)
    assert time.perf_counter() - began < 0.2
    full = lower_bound(instance, problem)  # no limit: Held-Karp included
    assert full >= quick
    began = time.perf_counter()
    assert lower_bound(instance, problem, seconds=0.0) == full  # remembered: free and full
    assert time.perf_counter() - began < 0.2


def test_conflict_clique_is_skipped_above_its_size(monkeypatch):
    """Above CLIQUE_MAX_KPOIS KPOIs no clique is looked for (an empty one bounds nothing)."""
    angles = np.arange(12) * np.pi / 6
    points = np.vstack(([0.0, 0.0], np.column_stack((np.cos(angles), np.sin(angles)))))
    D = np.linalg.norm(points[:, None] - points[None, :], axis=2)
    monkeypatch.setattr(bounds, "CLIQUE_MAX_KPOIS", 11)
    assert bounds.conflict_clique(D, 1.0, tours=False) == []
    assert bounds.robots_lower_bound(D, 1.0, tours=False) == 7  # the spanning-tree bound alone
