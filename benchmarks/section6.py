"""The paper's Section VI rerun, with the exact optimum beside every greedy answer.

Run from the repository root::

    python -m benchmarks.section6 [--quick] [--out reports/section6.md]

It writes the report (default ``reports/section6.md``; ``reports/section6-quick.md``
with ``--quick``) and, in the folder of the same name beside it, the figures (PNG),
the CSV of every row and the instance files, one per map and start, which
``parcover solve`` reads.

What is measured (paper, Section VI and Figs. 4-7):

- Two Player/Stage floor plans, an office (``hospital_section.png``) and a simple
  room layout (``simple_rooms.png``), with :data:`NODES` random positions each
  (seeded), joined by the paper's vertical cell decomposition
  (:func:`parcover.maps.instance_from_map`, ``graph="decomposition"``).
- The paper numbers these positions 1..20 and lets "the start node be any node"
  (Fig. 5: node 6, node 20; Fig. 6: the start node on the x-axis). So for every
  start ``j`` the instance has start ``j`` and the other 19 positions as KPOIs, on
  one and the same graph.
- Fig. 6(a): the path makespan of Algorithm 1 (``paper``, which reaches ``c_max``
  by construction, Prop. 1), of the MST branches (the paper's Fig. 5(b): one robot
  per leaf, ``mst`` with no binding robot limit), of nearest neighbour with as many
  robots as Algorithm 1 (``nn``), and the exact optimum with as many robots as
  Algorithm 1 (``exact``).
- Fig. 6(b): the robots of Algorithm 1 against the exact fewest robots at
  ``c_max``; for context the robots of ``nn`` and ``mst`` adapted to the deadline
  ``c_max``, and the MST's leaf count used in Fig. 6(a).
- Fig. 7: for one start per map, Algorithm 2's tours (``paper``, tours, no
  deadline) against kNN and kNI with ``k`` = the number of Algorithm 2's tours
  (in the paper both were 4: "4-NN", "4-NI") and the exact least tour makespan
  with ``k`` robots.

Every answer comes from :func:`parcover.solve`, which verifies the routes and sets
an honest status: an exact run stopped by its time limit is ``feasible`` with a
proven bound, shown as ``value (>= bound)``.
"""

from __future__ import annotations

import argparse
import shlex
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

import parcover
from benchmarks.common import ROOT, Config, Section, compile_pricing, markdown_table
from parcover.instance import Instance
from parcover.io import write_instance
from parcover.maps import instance_from_map
from parcover.plot import plot_side_by_side, plt, save_figure
from parcover.result import Result

__all__ = [
    "MapCase",
    "Settings",
    "MAPS",
    "NODES",
    "FULL",
    "QUICK",
    "PAPER",
    "map_graph",
    "rooted",
    "path_row",
    "tour_rows",
    "run",
    "main",
]

NODES = 20
MAP_DIR = ROOT / "instances" / "maps"


@dataclass(frozen=True)
class MapCase:
    """One floor plan of the rerun.

    Attributes
    ----------
    name
        Short name used in file names and tables.
    image
        Bitmap in ``instances/maps``.
    metres_per_pixel
        Its scale (``instances/maps/README.md``).
    seed
        Seed of the random positions.
    tour_start
        The start node of the Fig. 7 comparison (and of the Fig. 5 drawing).
    """

    name: str
    image: str
    metres_per_pixel: float | tuple[float, float]
    seed: int
    tour_start: int


MAPS = (
    MapCase("office", "hospital_section.png", (0.0368, 0.0406), seed=1, tour_start=6),
    MapCase("rooms", "simple_rooms.png", 0.05, seed=1, tour_start=20),
)


@dataclass(frozen=True)
class Settings:
    """How much of the rerun to do.

    Attributes
    ----------
    starts
        Start nodes to try (``None``: all 1..:data:`NODES`).
    exact_seconds
        Time limit of each exact path solve.
    tour_seconds
        Time limit of the exact tour solve of Fig. 7.
    tour_maps
        Maps on which Fig. 7 is rerun.
    """

    starts: tuple[int, ...] | None
    exact_seconds: float
    tour_seconds: float
    tour_maps: tuple[str, ...]


