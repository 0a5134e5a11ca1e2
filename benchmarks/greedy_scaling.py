"""Greedy scaling: time and memory of the greedy methods, 100 to 5,000 KPOIs.

The paper's Algorithm 1 (literal and nearest-end readings), Algorithm 1-1 at a deadline of
``1.2 c_max``, Algorithm 2 (tours, Algorithm 1's paths paired as published) and the
constructions of :mod:`parcover.algorithms.baselines` (``mst``, ``nn``, ``knn``, ``kni``,
``split``) run on seeded uniform random Euclidean instances. The constructions answer two
questions: the paper's (fewest robots at the least makespan ``c_max``, paths) and a robot
limit of 10 (least makespan, paths). Building the instance (its distance matrix) is timed
separately. Each method is called directly, without :func:`parcover.solve`'s verification.

Time is the best of a few repeats (one for the largest sizes); peak memory is measured in a
separate run with :mod:`tracemalloc` (numpy's allocations included) beyond the instance
itself. The growth exponent is the least-squares slope of ``log(time)`` on ``log(n)`` over
``n >= 500`` (over every size in the quick run, which stops at 500). The target:
5,000 KPOIs in under 2 s on one core, Algorithm 1 and every construction.
"""

from __future__ import annotations

import time
import tracemalloc
from collections.abc import Callable, Sequence

import numpy as np
import pandas as pd

from benchmarks.common import Config, Section, markdown_table
from parcover import Instance
from parcover.algorithms import baselines
from parcover.algorithms.paper import LITERAL, NEAREST_END, algorithm_1, algorithm_2
from parcover.problem import Problem

SIZES = (100, 200, 500, 1000, 2000, 5000)
QUICK_SIZES = (100, 200, 500)
FIT_FROM = 500
TARGET_N = 5000
TARGET_SECONDS = 2.0
BUILD = "build the instance"

Method = Callable[[Instance], list[list[int]]]


def _construction(function: Callable[..., object], robots: int | None) -> Method:
    """A baseline on paths: fewest robots at ``c_max`` (``robots=None``) or at most ``robots``."""
    problem = Problem("paths", robots=robots)
    return lambda instance: function(instance, problem).routes  # type: ignore[attr-defined]


def methods() -> dict[str, Method]:
    """The methods timed, by the name shown in the report."""
    out: dict[str, Method] = {
        "Alg 1 (paper)": lambda inst: algorithm_1(inst, reading=LITERAL),
        "Alg 1 (nearest-end)": lambda inst: algorithm_1(inst, reading=NEAREST_END),
        "Alg 1-1 (1.2 c_max)": lambda inst: algorithm_1(inst, 1.2 * inst.c_max),
        "Alg 2 (tours)": lambda inst: algorithm_2(inst, algorithm_1(inst)),
    }
    for info in baselines.METHODS:
        out[f"{info.name} (c_max)"] = _construction(info.function, None)
        out[f"{info.name} (K=10)"] = _construction(info.function, 10)
    return out


def instance_points(n: int, seed: int) -> np.ndarray:
    """A start and ``n`` KPOIs uniform in a 1000 x 1000 square (start first)."""
    return np.random.default_rng(seed).uniform(0.0, 1000.0, size=(n + 1, 2))


def best_time(call: Callable[[], object], repeats: int) -> tuple[float, object]:
    """Least wall-clock time of ``repeats`` calls, and the last call's value."""
    best, value = np.inf, None
    for _ in range(repeats):
        started = time.perf_counter()
        value = call()
        best = min(best, time.perf_counter() - started)
    return best, value


def peak_memory(call: Callable[[], object]) -> float:
    """Peak memory (MiB) allocated during one call, as :mod:`tracemalloc` sees it."""
    tracemalloc.start()
    try:
        call()
        return tracemalloc.get_traced_memory()[1] / 2**20
    finally:
        tracemalloc.stop()


def growth_exponent(sizes: Sequence[float], seconds: Sequence[float], least: float = FIT_FROM) -> float:
    """Least-squares slope of ``log(seconds)`` on ``log(size)`` over sizes ``>= least``.

    ``nan`` with fewer than two such sizes (or a non-positive time among them).
    """
    x = np.asarray(sizes, dtype=float)
    y = np.asarray(seconds, dtype=float)
    keep = x >= least
    if keep.sum() < 2 or (y[keep] <= 0).any():
        return float("nan")
    return float(np.polyfit(np.log(x[keep]), np.log(y[keep]), 1)[0])


def measure(sizes: Sequence[int], timed: dict[str, Method], log: Callable[[str], None]) -> pd.DataFrame:
    """One row per (method, n): seconds (best of a few), peak MiB, routes; plus the build rows."""
    rows = []
    for n in sizes:
        repeats = 3 if n <= 1000 else 1
        points = instance_points(n, seed=n)
        seconds, instance = best_time(lambda: Instance.from_points(points), repeats)
        assert isinstance(instance, Instance)
        memory = peak_memory(lambda: Instance.from_points(points))
        rows.append({"method": BUILD, "n": n, "seconds": seconds, "peak_mib": memory, "routes": np.nan})
        for name, method in timed.items():
            seconds, routes = best_time(lambda: method(instance), repeats)
            memory = peak_memory(lambda: method(instance))
            rows.append({"method": name, "n": n, "seconds": seconds, "peak_mib": memory,
                         "routes": len(routes)})  # type: ignore[arg-type]
        log(f"[greedy_scaling] n = {n} done")
    return pd.DataFrame(rows)


