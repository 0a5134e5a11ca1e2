"""Exact MILP methods for the parallel coverage problem (paths and tours from one start).

Input everywhere is a metric distance matrix ``D`` of shape ``(n+1, n+1)``, index 0 the
start and ``1..n`` the KPOIs. Methods:

- :mod:`milp.arcflow`: compact arc-flow MILP with distance flow (HiGHS), arc pruning,
  warm start; the default.
- :mod:`milp.setpart`: Held-Karp over all subsets plus set partitioning (``n <= 20``),
  an independent check.
- :mod:`milp.branchprice`: branch-and-price over ng-routes (:mod:`milp.ngroute`, numba
  labelling): fewest routes within a deadline, least makespan as a sequence of those;
  the tree of each decision in :mod:`milp.tree`, its column pool and branching nodes
  in :mod:`milp.columns`, its subset-row cut
  separation in :mod:`milp.cuts`, the readiness of its compiled functions in
  :mod:`milp.compiling` (cached where :mod:`milp.jit` finds a writable folder), its
  route listing in :mod:`milp.enumeration`.
- :mod:`milp.branchcut`: branch-and-cut over a three-index model (robots' own edge
  copies, subtour cuts separated by minimum cuts): the least makespan with few long
  routes; :mod:`milp.race` runs it against branch-and-price in another process, which
  ends with its parent (:mod:`milp.orphans`).
- :mod:`milp.cvx`: the arc-flow model written in cvxpy, for reading (imported on demand,
  ``from milp import cvx``: cvxpy takes most of a second to load).
- :mod:`milp.bounds`: spanning-tree bounds every model starts from.
- :mod:`milp.colgen`: certified lower bounds from column generation over routes
  (relaxed pricing, valid when stopped early), for instances too large to prove.
- :func:`frontier`: optimal makespan for ``k = 1, 2, ...`` robots.

This package imports only numpy, scipy, numba, highspy and cvxpy, each on first use: the names
below are loaded when first read (``milp.arcflow``, ``from milp import setpart``), so
``import milp`` costs nothing and a program pays only for the models it runs.
"""

from __future__ import annotations

import importlib
from typing import Any

_SUBMODULES = ("arcflow", "bounds", "branchcut", "branchprice", "colgen", "cvx", "race", "setpart")
# Public functions and classes -> the module defining them.
_DEFINED_IN = {
    "ArcModel": "milp.arcflow",
    "build_model": "milp.arcflow",
    "min_makespan": "milp.arcflow",
    "min_robots": "milp.arcflow",
    "frontier": "milp.frontier",
    "write_model": "milp.highs",
    "MilpResult": "milp.result",
    "relative_gap": "milp.result",
}

__all__ = sorted((*_SUBMODULES, *_DEFINED_IN))


def __getattr__(name: str) -> Any:
    """Import a public name's module on first use (PEP 562)."""
    if name in _SUBMODULES:
        value = importlib.import_module(f"milp.{name}")
    elif name in _DEFINED_IN:
        value = getattr(importlib.import_module(_DEFINED_IN[name]), name)
    else:
        raise AttributeError(f"module 'milp' has no attribute {name!r}")
    globals()[name] = value
    return value