FULL = Settings(starts=None, exact_seconds=30.0, tour_seconds=60.0, tour_maps=("office", "rooms"))
QUICK = Settings(starts=(6, 20), exact_seconds=3.0, tour_seconds=3.0, tour_maps=("office",))

# The paper's own numbers (Section VI): Fig. 5(a)/(b) at start node 6 on the office map,
# Fig. 7(a)/(b) and the 4-NI figure in the text, same map and start.
PAPER = {
    "alg1_path": 569.0,
    "mst_path": 739.0,
    "alg2_tour": 1500.0,
    "knn_tour": 2440.0,
    "kni_tour": 2531.0,
    "alg1_robots": 9,
    "alg2_tours": 4,
}


# ------------------------------------------------------------------------ instances


def map_graph(case: MapCase, nodes: int = NODES) -> Instance:
    """The decomposition graph over ``nodes`` random positions of a map, numbered 1..nodes.

    The positions are the KPOIs that :func:`parcover.maps.instance_from_map` samples
    with ``case.seed`` (its random start is discarded); the graph is then built
    with position 1 as the start and every other as a KPOI (paper, Section VI,
    Fig. 4), and relabelled so that position ``j`` has id ``"j"``. The graph does not
    depend on which position is the start, so :func:`rooted` re-roots it.
    """
    image = MAP_DIR / case.image
    sampled = instance_from_map(image, case.metres_per_pixel, kpois=nodes, seed=case.seed)
    assert sampled.coordinates is not None
    points = [sampled.coordinates[k] for k in sampled.kpois]
    built = instance_from_map(image, case.metres_per_pixel, kpois=points[1:], start=points[0])
    assert built.coordinates is not None and built.edges is not None
    label = {"s": "1", **{str(i): str(i + 1) for i in range(1, nodes)}}

    def rename(v: str) -> str:
        return label.get(v, v)

    return Instance(
        "1",
        tuple(str(j) for j in range(2, nodes + 1)),
        coordinates={rename(v): xy for v, xy in built.coordinates.items()},
        edges=tuple((rename(u), rename(v), w) for u, v, w in built.edges),
        name=f"{case.name}-start1",
        map=built.map,
    )


def rooted(graph: Instance, start: int, name: str) -> Instance:
    """``graph`` with node ``start`` as the start and every other numbered node a KPOI."""
    nodes = sorted((graph.start, *graph.kpois), key=int)
    return graph.replace(
        start=str(start), kpois=tuple(v for v in nodes if v != str(start)), name=name, start_is_kpoi=False
    )


# ---------------------------------------------------------------------- measuring


def path_row(
    instance: Instance, case: str, start: int, exact_seconds: float
) -> tuple[dict[str, Any], dict[str, Result]]:
    """One start node of Fig. 6: every method's path answer, and the results drawn later.

    Returns
    -------
    row
        ``c_max``; Algorithm 1's makespan and robots; the MST branches' makespan and
        robots; ``nn`` with Algorithm 1's robots; ``exact`` with Algorithm 1's
        robots (status, bound); the exact fewest robots at ``c_max`` (status,
        bound); the robots of ``nn`` and ``mst`` at the deadline ``c_max``; seconds
        of the two exact solves.
    results
        ``paper`` and ``mst`` results (for the Fig. 5 drawing).
    """
    paper = parcover.solve(instance, method="paper")
    k = paper.robots
    mst = parcover.solve(instance, method="mst", robots=instance.n)  # every leaf its own robot
    nn = parcover.solve(instance, method="nn", robots=k)
    exact_k = parcover.solve(instance, method="exact", robots=k, time_limit=exact_seconds)
    fewest = parcover.solve(instance, method="exact", time_limit=exact_seconds)
    nn_cmax = parcover.solve(instance, method="nn")
    mst_cmax = parcover.solve(instance, method="mst")
    row = {
        "map": case,
        "start": start,
        "kpois": instance.n,
        "c_max": instance.c_max,
        "paper_makespan": paper.makespan,
        "paper_robots": k,
        "mst_makespan": mst.makespan,
        "mst_robots": mst.robots,
        "nn_makespan": nn.makespan,
        "nn_robots": nn.robots,
        "exact_makespan": exact_k.makespan,
        "exact_robots_used": exact_k.robots,
        "exact_status": exact_k.status.value,
        "exact_bound": exact_k.bound,
        "exact_seconds": exact_k.seconds,
        "fewest_robots": fewest.robots,
        "fewest_status": fewest.status.value,
        "fewest_bound": fewest.bound,
        "fewest_seconds": fewest.seconds,
        "nn_cmax_robots": nn_cmax.robots,
        "mst_cmax_robots": mst_cmax.robots,
    }
    return row, {"paper": paper, "mst": mst}


