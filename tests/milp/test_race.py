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
    """60 KPOIs, 2 tours, 5 s: neither proves; both answers (valid, with bounds) are back
    within the limit and the grace."""
    D = euclidean(60, 3)
    began = time.perf_counter()
    answers = race.race(BOTH, (D, 2), {"tours": True}, 5.0)
    assert time.perf_counter() - began <= 5.0 + race.GRACE_SECONDS + 0.5
    assert set(answers) == set(BOTH)
    for answer in answers.values():
        assert answer.status == "feasible"
        check_solution(D, answer, tours=True, k=2)


def test_an_entrant_that_fails_is_reported():
    with pytest.raises(RuntimeError, match="k must be at least 1"):
        race.race({"branchcut": "milp.branchcut:min_makespan"}, (euclidean(5, 1), 0), {"tours": True}, 30)
