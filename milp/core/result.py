"""The answer every solver in :mod:`milp` returns."""

from __future__ import annotations

from dataclasses import dataclass, field

STATUSES = ("optimal", "feasible", "infeasible", "unknown")


@dataclass(frozen=True)
class MilpResult:
    """Outcome of one exact solve.

    Attributes
    ----------
    status : str
        ``"optimal"``: the routes are proven optimal (to a relative tolerance of about
        1e-9); ``"feasible"``: the routes are valid but optimality is not proven;
        ``"infeasible"``: proven that no valid route set exists; ``"unknown"``: nothing
        was found and nothing was proven (e.g. the time limit struck first).
    routes : list of list of int
        KPOI indices ``1..n`` in visiting order, one list per robot. The start 0 is not
        included, nor the closing 0 of a tour. Empty when there is no solution.
    objective : float or None
        The makespan (``min_makespan``, ``frontier``) or the number of routes
        (``min_robots``), recomputed from the distance matrix; None without a solution.
    bound : float or None
        A proven lower bound on the optimal objective; None when nothing is proven.
        Equal to ``objective`` when the status is ``"optimal"``.
    gap : float or None
        ``(objective - bound) / objective``. It is 0 when the status is ``"optimal"``
        and also when ``objective == bound == 0`` (a zero makespan, e.g. every KPOI at
        the start, is optimal and has no relative gap). It is None when there is no
        solution or no bound.
    nodes : int
        Branch-and-bound nodes explored (summed over every MILP solved).
    seconds : float
        Wall-clock time of the call.
    message : str
        Human-readable detail (solver status, reason for infeasibility, ...).
    """

    status: str
    routes: list[list[int]] = field(default_factory=list)
    objective: float | None = None
    bound: float | None = None
    gap: float | None = None
    nodes: int = 0
    seconds: float = 0.0
    message: str = ""

    def __post_init__(self) -> None:
        if self.status not in STATUSES:
            raise ValueError(f"unknown status {self.status!r}")


def relative_gap(objective: float | None, bound: float | None) -> float | None:
    """The relative gap ``(objective - bound) / objective`` with its edge cases.

    Parameters
    ----------
    objective, bound : float or None
        Incumbent value and proven lower bound.

    Returns
    -------
    float or None
        None when either is missing; 0 when ``objective <= bound`` (which covers
        ``objective == bound == 0``); otherwise the ratio (``inf`` is impossible because
        ``objective > bound >= 0`` implies ``objective > 0``).
    """
    if objective is None or bound is None:
        return None
    if objective <= bound:
        return 0.0
    return (objective - bound) / objective