def summary(frame: pd.DataFrame, least: float) -> pd.DataFrame:
    """Methods as rows: seconds at each n and the growth exponent."""
    wide = frame.pivot(index="method", columns="n", values="seconds")
    wide = wide.loc[list(dict.fromkeys(frame["method"]))]
    wide.columns = [f"{n} s" for n in wide.columns]
    sizes = sorted(frame["n"].unique())
    exponents = [
        growth_exponent(sizes, frame[frame["method"] == m].sort_values("n")["seconds"], least) for m in wide.index
    ]
    wide.insert(len(wide.columns), "exponent", exponents)
    return wide.reset_index()


def target_line(frame: pd.DataFrame) -> str:
    """The target (5,000 KPOIs in under 2 s) and the figure reached."""
    head = f"5,000 KPOIs under {TARGET_SECONDS:g} s on one core"
    at = frame[(frame["n"] == TARGET_N) & (frame["method"] != BUILD)]
    if at.empty:
        return f"{head}: not measured (quick run, largest n = {frame['n'].max()})"
    fast = at[at["seconds"] < TARGET_SECONDS]["method"].tolist()
    slow = at[at["seconds"] >= TARGET_SECONDS]["method"].tolist()
    worst = at.loc[at["seconds"].idxmax()]
    alg1 = float(at[at["method"] == "Alg 1 (paper)"]["seconds"].iloc[0])
    verdict = "met" if not slow else "not met"
    missed = f"; over it: {', '.join(slow)}" if slow else ""
    return (
        f"{head}: {verdict} on this shared machine — {len(fast)} of {len(at)} method runs under it{missed}; "
        f"slowest {worst['method']} {worst['seconds']:.2f} s ({worst['seconds'] / alg1:.0f}x Algorithm 1's "
        f"{alg1:.2f} s in the same run)"
    )


def plot(frame: pd.DataFrame, least: float, path) -> None:
    """Log-log time against n, one line per method, the exponent in the legend."""
    from parcover.plot import plt, save_figure

    figure, axes = plt.subplots(figsize=(11, 6))
    colours = plt.get_cmap("tab20").colors
    for index, name in enumerate(dict.fromkeys(frame["method"])):
        rows = frame[frame["method"] == name].sort_values("n")
        slope = growth_exponent(rows["n"], rows["seconds"], least)
        colour = "black" if name == BUILD else colours[index % len(colours)]
        style = "--" if name == BUILD or name.endswith("(K=10)") else "-"
        axes.loglog(rows["n"], rows["seconds"], style, color=colour, marker="o", markersize=3,
                    label=f"{name} (slope {slope:.2f})")
    axes.axhline(TARGET_SECONDS, color="grey", linewidth=0.8, linestyle=":")
    axes.set_xlabel("KPOIs n")
    axes.set_ylabel("seconds (best of repeats)")
    axes.set_title("Greedy methods on uniform random Euclidean instances")
    axes.legend(fontsize=8, loc="center left", bbox_to_anchor=(1.01, 0.5))
    axes.grid(True, which="both", linewidth=0.3)
    save_figure(figure, path, dpi=120)


def run(config: Config) -> Section:
    """The section: measure, fit, plot, tabulate."""
    sizes = QUICK_SIZES if config.quick else SIZES
    least = min(sizes) if config.quick else FIT_FROM
    frame = measure(sizes, methods(), config.log)
    wide = summary(frame, least)
    memory = frame.pivot(index="method", columns="n", values="peak_mib").loc[wide["method"]]
    memory.columns = [f"{n} MiB" for n in memory.columns]
    path, link = config.figure("greedy_scaling.png")
    plot(frame, least, path)
    fit = f"n >= {FIT_FROM}" if not config.quick else f"all sizes (quick run: {', '.join(map(str, sizes))})"
    markdown = "\n\n".join([
        "Algorithm 1, 1-1 (deadline 1.2 c_max), 2 (tours) and the constructions (paths; `(c_max)`: fewest "
        "robots at the least makespan, `(K=10)`: least makespan with 10 robots) on uniform random Euclidean "
        "instances, called directly (no verification). Time: best of 3 runs (1 run from 2,000 KPOIs); "
        f"exponent: least-squares slope of log time on log n over {fit}. The machine is shared: compare "
        "methods within this run.",
        f"![greedy scaling]({link})",
        "Seconds:",
        markdown_table(wide),
        "Peak memory beyond the instance (tracemalloc, MiB; the build row is the instance itself, "
        "whose distance matrix holds (n+1)^2 floats):",
        markdown_table(memory.reset_index()),
    ])
    return Section(
        title="Greedy scaling",
        markdown=markdown,
        tables={"greedy_scaling": frame, "greedy_scaling_summary": wide},
        targets=[target_line(frame)],
    )
