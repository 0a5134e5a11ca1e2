"""Spanning-tree bounds (milp/bounds.py): the tree by a second algorithm, the bounds
never above the optimum, zero distances included."""

from __future__ import annotations

import networkx as nx
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from milp import bounds, setpart
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
    # deadline 1.5 (paths): q routes of total <= 1.5 q must reach the tree's 3, so q >= 2
    assert bounds.robots_lower_bound(D, 1.5, tours=False) == 2
    # tours within 6: tree 3 plus the smallest closing arc 1 is 4 <= 6, one route
    assert bounds.robots_lower_bound(D, 6.0, tours=True) == 1


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
