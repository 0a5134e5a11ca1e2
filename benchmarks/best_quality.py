"""Makespan of ``best`` against the construction it starts from (a script, not a test).

Run: ``python benchmarks/best_quality.py [SECONDS]``. On uniform random Euclidean
instances of 50, 100 and 200 KPOIs (``generate.random_points(n, seed=n)``) with
K = 3 and 5 paths and tours, ``best`` runs with a time limit of ``SECONDS`` (default 5)
through :func:`parcover.solve` (so its routes are verified). The table shows the
construction chosen as start, its makespan, the final makespan, the improvement in
percent, the ruin-and-recreate rounds and the seconds used. With a time limit the
numbers depend on the machine's speed.
"""

from __future__ import annotations

import sys

from parcover import generate, solve

SIZES = (50, 100, 200)
ROBOTS = (3, 5)


def main(seconds: float = 5.0) -> None:
    header = ("KPOIs", "routes", "K", "start", "start ms", "best ms", "gain %", "rounds", "seconds")
    widths = (5, 6, 2, 18, 9, 9, 6, 6, 7)
    print(" ".join(f"{h:>{w}}" for h, w in zip(header, widths)))
    for n in SIZES:
        instance = generate.random_points(n, seed=n)
        for routes in ("paths", "tours"):
            for k in ROBOTS:
                result = solve(instance, routes, robots=k, method="best", time_limit=seconds)
                start = result.info["start_value"][0]
                gain = 100 * (start - result.makespan) / start
                row = (n, routes, k, result.info["start"], f"{start:.2f}", f"{result.makespan:.2f}",
                       f"{gain:.1f}", result.info["iterations"], f"{result.seconds:.1f}")
                print(" ".join(f"{c:>{w}}" for c, w in zip(row, widths)), flush=True)


if __name__ == "__main__":
    main(*(float(a) for a in sys.argv[1:2]))
