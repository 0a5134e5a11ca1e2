"""Exact MILP methods for the parallel coverage problem (paths and tours from one start).

Input everywhere is a metric distance matrix ``D`` of shape ``(n+1, n+1)``, index 0 the
start and ``1..n`` the KPOIs. The package, as its folder reads:

- :mod:`milp.core`: what every method shares: the result, route arithmetic, merging KPOIs at
  distance 0, HiGHS plumbing, the time limit, sizes, compiling, progress lines, child processes.
- :mod:`milp.bounds`: spanning-tree and Held-Karp lower bounds every method starts from;
  :mod:`milp.warmstart`: the valid solution every method starts from.
- :mod:`milp.compact`: the compact arc-flow MILP with distance flow (HiGHS, arc pruning, warm
  start), the same model in cvxpy for reading, and the frontier with it.
- :mod:`milp.setpart`: Held-Karp over all subsets plus set partitioning (``n <= 20``), an
  independent check.
- :mod:`milp.branchprice`: branch-and-price over ng-routes (numba labelling): fewest routes
  within a deadline, least makespan as a sequence of those; with its tree, columns, cuts, route
  enumeration, and certified column-generation bounds for instances too large to prove.
- :mod:`milp.branchcut`: branch-and-cut over a three-index model (robots' own edge copies,
  subtour cuts separated by minimum cuts): the least makespan with few long routes.
- :mod:`milp.race`: methods side by side in other processes; the first proof wins.

This package imports only numpy, scipy, numba, highspy and cvxpy, each on first use: the names
below are loaded when first read (``milp.arcflow``, ``from milp import setpart``), so
``import milp`` costs nothing and a program pays only for the models it runs. Modules that
moved into the subpackages stay importable under their former names (``milp.arcflow``,
``milp.colgen``, ``milp.result``, ...).
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.util
import sys
from collections.abc import Sequence
from importlib.machinery import ModuleSpec
from types import ModuleType

from milp.core.lazy import lazy_getattr

#: Former module paths -> where the module lives now.
_MOVED = {
    **{f"milp.{name}": f"milp.core.{name}"
       for name in ("result", "routes", "highs", "merge", "sizes", "jit", "progress", "orphans")},
    "milp.deadline": "milp.core.timelimit",
    **{f"milp.{name}": f"milp.compact.{name}" for name in ("arcflow", "cvx")},
    **{f"milp.{name}": f"milp.branchprice.{name}"
       for name in ("ngroute", "columns", "cuts", "tree", "enumeration", "colgen", "compiling")},
}
_SUBMODULES = {
    "arcflow": "milp.compact.arcflow", "cvx": "milp.compact.cvx", "colgen": "milp.branchprice.colgen",
    **{name: f"milp.{name}" for name in ("bounds", "branchcut", "branchprice", "race", "setpart")},
}
# Public functions and classes -> the module defining them.
_DEFINED_IN = {
    "ArcModel": "milp.compact.arcflow",
    "build_model": "milp.compact.arcflow",
    "min_makespan": "milp.compact.arcflow",
    "min_robots": "milp.compact.arcflow",
    "frontier": "milp.compact.frontier",
    "write_model": "milp.core.highs",
    "MilpResult": "milp.core.result",
    "relative_gap": "milp.core.result",
}

__all__ = sorted((*_SUBMODULES, *_DEFINED_IN))

# Public names and moved modules (``milp.arcflow``) imported on first read.
__getattr__ = lazy_getattr(__name__, globals(), _DEFINED_IN,
                           {**{former.removeprefix("milp."): now for former, now in _MOVED.items()}, **_SUBMODULES})


class _FormerPaths(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """``import milp.arcflow`` (a former path) gives the module where it lives now."""

    def find_spec(self, fullname: str, path: Sequence[str] | None = None,
                  target: ModuleType | None = None) -> ModuleSpec | None:
        return importlib.util.spec_from_loader(fullname, self) if fullname in _MOVED else None

    def create_module(self, spec: ModuleSpec) -> None:
        return None  # a placeholder, replaced in exec_module

    def exec_module(self, module: ModuleType) -> None:
        # The import system returns whatever sys.modules holds under the name afterwards.
        sys.modules[module.__name__] = importlib.import_module(_MOVED[module.__name__])


if not any(isinstance(finder, _FormerPaths) for finder in sys.meta_path):
    sys.meta_path.append(_FormerPaths())