def tour_rows(
    instance: Instance, case: str, start: int, tour_seconds: float
) -> tuple[list[dict[str, Any]], list[Result]]:
    """Fig. 7 at one start: Algorithm 2, kNN, kNI and the exact optimum with ``k`` robots.

    ``k`` is the number of Algorithm 2's tours (the paper's 4 in "4-NN", "4-NI" is
    Algorithm 2's count on its instance). When ``k != 4``, kNN and kNI with 4 robots
    are added, for the literal reading.
    """
    paper = parcover.solve(instance, routes="tours", method="paper")
    k = paper.robots
    results = [
        paper,
        parcover.solve(instance, routes="tours", method="knn", robots=k),
        parcover.solve(instance, routes="tours", method="kni", robots=k),
        parcover.solve(instance, routes="tours", method="exact", robots=k, time_limit=tour_seconds),
    ]
    if k != PAPER["alg2_tours"]:
        results += [
            parcover.solve(instance, routes="tours", method=m, robots=PAPER["alg2_tours"]) for m in ("knn", "kni")
        ]
    rows = [
        {
            "map": case,
            "start": start,
            "method": r.method,
            "robots_limit": r.robots_limit,
            "robots": r.robots,
            "makespan": r.makespan,
            "status": r.status.value,
            "bound": r.bound,
            "vs_alg2": r.makespan / paper.makespan,
            "seconds": r.seconds,
        }
        for r in results
    ]
    return rows, results[:4]


# ------------------------------------------------------------------------ drawing


def _plot_fig6(paths: pd.DataFrame, path: Path) -> None:
    """Fig. 6 style: makespan (top) and robots (bottom) over the start node, per map."""
    maps = list(dict.fromkeys(paths["map"]))
    fig, axes = plt.subplots(2, len(maps), figsize=(6.5 * len(maps), 7.5), squeeze=False)
    for col, name in enumerate(maps):
        rows = paths[paths["map"] == name].sort_values("start")
        x = rows["start"].to_numpy()
        top, bottom = axes[0][col], axes[1][col]
        top.plot(x, rows["mst_makespan"], "s-", color="tab:green", label="MST branches (own robots)")
        top.plot(x, rows["nn_makespan"], "^-", color="tab:red", label="NN (Alg. 1's robots)")
        top.plot(x, rows["paper_makespan"], "o-", color="tab:blue", label="Algorithm 1 (= c_max)")
        _exact_series(top, x, rows["exact_makespan"], rows["exact_status"], rows["exact_bound"],
                      "exact (Alg. 1's robots)")
        top.set_ylabel("path makespan (m)")
        top.set_title(f"{name}: Fig. 6(a), path makespan by start node", fontsize=10)
        bottom.plot(x, rows["mst_robots"], "s:", color="tab:green", alpha=0.6, label="MST leaves (as in top)")
        bottom.plot(x, rows["nn_cmax_robots"], "^-", color="tab:red", label="NN at c_max")
        bottom.plot(x, rows["paper_robots"], "o-", color="tab:blue", label="Algorithm 1 at c_max")
        _exact_series(bottom, x, rows["fewest_robots"], rows["fewest_status"], rows["fewest_bound"],
                      "exact fewest at c_max")
        bottom.set_ylabel("robots")
        bottom.set_xlabel("start node")
        bottom.set_title(f"{name}: Fig. 6(b), robots by start node", fontsize=10)
        for ax in (top, bottom):
            ax.set_xticks(x)
            ax.grid(alpha=0.3)
            ax.legend(fontsize=7, framealpha=0.6)
        bottom.yaxis.get_major_locator().set_params(integer=True)
    save_figure(fig, path, dpi=110)


