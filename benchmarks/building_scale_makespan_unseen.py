"""Building scale, least makespan, re-measured on a seed the grid's design never saw.

The cells of :mod:`benchmarks.building_scale_makespan` (k = 5 at 75 KPOIs, 4 at 60, 3 at
50, paths and tours, uniform and clustered, 300 s a cell, ``parcover``'s default
``exact``) on seed :data:`benchmarks.building_scale_unseen.SEED` (21), which no design
choice of the makespan search was measured on. Quick: 12 KPOIs, k = 3, clustered, 5 s.
"""

from __future__ import annotations

import pandas as pd

from benchmarks.building_scale import cells_section
from benchmarks.building_scale_makespan import CELLS, KINDS, LIMIT, SEEDS, makespan_rows
from benchmarks.building_scale_unseen import SEED
from benchmarks.common import Config, Section

QUICK = {"cells": ((12, 3),), "kinds": ("clustered",), "limit": 5.0}


def run(config: Config) -> Section:
    """Every least-makespan cell on the unseen seed; table and target lines."""
    cells, kinds, limit = (QUICK["cells"], QUICK["kinds"], QUICK["limit"]) if config.quick else (CELLS, KINDS, LIMIT)
    frame = pd.DataFrame(makespan_rows(config, "building_scale_makespan_unseen", cells, kinds, (SEED,), limit))
    intro = (
        "The least-makespan cells of the section above ("
        + ", ".join(f"k = {k} at {n} KPOIs" for n, k in cells)
        + f", paths and tours, {' and '.join(kinds)}, {limit:g} s a cell) on seed {SEED}, which the grid "
        f"(seeds {', '.join(map(str, SEEDS))}) and the makespan search's design never used.")
    return cells_section("Building scale, least makespan, unseen seed", "building_scale_makespan_unseen",
                         intro, frame)
