"""parcover: exact and greedy solvers for the multi-robot parallel coverage problem.

Robots all start at one node and must visit every key position of interest (KPOI);
parcover answers, for paths and tours, the least makespan with k robots, the fewest
robots within a deadline, and the whole robots-versus-time frontier, and checks the
greedy algorithms of Min & Papanikolopoulos against the exact optima.

>>> import parcover as pc
>>> inst = pc.generate.grid(3, 3)
>>> inst.c_max
4.0
"""

from importlib.metadata import PackageNotFoundError, version

from milp.core.lazy import lazy_getattr
from parcover import generate
from parcover.errors import InputError
from parcover.frontier import frontier
from parcover.instance import Instance, InstanceError, MapInfo, ShortEdgeWarning
from parcover.io import FileFormatError, load, read_instance, write_instance
from parcover.problem import MethodInfo, Problem, Solution
from parcover.result import Frontier, FrontierPoint, Result, Status
from parcover.solve import METHODS, SolverError, available_methods, register_method, solve
from parcover.verify import InvalidSolution, Verdict
from parcover.certify import verify  # the verifier, then re-proving the claims when asked

#: Public names loaded on first use: drawing loads matplotlib, which a solve does not need.
_LAZY = {"plot_routes": "parcover.plot", "save_routes_plot": "parcover.plot"}

# The drawing functions of :mod:`parcover.plot`, imported when first asked for.
__getattr__ = lazy_getattr(__name__, globals(), _LAZY)


def __dir__() -> list[str]:
    """The module's names, the lazy ones included (for tab completion)."""
    return sorted(set(globals()) | set(_LAZY))


try:
    __version__ = version("parcover")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0.0.0+unknown"

__all__ = [
    "Instance",
    "InstanceError",
    "InputError",
    "FileFormatError",
    "MapInfo",
    "ShortEdgeWarning",
    "Problem",
    "Solution",
    "MethodInfo",
    "Result",
    "Status",
    "Frontier",
    "FrontierPoint",
    "Verdict",
    "InvalidSolution",
    "SolverError",
    "METHODS",
    "available_methods",
    "register_method",
    "load",
    "read_instance",
    "write_instance",
    "solve",
    "frontier",
    "verify",
    "plot_routes",
    "save_routes_plot",
    "generate",
    "__version__",
]