def _exact_series(
    ax: Any, x: np.ndarray, values: pd.Series, status: pd.Series, bound: pd.Series, label: str
) -> None:
    """Exact answers: filled when proven optimal, hollow with a bar down to the bound otherwise."""
    proven = (status == "optimal").to_numpy()
    v = values.to_numpy(dtype=float)
    ax.plot(x, v, "-", color="black", lw=0.8)
    ax.scatter(x[proven], v[proven], marker="D", color="black", zorder=3, label=f"{label}, optimal")
    if (~proven).any():
        b = bound.to_numpy(dtype=float)
        ax.scatter(x[~proven], v[~proven], marker="D", facecolor="none", edgecolor="black", zorder=3,
                   label=f"{label}, not proven")
        ax.vlines(x[~proven], b[~proven], v[~proven], color="tab:orange", lw=2, label="proven bound")


# ------------------------------------------------------------------------ report


def _value(value: float, status: str, bound: float | None, fmt: str) -> str:
    """``value`` with ``(>= bound)`` when not proven optimal."""
    text = format(value, fmt)
    return text if status == "optimal" else f"{text} (≥ {format(bound, fmt)})"


def _paths_table(paths: pd.DataFrame) -> pd.DataFrame:
    return pd.DataFrame(
        {
            "start": paths["start"],
            "c_max": paths["c_max"].map(lambda v: f"{v:.2f}"),
            "Alg. 1": paths["paper_makespan"].map(lambda v: f"{v:.2f}"),
            "MST (robots)": [f"{m:.2f} ({r})" for m, r in zip(paths["mst_makespan"], paths["mst_robots"])],
            "NN": paths["nn_makespan"].map(lambda v: f"{v:.2f}"),
            "exact": [_value(v, s, b, ".2f") for v, s, b in
                      zip(paths["exact_makespan"], paths["exact_status"], paths["exact_bound"])],
            "MST / Alg. 1": (paths["mst_makespan"] / paths["paper_makespan"]).map(lambda v: f"{v:.3f}"),
            "NN / Alg. 1": (paths["nn_makespan"] / paths["paper_makespan"]).map(lambda v: f"{v:.3f}"),
            "robots Alg. 1": paths["paper_robots"],
            "robots exact": [_value(v, s, b, ".0f") for v, s, b in
                             zip(paths["fewest_robots"], paths["fewest_status"], paths["fewest_bound"])],
            "robots NN": paths["nn_cmax_robots"],
            "robots MST": paths["mst_cmax_robots"],
            "exact s": [f"{a:.1f} + {b:.1f}" for a, b in zip(paths["exact_seconds"], paths["fewest_seconds"])],
        }
    )


def _tours_table(tours: pd.DataFrame) -> pd.DataFrame:
    return pd.DataFrame(
        {
            "method": tours["method"],
            "robot limit": tours["robots_limit"].map(lambda v: "-" if pd.isna(v) else str(int(v))),
            "robots": tours["robots"],
            "tour makespan (m)": [_value(v, s, b, ".2f") if m == "exact" else f"{v:.2f}" for m, v, s, b in
                                  zip(tours["method"], tours["makespan"], tours["status"], tours["bound"])],
            "/ Alg. 2": tours["vs_alg2"].map(lambda v: f"{v:.3f}"),
        }
    )


