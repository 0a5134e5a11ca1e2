"""The time limit holds: one deadline shared by every phase.

The CLI tests run ``parcover solve --time-limit 2`` in a subprocess on random instances
and compare its wall time with ``2 * 1.1`` plus the start-up of ``parcover --help``
measured just before in the same way (the machine is shared, so a fixed start-up
allowance would be either loose or flaky).
"""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from milp.core.timelimit import TimeLimit
from milp.core.routes import route_cost
from milp.warmstart import two_opt
from parcover import Instance, solve, verify
from parcover.generate import random_points
from parcover.io import read_instance, write_instance
from parcover.algorithms.baselines import _mst_preorder

LIMIT = 2.0
PARCOVER = [sys.executable, "-m", "parcover"]


def _wall(args: list[str]) -> tuple[float, subprocess.CompletedProcess[str]]:
    began = time.perf_counter()
    done = subprocess.run(PARCOVER + args, capture_output=True, text=True, timeout=120)
    return time.perf_counter() - began, done


def _instance(tmp_path: Path, n: int) -> Path:
    path = tmp_path / f"random{n}.json"
    write_instance(random_points(n, seed=1), path)
    return path


@pytest.mark.parametrize(
    "n", [200, 400, *(pytest.param(n, marks=pytest.mark.slow) for n in (1000, 2000, 3000))]
)
@pytest.mark.parametrize("question", [["--robots", "3"], []], ids=["makespan", "robots"])
def test_default_method_answers_within_the_limit(tmp_path: Path, n: int, question: list[str]) -> None:
    instance = _instance(tmp_path, n)
    startup, _ = _wall(["--help"])
    out = tmp_path / "result.json"
    wall, done = _wall(["solve", str(instance), *question, "--time-limit", str(LIMIT), "--json", "--out", str(out)])
    assert done.returncode == 0, done.stderr
    assert wall <= LIMIT * 1.1 + startup, f"{wall:.2f} s for a {LIMIT} s limit (start-up {startup:.2f} s)"
    result = json.loads(out.read_text())
    assert result["status"] in ("optimal", "feasible", "unknown")
    if result["routes"]:
        assert verify(read_instance(instance), result).feasible


def test_exact_above_branchprice_size_loads_neither_branchprice_nor_setpart() -> None:
    # Neither can take the instance, and importing branchprice (numba) took 0.7 s of a 3 s
    # limit at 3000 KPOIs.
    from milp import branchprice
    from parcover.exact import BRANCHPRICE_MAX_KPOIS

    assert BRANCHPRICE_MAX_KPOIS == branchprice.MAX_KPOIS
    script = ("import sys; from parcover import solve; from parcover.generate import random_points; "
              f"solve(random_points({BRANCHPRICE_MAX_KPOIS + 1}, seed=1), robots=3, time_limit=0.5); "
              "print(sorted(m for m in ('milp.branchprice.search', 'milp.branchprice.ngroute', 'milp.setpart', 'numba') if m in sys.modules))")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["[]"]


def test_best_converts_an_instances_distances_once() -> None:
    from parcover.algorithms.moves import Search
    from parcover.problem import Problem

    instance, other = random_points(9, seed=1), random_points(9, seed=2)
    search = Search(instance, Problem("paths", robots=2))
    assert Search(instance, Problem("tours")).d is search.d
    assert search.d == [[*row, 0.0] for row in instance.distances.tolist()] + [[0.0] * 11]
    assert Search(other, Problem("paths", robots=2)).d is not search.d


@pytest.mark.parametrize("shift, symmetric", [(0.0, True), (1e-13, True), (1e-9, False), (-1e-9, False)])
def test_symmetry_is_checked_to_round_off(shift: float, symmetric: bool) -> None:
    from milp.core.routes import check_distance_matrix

    D = random_points(300, seed=1).distances.copy()  # more rows than one block of the test
    D[7, 290] += shift * D.max()
    if symmetric:
        check_distance_matrix(D)
    else:
        with pytest.raises(ValueError, match="symmetric"):
            check_distance_matrix(D)


def test_a_limit_spent_before_the_method_starts_gives_unknown() -> None:
    instance = Instance.from_points([(0, 0), (1, 0), (0, 1)])
    clock = TimeLimit(1e-6)
    time.sleep(0.01)
    result = solve(instance, robots=1, time_limit=clock)
    assert result.status.value == "unknown" and not result.routes
    assert "time limit" in result.info["message"]


def test_a_non_positive_limit_is_refused() -> None:
    from parcover.errors import InputError

    with pytest.raises(InputError, match="positive"):
        solve(Instance.from_points([(0, 0), (1, 0)]), robots=1, time_limit=TimeLimit(0.0))


def test_deadline_counts_down_and_expires() -> None:
    unlimited = TimeLimit(None)
    assert unlimited.unlimited and unlimited.remaining() is None and not unlimited.expired()
    assert unlimited.fraction(0.5).unlimited and unlimited.earlier(1.0).unlimited
    clock = TimeLimit(0.2)
    assert 0.0 < clock.remaining() <= 0.2 and not clock.expired()
    assert clock.fraction(0.5).remaining() <= 0.1 + 1e-9
    assert clock.earlier(0.15).remaining() <= 0.05 + 1e-9
    assert clock.earlier(1.0).expired()
    assert TimeLimit.of(clock) is clock
    assert TimeLimit.of(3.0).remaining() == pytest.approx(3.0, abs=0.1)
    time.sleep(0.21)
    assert clock.expired() and clock.remaining() == 0.0


