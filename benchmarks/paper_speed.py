"""Time the paper's Algorithm 1 on random Euclidean instances (a script, not a test).

Run: ``python benchmarks/paper_speed.py``. Building each instance (the distance
matrix) is timed separately from Algorithm 1 itself; the target is under 2 s for
5,000 KPOIs on one core (the algorithm is O(n^2): one masked argmin over a row of
the distance matrix per insertion or refusal).
"""

from __future__ import annotations

import time

import numpy as np

from parcover import Instance
from parcover.algorithms.paper import LITERAL, NEAREST_END, algorithm_1

SIZES = (1000, 2000, 5000)


def main() -> None:
    print(f"{'KPOIs':>6} {'build s':>8} {'literal s':>10} {'nearest-end s':>14} {'paths':>6} {'paths (end)':>12}")
    for n in SIZES:
        points = np.random.default_rng(n).uniform(0, 1000, size=(n + 1, 2))
        started = time.perf_counter()
        instance = Instance.from_points(points)
        built = time.perf_counter() - started
        timings, counts = [], []
        for reading in (LITERAL, NEAREST_END):
            started = time.perf_counter()
            paths = algorithm_1(instance, reading=reading)
            timings.append(time.perf_counter() - started)
            counts.append(len(paths))
        print(f"{n:>6} {built:>8.2f} {timings[0]:>10.2f} {timings[1]:>14.2f} {counts[0]:>6} {counts[1]:>12}")


if __name__ == "__main__":
    main()
