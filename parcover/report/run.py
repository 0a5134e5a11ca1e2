"""Answering a gap report's grid: :func:`gaps`, its tasks and their rows.

The work is one :class:`_Task` per instance x route kind; a task solves each pending
(question, method) unit and its reference (:func:`_unit_rows`), giving one row per
comparison (:func:`_row`, with :func:`gap_to_optimum`). Tasks run in-process, on a
local process pool or on a Dask cluster (:func:`_run`); the rows go to the CSV store
(:mod:`parcover.report.store`) as they come.
"""

from __future__ import annotations

import concurrent.futures
import math
import multiprocessing
import os
import sys
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pandas as pd

from parcover.errors import InputError
from parcover.instance import Instance
from parcover.problem import MethodInfo, Problem, meets_deadline
from parcover.report.spec import (
    GridQuestion,
    InstanceInput,
    _whole,
    load_instances,
    questions,
)
from parcover.report.store import (
    _UNIT_KEY,
    AS_ASKED,
    MAKESPAN_AT_ROBOTS,
    ROBOTS_AT_MAKESPAN,
    _check_request,
    _CsvSink,
    _empty,
    _frame,
    _kept_rows,
    _sort_order,
    _sorted,
    _typed,
    _write_csv_atomically,
)
from parcover.result import Result, RoutesKind, Status
from parcover.result import gap as solver_gap

if TYPE_CHECKING:
    from tqdm import tqdm

# ---------------------------------------------------------------- one task


@dataclass(frozen=True)
class _Task:
    """Everything a worker needs for one instance x route kind (picklable)."""

    instance: dict[str, Any]  # parcover.io.instance_to_dict form: Instance itself does not pickle
    routes: RoutesKind
    questions: tuple[GridQuestion, ...]
    methods: tuple[MethodInfo, ...]
    reference: MethodInfo
    time_limit: float | None
    seed: int
    done: frozenset[tuple[str, str]]  # (question label, method) units already in the CSV

    def units(self) -> list[tuple[GridQuestion, MethodInfo]]:
        """The (question, method) pairs this task still has to compute."""
        return [(q, m) for q in self.questions for m in self.methods if (q.label, m.name) not in self.done]


def _task_rows(task: _Task) -> list[dict[str, Any]]:
    """The rows of one task: each pending (question, method) against its reference.

    Runs in a worker (:func:`_unit_rows`, collected).
    """
    return [row for rows in _unit_rows(task) for row in rows]


def _unit_rows(task: _Task) -> Iterator[list[dict[str, Any]]]:
    """The rows of each pending (question, method) of ``task``, one list per unit.

    Registers the task's methods the worker lacks (a method the caller registered;
    a label ``NAME:OPTION=VALUE`` is parsed by :func:`parcover.solve.solve` from its
    base method, so only a label whose base is missing is registered), rebuilds the
    instance, and solves each distinct question once per method (the reference included).
    """
    from parcover.io import instance_from_dict
    from parcover.solve import available_methods, register_method, solve

    registry = available_methods()
    for info in (*task.methods, task.reference):
        if info.name.split(":")[0] not in registry:
            register_method(info)
    instance = instance_from_dict(task.instance)
    cache: dict[tuple[str, int | None, float | None], Result] = {}

    def answer(method: str, robots: int | None, deadline: float | None) -> Result:
        key = (method, robots, deadline)
        if key not in cache:
            cache[key] = solve(
                instance, task.routes, robots=robots, deadline=deadline, method=method,
                time_limit=task.time_limit, seed=task.seed,
            )
        return cache[key]

    for question, method in task.units():
        result = answer(method.name, question.robots, question.deadline(instance, task.routes))
        yield [
            _row(task, instance, question, result, compared, answer(task.reference.name, robots, limit))
            for compared, robots, limit in _comparisons(result, question, instance, task.routes)
        ]


def _comparisons(
    result: Result, question: GridQuestion, instance: Instance, routes: RoutesKind
) -> list[tuple[str, int | None, float | None]]:
    """The questions ``result`` is compared on: (compared, robot limit, deadline).

    One, as asked; two when the method dropped the deadline (:mod:`parcover.report`, "Methods that drop
    the deadline").
    """
    if result.objective == "robots" and result.deadline is None and result.has_routes:
        return [(ROBOTS_AT_MAKESPAN, None, result.makespan), (MAKESPAN_AT_ROBOTS, result.robots, None)]
    return [(AS_ASKED, question.robots, question.deadline(instance, routes))]


