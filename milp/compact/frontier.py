"""The robots-vs-makespan frontier with the arc-flow model."""

from __future__ import annotations

import numpy as np

from milp.compact import arcflow
from milp.core.result import MilpResult
from milp.core.routes import check_distance_matrix, least_makespan, within


def frontier(D: np.ndarray, *, tours: bool, time_limit: float | None = None) -> list[MilpResult]:
    """Optimal makespan for ``k = 1, 2, ...`` robots until the least possible makespan.

    Each ``k`` is warm-started from the routes of ``k - 1`` (valid for ``k`` robots too),
    so the makespans never increase. The list stops at the first ``k`` whose makespan
    reaches ``c_max`` (paths) / ``2 c_max`` (tours), which ``k = n`` always does.

    Parameters
    ----------
    D : numpy.ndarray
        ``(n+1, n+1)`` metric distance matrix, index 0 the start.
    tours : bool
        Tours (return to 0) or open paths.
    time_limit : float, optional
        Seconds per value of ``k``; None for no limit.

    Returns
    -------
    list of MilpResult
        Entry ``k - 1`` is :func:`milp.compact.arcflow.min_makespan` for ``k`` robots.
    """
    D = check_distance_matrix(D)
    least = least_makespan(D, tours=tours)
    results: list[MilpResult] = []
    routes = None
    for k in range(1, len(D)):
        result = arcflow.min_makespan(D, k, tours=tours, time_limit=time_limit, warm_start=routes)
        results.append(result)
        routes = result.routes
        if within(result.objective, least):
            break
    return results
