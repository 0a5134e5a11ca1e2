"""The solve log (``--log``, or :mod:`logging` from Python): progress on stderr only."""

from __future__ import annotations

import json
import logging
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from milp import race
from milp.core.progress import log_to_stderr
from parcover import generate, solve

INSTANCES = Path(__file__).resolve().parent.parent / "instances"
LINE = re.compile(r"^\s*\d+\.\d\d s  \S")  # "   1.23 s  message"


def _cli(*argv: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "parcover", *argv], capture_output=True, text=True, timeout=120)


def _without_time(text: str) -> str:
    return "\n".join(line for line in text.splitlines() if not line.startswith("time "))


def test_log_goes_to_stderr_and_leaves_stdout_unchanged(tmp_path):
    instance = str(INSTANCES / "random12_s2.json")
    quiet = _cli("solve", instance, "--robots", "3", "--method", "branchprice")
    logged = _cli("solve", instance, "--robots", "3", "--method", "branchprice", "--log")
    assert quiet.returncode == logged.returncode == 0
    assert quiet.stderr == ""  # quiet by default
    assert _without_time(logged.stdout) == _without_time(quiet.stdout)
    lines = logged.stderr.splitlines()
    assert lines and all(LINE.match(line) for line in lines), logged.stderr
    assert any("warm start" in line for line in lines)
    assert any("branch-and-price" in line and "bound" in line for line in lines)
    assert "solve: optimal" in lines[-1]


def test_log_with_json_keeps_stdout_one_object():
    done = _cli("solve", str(INSTANCES / "random8_s1.json"), "--robots", "2", "--json", "--log")
    assert done.returncode == 0
    assert json.loads(done.stdout)["status"] == "optimal"
    assert "solve:" in done.stderr


def test_python_users_get_the_same_lines_through_logging(caplog):
    instance = generate.random_points(9, 3)
    with caplog.at_level(logging.INFO, logger="parcover"):
        solve(instance, "tours", robots=2, method="best", time_limit=20)
    messages = [r.getMessage() for r in caplog.records]
    assert any(m.startswith("best: starts from") for m in messages)
    assert any(m.startswith("solve: feasible") or m.startswith("solve: optimal") for m in messages)


def test_race_entrants_log_on_the_parent_stream(tmp_path):
    # Each entrant runs in its own interpreter; with logging on, its lines arrive on the
    # parent's stream, prefixed with its name, on the parent's clock.
    points = np.random.default_rng(5).uniform(0, 100, size=(9, 2))
    D = np.linalg.norm(points[:, None] - points[None], axis=2)
    path = tmp_path / "log.txt"
    logger = logging.getLogger("milp")
    with path.open("w") as stream:
        log_to_stderr(("milp",), stream=stream)
        try:
            race.race({"branchcut": "milp.branchcut:min_makespan"}, (D, 2), {"tours": True}, 60.0)
        finally:
            for handler in list(logger.handlers):
                logger.removeHandler(handler)
            logger.setLevel(logging.NOTSET)
    text = path.read_text()
    assert "race: branchcut started" in text
    assert "[branchcut] branch-and-cut:" in text
    assert all(LINE.match(line) for line in text.splitlines()), text


def test_an_infeasible_answer_says_which_kpoi_is_too_far(capsys):
    instance = generate.random_points(6, 1)
    result = solve(instance, "tours", deadline=1.0)
    assert result.status.value == "infeasible"
    assert re.search(r"KPOI \S+ is 2 x [\d.]+ = [\d.]+ there and back, above the deadline 1", result.note)
    assert result.to_dict()["note"] == result.note


@pytest.mark.parametrize("question, unit", [(["--robots", "2"], "(makespan: no less)"), ([], "robots (no fewer)")])
def test_the_summary_says_what_the_bound_bounds(question, unit):
    done = _cli("solve", str(INSTANCES / "random8_s1.json"), *question)
    bound = next(line for line in done.stdout.splitlines() if line.startswith("bound"))
    assert unit in bound