def _row(
    task: _Task, instance: Instance, question: GridQuestion, result: Result, compared: str, reference: Result
) -> dict[str, Any]:
    """One row of gaps.csv (columns: :data:`COLUMNS`)."""
    objective = reference.objective
    value = _value(result, objective)
    optimum = _optimum(reference)
    return {
        "instance": instance.name,
        "n": instance.n,
        "routes": task.routes,
        "question": question.label,
        "method": result.method,
        "compared": compared,
        "objective": objective,
        "robots_limit": reference.robots_limit,
        "deadline": reference.deadline if objective == "robots" else None,
        "status": result.status.value,
        "value": value,
        "robots": result.robots,
        "makespan": result.makespan,
        "bound": result.bound if compared == AS_ASKED else None,
        "reference": reference.method,
        "reference_status": reference.status.value,
        "reference_value": reference.value,
        "optimum": optimum,
        "gap_to_optimum": gap_to_optimum(value, optimum),
        "gap": solver_gap(value, optimum),
        "at_optimum": reference.status is Status.OPTIMAL and value is not None and meets_deadline(value, optimum),
        "seed": task.seed,
        "time_limit": task.time_limit,
        "reference_seconds": reference.seconds,
        "seconds": result.seconds,
    }


def _value(result: Result, objective: str) -> float | None:
    """The result's makespan or robot count (it may be compared on the other objective)."""
    if not result.has_routes:
        return None
    return result.makespan if objective == "makespan" else float(result.robots)


def _optimum(reference: Result) -> float | None:
    """The reference's value when proven optimal, else its best proven bound."""
    if reference.status is Status.OPTIMAL:
        return reference.value
    if reference.status is Status.INFEASIBLE:
        return None
    return reference.bound


def gap_to_optimum(value: float | None, optimum: float | None) -> float | None:
    """``(value - optimum) / optimum``; 0 within the tolerance, ``inf`` over a 0 optimum."""
    if value is None or optimum is None:
        return None
    if meets_deadline(value, optimum):
        return 0.0
    return math.inf if optimum == 0 else (value - optimum) / optimum


# ---------------------------------------------------------------- the grid


def gaps(
    instances: InstanceInput | Iterable[InstanceInput],
    methods: Sequence[str],
    *,
    routes: Sequence[RoutesKind] = ("paths", "tours"),
    robots: Sequence[int] = (2, 3),
    deadlines: Sequence[str | float] = ("least",),
    reference: str = "exact",
    time_limit: float | None = 60,
    seed: int = 0,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: bool | None = None,
    csv_path: str | os.PathLike[str] | None = None,
) -> pd.DataFrame:
    """Gaps of ``methods`` against ``reference`` on every instance x route kind x question.

    Parameters
    ----------
    instances
        :class:`Instance` objects, instance files, folders or generator specs
        (:func:`load_instances`).
    methods
        Names from :func:`parcover.available_methods`.
    routes
        Route kinds.
    robots
        Robot limits: one ``makespan`` question each.
    deadlines
        ``"least"`` (the paper's question) or factors of the least makespan: one
        ``robots`` question each.
    reference
        The exact method giving ``optimum`` (:mod:`parcover.report`, "Reference and optimum").
    time_limit
        Seconds per solve, methods and reference alike (None: no limit).
    seed
        Seed passed to every solve.
    workers
        Local processes (default ``min(2, cpu count)``; 1 runs in-process).
    scheduler
        Address of a Dask scheduler: run there instead of locally.
    progress
        Show a tqdm bar on stderr (default: when stderr is a terminal).
    csv_path
        Append each row to this CSV as it is computed; rows already there (same
        reference, seed and time limit) are kept and skipped. At the end the file
        holds exactly the returned rows, sorted.

    Returns
    -------
    pandas.DataFrame
        Columns :data:`COLUMNS`, sorted by input order.

    Raises
    ------
    InputError
        Before any work, on an unknown method, a bad question or instance, or a CSV
        from other settings.
    """
    infos, ref_info = _resolve_methods(methods, reference)
    kinds = _route_kinds(routes)
    grid = questions(robots, deadlines)
    if time_limit is not None and not (isinstance(time_limit, (int, float)) and time_limit > 0):
        raise InputError(f"The time limit must be a positive number of seconds, got {time_limit!r}.")
    settings = {
        "reference": reference,
        "seed": _whole(seed, "seed", 0),
        "time_limit": None if time_limit is None else float(time_limit),
    }
    workers = min(2, os.cpu_count() or 1) if workers is None else _whole(workers, "workers", 1)
    insts = load_instances(instances)
    _check_report_memory(insts, len(kinds), len(grid), len(infos), workers if scheduler is None else 0)
    order = _sort_order(insts, kinds, grid, infos)
    kept = _kept_rows(csv_path, settings) if csv_path is not None else _empty()
    _check_request(kept, order, csv_path)
    tasks = _pending_tasks(insts, kinds, grid, infos, ref_info, settings, kept)
    sink = _CsvSink(csv_path, kept)
    with _progress_bar(sum(len(t.units()) for t in tasks), progress) as bar:
        for units, rows in _run(tasks, workers, scheduler):
            sink.write(rows)
            bar.update(units)
    table = _sorted(_typed(pd.concat([kept, _frame(sink.rows)], ignore_index=True)), order)
    if csv_path is not None:
        _write_csv_atomically(table, Path(csv_path))
    return table