def _summary(paths: pd.DataFrame) -> pd.DataFrame:
    """Per map: mean and range of the ratios to Algorithm 1, and robot counts compared."""
    out = []
    for name, rows in paths.groupby("map", sort=False):
        mst = rows["mst_makespan"] / rows["paper_makespan"]
        nn = rows["nn_makespan"] / rows["paper_makespan"]
        proven = rows["fewest_status"] == "optimal"
        extra = rows["paper_robots"] - rows["fewest_robots"]
        out.append(
            {
                "map": name,
                "starts": len(rows),
                "MST / Alg. 1 mean": mst.mean(),
                "MST / Alg. 1 range": f"{mst.min():.3f}-{mst.max():.3f}",
                "NN / Alg. 1 mean": nn.mean(),
                "NN / Alg. 1 range": f"{nn.min():.3f}-{nn.max():.3f}",
                "exact = Alg. 1 makespan": int((np.isclose(rows["exact_makespan"], rows["paper_makespan"])).sum()),
                "fewest robots proven": int(proven.sum()),
                "Alg. 1 robots / exact mean": (rows["paper_robots"] / rows["fewest_robots"]).mean(),
                "Alg. 1 uses more robots": int((extra > 0).sum()),
                "max extra robots": int(extra.max()),
                "NN at c_max uses fewer robots than Alg. 1": int((rows["nn_cmax_robots"] < rows["paper_robots"]).sum()),
                "MST leaves / Alg. 1 robots mean": (rows["mst_robots"] / rows["paper_robots"]).mean(),
            }
        )
    return pd.DataFrame(out)


def _ratio_lines(paths: pd.DataFrame, tours: pd.DataFrame) -> list[str]:
    """Our ratios beside the paper's (its KPOIs are unpublished: only ratios compare)."""
    lines = ["| ratio | paper (its own instance) | this rerun |", "|---|---|---|"]
    office6 = paths[(paths["map"] == "office") & (paths["start"] == 6)]
    mst6 = "-" if office6.empty else f"{float(office6['mst_makespan'].iloc[0] / office6['paper_makespan'].iloc[0]):.3f}"
    robots6 = "-" if office6.empty else str(int(office6["paper_robots"].iloc[0]))
    mean = paths.groupby("map", sort=False).apply(lambda r: (r["mst_makespan"] / r["paper_makespan"]).mean())
    means = ", ".join(f"{m} {v:.3f}" for m, v in mean.items())
    mst, alg1 = PAPER["mst_path"], PAPER["alg1_path"]
    lines += [
        f"| MST / Alg. 1 path makespan, office, start 6 (Fig. 5) | {mst:.0f} / {alg1:.0f} = {mst / alg1:.3f} | {mst6} |",
        f"| MST / Alg. 1 path makespan, mean over starts (Fig. 6(a)) | not printed | {means} |",
        f"| Alg. 1 robots, office, start 6 | {PAPER['alg1_robots']} | {robots6} |",
    ]
    alg2_paper, tours_paper = PAPER["alg2_tour"], PAPER["alg2_tours"]
    for name, rows in tours.groupby("map", sort=False):
        alg2 = rows[rows["method"] == "paper"].iloc[0]
        k = int(alg2["robots"])
        for method, label in (("knn", "NN"), ("kni", "NI")):
            theirs = PAPER[f"{method}_tour"]
            ours = rows[(rows["method"] == method) & (rows["robots_limit"] == k)]["vs_alg2"].iloc[0]
            lines.append(
                f"| {k}-{label} / Alg. 2 tour makespan, {name}, start {alg2['start']} (Fig. 7) | "
                f"{theirs:.0f} / {alg2_paper:.0f} = {theirs / alg2_paper:.3f} ({tours_paper} tours) | "
                f"{ours:.3f} ({k} tours) |"
            )
        exact = rows[rows["method"] == "exact"].iloc[0]
        note = "" if exact["status"] == "optimal" else f" (not proven; bound {exact['bound'] / alg2['makespan']:.3f})"
        lines.append(
            f"| exact / Alg. 2 tour makespan, {k} robots, {name} | not measured | {exact['vs_alg2']:.3f}{note} |"
        )
    return lines


