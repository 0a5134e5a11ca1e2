"""Maps speed: building instances from Stage floor-plan bitmaps, every build against a target time.

Each Stage map of ``instances/maps`` at its scale there (Stage's world files where one
uses it: the office floor ``hospital_section.png``, the full ``hospital.png`` (140 m x 60 m), the
``autolab.png`` lab, ``cave.png``, ``sal2.png`` whose rooms have no doors; our choice for
``simple_rooms.png`` and the SLAM grid ``SRI-AIC-kwing.png``) with 50 and 100 KPOIs
(``hospital_section.png`` with 20 in the quick run) is built with both graph methods of
:mod:`parcover.maps` (tracing, sampling, graph and the instance's shortest paths
included): the time, the graph size, and how much longer the decomposition's distances
are than the visibility graph's (:func:`parcover.maps.distance_ratio`). The target is every
build within 5 s.
"""

from __future__ import annotations

import time
from pathlib import Path

import pandas as pd

from benchmarks.common import ROOT, Config, Section, markdown_table
from parcover.maps import distance_ratio, instance_from_map

MAPS = ROOT / "instances" / "maps"
# (bitmap, metres per pixel), the scales of instances/maps/README.md
FULL = (
    ("hospital_section.png", (0.0368, 0.0406)),
    ("hospital.png", (0.0449, 0.0505)),
    ("autolab.png", (0.0247, 0.0290)),
    ("cave.png", 0.032),
    ("simple_rooms.png", 0.05),
    ("sal2.png", 0.03),
    ("SRI-AIC-kwing.png", 0.1),
)
QUICK = FULL[:1]
GRAPHS = ("decomposition", "visibility")
KPOIS, QUICK_KPOIS = (50, 100), (20,)
TARGET_SECONDS = 5.0


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
    """The target (every map, both graphs, 50 and 100 KPOIs, each build within 5 s) and the figure reached."""
    kpois = " and ".join(str(k) for k in KPOIS)
    head = f"every Stage map, both graphs, {kpois} KPOIs: each build within {TARGET_SECONDS:g} s"
    slowest = frame.loc[frame["seconds"].idxmax()]
    worst = f"slowest {slowest['map']} {slowest['graph']} {slowest['kpois']} KPOIs {slowest['seconds']:.2f} s"
    if tuple(sorted(frame["kpois"].unique())) != KPOIS or set(frame["map"]) != {image for image, _ in FULL}:
        shown = " and ".join(str(k) for k in sorted(frame["kpois"].unique()))
        return f"{head}: not measured (quick run: {shown} KPOIs on {', '.join(frame['map'].unique())}; {worst})"
    over = frame[frame["seconds"] >= TARGET_SECONDS]
    verdict = "met" if over.empty else "not met"
    return f"{head}: {verdict} — {len(frame) - len(over)} of {len(frame)} builds within it; {worst}"


def run(config: Config) -> Section:
    """The section: build each map with each graph method and number of KPOIs, tabulate."""
    cases, sizes = (QUICK, QUICK_KPOIS) if config.quick else (FULL, KPOIS)
    rows = []
    for image, scale in cases:
        for kpois in sizes:
            rows += measure_map(MAPS / image, scale, kpois)
        config.log(f"[maps_speed] {image} done")
    frame = pd.DataFrame(rows)
    shown = frame[["map", "kpois", "graph", "seconds", "nodes", "edges", "ratio_median", "ratio_p95", "ratio_max"]]
    sizes_text = " and ".join(str(k) for k in sizes)
    markdown = "\n\n".join([
        f"Instances built from Stage bitmaps ({sizes_text} KPOIs, seed 0; scales as in `instances/maps/README.md`), "
        "with the paper's vertical cell decomposition and with a visibility graph (true shortest paths); the time "
        "covers reading and tracing the bitmap, sampling, the graph and the instance's shortest paths. `ratio_*`: "
        "decomposition distance / visibility distance over all pairs of key nodes (1 = as short as the true "
        "shortest path).",
        markdown_table(shown),
    ])
    return Section(title="Maps speed", markdown=markdown, tables={"maps_speed": frame},
                   targets=[target_line(frame)])