def _check_report_memory(insts: list[Instance], route_kinds: int, questions: int, methods: int, workers: int) -> None:
    """Refuse, before any solve, a report whose instances, rows (one per instance x
    route kind x question x method, two for a method that drops the deadline) and
    workers' instances (each worker builds one at a time) need more memory than there is."""
    from parcover.memory import check_memory, footprint_of, report_rows_bytes

    sizes = [footprint_of(inst) for inst in insts]
    rows = report_rows_bytes(len(insts), route_kinds, questions, methods)
    needed = sum(f.kept for f in sizes) + rows + workers * max(f.peak for f in sizes)
    check_memory(needed, f"A report of {len(insts)} instances x {route_kinds} route kinds x {questions} questions "
                 f"x {methods} methods")


def _pending_tasks(
    insts: list[Instance],
    kinds: Sequence[RoutesKind],
    grid: list[GridQuestion],
    infos: tuple[MethodInfo, ...],
    ref_info: MethodInfo,
    settings: dict[str, Any],
    kept: pd.DataFrame,
) -> list[_Task]:
    """One task per instance x route kind that still has (question, method) units to run."""
    done = {tuple(k) for k in kept[_UNIT_KEY].itertuples(index=False)}
    tasks = [
        _Task(
            _instance_dict(inst), kind, tuple(grid), infos, ref_info, settings["time_limit"], settings["seed"],
            frozenset((q, m) for (i, r, q, m) in done if i == inst.name and r == kind),
        )
        for inst in insts
        for kind in kinds
    ]
    return [t for t in tasks if t.units()]


def _resolve_methods(methods: Sequence[str], reference: str) -> tuple[tuple[MethodInfo, ...], MethodInfo]:
    from parcover.solve import method_with_options

    labels = [methods] if isinstance(methods, str) else list(methods)
    if not labels:
        raise InputError("No methods given.")
    if len(set(labels)) != len(labels):
        raise InputError("A method is listed twice.")
    return tuple(method_with_options(label) for label in labels), method_with_options(reference)


def _route_kinds(routes: Sequence[str]) -> tuple[RoutesKind, ...]:
    kinds = (routes,) if isinstance(routes, str) else tuple(routes)
    for kind in kinds:
        Problem(kind)  # raises InputError on an unknown kind
    if not kinds or len(set(kinds)) != len(kinds):
        raise InputError("Give each route kind once.")
    return kinds


def _instance_dict(instance: Instance) -> dict[str, Any]:
    from parcover.io import instance_to_dict

    return instance_to_dict(instance)


def _run(tasks: list[_Task], workers: int, scheduler: str | None) -> Iterator[tuple[int, list[dict[str, Any]]]]:
    """(units done, their rows) in completion order: in-process (row by row), on local
    processes or on Dask (task by task)."""
    if scheduler is not None:
        yield from _run_on_dask(tasks, scheduler)
        return
    if workers == 1 or len(tasks) <= 1:
        for task in tasks:
            yield from ((1, rows) for rows in _unit_rows(task))
        return
    context = multiprocessing.get_context()
    parent = None if context.get_start_method() == "forkserver" else os.getpid()
    pool = concurrent.futures.ProcessPoolExecutor(
        max_workers=workers, mp_context=context, initializer=_start_worker, initargs=(parent, workers)
    )
    finished = False
    try:
        futures = {pool.submit(_task_rows, task): task for task in tasks}
        for future in concurrent.futures.as_completed(futures):
            yield len(futures[future].units()), future.result()
        finished = True
    finally:
        if not finished:  # an error, an interrupt, or the caller stopped early: the rest is abandoned
            _stop_workers(pool)
        pool.shutdown(wait=finished, cancel_futures=True)


def _start_worker(parent: int | None, workers: int) -> None:
    """A pool worker ends with this process, whatever ends it (SIGKILL included: no
    orphans), and counts as one of ``workers`` sharing the cores (an exact solve races
    its methods only on cores of its own, :func:`milp.race.share_cores`)."""
    from milp.core.orphans import exit_with_parent
    from milp.race import share_cores

    exit_with_parent(parent)
    share_cores(workers)


def _stop_workers(pool: concurrent.futures.ProcessPoolExecutor) -> None:
    """End a pool's workers now, their tasks abandoned (Python 3.14's ``terminate_workers``;
    before it, each worker process)."""
    if hasattr(pool, "terminate_workers"):
        pool.terminate_workers()
        return
    for process in list((pool._processes or {}).values()):
        process.terminate()


def _run_on_dask(tasks: list[_Task], scheduler: str) -> Iterator[tuple[int, list[dict[str, Any]]]]:
    try:
        from dask.distributed import Client, as_completed
    except ImportError:
        raise InputError("scheduler= needs dask.distributed: pip install 'parcover[dask]'.") from None
    with Client(scheduler) as client:
        futures = client.map(_task_rows, tasks, pure=False)
        owner = {f.key: t for f, t in zip(futures, tasks)}
        try:
            for future in as_completed(futures):
                yield len(owner[future.key].units()), future.result()
        finally:
            client.cancel(futures)


def _progress_bar(total: int, progress: bool | None) -> tqdm:
    from tqdm import tqdm

    show = sys.stderr.isatty() if progress is None else progress
    return tqdm(total=total, disable=not show, file=sys.stderr, unit="question", desc="gaps")
