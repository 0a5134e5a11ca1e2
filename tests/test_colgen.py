"""Certified column-generation bounds (milp/branchprice/colgen.py) never exceed the exact optimum."""

from __future__ import annotations

from itertools import permutations

import numpy as np
import pytest

from milp import arcflow, setpart
from milp.branchprice import colgen
from milp.core.merge import merge_zero_distances
from milp.core.routes import least_makespan


def _euclidean(n: int, seed: int, coincident: bool = False) -> np.ndarray:
    """Start and ``n`` KPOIs in a 100 x 100 square; optionally KPOI 2 on KPOI 1 and KPOI 3
    on the start (zero distances)."""
    points = np.random.default_rng(seed).uniform(0.0, 100.0, size=(n + 1, 2))
    if coincident:
        points[2], points[3] = points[1], points[0]
    return np.linalg.norm(points[:, None, :] - points[None, :, :], axis=2)


def _trivial(D: np.ndarray, k: int, tours: bool) -> float:
    return max(least_makespan(D, tours=tours),
               arcflow.makespan_lower_bound(merge_zero_distances(D).D, k, tours=tours))


CASES = [(n, seed, tours, k) for n, seed in ((5, 1), (6, 2), (7, 3), (8, 4), (9, 5))
         for tours in (False, True) for k in (1, 2, 3)]


@pytest.mark.parametrize("n, seed, tours, k", CASES)
def test_makespan_bound_between_trivial_and_optimum(n, seed, tours, k):
    D = _euclidean(n, seed, coincident=seed == 4)
    optimum = setpart.min_makespan(D, k, tours=tours).objective
    info = colgen.makespan_bound(D, k, tours=tours, upper=1.25 * optimum)
    assert info.bound <= optimum * (1 + 1e-9)
    assert info.bound >= _trivial(D, k, tours) - 1e-9
    assert info.bound == colgen.makespan_lower_bound(D, k, tours=tours, upper=1.25 * optimum)


@pytest.mark.parametrize("tours", [False, True])
def test_bisection_starts_from_a_given_lower_bound(tours):
    """``lower``: a bound certified elsewhere; the bisection starts from it (never returns
    less) and still stays at or below the optimum."""
    D = _euclidean(8, 6)
    optimum = setpart.min_makespan(D, 2, tours=tours).objective
    free = colgen.makespan_bound(D, 2, tours=tours, upper=1.25 * optimum)
    given = 0.5 * (free.bound + optimum)  # above what the q-routes prove here, still valid
    assert free.bound < given
    started = colgen.makespan_bound(D, 2, tours=tours, upper=1.25 * optimum, lower=given)
    assert given <= started.bound <= optimum * (1 + 1e-9)
    assert all(T > given for T, *_ in started.steps)


def test_bound_improves_on_trivial_for_one_tour():
    # One tour through 8 KPOIs: the LP over q-routes must see that a single walk within
    # T covers all KPOIs, far above 2 c_max and the spanning-tree bound here.
    D = _euclidean(8, 7)
    optimum = setpart.min_makespan(D, 1, tours=True).objective
    info = colgen.makespan_bound(D, 1, tours=True, upper=optimum)
    assert _trivial(D, 1, True) < info.bound <= optimum * (1 + 1e-9)
    assert info.bound >= 0.9 * optimum


def test_two_points_on_a_line_is_exact_up_to_the_bisection_tolerance():
    # Start 0, KPOIs at 1 and 2 on a line, one path: optimum 2 (0 -> 1 -> 2); the trivial
    # bound c_max = 2 is already optimal, so nothing is bisected.
    x = np.array([0.0, 1.0, 2.0])
    D = np.abs(x[:, None] - x[None, :])
    assert colgen.makespan_lower_bound(D, 1, tours=False, upper=2.0) == pytest.approx(2.0)
    # Tours with one robot: 0 -> 1 -> 2 -> 0 = 4 = 2 c_max.
    assert colgen.makespan_lower_bound(D, 1, tours=True, upper=4.0) == pytest.approx(4.0)


def test_square_tours_bound_by_hand():
    # Start at corner (0, 0) of a unit square, KPOIs at the other corners. One tour: the
    # perimeter 4 is optimal; 2 c_max = 2 sqrt 2 is not, and the LP must rise above it.
    pts = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
    D = np.linalg.norm(pts[:, None] - pts[None], axis=2)
    bound = colgen.makespan_lower_bound(D, 1, tours=True, upper=4.0)
    assert 2 * np.sqrt(2) < bound <= 4.0


