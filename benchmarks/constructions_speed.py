"""Time the baseline constructions on random Euclidean instances (a script, not a test).

Run: ``python benchmarks/constructions_speed.py [SIZES...]``. Each method of
:mod:`parcover.algorithms.baselines` answers two questions on 1,000, 2,000 and 5,000
uniform random KPOIs, for paths and tours: a robot limit of 10 (``robots=10``) and
the paper's question (fewest robots at the least makespan, ``c_max`` or
``2 c_max``), which makes ``knn`` and ``kni`` search the robot count. Building the
instance (its distance matrix) is timed separately. The target is under 2 s for
5,000 KPOIs on one core (``split`` may take longer: its 2-opt tour). Methods are
called directly, without :func:`parcover.solve`'s verification.
"""

from __future__ import annotations

import sys
import time

import numpy as np

from parcover import Instance
from parcover.algorithms.baselines import METHODS
from parcover.problem import Problem

SIZES = (1000, 2000, 5000)
QUESTIONS = (("K=10", 10), ("deadline", None))


def main(sizes: tuple[int, ...] = SIZES) -> None:
    header = ("KPOIs", "build s", "method", "routes", "question", "seconds", "robots")
    print(" ".join(f"{h:>{w}}" for h, w in zip(header, (6, 8, 6, 6, 9, 8, 7))))
    for n in sizes:
        points = np.random.default_rng(n).uniform(0, 1000, size=(n + 1, 2))
        started = time.perf_counter()
        instance = Instance.from_points(points)
        built = time.perf_counter() - started
        for info in METHODS:
            for routes in ("paths", "tours"):
                for label, robots in QUESTIONS:
                    problem = Problem(routes, robots=robots)
                    started = time.perf_counter()
                    solution = info.function(instance, problem)
                    seconds = time.perf_counter() - started
                    print(
                        f"{n:>6} {built:>8.2f} {info.name:>6} {routes:>6} {label:>9} "
                        f"{seconds:>8.2f} {len(solution.routes):>7}",
                        flush=True,
                    )


if __name__ == "__main__":
    main(tuple(int(a) for a in sys.argv[1:]) or SIZES)
