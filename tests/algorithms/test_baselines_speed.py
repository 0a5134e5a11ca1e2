"""The fast parts of the baselines against plain reference versions of the same rules.

``_two_opt`` evaluates only candidate moves and ``_TourSplit.least_pieces`` tests every robot
count at once; both must give exactly what the plain rules give: a 2-opt that scans every
move of each first edge, and a loop over ``k`` that cuts and costs each one in turn. The
references below are written from the rules in the docstrings, not from the fast code.
"""

from __future__ import annotations

import time

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from strategies import instances

from parcover import Instance
from parcover.algorithms import baselines
from parcover.problem import meets_deadline


def reference_two_opt(d: np.ndarray, order: list[int], tours: bool) -> list[int]:
    """For each edge (a, b) in turn, apply the reversal b..c of largest gain (first c on ties)
    when it beats 1e-12 times the route length; sweep until no edge improves."""
    seq = [0, *order, 0]
    m = len(seq)

    def w(i: int) -> float:  # length of edge i (seq[i], seq[i+1]); a path's last edge is free
        return 0.0 if (not tours and i == m - 2) else float(d[seq[i], seq[i + 1]])

    improved = True
    while improved:
        improved = False
        for i in range(m - 3):
            best, best_j = -np.inf, None
            for j in range(i + 2, m - 1):
                second = 0.0 if (not tours and j == m - 2) else float(d[seq[i + 1], seq[j + 1]])
                gain = w(i) + w(j) - float(d[seq[i], seq[j]]) - second
                if gain > best:
                    best, best_j = gain, j
            total = sum(w(k) for k in range(m - 1))
            if best_j is not None and best > 1e-12 * max(total, 1.0):
                seq[i + 1 : best_j + 1] = seq[i + 1 : best_j + 1][::-1]
                improved = True
    return seq[1:-1]


def reference_least_pieces(split: baselines._TourSplit, limit: float) -> int | None:
    for k in range(1, len(split.order) + 1):
        bounds = split.bounds(k)
        first, last = split.order[bounds[:-1]], split.order[bounds[1:] - 1]
        cost = split.d[0, first] + split.prefix[bounds[1:] - 1] - split.prefix[bounds[:-1]]
        if split.tours:
            cost = cost + split.d[last, 0]
        if meets_deadline(float(cost.max()), limit):
            return k
    return None


def shuffled_order(instance: Instance, seed: int) -> list[int]:
    return [int(v) for v in np.random.default_rng(seed).permutation(np.arange(1, instance.n + 1))]


@settings(max_examples=40, deadline=None)
@given(instances(1, 25), st.booleans(), st.integers(0, 3))
def test_two_opt_applies_the_moves_of_a_full_scan(instance: Instance, tours: bool, seed: int) -> None:
    d = instance.distances
    order = shuffled_order(instance, seed)
    fast = baselines._two_opt(d, order, tours, time.perf_counter(), None)
    assert fast == reference_two_opt(d, order, tours)


def test_two_opt_on_coincident_points_and_a_larger_instance() -> None:
    # Integer points in a 4 x 4 square: many zero distances and ties; 60 KPOIs exceed the
    # neighbour lists (12), so the lists and the far-edge fallback are both exercised.
    points = np.random.default_rng(7).integers(0, 4, size=(61, 2)).astype(float)
    for inst in (Instance.from_points(points), Instance.from_points(np.random.default_rng(8).uniform(0, 9, (61, 2)))):
        order = shuffled_order(inst, 1)
        for tours in (False, True):
            assert baselines._two_opt(inst.distances, order, tours, time.perf_counter(), None) == (
                reference_two_opt(inst.distances, order, tours)
            )


@settings(max_examples=40, deadline=None)
@given(instances(1, 40), st.booleans(), st.integers(0, 3), st.floats(1.0, 3.0))
def test_least_pieces_is_the_first_k_that_meets_the_limit(
    instance: Instance, tours: bool, seed: int, factor: float
) -> None:
    split = baselines._TourSplit(instance.distances, shuffled_order(instance, seed), tours)
    limit = factor * (2 if tours else 1) * instance.c_max
    assert split.least_pieces(limit) == reference_least_pieces(split, limit)