@pytest.mark.parametrize("n, seed, tours", [(6, 11, False), (7, 12, True), (8, 13, True), (9, 14, False)])
def test_robots_bound_at_most_setpart(n, seed, tours):
    D = _euclidean(n, seed, coincident=seed == 13)
    for factor in (1.0, 1.3, 2.0):
        deadline = factor * least_makespan(D, tours=tours)
        fewest = setpart.min_robots(D, deadline, tours=tours).objective
        bound = colgen.robots_lower_bound(D, deadline, tours=tours)
        assert 1 <= bound <= fewest
        assert bound >= arcflow.robots_lower_bound(merge_zero_distances(D).D, deadline, tours=tours)


def test_robots_bound_star_needs_one_robot_per_kpoi():
    # Fig. 3-like star: 6 KPOIs on a unit circle around the start; tours at deadline
    # 2 c_max = 2 can only visit one KPOI each (two neighbours cost 1 + 1 + 1 > 2).
    angles = np.arange(6) * np.pi / 3
    pts = np.vstack([[0.0, 0.0], np.c_[np.cos(angles), np.sin(angles)]])
    D = np.linalg.norm(pts[:, None] - pts[None], axis=2)
    assert colgen.robots_lower_bound(D, 2.0, tours=True) == 6


def test_the_messages_are_the_stop_reasons_in_words():
    # robots_bound reports why its column generation stopped; the texts are what users read
    D = _euclidean(8, 21)
    info = colgen.robots_bound(D, 1.3 * least_makespan(D, tours=False), tours=False)
    assert type(info.message) is str and info.message in set(colgen.Stop)
    stopped = colgen._Stopped(1.0, 2.0, 3, colgen.Stop.MASTER_FAILED, "Infeasible")
    assert stopped.message == "master LP: Infeasible"
    assert colgen._Stopped(1.0, 2.0, 3, colgen.Stop.LP_SOLVED).message == "LP solved"


def test_time_limit_still_valid():
    D = _euclidean(9, 21)
    optimum = setpart.min_makespan(D, 2, tours=True).objective
    bound = colgen.makespan_lower_bound(D, 2, tours=True, upper=1.5 * optimum, time_limit=1e-6)
    assert _trivial(D, 2, True) - 1e-9 <= bound <= optimum


@pytest.mark.parametrize("tours", [False, True])
def test_pricing_value_covers_every_real_route(tours):
    # The certificate needs M >= the prize of every real route within T; check it against
    # all 1956 ordered selections of 6 KPOIs, with random prizes.
    D = _euclidean(6, 31)
    T = 1.1 * setpart.min_makespan(D, 2, tours=tours).objective
    delta = T / colgen.GRID
    pricer = colgen._Pricer(D, tours=tours, delta=delta)
    prize = np.random.default_rng(5).uniform(0.0, 1.0, 6)
    M, walks, _ = pricer.price(prize, pricer.budget(T, delta))
    best = 0.0
    for size in range(1, 7):
        for route in permutations(range(1, 7), size):
            stops = [0, *route, 0] if tours else [0, *route]
            if D[stops[:-1], stops[1:]].sum() <= T:
                best = max(best, prize[np.array(route) - 1].sum())
    assert M >= best - 1e-12
    # The traced best walk is worth M.
    assert prize[walks[0] - 1].sum() == pytest.approx(M)


@pytest.mark.parametrize("n, seed, tours", [(8, 21, False), (9, 22, True), (12, 23, False), (25, 24, True)])
def test_master_routes_are_valid_and_no_fewer_than_the_optimum(n, seed, tours):
    from milp.core.routes import check_routes, route_cost, within

    D = _euclidean(n, seed)
    for factor in (1.0, 1.3):
        deadline = factor * least_makespan(D, tours=tours)
        info = colgen.robots_bound(D, deadline, tours=tours, routes=True)
        check_routes(info.routes, n)  # every KPOI on exactly one route
        assert all(within(route_cost(D, r, tours=tours), deadline) for r in info.routes)
        assert len(info.routes) >= info.robots()
        if n <= 12:
            assert len(info.routes) >= setpart.min_robots(D, deadline, tours=tours).objective