def _findings(paths: pd.DataFrame, tours: pd.DataFrame) -> list[str]:
    """What the rows say, in sentences built from the rows (nothing hard-coded)."""
    starts = len(paths)
    lowest = int((paths["paper_makespan"] <= paths[["mst_makespan", "nn_makespan"]].min(axis=1) * (1 + 1e-9)).sum())
    more = int((paths["paper_robots"] > paths["fewest_robots"]).sum())
    equal = int(np.isclose(paths["exact_makespan"], paths["paper_makespan"], rtol=1e-9).sum())
    nn_fewer = int((paths["nn_cmax_robots"] < paths["paper_robots"]).sum())
    lines = [
        f"- Fig. 6(a): Algorithm 1's makespan is the lowest of the three greedy methods at {lowest} of "
        f"{starts} (map, start) pairs, as in the paper. It is `c_max`, the least makespan with any "
        "number of robots (Prop. 1), so the exact optimum with Algorithm 1's robots equals it "
        f"({equal} of {starts} pairs): the exact series coincides with Algorithm 1, and the "
        "comparison is about the baselines.",
        f"- Fig. 6(b): where Algorithm 1 falls short is the robot count. At {more} of {starts} pairs the "
        "exact method found (verified) routes within `c_max` with fewer robots than Algorithm 1, up to "
        f"{int((paths['paper_robots'] - paths['fewest_robots']).max())} fewer; plain nearest neighbour "
        f"under the deadline `c_max` needs fewer robots than Algorithm 1 at {nn_fewer} of {starts} pairs.",
    ]
    if more:
        lines[-1] += " So Algorithm 1's count is not \"the optimal number of robots\" the paper claims for it."
    for (name, start), rows in tours.groupby(["map", "start"], sort=False):
        alg2 = rows[rows["method"] == "paper"].iloc[0]
        k = int(alg2["robots"])
        same = rows[rows["robots_limit"] == k].set_index("method")
        exact = same.loc["exact"]
        proof = "proven optimal" if exact["status"] == "optimal" else "not proven optimal"
        lines.append(
            f"- Fig. 7, {name}, start {start}: Algorithm 2's {k} tours beat {k}-NN and {k}-NI "
            f"(ratios {same.loc['knn', 'vs_alg2']:.3f} and {same.loc['kni', 'vs_alg2']:.3f}), as in the paper; "
            f"but {k} robots can do {100 * (1 - exact['vs_alg2']):.1f}% better than Algorithm 2 "
            f"(exact, {proof})."
            if min(same.loc["knn", "vs_alg2"], same.loc["kni", "vs_alg2"]) > 1 else
            f"- Fig. 7, {name}, start {start}: {k}-NN / Algorithm 2 = {same.loc['knn', 'vs_alg2']:.3f}, "
            f"{k}-NI / Algorithm 2 = {same.loc['kni', 'vs_alg2']:.3f}; exact / Algorithm 2 = "
            f"{exact['vs_alg2']:.3f} ({proof})."
        )
    return lines