def test_the_first_ctrl_c_expires_every_limit_and_a_second_raises(capfd) -> None:
    """interrupt_stops: the first SIGINT expires every thread's time limit and writes the
    notice; a second raises KeyboardInterrupt; the interrupt ends with the block."""
    import os
    import signal
    import threading

    from milp.core.timelimit import interrupt_stops, interrupted, stop_requested

    def wait_for(condition) -> None:  # a signal's Python handler runs at the next bytecode
        ends = time.perf_counter() + 5.0
        while not condition() and time.perf_counter() < ends:
            time.sleep(0.01)

    clock, seen = TimeLimit(60.0), []
    with pytest.raises(KeyboardInterrupt):
        with interrupt_stops("stopping"):
            os.kill(os.getpid(), signal.SIGINT)
            wait_for(interrupted)
            other = threading.Thread(target=lambda: seen.append(stop_requested()))
            other.start()
            other.join()
            assert clock.expired() and clock.remaining() == 0.0 and seen == [True]
            os.kill(os.getpid(), signal.SIGINT)
            wait_for(lambda: False)
    assert not interrupted() and not clock.expired()
    assert capfd.readouterr().err == "stopping\n"


def test_an_interrupted_solve_says_so() -> None:
    from milp.core.timelimit import interrupt, interrupt_stops

    instance = Instance.from_points([(0, 0), (1, 0), (0, 1)])
    with interrupt_stops(""):
        interrupt()
        result = solve(instance, robots=1)
    assert result.status.value == "unknown" and "interrupted (Ctrl-C)" in result.info["message"]


def test_an_interrupt_stops_a_highs_mip() -> None:
    """HiGHS' MIP search stops once asked (milp.core.highs' interrupt callback): a market
    split problem (Cornuejols and Dawande 1999; 4 rows, 30 binaries), which HiGHS does not
    solve in 10 s, ends within seconds of the interrupt with its incumbent, unproven."""
    import threading

    from scipy import sparse

    from milp.core.highs import make_lp, solve_lp
    from milp.core.timelimit import interrupt, interrupt_stops

    rows, columns = 4, 30
    A = np.random.default_rng(1).integers(0, 100, size=(rows, columns)).astype(float)
    rhs = np.floor(A.sum(axis=1) / 2)  # minimise the total deviation |Ax - rhs|
    matrix = sparse.hstack([sparse.csc_matrix(A), sparse.identity(rows), -sparse.identity(rows)]).tocsc()
    lp = make_lp(np.r_[np.zeros(columns), np.ones(2 * rows)],
                 (np.zeros(columns + 2 * rows), np.r_[np.ones(columns), np.full(2 * rows, np.inf)]),
                 matrix, (rhs, rhs), np.r_[np.ones(columns, bool), np.zeros(2 * rows, bool)])
    with interrupt_stops(""):
        threading.Timer(1.0, interrupt).start()
        began = time.perf_counter()
        solved = solve_lp(lp, time_limit=60.0)
        took = time.perf_counter() - began
    assert took < 1.0 + 10.0
    assert solved.status == "feasible" and "Interrupted" in solved.message


def test_an_expired_deadline_stops_two_opt_at_once() -> None:
    points = np.random.default_rng(3).uniform(0, 100, (41, 2))
    D = np.hypot(*(points[:, None, :] - points[None, :, :]).transpose(2, 0, 1))
    order = list(range(1, 41))
    assert two_opt(D, order, tours=True, time_limit=TimeLimit(0.0)) == order
    assert route_cost(D, two_opt(D, order, tours=True), tours=True) < route_cost(D, order, tours=True)


def _reference_two_opt(D: np.ndarray, route: list[int], *, tours: bool) -> list[int]:
    """The definition: first improving reversal by full re-costing, scan on."""
    best, best_cost = list(route), route_cost(D, route, tours=tours)
    improved = True
    while improved:
        improved = False
        for i in range(len(best) - 1):
            for j in range(i + 1, len(best)):
                candidate = best[:i] + best[i : j + 1][::-1] + best[j + 1 :]
                cost = route_cost(D, candidate, tours=tours)
                if cost < best_cost - 1e-9:
                    best, best_cost, improved = candidate, cost, True
    return best


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 14), st.integers(0, 10**6), st.booleans(), st.booleans())
def test_priced_two_opt_makes_the_moves_of_full_recosting(n: int, seed: int, tours: bool, grid: bool) -> None:
    rng = np.random.default_rng(seed)
    points = rng.uniform(0, 10, (n + 1, 2))
    if grid:  # ties and coincident points
        points = np.round(points / 3)
    D = np.hypot(*(points[:, None, :] - points[None, :, :]).transpose(2, 0, 1))
    route = [int(v) for v in rng.permutation(np.arange(1, n + 1))]
    assert two_opt(D, route, tours=tours) == _reference_two_opt(D, route, tours=tours)


def test_mst_preorder_ends_on_infinite_distances() -> None:
    # Coordinates near 1e200 once gave infinite distances; Prim's np.argmin then picked
    # the start again and the depth-first walk never ended (`best` never stopped).
    d = np.full((5, 5), np.inf)
    np.fill_diagonal(d, 0.0)
    order, leaf = _mst_preorder(d)
    assert sorted(order) == [1, 2, 3, 4] and len(leaf) == 4
