"""When ``best`` stops: a time limit is a cap (a proven bound, convergence or the limit,
whichever comes first), ``until=limit`` spends it, and the answer depends on the seed."""

from __future__ import annotations

import time

import pytest

from parcover import generate, solve
from parcover.algorithms.local_search import PATIENCE_MIN, PATIENCE_PER_KPOI, best, patience
from parcover.bounds import lower_bound
from parcover.errors import InputError
from parcover.problem import Problem


def test_patience_grows_with_the_instance():
    assert patience(1) == PATIENCE_MIN
    assert patience(1000) == 1000 * PATIENCE_PER_KPOI
    assert patience(8) <= patience(50) <= patience(200)


@pytest.mark.parametrize("routes", ["paths", "tours"])
def test_a_long_limit_is_not_spent_on_a_small_instance(routes):
    # 8 KPOIs: a few hundred rounds take well under a second; a 60 s limit must not be
    # waited for (it was, whole, before the limit became a cap).
    instance = generate.random_points(8, 5)
    began = time.perf_counter()
    solution = best(instance, Problem(routes, robots=2), time_limit=60.0, seed=0)
    assert time.perf_counter() - began < 10.0
    # it stopped by a rule of its own: at most patience(n) rounds after its last improvement
    assert 0 < solution.info["iterations"] < 60 * 10_000


def test_convergence_means_patience_rounds_without_improvement():
    instance = generate.random_points(9, 6)
    problem = Problem("paths", robots=3)
    solution = best(instance, problem, time_limit=60.0, seed=1)
    rounds = solution.info["iterations"]
    if rounds == 0:  # the construction met the lower bound: nothing to search
        assert solution.info["value"][0] <= lower_bound(instance, problem) * (1 + 1e-9)
    else:  # the last `patience` rounds found nothing better
        assert rounds >= patience(instance.n)


def test_the_search_stops_at_a_proven_lower_bound(fig3_star):
    # Fig. 3 with 6 paths: each KPOI on its own path costs c_max = 1, the lower bound;
    # any construction reaches it, so no round is run although 60 s are allowed.
    solution = best(fig3_star, Problem("paths", robots=6), time_limit=60.0, seed=0)
    assert solution.info["value"][0] == pytest.approx(1.0)
    assert solution.info["iterations"] == 0


def test_same_seed_same_answer_under_a_limit():
    # The schedule follows the rounds, not the clock, when it fits in the limit.
    instance = generate.random_points(12, 3)
    problem = Problem("tours", robots=3)
    first = best(instance, problem, time_limit=30.0, seed=4)
    second = best(instance, problem, time_limit=30.0, seed=4)
    assert first.routes == second.routes
    assert first.info["iterations"] == second.info["iterations"]


def test_until_limit_spends_the_whole_limit():
    instance = generate.random_points(8, 5)
    began = time.perf_counter()
    best(instance, Problem("paths", robots=2), time_limit=1.0, seed=0, until="limit")
    assert time.perf_counter() - began >= 0.9


def test_until_is_checked():
    instance = generate.random_points(5, 1)
    with pytest.raises(InputError, match="until must be one of converged, limit"):
        best(instance, Problem("paths", robots=2), time_limit=1.0, until="never")
    with pytest.raises(InputError, match="give one"):  # until=limit needs a limit
        best(instance, Problem("paths", robots=2), until="limit")


def test_a_method_label_passes_text_options():
    instance = generate.random_points(6, 2)
    result = solve(instance, "paths", robots=2, method="best:until=limit", time_limit=0.5)
    assert result.method == "best:until=limit"
    with pytest.raises(InputError, match="needs a number"):
        solve(instance, "paths", robots=2, method="best:iterations=many")


def test_robots_question_stops_early_too():
    instance = generate.random_points(10, 7)
    began = time.perf_counter()
    result = solve(instance, "tours", method="best", time_limit=60.0)
    assert time.perf_counter() - began < 10.0
    assert result.robots >= result.bound


def test_best_never_starts_from_a_labelled_best(monkeypatch):
    # A registered label of best (as a report's worker once registered best:iterations=5)
    # is best itself: trying it as a construction recursed until RecursionError (minutes,
    # and answers that changed from call to call).
    from parcover.solve import METHODS, available_methods, method_with_options

    available_methods()
    monkeypatch.setitem(METHODS, "best:iterations=5", method_with_options("best:iterations=5"))
    instance = generate.random_points(12, 4)
    began = time.perf_counter()
    first = best(instance, Problem("tours", robots=3), seed=3, iterations=10)
    second = best(instance, Problem("tours", robots=3), seed=3, iterations=10)
    assert time.perf_counter() - began < 10.0
    assert not first.info["start"].startswith("best")
    assert first.routes == second.routes


def test_a_report_with_a_label_registers_nothing():
    from parcover import report
    from parcover.solve import METHODS

    report.gaps("random:n=5:seeds=0", ["best:iterations=3"], routes=("paths",), robots=(2,), deadlines=(),
                reference="setpart", time_limit=None, seed=0, workers=1, progress=False)
    assert not [name for name in METHODS if ":" in name]


def test_an_astronomical_limit_returns(tmp_path):
    # `solve X --method best --robots 2 --time-limit 1e300` on 3 KPOIs never returned when
    # the limit was a budget.
    import subprocess
    import sys

    path = tmp_path / "r3.json"
    from parcover import write_instance

    write_instance(generate.random_points(3, 1), path)
    done = subprocess.run([sys.executable, "-m", "parcover", "solve", str(path), "--method", "best",
                           "--robots", "2", "--time-limit", "1e300"], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0 and "status" in done.stdout
