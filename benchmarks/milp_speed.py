"""Time the arc-flow MILP (:mod:`milp.arcflow`) on random Euclidean instances.

Run from the repository root::

    python benchmarks/milp_speed.py [--time-limit SECONDS] [--seed S]

Prints one row per instance: min_makespan with k = 3 paths on 15, 20, 25, 30 KPOIs and
min_robots at a deadline on 50 KPOIs. Targets: 20 KPOIs proven within 3 s, 30 within
60 s, 50 KPOIs under a deadline within 10 s.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from milp import arcflow  # noqa: E402
from milp.routes import least_makespan  # noqa: E402


def euclidean(n: int, seed: int) -> np.ndarray:
    """Distance matrix of a start and ``n`` KPOIs uniform in a 100 x 100 square."""
    points = np.random.default_rng(seed).uniform(0.0, 100.0, size=(n + 1, 2))
    return np.linalg.norm(points[:, None, :] - points[None, :, :], axis=2)


def main() -> None:
    """Run the timings and print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--time-limit", type=float, default=120.0)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    print(f"{'problem':<34}{'status':<11}{'objective':>11}{'bound':>11}{'gap':>9}{'nodes':>8}{'seconds':>9}")
    for n in (15, 20, 25, 30):
        result = arcflow.min_makespan(euclidean(n, args.seed), 3, tours=False, time_limit=args.time_limit)
        _row(f"min_makespan n={n} k=3 paths", result)
    D = euclidean(50, args.seed)
    deadline = 1.5 * least_makespan(D, tours=False)
    result = arcflow.min_robots(D, deadline, tours=False, time_limit=args.time_limit)
    _row(f"min_robots n=50 paths U={deadline:.1f}", result)


def _row(name: str, result) -> None:
    """Print one result line."""
    gap = "-" if result.gap is None else f"{100 * result.gap:.2f}%"
    print(f"{name:<34}{result.status:<11}{result.objective:>11.3f}{result.bound:>11.3f}"
          f"{gap:>9}{result.nodes:>8}{result.seconds:>9.2f}", flush=True)


if __name__ == "__main__":
    main()