def run(config: Config, settings: Settings | None = None) -> Section:
    """Rerun Section VI; figures, CSVs and instance files go to ``config.figures``.

    ``settings`` defaults to :data:`QUICK` when ``config.quick``, else :data:`FULL`.
    """
    settings = settings or (QUICK if config.quick else FULL)
    began = time.perf_counter()
    path_rows: list[dict[str, Any]] = []
    tour_records: list[dict[str, Any]] = []
    drawings: list[str] = []
    for case in MAPS:
        graph = map_graph(case)
        starts = settings.starts or tuple(range(1, NODES + 1))
        for start in starts:
            instance = rooted(graph, start, f"{case.name}-start{start}")
            write_instance(instance, config.figures / f"{instance.name}.json")
            config.log(f"[section6] {instance.name}: paths ...")
            row, results = path_row(instance, case.name, start, settings.exact_seconds)
            path_rows.append(row)
            if start == case.tour_start:
                file, link = config.figure(f"fig5_{instance.name}.png")
                plot_side_by_side(instance, [results["paper"], results["mst"]], file,
                                  titles=["Fig. 5(a) style: Algorithm 1 paths", "Fig. 5(b) style: MST branches"])
                drawings.append(f"![Fig. 5 style, {instance.name}]({link})")
        if case.name in settings.tour_maps:
            instance = rooted(graph, case.tour_start, f"{case.name}-start{case.tour_start}")
            config.log(f"[section6] {instance.name}: tours ...")
            rows, results = tour_rows(instance, case.name, case.tour_start, settings.tour_seconds)
            tour_records += rows
            k = results[0].robots
            titles = ["Algorithm 2 tours", f"{k}-NN tours", f"{k}-NI tours", f"exact, {k} robots"]
            for part, pair in (("ab", slice(0, 2)), ("cd", slice(2, 4))):
                file, link = config.figure(f"fig7{part}_{instance.name}.png")
                plot_side_by_side(instance, results[pair], file, titles=titles[pair])
                drawings.append(f"![Fig. 7 style ({part}), {instance.name}]({link})")
    paths, tours = pd.DataFrame(path_rows), pd.DataFrame(tour_records)
    fig6_file, fig6_link = config.figure("fig6.png")
    _plot_fig6(paths, fig6_file)
    seconds = time.perf_counter() - began
    markdown = _markdown(paths, tours, settings, fig6_link, drawings, seconds)
    return Section(title="Section VI rerun", markdown=markdown, tables={"paths": paths, "tours": tours},
                   targets=[])


def _markdown(paths: pd.DataFrame, tours: pd.DataFrame, settings: Settings, fig6: str,
              drawings: list[str], seconds: float) -> str:
    maps = ", ".join(
        f"`{c.image}` ({c.name}, {c.metres_per_pixel} m/px, seed {c.seed})" for c in MAPS
    )
    parts = [
        f"Maps: {maps}; {NODES} random positions each, numbered 1..{NODES} as in the paper; "
        "the paper's graph (vertical cell decomposition, virtual nodes on the cell boundaries, "
        "Euclidean weights in metres). Costs are in metres.",
        "",
        f"Time limits: {settings.exact_seconds:g} s for each exact path solve (two per start), "
        f"{settings.tour_seconds:g} s for each exact tour solve. The whole run took {seconds:.0f} s. "
        "On a busier machine a few more solves may stop at their limit: the values stay, "
        "only their `(≥ bound)` marks change.",
        "",
        "**The paper's KPOIs are not published**, nor the scale of its maps (its costs look like "
        "pixels); so only ratios between methods compare with the paper's numbers, never the costs.",
        "",
        "### Decisions",
        "",
        "- *Start node.* The paper numbers its 20 random positions and \"the start node can be chosen "
        "as any node\" (Fig. 5: nodes 6 and 20; Fig. 6: start node on the x-axis). So each position "
        "in turn is the start and the other 19 are the KPOIs, on one graph per map. The instance "
        "file of every (map, start) is in the figures folder (`<map>-start<j>.json`): "
        "`parcover solve reports/section6/office-start6.json --method paper` reruns one.",
        "- *Fig. 6(a).* Algorithm 1 (`paper`) at `c_max`; the MST as the paper draws it in Fig. 5(b): "
        "one robot per leaf of the tree rooted at the start (`mst` with a robot limit of n, so it is "
        "never cut), its makespan the longest branch; NN with as many robots as Algorithm 1 "
        "(`nn --robots k`: the paper does not say how many robots its NN had); the exact optimum "
        "with as many robots as Algorithm 1 (`exact --robots k`).",
        "- *Fig. 6(b).* Algorithm 1's robots against the exact fewest robots at the deadline `c_max` "
        "(`exact`, no robot limit). For context: `nn` and `mst` adapted to the deadline `c_max` "
        "(NN starts a new robot when the next move would break it; MST branches cut to meet it).",
        "- *Fig. 7.* Algorithm 2 (`paper --routes tours`, no deadline: the published algorithm, "
        "pairing Algorithm 1's paths) against kNN and kNI with k = Algorithm 2's number of tours "
        "(in the paper 4, Algorithm 2's count there), and the exact least tour makespan with k robots. "
        "The start is node 6 on the office map (as the paper) and node 20 on the rooms map. When "
        "k is not 4, 4-NN and 4-NI are listed too.",
        "",
        "### Comparison with the paper's numbers",
        "",
        *_ratio_lines(paths, tours),
        "",
        "### Summary over the starts",
        "",
        markdown_table(_summary(paths)),
        "",
        *_findings(paths, tours),
        "",
        f"![Fig. 6 style: makespan and robots by start node]({fig6})",
        "",
        "### Paths, every start (Fig. 6)",
        "",
        "`exact` is the least makespan with Algorithm 1's robots; `robots exact` the fewest robots "
        "at `c_max`; a value with `(≥ b)` was not proven optimal within the time limit and `b` is "
        "the proven bound. `robots NN` / `robots MST`: the baselines adapted to the deadline `c_max`. "
        "`exact s`: seconds of the two exact solves.",
        "",
    ]
    for name, rows in paths.groupby("map", sort=False):
        parts += [f"**{name}**", "", markdown_table(_paths_table(rows)), ""]
    if not tours.empty:
        parts += ["### Tours at one start (Fig. 7)", ""]
        for (name, start), rows in tours.groupby(["map", "start"], sort=False):
            parts += [f"**{name}, start {start}**", "", markdown_table(_tours_table(rows)), ""]
    parts += ["### Drawings (Figs. 5 and 7 style)", "", *[f"{d}\n" for d in drawings]]
    return "\n".join(parts)


