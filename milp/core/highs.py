"""HiGHS plumbing shared by the MILP models: options, statuses, bounds, export.

Models are handed over as a :class:`highspy.HighsLp` built in bulk from CSC arrays
(:func:`make_lp`), solved by :func:`solve_lp` and exported by :func:`write_model`.
"""

from __future__ import annotations

import ctypes
import os
import sys
from dataclasses import dataclass
from pathlib import Path

import highspy
import numpy as np
from scipy import sparse

from milp.core.timelimit import stop_requested


def _absorb_banner() -> None:
    """Build the process's first ``Highs`` with the C-level stdout sent to /dev/null.

    HiGHS 1.16 prints a two-line banner on stdout when the first ``Highs`` of a process is
    built, before any ``output_flag`` can be set; that would end up in ``parcover``'s
    console output and JSON. It prints once per process, so absorbing it here (at import,
    before any solver is built, cvxpy's included) keeps every later solve silent.
    """
    sys.stdout.flush()
    saved = os.dup(1)
    try:
        with open(os.devnull, "w") as null:
            os.dup2(null.fileno(), 1)
            highspy.Highs()
            ctypes.CDLL(None).fflush(None)  # the banner may sit in C's stdout buffer
    finally:
        os.dup2(saved, 1)
        os.close(saved)


_absorb_banner()

#: Relative and absolute MIP gaps: "optimal" then means exact to about 1e-9 relative
#: (HiGHS' defaults, 1e-4 and 1e-6, stop 0.01% above the optimum).
MIP_REL_GAP = 1e-9
MIP_ABS_GAP = 1e-9
#: Slack allowed between a proven bound and an objective (solver feasibility tolerance).
BOUND_SLACK = 1e-6
THREADS = min(2, os.cpu_count() or 1)

_SOLVED = {
    highspy.HighsModelStatus.kOptimal: "optimal",
    highspy.HighsModelStatus.kInfeasible: "infeasible",
}


@dataclass(frozen=True)
class LpSolve:
    """What one HiGHS MIP solve established.

    Attributes
    ----------
    status : str
        One of ``optimal``, ``feasible``, ``infeasible``, ``unknown`` (see
        :class:`milp.core.result.MilpResult`).
    values : numpy.ndarray or None
        Column values of the best solution found; None without one.
    objective : float or None
        HiGHS' objective value of ``values``.
    bound : float or None
        HiGHS' proven dual bound (None when infeasible or nothing proven).
    nodes : int
        Branch-and-bound nodes.
    message : str
        HiGHS' model status as text.
    """

    status: str
    values: np.ndarray | None
    objective: float | None
    bound: float | None
    nodes: int
    message: str


def make_lp(
    cost: np.ndarray,
    col_bounds: tuple[np.ndarray, np.ndarray],
    matrix: sparse.spmatrix,
    row_bounds: tuple[np.ndarray, np.ndarray],
    integer: np.ndarray,
) -> highspy.HighsLp:
    """Assemble a minimisation MILP as a :class:`highspy.HighsLp` from arrays.

    Parameters
    ----------
    cost : numpy.ndarray
        Objective coefficients, one per column.
    col_bounds, row_bounds : tuple of numpy.ndarray
        ``(lower, upper)`` per column / row; use ``numpy.inf`` for none.
    matrix : scipy.sparse.spmatrix
        Constraint matrix, rows by columns.
    integer : numpy.ndarray of bool
        Which columns are integer.

    Returns
    -------
    highspy.HighsLp
    """
    csc = sparse.csc_matrix(matrix)
    csc.sum_duplicates()
    lp = highspy.HighsLp()
    lp.num_col_, lp.num_row_ = int(csc.shape[1]), int(csc.shape[0])
    lp.col_cost_ = np.asarray(cost, dtype=np.float64)
    lp.col_lower_, lp.col_upper_ = (np.asarray(b, dtype=np.float64) for b in col_bounds)
    lp.row_lower_, lp.row_upper_ = (np.asarray(b, dtype=np.float64) for b in row_bounds)
    lp.a_matrix_.format_ = highspy.MatrixFormat.kColwise
    lp.a_matrix_.start_ = csc.indptr.astype(np.int32)
    lp.a_matrix_.index_ = csc.indices.astype(np.int32)
    lp.a_matrix_.value_ = csc.data.astype(np.float64)
    lp.integrality_ = [
        highspy.HighsVarType.kInteger if flag else highspy.HighsVarType.kContinuous
        for flag in np.asarray(integer, dtype=bool)
    ]
    return lp


