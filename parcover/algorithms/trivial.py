"""The trivial method: one robot per KPOI (or KPOIs dealt out in list order).

It needs no search and is always valid when a solution exists: a route from the start
straight to one KPOI costs ``d(s, v) <= c_max`` (``2 d(s, v)`` as a tour), so it meets
every deadline ``>= c_max`` (paper, Prop. 1 and Prop. 2's upper end ``|V|``).
"""

from __future__ import annotations

import numpy as np

from parcover.instance import Instance
from parcover.problem import MethodInfo, Problem, Solution

__all__ = ["one_per_kpoi", "METHODS"]


def one_per_kpoi(
    instance: Instance, problem: Problem, *, time_limit: float | None = None, seed: int = 0
) -> Solution:
    """One route per KPOI; with a robot limit ``k < n``, KPOIs in list order are cut
    into ``k`` consecutive blocks of near-equal size."""
    n = instance.n
    robots = n if problem.robots is None else min(problem.robots, n)
    blocks = np.array_split(np.arange(1, n + 1), robots)
    return Solution(routes=[[int(i) for i in block] for block in blocks])


METHODS = (
    MethodInfo(
        "trivial",
        one_per_kpoi,
        "one robot per KPOI (under a robot limit, KPOIs dealt out in list order)",
    ),
)