def _render(section: Section, command: str, settings: Settings) -> str:
    """The report: title, command, machine, then the section's body."""
    from parcover.report import machine_info

    machine = machine_info()
    return "\n".join(
        [
            "# The paper's Section VI, rerun with exact optima",
            "",
            "Regenerate with (from the repository root):",
            "",
            f"    {command}",
            "",
            f"- machine: {machine['cpu']}, {machine['cores']} cores (shared), {machine['memory_gb']} GB, "
            f"{machine['platform']}, Python {machine['python']}",
            f"- exact time limits: {settings.exact_seconds:g} s per path solve, {settings.tour_seconds:g} s "
            "per tour solve (HiGHS); a run stopped by its limit is reported with its proven bound",
            f"- written {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}",
            "",
            section.markdown.strip(),
            "",
        ]
    )


def main(argv: list[str] | None = None) -> int:
    """Parse the arguments, rerun Section VI, write the report; exit status 0."""
    parser = argparse.ArgumentParser(prog="python -m benchmarks.section6", description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="2 starts per map, short limits (under a minute)")
    parser.add_argument("--out", type=Path, help="report file (default: reports/section6[-quick].md)")
    args = parser.parse_args(argv)
    out = args.out or Path("reports") / ("section6-quick.md" if args.quick else "section6.md")
    figures = out.with_suffix("")
    figures.mkdir(parents=True, exist_ok=True)
    config = Config(quick=args.quick, figures=figures, figures_link=figures.name)
    settings = QUICK if args.quick else FULL
    compile_pricing(config)
    section = run(config, settings)
    for table, frame in section.tables.items():
        frame.to_csv(figures / f"{table}.csv", index=False)
    words = sys.argv[1:] if argv is None else argv
    command = " ".join(["python -m benchmarks.section6", *(shlex.quote(w) for w in words)])
    out.write_text(_render(section, command, settings), encoding="utf-8")
    config.log(f"[section6] wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
