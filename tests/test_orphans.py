"""No orphans: a killed ``parcover report`` (any signal, SIGKILL
included) leaves no pool worker behind, nor does one that ends or fails, and a child
that calls :func:`milp.core.orphans.exit_with_parent` ends with its parent."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time

import pytest

from parcover import MethodInfo, generate
from parcover.algorithms.trivial import one_per_kpoi
from parcover.report import gaps
from parcover.solve import METHODS

psutil = pytest.importorskip("psutil")  # a dependency of dask.distributed, in the test extras


def _gone(processes: list, seconds: float) -> list:
    """Those of ``processes`` still running (zombies count as gone) after up to ``seconds``."""
    deadline = time.monotonic() + seconds
    alive = list(processes)
    while alive and time.monotonic() < deadline:
        time.sleep(0.1)
        alive = [p for p in alive if _running(p)]
    return alive


def _running(process) -> bool:
    try:
        return process.status() != psutil.STATUS_ZOMBIE
    except psutil.NoSuchProcess:
        return False


def _children_once_started(parent, count: int, seconds: float = 60) -> list:
    """``parent``'s descendants once it has ``count`` children."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if len(parent.children()) >= count:
            return parent.children(recursive=True)
        time.sleep(0.1)
    raise AssertionError(f"{parent.pid} did not start {count} children within {seconds} s")


@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGTERM])
def test_a_killed_report_leaves_no_worker(tmp_path, sig):
    report = subprocess.Popen(
        [sys.executable, "-m", "parcover", "report", "random:n=12:seeds=0..20", "--workers", "2", "--no-plots",
         "--no-progress", "--out", str(tmp_path / "r")],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
    )
    try:
        workers = _children_once_started(psutil.Process(report.pid), 2)
    finally:
        report.send_signal(sig)
        report.wait(timeout=30)
    assert len(workers) >= 2
    assert _gone(workers, 10) == []


def test_an_interrupted_report_leaves_no_worker(tmp_path):
    # Ctrl-C reaches the whole process group: the report stops, its workers with it. The
    # report gets SIGINT's default disposition, as from a terminal: a test run started in
    # the background (`bash .ci/run &`) ignores SIGINT, and its children inherit that.
    report = subprocess.Popen(
        [sys.executable, "-m", "parcover", "report", "random:n=12:seeds=0..20", "--workers", "2", "--no-plots",
         "--no-progress", "--out", str(tmp_path / "r")],
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, start_new_session=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    try:
        workers = _children_once_started(psutil.Process(report.pid), 2)
        time.sleep(1)  # the workers' initializers have run
    finally:
        os.killpg(report.pid, signal.SIGINT)
        _, err = report.communicate(timeout=30)
    assert report.returncode == 130 and "interrupted" in err, err
    assert "kept in" in err and "the same command resumes from them" in err, err
    assert _gone(workers, 10) == []


_PARENT = textwrap.dedent("""
    import subprocess, sys, time
    child = subprocess.Popen([sys.executable, "-c", sys.argv[1]], stdout=sys.stdout)
    time.sleep(600)
""")

_CHILD = textwrap.dedent("""
    import os, time
    from milp.core import orphans
    {start}
    print(os.getpid(), flush=True)
    while True:  # also with the GIL held in compiled code the kernel ends it; here it sleeps
        time.sleep(1)
""")


@pytest.mark.parametrize("start", ["orphans.exit_with_parent()", "orphans.watch_parent()"],
                         ids=["kernel-and-thread", "thread-alone"])
def test_a_child_ends_with_its_killed_parent(start):
    parent = subprocess.Popen([sys.executable, "-c", _PARENT, _CHILD.format(start=start)], stdout=subprocess.PIPE,
                              text=True)
    child = psutil.Process(int(parent.stdout.readline()))
    assert child.ppid() == parent.pid
    parent.kill()
    parent.wait()
    started = time.monotonic()
    assert _gone([child], 10) == []
    assert time.monotonic() - started < 2  # the thread looks every 0.5 s


def test_a_child_whose_parent_is_already_gone_ends_at_once():
    code = "from milp import orphans; orphans.exit_with_parent(parent=1); print('ran on')"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert done.returncode == 70 and done.stdout == ""


# -- in-process reports: the pool's workers end with the report ---------------------


def sleeps_or_fails(instance, problem, *, time_limit=None, seed=0):
    """Test method (module-level: forked workers find it): fails on star-3, sleeps elsewhere."""
    if instance.name == "star-3":
        raise RuntimeError("planted failure")
    time.sleep(60)
    return one_per_kpoi(instance, problem)


def _new_workers(before: set[int]) -> list:
    """Children of this process started since ``before`` (not multiprocessing's resource tracker)."""
    found = []
    for process in psutil.Process().children(recursive=True):
        try:
            if process.pid not in before and "resource_tracker" not in " ".join(process.cmdline()):
                found.append(process)
        except psutil.NoSuchProcess:  # ended meanwhile
            pass
    return found


def test_a_finished_report_leaves_no_worker():
    before = {p.pid for p in psutil.Process().children(recursive=True)}
    rows = gaps([generate.star(3), generate.star(4)], ["trivial"], routes=("paths",), robots=(2,), deadlines=(),
                reference="trivial", workers=2, progress=False)
    assert len(rows) == 2
    assert _gone(_new_workers(before), 2) == []


def test_a_failing_report_stops_its_other_workers(monkeypatch):
    monkeypatch.setitem(METHODS, "sleepy", MethodInfo("sleepy", sleeps_or_fails, "test only"))
    before = {p.pid for p in psutil.Process().children(recursive=True)}
    started = time.monotonic()
    with pytest.raises(RuntimeError, match="planted failure"):
        gaps([generate.star(3), generate.star(4)], ["sleepy"], routes=("paths",), robots=(2,), deadlines=(),
             reference="trivial", workers=2, progress=False)
    assert _gone(_new_workers(before), 5) == []
    assert time.monotonic() - started < 20  # the sleeping worker was not waited for
