"""Building scale: the paper's questions at 100 KPOIs on uniform, clustered and map instances.

The fewest robots within the least possible makespan (``c_max`` for paths, ``2 c_max``
for tours) and within 1.2 x it, on 100 KPOIs: uniform random points, clustered ones
(Gaussian rooms: ``parcover generate random --layout clustered``, three centres) and
maps (visibility graphs of Stage floor plans in ``instances/maps/``: ``hospital.png``
and ``sal2.png``), seeds 1-3, solved by ``parcover``'s default ``exact``
(branch-and-price at this size, warm start from ``best`` counted) within 120 s each.
Target: every cell proven. The least makespan at 50-75 KPOIs is
:mod:`benchmarks.building_scale_makespan`. Quick: 20 KPOIs, seed 1, 5 s.
"""

from __future__ import annotations

import time
from pathlib import Path

import pandas as pd

from benchmarks.common import ROOT, Config, Section, markdown_table
from benchmarks.exact_scaling import _cells_target, solve_cell
from milp.core.routes import least_makespan
from parcover import Instance

#: Map instances: (name, bitmap in instances/maps, metres per pixel: instances/maps/README.md).
MAPS = (("hospital", "hospital.png", (0.0449, 0.0505)), ("sal2", "sal2.png", 0.03))
#: Maps the grid does not use (:mod:`benchmarks.building_scale_unseen`).
UNSEEN_MAPS = (("autolab", "autolab.png", (0.0247, 0.0290)), ("kwing", "SRI-AIC-kwing.png", 0.1))
KINDS = ("uniform", "clustered", *(name for name, _, _ in MAPS))
SEEDS = (1, 2, 3)
N, LIMIT = 100, 120.0
#: (routes, deadline factor over the least makespan).
QUESTIONS = (("paths", 1.0), ("tours", 1.0), ("paths", 1.2), ("tours", 1.2))
QUICK = {"n": 20, "seeds": (1,), "limit": 5.0, "kinds": ("clustered", "sal2")}


def instance(kind: str, n: int, seed: int) -> Instance:
    """The ``kind`` instance (``uniform``, ``clustered`` or a map of :data:`MAPS` or
    :data:`UNSEEN_MAPS`) of ``n`` KPOIs."""
    from parcover.generate import random_points
    from parcover.maps import instance_from_map

    if kind in ("uniform", "clustered"):
        return random_points(n, seed, layout=kind)
    image, scale = {name: (image, scale) for name, image, scale in MAPS + UNSEEN_MAPS}[kind]
    return instance_from_map(Path(ROOT) / "instances" / "maps" / image, scale, kpois=n, seed=seed,
                             graph="visibility")


def run(config: Config) -> Section:
    """Every fewest-robots cell; table and targets."""
    quick = config.quick
    n = QUICK["n"] if quick else N
    seeds = QUICK["seeds"] if quick else SEEDS
    limit = QUICK["limit"] if quick else LIMIT
    kinds = QUICK["kinds"] if quick else KINDS
    frame = pd.DataFrame(robots_rows(config, [(kind, seed) for kind in kinds for seed in seeds], n, limit))
    intro = (
        f"The paper's question at building scale: the fewest robots within the least possible "
        f"makespan (`c_max` for paths, `2 c_max` for tours) and within 1.2 x it, {n} KPOIs, "
        f"seeds {', '.join(map(str, seeds))}, {limit:g} s a cell, `parcover solve`'s default `exact` "
        "(branch-and-price here; the warm start from `best` counted in its seconds). Instances: "
        "`uniform` and `clustered` from `parcover generate random` (the clustered ones draw "
        "KPOIs around three centres: rooms), and visibility-graph maps of Stage floor plans "
        f"({', '.join(f'`{image}`' for _, image, _ in MAPS)}; `parcover generate map --graph "
        "visibility`, KPOIs drawn with the seed). A cell left unproven shows its robots and the "
        "certified bound.")
    return cells_section("Building scale", "building_scale", intro, frame)


def cells_section(title: str, table: str, intro: str, frame: pd.DataFrame) -> Section:
    """A section of building-scale cells: ``intro``, a target line per question and kind
    (:func:`target_lines`), and the results (:func:`results_table`), ``frame`` kept as
    ``table``."""
    lines = target_lines(frame)
    markdown = "\n\n".join([intro, "### Targets", "\n".join(f"- {line}" for line in lines),
                             "### Results", markdown_table(results_table(frame))])
    return Section(title, markdown, tables={table: frame}, targets=lines)


def robots_rows(config: Config, cells: list[tuple[str, int]], n: int, limit: float) -> list[dict]:
    """Every question of :data:`QUESTIONS` on each ``(kind, seed)`` instance of ``n`` KPOIs."""
    rows = []
    for number, (kind, seed) in enumerate(cells, 1):
        began = time.perf_counter()
        inst = instance(kind, n, seed)
        config.log(f"[building_scale] {number}/{len(cells)} {kind} seed {seed}: built in "
                   f"{time.perf_counter() - began:.1f} s")
        for routes, factor in QUESTIONS:
            tours = routes == "tours"
            deadline = factor * least_makespan(inst.distances, tours=tours)
            question = f"robots U={factor:g} x least"
            config.log(f"[building_scale] {kind} seed {seed} {routes} {question}")
            out = solve_cell(inst, "exact", tours=tours, k=None, deadline=deadline, limit=limit)
            rows.append({"part": "robots", "kind": kind, "n": n, "seed": seed, "routes": routes,
                         "question": question, "limit": limit, **out})
    return rows


def results_table(frame: pd.DataFrame) -> pd.DataFrame:
    """One row per cell: kind, n, seed, routes, question, our outcome."""
    out = []
    for row in frame.to_dict("records"):
        if row["status"] == "optimal":
            outcome = f"optimal {row['objective']:.6g} in {row['seconds']:.1f} s"
        elif row["objective"] is None or pd.isna(row["objective"]):
            outcome = str(row["status"])
        else:
            outcome = f"{row['status']} {row['objective']:.6g} (bound {row['bound']:.6g})"
        out.append({"kind": row["kind"], "n": row["n"], "seed": row["seed"], "routes": row["routes"],
                    "question": row["question"], "exact": outcome})
    return pd.DataFrame(out)


def target_lines(frame: pd.DataFrame) -> list[str]:
    """One line per part, question and kind: met when every cell is proven within its limit."""
    lines = []
    for (part, question, routes), cells in frame.groupby(["part", "question", "routes"], sort=False):
        for kind, of_kind in cells.groupby("kind", sort=False):
            n, limit = int(of_kind["n"].iloc[0]), float(of_kind["limit"].iloc[0])
            title = f"building scale, {question} {routes}, {kind}, n = {n}: proven within {limit:g} s"
            lines.append(_cells_target(of_kind, title, limit, lambda r: f"seed {r.seed}"))
    return lines
