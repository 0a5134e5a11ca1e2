"""Building scale re-measured on what the grid's design never saw: fresh seeds and maps.

The questions of :mod:`benchmarks.building_scale` (the fewest robots within the least
makespan and within 1.2 x it, paths and tours, 100 KPOIs, 120 s a cell, ``parcover``'s
default ``exact``) on uniform and clustered instances of seed 21 and on two Stage floor
plans the grid does not use (:data:`benchmarks.building_scale.UNSEEN_MAPS`: ``autolab.png``
and ``SRI-AIC-kwing.png``), seed 21. Quick: 20 KPOIs, ``autolab`` only, 5 s.
"""

from __future__ import annotations

import pandas as pd

from benchmarks.building_scale import LIMIT, N, QUESTIONS, UNSEEN_MAPS, cells_section, robots_rows
from benchmarks.common import Config, Section

SEED = 21
KINDS = ("uniform", "clustered", *(name for name, _, _ in UNSEEN_MAPS))
QUICK = {"n": 20, "limit": 5.0, "kinds": ("autolab",)}


def run(config: Config) -> Section:
    """Every question on every unseen instance; table and target lines."""
    n, limit, kinds = (QUICK["n"], QUICK["limit"], QUICK["kinds"]) if config.quick else (N, LIMIT, KINDS)
    frame = pd.DataFrame(robots_rows(config, [(kind, SEED) for kind in kinds], n, limit))
    maps = ", ".join(f"`{image}`" for _, image, _ in UNSEEN_MAPS)
    intro = (
        f"The building-scale questions ({len(QUESTIONS)} per instance: the fewest robots within "
        f"the least makespan and within 1.2 x it, paths and tours), {n} KPOIs, {limit:g} s a cell, "
        f"on instances never used while designing: uniform and clustered of seed {SEED}, and the "
        f"Stage floor plans {maps} (visibility graphs, KPOIs drawn with seed {SEED}).")
    return cells_section("Building scale, unseen instances", "building_scale_unseen", intro, frame)
