"""What every benchmark section shares: its settings, its output, peers in subprocesses.

A section is a module with ``run(config: Config) -> Section``; :mod:`benchmarks.__main__`
runs the sections in order and writes ``benchmarks.md`` with each section's markdown, the
CSV of each of its tables and its figures (PNG) in the figures folder beside it.

Peers (OR-Tools, PyVRP) run in their own Python process (:func:`run_peer`): OR-Tools ships
its own HiGHS, so ortools and highspy cannot be imported into one process.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

ROOT = Path(__file__).resolve().parent.parent


@dataclass(frozen=True)
class Config:
    """Settings of one benchmark run.

    Attributes
    ----------
    quick
        A smoke run of a few minutes (CI): fewer sizes, seeds and seconds.
    figures
        Folder for the sections' PNG figures and CSV tables (created by the runner).
    figures_link
        The same folder as the report links it (relative to the report's folder).
    log
        Prints one progress line (to stderr).
    """

    quick: bool
    figures: Path
    figures_link: str
    log: Callable[[str], None] = lambda line: print(line, file=sys.stderr, flush=True)

    def figure(self, name: str) -> tuple[Path, str]:
        """Where to save figure ``name`` (e.g. ``"greedy_scaling.png"``) and its markdown link."""
        return self.figures / name, f"{self.figures_link}/{name}"


@dataclass
class Section:
    """One section of the report.

    Attributes
    ----------
    title
        Its heading.
    markdown
        Its body: tables, figure links (from :meth:`Config.figure`), findings.
    tables
        DataFrames written as ``<figures>/<name>.csv``.
    targets
        One line per target of the section: the target and the figure reached.
    """

    title: str
    markdown: str
    tables: dict[str, pd.DataFrame] = field(default_factory=dict)
    targets: list[str] = field(default_factory=list)


def compile_pricing(config: Config) -> None:
    """Compile branch-and-price's numba pricing before anything is timed (about 10 s on
    the first run after installation, then loaded from numba's cache in a fraction of a
    second): the benchmarks time solves, not the one-off compilation, and without it a
    time limit under :data:`milp.branchprice.COMPILE_SECONDS` makes ``exact`` skip
    branch-and-price on a fresh installation."""
    from milp import branchprice

    began = time.perf_counter()
    branchprice.compile_pricing()
    config.log(f"[benchmarks] branch-and-price's pricing compiled or loaded in {time.perf_counter() - began:.1f} s")


def euclidean_points(n: int, seed: int) -> np.ndarray:
    """A start (row 0) and ``n`` KPOIs uniform in a 100 x 100 square, seeded."""
    return np.random.default_rng(seed).uniform(0.0, 100.0, size=(n + 1, 2))


def euclidean_distances(n: int, seed: int) -> np.ndarray:
    """Distances between :func:`euclidean_points` (start at index 0)."""
    points = euclidean_points(n, seed)
    return np.linalg.norm(points[:, None, :] - points[None, :, :], axis=2)


def markdown_table(frame: pd.DataFrame, floatfmt: str = ".3g") -> str:
    """``frame`` as a GitHub markdown table (NaN shown as ``-``)."""
    columns = [str(c) for c in frame.columns]
    lines = ["| " + " | ".join(columns) + " |", "|" + "|".join("---" for _ in columns) + "|"]
    for row in frame.itertuples(index=False):
        cells = []
        for value in row:
            if value is None or (isinstance(value, float) and np.isnan(value)):
                cells.append("-")
            elif isinstance(value, float):
                cells.append(format(value, floatfmt))
            else:
                cells.append(str(value))
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def run_peer(name: str, payload: dict[str, Any], timeout: float) -> dict[str, Any]:
    """Run ``benchmarks/peers/<name>.py`` in its own Python process and return its answer.

    The payload goes to the peer's stdin as JSON, the answer comes back on its stdout as
    JSON. The answer is ``{"unavailable": reason}`` when the peer's package is not
    installed (the ``[bench]`` extra), ``{"error": message}`` when the process fails or
    overruns ``timeout`` seconds; otherwise whatever the peer reports (its docstring).
    ``seconds`` (wall clock of the whole process, start-up included) is always added.
    """
    started = time.perf_counter()
    try:
        done = subprocess.run(
            [sys.executable, "-m", f"benchmarks.peers.{name}"],
            input=json.dumps(payload), capture_output=True, text=True, timeout=timeout, cwd=ROOT,
            env={**os.environ, "PYTHONPATH": str(ROOT)},
        )
    except subprocess.TimeoutExpired:
        return {"error": f"{name} overran {timeout:.0f} s", "seconds": time.perf_counter() - started}
    if done.returncode != 0:
        last = (done.stderr.strip().splitlines() or ["no message"])[-1]
        return {"error": f"{name} exited {done.returncode}: {last}", "seconds": time.perf_counter() - started}
    answer = json.loads(done.stdout)
    answer.setdefault("seconds", time.perf_counter() - started)
    return answer


def peer_main(solve: Callable[[dict[str, Any]], dict[str, Any]], module: str) -> None:
    """The ``__main__`` of a peer: JSON in on stdin, ``solve``'s JSON out on stdout.

    Answers ``{"unavailable": ...}`` when ``module`` cannot be imported.
    """
    payload = json.load(sys.stdin)
    try:
        __import__(module)
    except ImportError as error:
        json.dump({"unavailable": f"{module} is not installed ({error}); pip install -e '.[bench]'"}, sys.stdout)
        return
    json.dump(solve(payload), sys.stdout)
