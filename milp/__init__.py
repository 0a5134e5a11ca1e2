"""Exact MILP methods for the parallel coverage problem (paths and tours from one start).

Input everywhere is a metric distance matrix ``D`` of shape ``(n+1, n+1)``, index 0 the
start and ``1..n`` the KPOIs. Methods:

- :mod:`milp.arcflow`: compact arc-flow MILP with distance flow (HiGHS), arc pruning,
  warm start; the default.
- :mod:`milp.setpart`: Held-Karp over all subsets plus set partitioning (``n <= 16``),
  an independent check.
- :mod:`milp.branchprice`: branch-and-price over ng-routes (:mod:`milp.ngroute`, numba
  labelling): fewest routes within a deadline, least makespan as a sequence of those.
- :mod:`milp.cvx`: the arc-flow model written in cvxpy, for reading.
- :mod:`milp.bounds`: spanning-tree bounds every model starts from.
- :mod:`milp.colgen`: certified lower bounds from column generation over routes
  (relaxed pricing, valid when stopped early), for instances too large to prove.
- :func:`frontier`: optimal makespan for ``k = 1, 2, ...`` robots.

This package imports only numpy, scipy, numba, highspy and cvxpy.
"""

from milp import arcflow, bounds, branchprice, colgen, cvx, setpart
from milp.arcflow import ArcModel, build_model, min_makespan, min_robots
from milp.frontier import frontier
from milp.highs import write_model
from milp.result import MilpResult, relative_gap

__all__ = [
    "ArcModel",
    "MilpResult",
    "arcflow",
    "bounds",
    "branchprice",
    "colgen",
    "build_model",
    "cvx",
    "frontier",
    "min_makespan",
    "min_robots",
    "relative_gap",
    "setpart",
    "write_model",
]
