"""Ctrl-C during ``parcover solve``: it stops the solve as its time limit would, and the
best routes found so far are printed, verified, with exit status 130
(milp.core.timelimit.interrupt_stops, tested further in test_time_limit.py; the race's
entrants are told on their standard input, milp.race)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from parcover import cli
from parcover.generate import random_points
from parcover.io import read_instance, write_instance
from parcover.verify import verify

#: Seconds a solve may take to end after the Ctrl-C (it stops within a pricing round).
ENDS_WITHIN = 60.0


@pytest.fixture(scope="module")
def clustered_60(tmp_path_factory) -> Path:
    """60 KPOIs in rooms: 4 tours are not proven in minutes (the building-scale grid's
    clustered 60-KPOI tours never are in 300 s), so the solve is still running when the
    test interrupts it."""
    path = tmp_path_factory.mktemp("interrupt") / "clustered60.json"
    write_instance(random_points(60, 5, layout="clustered"), path)
    return path


def _solve_until(instance: Path, out: Path, logged: str) -> subprocess.Popen:
    """``parcover solve --log`` (exact, 4 tours, no time limit) in a session of its own,
    as a terminal runs it, once its log has shown a line with ``logged``."""
    process = subprocess.Popen(
        [sys.executable, "-m", "parcover", "solve", str(instance), "--robots", "4", "--routes", "tours",
         "--log", "--out", str(out)],
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, start_new_session=True)
    lines: list[str] = []
    for line in process.stderr:
        lines.append(line)
        if logged in line:
            return process
    process.wait()
    pytest.fail(f"the solve ended before logging {logged!r}:\n{''.join(lines)}")


def _ctrl_c(process: subprocess.Popen) -> None:
    """Ctrl-C as a terminal sends it: SIGINT to the foreground process group."""
    os.killpg(process.pid, signal.SIGINT)


def _ended(process: subprocess.Popen) -> str:
    """The rest of its stderr once it has ended (within :data:`ENDS_WITHIN`)."""
    timer = threading.Timer(ENDS_WITHIN, process.kill)
    timer.start()
    try:
        rest = process.stderr.read()
        process.wait()
    finally:
        timer.cancel()
    assert process.returncode != -signal.SIGKILL, f"still running {ENDS_WITHIN:g} s after Ctrl-C"
    return rest


def test_ctrl_c_stops_a_solve_with_its_best_routes_verified(clustered_60, tmp_path):
    out = tmp_path / "result.json"
    # once branch-and-price's rival runs in another process: both are asked to stop
    process = _solve_until(clustered_60, out, "race: best started")
    _ctrl_c(process)
    began = time.perf_counter()
    err = _ended(process)
    assert process.returncode == cli.INTERRUPTED_STATUS
    assert "stopping with the best routes found so far" in err and "Traceback" not in err
    assert time.perf_counter() - began < ENDS_WITHIN
    result = json.loads(out.read_text())
    assert result["status"] == "feasible" and "interrupted (Ctrl-C)" in result["note"]
    assert result["bound"] is not None and result["bound"] <= result["makespan"]
    verdict = verify(read_instance(clustered_60), result)
    assert verdict.valid, verdict.violations()
    assert verdict.makespan == pytest.approx(result["makespan"])


def test_a_long_solve_on_a_terminal_says_how_to_follow_or_stop_it(capsys, monkeypatch):
    """Without --log, a solve on a terminal prints one line once it has run a while; off
    a terminal (a script, a pipe) it prints none."""
    monkeypatch.setattr(cli, "STILL_SOLVING_SECONDS", 0.05)
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    real = cli.solve

    def slow(*args, **kwargs):
        time.sleep(0.5)
        return real(*args, **kwargs)

    monkeypatch.setattr(cli, "solve", slow)
    grid = str(Path(__file__).resolve().parents[1] / "instances" / "fig1_grid.json")
    assert cli.main(["solve", grid, "--robots", "2"]) == 0
    err = capsys.readouterr().err
    assert "still solving (exact, no time limit); --log shows its progress" in err
    monkeypatch.setattr(sys.stderr, "isatty", lambda: False)  # not on a terminal: nothing
    assert cli.main(["solve", grid, "--robots", "2"]) == 0
    assert "still solving" not in capsys.readouterr().err
