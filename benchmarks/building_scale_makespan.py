"""Building scale, least makespan: a few long routes over 50-75 KPOIs.

The least makespan with k = 5 robots at 75 KPOIs, k = 4 at 60 and k = 3 at 50 (run in
that order), paths and tours, on uniform and clustered instances (``parcover generate random``, as
:mod:`benchmarks.building_scale`), seeds 1 and 2, solved by ``parcover``'s default ``exact``
(branch-and-price here, raced against branch-and-cut for few routes; the warm start from
``best`` counted) within 300 s each. Target: every cell proven. Quick: 12 KPOIs, k = 3,
uniform, seed 1, 5 s.
"""

from __future__ import annotations

import pandas as pd

from benchmarks.building_scale import cells_section, instance
from benchmarks.common import Config, Section
from benchmarks.exact_scaling import solve_cell

#: (n, k) cells, the kinds and seeds of each, and the seconds a cell.
CELLS, KINDS, SEEDS, LIMIT = ((75, 5), (60, 4), (50, 3)), ("uniform", "clustered"), (1, 2), 300.0
QUICK = {"cells": ((12, 3),), "kinds": ("uniform",), "seeds": (1,), "limit": 5.0}


def run(config: Config) -> Section:
    """Every least-makespan cell; table and target lines."""
    cells, kinds, seeds, limit = ((QUICK["cells"], QUICK["kinds"], QUICK["seeds"], QUICK["limit"])
                                  if config.quick else (CELLS, KINDS, SEEDS, LIMIT))
    frame = pd.DataFrame(makespan_rows(config, "building_scale_makespan", cells, kinds, seeds, limit))
    intro = (
        "The least makespan with a few long routes at building scale: "
        + ", ".join(f"k = {k} at {n} KPOIs" for n, k in cells)
        + f", paths and tours, {' and '.join(kinds)} instances (`parcover generate random`; the "
        f"clustered ones draw KPOIs around three centres), seeds {', '.join(map(str, seeds))}, "
        f"{limit:g} s a cell, `parcover solve`'s default `exact` (the warm start from `best` counted in "
        "its seconds). A cell left unproven shows its makespan and the certified bound.")
    return cells_section("Building scale, least makespan", "building_scale_makespan", intro, frame)


def makespan_rows(config: Config, section: str, cells: tuple[tuple[int, int], ...], kinds: tuple[str, ...],
                  seeds: tuple[int, ...], limit: float) -> list[dict]:
    """The least makespan of every ``(n, k)`` cell on each kind and seed, paths and tours,
    ``limit`` seconds each (progress logged under ``section``'s name)."""
    rows = []
    total = len(cells) * len(kinds) * len(seeds)
    number = 0
    for n, k in cells:
        for kind in kinds:
            for seed in seeds:
                number += 1
                inst = instance(kind, n, seed)
                for routes in ("paths", "tours"):
                    config.log(f"[{section}] {number}/{total} {kind} n={n} k={k} seed {seed} {routes}")
                    out = solve_cell(inst, "exact", tours=routes == "tours", k=k, deadline=None, limit=limit)
                    rows.append({"part": "makespan", "kind": kind, "n": n, "seed": seed, "routes": routes,
                                 "question": f"makespan k={k}", "limit": limit, **out})
    return rows
