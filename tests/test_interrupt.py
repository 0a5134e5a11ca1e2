"""Ctrl-C during ``parcover solve``: it stops the solve as its time limit would, and the
best routes found so far are printed, verified, with exit status 130
(milp.core.timelimit.interrupt_stops, tested further in test_time_limit.py; the race's
entrants are told on their standard input, milp.race)."""

from __future__ import annotations

import importlib
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


def _ctrl_c_before(monkeypatch, module, name: str, when=lambda *args, **kwargs: True) -> None:
    """``module.name`` receives a real SIGINT (as from a terminal) just before it runs,
    each time ``when(*args, **kwargs)`` holds; then it runs."""
    real = getattr(module, name)

    def interrupted_first(*args, **kwargs):
        if when(*args, **kwargs):
            os.kill(os.getpid(), signal.SIGINT)  # handled in this (the main) thread at once
        return real(*args, **kwargs)

    monkeypatch.setattr(module, name, interrupted_first)


def test_a_solve_proven_before_its_ctrl_c_took_effect_exits_with_0(monkeypatch, capfd):
    """A Ctrl-C that lands once the method has proven its answer (here: while the result
    is being built and verified) leaves the answer whole: exit 0, status optimal."""
    module = importlib.import_module("parcover.solve")  # the package's name is the function
    _ctrl_c_before(monkeypatch, module, "build_result")
    grid = str(Path(__file__).resolve().parents[1] / "instances" / "fig1_grid.json")
    assert cli.main(["solve", grid, "--robots", "2", "--json"]) == 0
    printed = capfd.readouterr()
    assert "stopping with the best routes found so far" in printed.err
    assert json.loads(printed.out)["status"] == "optimal"


def test_ctrl_c_ends_a_frontier_with_the_points_found_so_far(monkeypatch, capfd, tmp_path):
    """Stopped while solving k = 2 (the grid's last point), the frontier keeps k = 1 and
    2, says where it ended, and exits with 130; the JSON carries the note."""
    module = importlib.import_module("parcover.frontier")  # the package's name is the function
    _ctrl_c_before(monkeypatch, module, "solve", lambda *args, robots, **kwargs: robots == 2)
    grid = str(Path(__file__).resolve().parents[1] / "instances" / "fig1_grid.json")
    out = tmp_path / "frontier.json"
    plot = tmp_path / "frontier.png"
    assert cli.main(["frontier", grid, "--out", str(out), "--plot", str(plot)]) == cli.INTERRUPTED_STATUS
    assert plot.stat().st_size > 0
    printed = capfd.readouterr()
    assert "parcover frontier: stopping with the points found so far" in printed.err
    assert "note      interrupted (Ctrl-C) at 2 robots" in printed.out
    written = json.loads(out.read_text())
    assert [p["robots"] for p in written["points"]] == [1, 2]
    assert written["points"][0]["status"] == "optimal" and written["points"][1]["status"] != "optimal"
    assert written["note"].startswith("interrupted (Ctrl-C) at 2 robots")
    monkeypatch.undo()
    assert cli.main(["frontier", grid, "--out", str(out)]) == 0  # the interrupt ended with the command
    assert "note" not in json.loads(out.read_text())


def test_the_plot_of_an_interrupted_frontier_says_so():
    from matplotlib import pyplot as plt

    from parcover.plot import draw_frontier
    from parcover.result import Frontier, FrontierPoint, Status

    point = FrontierPoint(1, 8.0, Status.FEASIBLE, 6.0)
    ax = draw_frontier(Frontier("grid", "paths", "exact", [point], note="interrupted (Ctrl-C) at 1 robots"))
    assert ax.get_title().endswith("frontier by exact; stopped by Ctrl-C at 1 robot")
    plt.close(ax.figure)
    ax = draw_frontier(Frontier("grid", "paths", "exact", [point]))
    assert ax.get_title().endswith("frontier by exact")
    plt.close(ax.figure)


def test_ctrl_c_leaves_a_certificate_undecided_and_says_why(monkeypatch, capfd, tmp_path):
    import parcover.certify

    grid = str(Path(__file__).resolve().parents[1] / "instances" / "fig1_grid.json")
    result = tmp_path / "result.json"
    assert cli.main(["solve", grid, "--robots", "2", "--out", str(result)]) == 0
    _ctrl_c_before(monkeypatch, parcover.certify, "_solve")
    assert cli.main(["verify", grid, str(result), "--certify"]) == cli.INTERRUPTED_STATUS
    printed = capfd.readouterr()
    assert "parcover verify: stopping with what the re-proof has found so far" in printed.err
    assert "did not prove before it was interrupted (Ctrl-C)" in printed.out
