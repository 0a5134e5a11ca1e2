"""Maps speed: building instances from Stage floor-plan bitmaps, against a target time.

For ``hospital_section.png`` at Stage's ``everything.world`` scale (40 m x 18 m: 0.0368 x
0.0406 m/px) with 50 KPOIs (20 in the quick run), and in the full run also ``cave.png``
(0.032 m/px), the instance is built with both graph methods of :mod:`parcover.maps`
(tracing, sampling, graph and the instance's shortest paths included): the time, the graph
size, and how much longer the decomposition's distances are than the visibility graph's
(:func:`parcover.maps.distance_ratio`). The target is a few seconds per build with 50 KPOIs.
"""

from __future__ import annotations

import time
from pathlib import Path

import pandas as pd

from benchmarks.common import ROOT, Config, Section, markdown_table
from parcover.maps import distance_ratio, instance_from_map

MAPS = ROOT / "instances" / "maps"
TARGET = ("hospital_section.png", (0.0368, 0.0406))
EXTRA = (("cave.png", 0.032),)
GRAPHS = ("decomposition", "visibility")
KPOIS, QUICK_KPOIS = 50, 20
TARGET_SECONDS = 5.0  # "a few seconds"


def measure_map(image: Path, scale: float | tuple[float, float], kpois: int) -> list[dict[str, object]]:
    """One row per graph method: build time, graph size, and the distance ratio (decomposition row)."""
    rows: list[dict[str, object]] = []
    built = {}
    for graph in GRAPHS:
        started = time.perf_counter()
        instance = instance_from_map(image, scale, kpois=kpois, seed=0, graph=graph)
        seconds = time.perf_counter() - started
        built[graph] = instance
        rows.append({"map": image.name, "kpois": kpois, "graph": graph, "seconds": seconds,
                     "nodes": len(instance.nodes), "edges": len(instance.edges)})
    ratio = distance_ratio(built["decomposition"], built["visibility"])
    for row in rows:
        for key in ("median", "mean", "p95", "max"):
            row[f"ratio_{key}"] = ratio[key] if row["graph"] == "decomposition" else 1.0
    return rows


def target_line(frame: pd.DataFrame) -> str:
    """The target (a few seconds per build with 50 KPOIs) and the figure reached."""
    rows = frame[frame["map"] == TARGET[0]]
    kpois = int(rows["kpois"].iloc[0])
    times = ", ".join(f"{r.graph} {r.seconds:.2f} s" for r in rows.itertuples())
    head = f"hospital_section.png with {KPOIS} KPOIs built in a few seconds (< {TARGET_SECONDS:g} s)"
    if kpois != KPOIS:
        return f"{head}: not measured (quick run: {kpois} KPOIs — {times})"
    verdict = "met" if (rows["seconds"] < TARGET_SECONDS).all() else "not met"
    return f"{head}: {verdict} — {times}"


def run(config: Config) -> Section:
    """The section: build each map with each graph method, tabulate."""
    kpois = QUICK_KPOIS if config.quick else KPOIS
    cases = [TARGET] if config.quick else [TARGET, *EXTRA]
    rows = []
    for image, scale in cases:
        rows += measure_map(MAPS / image, scale, kpois)
        config.log(f"[maps_speed] {image} done")
    frame = pd.DataFrame(rows)
    shown = frame[["map", "kpois", "graph", "seconds", "nodes", "edges", "ratio_median", "ratio_p95", "ratio_max"]]
    markdown = "\n\n".join([
        f"Instances built from Stage bitmaps ({kpois} KPOIs, seed 0), with the paper's trapezoidal "
        "decomposition and with a visibility graph (true shortest paths); the time covers tracing, sampling, "
        "the graph and the instance's shortest paths. `ratio_*`: decomposition distance / visibility distance "
        "over all pairs of key nodes (1 = as short as the true shortest path).",
        markdown_table(shown),
    ])
    return Section(title="Maps speed", markdown=markdown, tables={"maps_speed": frame},
                   targets=[target_line(frame)])