def new_highs(time_limit: float | None, options: dict | None = None) -> highspy.Highs:
    """A silent HiGHS instance with the exact-gap options, an optional time limit and
    any further ``options`` (HiGHS option name -> value). Its MIP search stops, as at its
    time limit, once the caller is asked to stop (a race's rival proved the answer, or
    Ctrl-C: :func:`milp.core.timelimit.stop_requested`)."""
    h = highspy.Highs()
    h.cbMipInterrupt += _interrupt_when_asked
    h.setOptionValue("output_flag", False)
    h.setOptionValue("mip_rel_gap", MIP_REL_GAP)
    h.setOptionValue("mip_abs_gap", MIP_ABS_GAP)
    h.setOptionValue("threads", THREADS)
    if time_limit is not None:
        h.setOptionValue("time_limit", float(max(time_limit, 1e-3)))
    for name, value in (options or {}).items():
        if h.setOptionValue(name, value) == highspy.HighsStatus.kError:
            raise ValueError(f"HiGHS rejects option {name}={value!r}")
    return h


def solve_lp(
    lp: highspy.HighsLp,
    *,
    time_limit: float | None,
    start: np.ndarray | None = None,
    options: dict | None = None,
) -> LpSolve:
    """Solve a MILP with HiGHS and map the outcome to the four statuses.

    Parameters
    ----------
    lp : highspy.HighsLp
        The model (minimisation).
    time_limit : float or None
        Seconds; None for no limit.
    start : numpy.ndarray, optional
        A feasible column vector passed to HiGHS as a warm start (``setSolution``).
    options : dict, optional
        Further HiGHS options for this solve.

    Returns
    -------
    LpSolve
        ``optimal``/``infeasible`` when HiGHS proves it; otherwise ``feasible`` when a
        solution exists (time limit etc.), with HiGHS' dual bound; else ``unknown``.

    Raises
    ------
    AssertionError
        If HiGHS reports a bound above its own objective (beyond tolerance).
    """
    h = new_highs(time_limit, options)
    h.passModel(lp)
    if start is not None:
        solution = highspy.HighsSolution()
        solution.col_value = np.asarray(start, dtype=np.float64)
        h.setSolution(solution)
    h.run()
    model_status = h.getModelStatus()
    info = h.getInfo()
    nodes = int(info.mip_node_count)
    message = h.modelStatusToString(model_status)
    has_solution = info.primal_solution_status == 2  # kSolutionStatusFeasible
    status = _SOLVED.get(model_status, "feasible" if has_solution else "unknown")
    if status == "infeasible" or not has_solution:
        bound = _finite(info.mip_dual_bound)
        return LpSolve(status, None, None, bound, nodes, message)
    values = np.asarray(h.getSolution().col_value, dtype=np.float64)
    objective = float(info.objective_function_value)
    bound = _finite(info.mip_dual_bound)
    if bound is not None:
        assert bound <= objective + BOUND_SLACK * max(1.0, abs(objective)), (bound, objective)
    return LpSolve(status, values, objective, bound, nodes, message)


def write_model(lp: highspy.HighsLp, path: str | os.PathLike[str]) -> Path:
    """Write a model to ``.mps`` or ``.lp`` (chosen by the suffix) via ``Highs.writeModel``.

    Parameters
    ----------
    lp : highspy.HighsLp
        The model, e.g. from :func:`milp.compact.arcflow.build_model`.
    path : path-like
        Destination ending in ``.mps`` or ``.lp``.

    Returns
    -------
    pathlib.Path
        The path written.
    """
    out = Path(path)
    if out.suffix not in (".mps", ".lp"):
        raise ValueError(f"model export needs a .mps or .lp path, got {out.name!r}")
    h = new_highs(None)
    h.passModel(lp)
    if h.writeModel(str(out)) == highspy.HighsStatus.kError:
        raise OSError(f"HiGHS could not write {out}")
    return out


def _interrupt_when_asked(event: highspy.highs.HighsCallbackEvent) -> None:
    """HiGHS' MIP interrupt callback: stop when :func:`stop_requested`."""
    if stop_requested():
        event.interrupt()


def _finite(value: float) -> float | None:
    """``value`` as a float, or None when HiGHS reports it as infinite/undefined."""
    value = float(value)
    return value if np.isfinite(value) and abs(value) < 1e30 else None
