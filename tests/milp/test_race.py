"""The race of exact methods in processes of their own (milp/race.py)."""

from __future__ import annotations

import time

import pytest

from milp import race
from milp_helpers import check_solution, euclidean

BOTH = {"branchprice": "milp.branchprice:min_makespan", "branchcut": "milp.branchcut:min_makespan"}


def test_the_first_proof_ends_the_race():
    """A small question both prove: one answer, proven, and valid."""
    D = euclidean(12, 3)
    answers = race.race(BOTH, (D, 2), {"tours": True}, 60)
    assert len(answers) == 1
    (answer,) = answers.values()
    assert answer.status == "optimal"
    check_solution(D, answer, tours=True, k=2)


def test_unproven_answers_come_back_within_the_time_limit():
    """60 KPOIs, 2 tours, 10 s: neither proves; both answers (valid, with bounds) are back
    within the limit and the grace. (With 5 s, a loaded machine spent the whole limit
    starting the two interpreters, and neither had an answer yet.)"""
    D = euclidean(60, 3)
    began = time.perf_counter()
    answers = race.race(BOTH, (D, 2), {"tours": True}, 10.0)
    assert time.perf_counter() - began <= 10.0 + race.GRACE_SECONDS + 0.5
    assert set(answers) == set(BOTH)
    for answer in answers.values():
        assert answer.status == "feasible"
        check_solution(D, answer, tours=True, k=2)


def test_an_entrant_that_fails_is_reported():
    with pytest.raises(RuntimeError, match="k must be at least 1"):
        race.race({"branchcut": "milp.branchcut:min_makespan"}, (euclidean(5, 1), 0), {"tours": True}, 30)


def test_an_interrupt_reaches_every_entrant():
    """Ctrl-C in the parent (milp.core.timelimit.interrupt) reaches the entrants, which run
    in sessions of their own, on their standard input: without a time limit of their own
    (the race's 120 s would end them at 120 s), both answer with valid unproven routes
    soon after."""
    import threading

    from milp.core.timelimit import interrupt, interrupt_stops

    D = euclidean(60, 3)
    with interrupt_stops(""):
        threading.Timer(8.0, interrupt).start()
        began = time.perf_counter()
        answers = race.race(BOTH, (D, 2), {"tours": True}, 120.0)
        took = time.perf_counter() - began
    assert took < 8.0 + 30.0
    assert set(answers) == set(BOTH)
    for answer in answers.values():
        assert answer.status == "feasible"
        check_solution(D, answer, tours=True, k=2)


def _waits_for_the_stop(D, k, *, tours, time_limit, warm_start=None):
    """An entrant here that proves nothing: it waits until stopped or out of time, as
    branch-and-price does between pricing rounds."""
    from milp.core.result import MilpResult
    from milp.core.timelimit import TimeLimit, stop_requested

    clock = TimeLimit(time_limit)
    while not clock.expired():
        time.sleep(0.02)
    return MilpResult("unknown", [], None, None, None, 0, 0.0, "stopped" if stop_requested() else "time limit")


def test_a_proof_elsewhere_stops_the_entrant_here():
    """branch-and-cut proves a small question in another process; the entrant here sees
    the stop within a look of the watching thread, and no entrant is left running."""
    import psutil

    D = euclidean(12, 3)
    began = time.perf_counter()
    answers = race.race_here("here", _waits_for_the_stop, {"branchcut": BOTH["branchcut"]}, (D, 2),
                             {"tours": True}, 60.0)
    assert time.perf_counter() - began < 30
    assert list(answers) == ["branchcut"] and answers["branchcut"].status == "optimal"
    check_solution(D, answers["branchcut"], tours=True, k=2)
    assert not psutil.Process().children(recursive=True)


def test_a_proof_here_ends_the_race_before_the_others_start():
    """branch-and-price proves in this process before ``others_after``: nothing else runs."""
    from milp import branchprice

    D = euclidean(12, 3)
    answers = race.race_here("branchprice", branchprice.min_makespan, {"branchcut": BOTH["branchcut"]}, (D, 2),
                             {"tours": True}, 60.0, others_after=30.0)
    assert list(answers) == ["branchprice"] and answers["branchprice"].status == "optimal"


def test_unproven_answers_here_and_elsewhere_come_back():
    """Nothing proven within 4 s: the answer here and the other's (when it answered in
    time) come back, and the race keeps to its limit and the grace."""
    import psutil

    D = euclidean(60, 3)
    began = time.perf_counter()
    answers = race.race_here("here", _waits_for_the_stop, {"branchcut": BOTH["branchcut"]}, (D, 2),
                             {"tours": True}, 4.0)
    assert time.perf_counter() - began <= 4.0 + race.GRACE_SECONDS + 0.5
    assert "here" in answers and answers["here"].message == "time limit"
    assert not psutil.Process().children(recursive=True)


def test_the_stop_is_per_thread():
    import threading

    from milp.core.timelimit import TimeLimit, stop_requested, stopping

    event = threading.Event()
    seen = []
    with stopping(event):
        event.set()
        assert stop_requested() and TimeLimit(10).expired() and TimeLimit(10).remaining() == 0.0
        other = threading.Thread(target=lambda: seen.append(stop_requested()))
        other.start()
        other.join()
    assert seen == [False] and not stop_requested()


def test_processes_sharing_the_cores_each_count_their_share(monkeypatch):
    all_cores = race.cores()
    monkeypatch.setattr(race, "_sharing", 1)
    race.share_cores(2)
    assert race.cores() == max(1, all_cores // 2)
    race.share_cores(all_cores + 1)
    assert race.cores() == 1
