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

from parcover import generate
from parcover.errors import InputError
from parcover.frontier import frontier
from parcover.instance import Instance, InstanceError, MapInfo, ShortEdgeWarning
from parcover.io import FileFormatError, load, read_instance, write_instance
from parcover.problem import MethodInfo, Problem, Solution
from parcover.result import Frontier, FrontierPoint, Result, Status
from parcover.solve import METHODS, SolverError, available_methods, register_method, solve
from parcover.verify import InvalidSolution, Verdict, verify

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
    "generate",
    "__version__",
]
