"""The heuristic-quality benchmark section: its peers, their verification, its ratios."""

from __future__ import annotations

import importlib.util
import math

import numpy as np
import pandas as pd
import pytest

from benchmarks import heuristic_quality as hq
from benchmarks.common import euclidean_distances, run_peer
from parcover import Instance

# Peers run in subprocesses (ortools and highspy clash in one process): check for the
# packages without importing them here.
needs_ortools = pytest.mark.skipif(
    importlib.util.find_spec("ortools") is None, reason="ortools not installed"
)


@pytest.fixture
def two_sided_line() -> Instance:
    """Start at 0, KPOIs at x = 1, 2 (right) and x = -1, -2 (left).

    With 2 robots the best plan sends one robot each way: paths of cost 2 (tours 4).
    A single path covering both sides costs at least 2 + 4 = 6.
    """
    return Instance.from_points([[0, 0], [1, 0], [2, 0], [-1, 0], [-2, 0]])


def no_log(line: str) -> None:
    pass


def test_random_instance_has_the_common_distances():
    np.testing.assert_allclose(hq.random_instance(7, 3).distances, euclidean_distances(7, 3), atol=1e-12)


@needs_ortools
@pytest.mark.parametrize("routes, makespan", [("paths", 2.0), ("tours", 4.0)])
def test_ortools_peer_finds_the_two_sided_optimum(two_sided_line, routes, makespan):
    payload = {"distances": two_sided_line.distances.tolist(), "robots": 2, "routes": routes,
               "time_limit": 0.5, "seed": 0}
    answer = run_peer("ortools_routing", payload, timeout=60)
    assert answer["solver"].startswith("ortools ")
    assert hq.checked_peer_routes(two_sided_line, answer, routes, robots=2) == (pytest.approx(makespan), 2)


@pytest.mark.parametrize("routes, deadline", [("paths", 2.0), ("tours", 4.0)])
def test_pyvrp_peer_needs_two_robots_on_the_two_sided_line(two_sided_line, routes, deadline):
    payload = {"distances": two_sided_line.distances.tolist(), "deadline": deadline, "routes": routes,
               "time_limit": 0.5, "seed": 0}
    answer = run_peer("pyvrp_fleet", payload, timeout=60)
    assert answer["status"] == "feasible"
    makespan, robots = hq.checked_peer_routes(two_sided_line, answer, routes, deadline=deadline)
    assert robots == 2
    assert makespan == pytest.approx(deadline)


@pytest.mark.parametrize(
    "answer, reason",
    [
        ({"unavailable": "ortools is not installed"}, "unavailable"),
        ({"error": "ortools_routing overran 9 s"}, "error: ortools_routing overran 9 s"),
        # KPOIs 3 and 4 are missing.
        ({"routes": [[1, 2]]}, "invalid"),
        # KPOI 5 does not exist (4 KPOIs).
        ({"routes": [[1, 2], [3, 4, 5]]}, "invalid"),
        # Three routes break the limit of two robots.
        ({"routes": [[1, 2], [3], [4]]}, "infeasible"),
    ],
)
def test_a_bad_peer_answer_is_reported_not_used(two_sided_line, answer, reason):
    checked = hq.checked_peer_routes(two_sided_line, answer, "paths", robots=2)
    assert isinstance(checked, str) and checked.startswith(reason)


def test_a_peer_route_past_the_deadline_is_infeasible(two_sided_line):
    # Right then left: 2 + 4 = 6 > 5.
    checked = hq.checked_peer_routes(two_sided_line, {"routes": [[1, 2, 3, 4]]}, "paths", deadline=5.0)
    assert isinstance(checked, str) and checked.startswith("infeasible")


def test_peer_values_are_recomputed_from_the_instance(two_sided_line):
    # Tours 0 -> 2 -> 1 -> 0 (cost 2 + 1 + 1 = 4) and 0 -> 3 -> 4 -> 0 (cost 4).
    # The peer's own claim (a makespan of 1) is ignored.
    answer = {"routes": [[2, 1], [3, 4]], "makespan": 1.0}
    checked = hq.checked_peer_routes(two_sided_line, answer, "tours", robots=2)
    assert checked == (pytest.approx(4.0), 2)


def test_ratio_summary_by_hand():
    s = hq.ratio_summary(pd.Series([0.9, 1.0, 1.1, math.nan]))
    # NaN (no verified peer answer) is left out; geometric mean (0.9 * 1.0 * 1.1) ** (1/3) = 0.99 ** (1/3).
    assert s["cells"] == 3 and s["at most 1"] == 2
    assert s["geomean"] == pytest.approx(0.99 ** (1 / 3))
    assert s["worst"] == 1.1 and s["best"] == 0.9


def test_target_line_says_not_met_when_one_ratio_exceeds_one():
    frame = pd.DataFrame({"best/ortools": [0.9, 1.0, 1.1], "ortools answer": ["ROUTING_SUCCESS"] * 3})
    line = hq.target_line(frame)
    assert ": not met: " in line and "worst 1.100" in line and "2 of 3 cells" in line


def test_target_line_without_a_peer_answer():
    frame = pd.DataFrame({"best/ortools": [math.nan], "ortools answer": ["unavailable"]})
    assert "not measured" in hq.target_line(frame) and "unavailable" in hq.target_line(frame)


@needs_ortools
def test_makespan_table_ratios_are_consistent():
    frame = hq.makespan_table((6,), (0,), (2,), 0.2, no_log)
    assert list(frame["routes"]) == ["paths", "tours"]
    assert frame["ortools"].notna().all()
    np.testing.assert_allclose(frame["best/ortools"], frame["best"] / frame["ortools"])
    np.testing.assert_allclose(frame["paper/ortools"], frame["paper"] / frame["ortools"])
    # A proven lower bound is below every verified value, the peer's included.
    assert (frame["bound"] <= frame[["best", "paper", "ortools"]].min(axis=1) * (1 + 1e-9)).all()
    # `best` starts from the best construction, and `paper` is one of them.
    assert (frame["best"] <= frame["paper"] * (1 + 1e-9)).all()


def test_fleet_table_ratios_are_consistent():
    frame = hq.fleet_table((6,), (0,), 0.2, no_log)
    instance = hq.random_instance(6, 0)
    np.testing.assert_allclose(frame["deadline"], [1.2 * instance.c_max, 2.4 * instance.c_max])
    assert frame["pyvrp"].notna().all()
    np.testing.assert_allclose(frame["best/pyvrp"], frame["best"] / frame["pyvrp"])
    assert (frame["bound"] <= frame[["best", "paper", "pyvrp"]].min(axis=1)).all()
    assert (frame[["best", "paper", "pyvrp"]] <= 6).all().all()


def test_a_ratio_one_in_floating_point_counts_as_met():
    # 0.1 + 0.2 + 0.3 summed the other way round differs in the last bit.
    ratio = (0.1 + 0.2 + 0.3) / (0.3 + 0.2 + 0.1)
    assert ratio > 1.0
    frame = pd.DataFrame({"best/ortools": [ratio], "ortools answer": ["ROUTING_SUCCESS"]})
    assert ": met: " in hq.target_line(frame)
