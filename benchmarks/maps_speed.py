"""Time building instances from Stage bitmaps (a script, not a test).

Run: ``python benchmarks/maps_speed.py [KPOIS]``. For ``hospital_section.png`` at
Stage's ``everything.world`` scale (40 m x 18 m: 0.0368 x 0.0406 m/px) and for
``cave.png`` (0.032 m/px), it builds the instance with both graph methods of
:mod:`parcover.maps` (tracing, sampling, graph and the instance's shortest paths
included), prints the time, the graph size and how much longer the decomposition's
distances are than the visibility graph's (:func:`parcover.maps.distance_ratio`).
The target is a few seconds per build with 50 KPOIs.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

from parcover.maps import distance_ratio, instance_from_map

MAPS = Path(__file__).resolve().parent.parent / "instances" / "maps"
CASES = (("hospital_section.png", (0.0368, 0.0406)), ("cave.png", 0.032))


def main(kpois: int = 50) -> None:
    print(f"{'map':<22} {'graph':<14} {'seconds':>8} {'nodes':>6} {'edges':>6}")
    for image, scale in CASES:
        built = {}
        for graph in ("decomposition", "visibility"):
            started = time.perf_counter()
            inst = instance_from_map(MAPS / image, scale, kpois=kpois, seed=0, graph=graph)
            seconds = time.perf_counter() - started
            built[graph] = inst
            print(f"{image:<22} {graph:<14} {seconds:>8.2f} {len(inst.nodes):>6} {len(inst.edges):>6}")
        r = distance_ratio(built["decomposition"], built["visibility"])
        print(
            f"{'':<22} decomposition / visibility over {r['pairs']} pairs: min {r['min']:.3f}, "
            f"median {r['median']:.3f}, mean {r['mean']:.3f}, p95 {r['p95']:.3f}, max {r['max']:.3f}"
        )


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:]))
