"""Optimality-gap reports: every method against an exact reference, on many instances.

:func:`gaps` answers a grid of coverage questions (docs/format.md section 1) on a set of
instances with each method and with an exact *reference* method, and returns one
row per instance x route kind x question x method (a :class:`pandas.DataFrame`,
written to ``gaps.csv`` row by row as it is computed). :func:`write_report` adds
``report.md`` (summary tables), ``meta.json`` (versions, seeds, limits, machine)
and PNG plots.

Questions
---------
For each route kind in ``routes``:

- ``robots<=K`` for each K in ``robots``: objective ``makespan`` with at most K robots.
- ``deadline=least``: objective ``robots`` at the least possible makespan (``c_max``,
  ``2 c_max`` for tours; paper, Prop. 1), asked with no deadline, as the paper does.
- ``deadline=F*least`` for a number F in ``deadlines``: objective ``robots`` with
  deadline ``F`` times the least possible makespan.

Reference and optimum
---------------------
For each instance x route kind x question, the reference method (default ``exact``)
is run ONCE, with the same time limit and seed as the methods. ``optimum`` is its
value when its status is ``optimal``, else its best proven lower bound
(``reference_status`` says which; ``NaN`` when it has neither, e.g. ``infeasible``).

Gaps
----
With ``value`` the method's makespan (objective ``makespan``) or robot count
(objective ``robots``):

- ``gap_to_optimum = (value - optimum) / optimum``: the relative excess over the
  optimum, "x % worse". This is the gap of every table in ``report.md``. When
  ``optimum`` is only a bound it over-estimates the true excess. It is 0 when
  ``value`` meets ``optimum`` within the contract's tolerance
  (:func:`parcover.problem.meets_deadline`), ``inf`` when ``optimum`` is 0 and
  ``value`` is not.
- ``gap = (value - optimum) / value``: the solver-style gap of
  :func:`parcover.result.gap`, in ``[0, 1)``.
- ``at_optimum``: the reference is ``optimal`` and ``value`` meets ``optimum`` within
  the tolerance ("how often a method is optimal").

Both gaps are ``NaN`` when the method or the reference has no value.

Methods that drop the deadline
------------------------------
A method may answer a robots question without its deadline (``paper`` with tours and
no deadline runs Algorithm 2 as published: :attr:`parcover.problem.Solution.drops_deadline`,
its :class:`~parcover.result.Result` has ``deadline`` None). Its routes have some
makespan ``M`` with ``R`` robots, and it is compared on the two questions it did
answer, giving two rows (column ``compared``):

- ``robots at its makespan``: objective ``robots``, ``value = R`` against the
  reference's fewest robots at deadline ``M``;
- ``makespan at its robots``: objective ``makespan``, ``value = M`` against the
  reference's least makespan with at most ``R`` robots.

Every other row has ``compared = "as asked"``.

Columns of gaps.csv
-------------------
``instance`` (name), ``n`` (KPOIs), ``routes``, ``question`` (label above),
``method``, ``compared``, then the question the row is compared on: ``objective``,
``robots_limit``, ``deadline`` (the deadline in force, for objective ``robots``);
the method's answer: ``status``, ``value``, ``robots``, ``makespan``, ``bound`` (its
own proven bound, on the question as asked); the reference's: ``reference`` (method
name), ``reference_status``, ``reference_value``, ``optimum``; then
``gap_to_optimum``, ``gap``, ``at_optimum``, the settings ``seed`` and
``time_limit``, and the wall-clock ``reference_seconds`` and ``seconds``.
:func:`read_gaps` reads the file back with the dtypes of :data:`COLUMNS`.

Execution
---------
Work is split into one task per instance x route kind (the reference then runs
once per distinct question, derived ones included). Tasks run in-process
(``workers=1``; each row is written as soon as it is computed), on local processes
(:class:`concurrent.futures.ProcessPoolExecutor`, default ``min(2, cpu count)``
workers) or on a Dask cluster (``scheduler=ADDRESS``); there a task's rows are
written when the task ends.
Methods travel with each task, so one registered with
:func:`parcover.solve.register_method` is available to workers that can import its
function. A method may be named with fixed options, ``NAME:OPTION=VALUE`` (e.g.
``best:iterations=100``: a fixed number of rounds, so the rows depend on the seed and not
on the machine's speed); the label is its name in the rows. Rows are sorted by the order of the inputs (instances, route kinds,
questions, methods), never by completion order, so every executor gives the same
rows (except ``seconds`` and ``reference_seconds``).

Resume: rows already in ``csv_path`` for the same settings are kept and their
questions skipped; a method's question with only part of its rows is recomputed.
"""

from __future__ import annotations

import concurrent.futures
import itertools
import json
import logging
import math
import multiprocessing
import os
import platform
import sys
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Union

import pandas as pd

from parcover.errors import InputError
from parcover.instance import Instance
from parcover.memory import Footprint
from parcover.problem import MethodInfo, Problem, meets_deadline
from parcover.result import Result, RoutesKind, Status, gap as solver_gap

__all__ = [
    "COLUMNS",
    "TIMING_COLUMNS",
    "Question",
    "questions",
    "gaps",
    "gap_to_optimum",
    "read_gaps",
    "parse_spec",
    "load_instances",
    "write_report",
    "summary_table",
    "worst_rows",
    "render_report",
    "draw_plots",
    "run_metadata",
    "machine_info",
]

log = logging.getLogger(__name__)

# pandas >= 3 has a string dtype "str" (missing values stay NaN); before, strings are objects.
_STRING_DTYPE = "str" if int(pd.__version__.split(".")[0]) >= 3 else "object"

InstanceInput = Union[Instance, str, os.PathLike]

# gaps.csv columns and their pandas dtypes (read_gaps restores them exactly).
COLUMNS: dict[str, str] = {
    "instance": "str",
    "n": "Int64",
    "routes": "str",
    "question": "str",
    "method": "str",
    "compared": "str",
    "objective": "str",
    "robots_limit": "Int64",
    "deadline": "float64",
    "status": "str",
    "value": "float64",
    "robots": "Int64",
    "makespan": "float64",
    "bound": "float64",
    "reference": "str",
    "reference_status": "str",
    "reference_value": "float64",
    "optimum": "float64",
    "gap_to_optimum": "float64",
    "gap": "float64",
    "at_optimum": "bool",
    "seed": "int64",
    "time_limit": "float64",
    "reference_seconds": "float64",
    "seconds": "float64",
}
TIMING_COLUMNS = ("reference_seconds", "seconds")
_UNIT_KEY = ["instance", "routes", "question", "method"]
AS_ASKED = "as asked"
ROBOTS_AT_MAKESPAN = "robots at its makespan"
MAKESPAN_AT_ROBOTS = "makespan at its robots"

_GENERATOR_KEYS = {
    "random": {"n": None, "seeds": 0},
    "graph": {"n": None, "seeds": 0, "virtual": -1},
    "grid": {"rows": None, "cols": None},
    "star": {"n": None},
}


# ---------------------------------------------------------------- questions


@dataclass(frozen=True)
class Question:
    """One coverage question of the grid: a robot limit, or a deadline factor.

    ``factor`` None with ``robots`` None is the paper's question (no deadline: the
    least possible makespan).
    """

    robots: int | None = None
    factor: float | None = None

    @property
    def label(self) -> str:
        if self.robots is not None:
            return f"robots<={self.robots}"
        return "deadline=least" if self.factor is None else f"deadline={self.factor!r}*least"

    @classmethod
    def from_label(cls, label: str) -> Question:
        """The question whose :attr:`label` is ``label``."""
        if label.startswith("robots<="):
            return cls(robots=int(label.removeprefix("robots<=")))
        if label == "deadline=least":
            return cls()
        return cls(factor=float(label.removeprefix("deadline=").removesuffix("*least")))

    def deadline(self, instance: Instance, routes: RoutesKind) -> float | None:
        """The deadline passed to :func:`parcover.solve` (None: the paper's question)."""
        if self.factor is None:
            return None
        return self.factor * Problem(routes).least_makespan(instance)


def questions(robots: Iterable[int], deadlines: Iterable[str | float]) -> list[Question]:
    """The grid's questions: one per robot limit, one per deadline (``"least"`` or a factor)."""
    found = [Question(robots=_whole(k, "robot limit", 1)) for k in robots]
    found += [Question() if d == "least" else Question(factor=_deadline_factor(d)) for d in deadlines]
    if not found:
        raise InputError("No questions: give robot limits or deadlines.")
    if len({q.label for q in found}) != len(found):
        raise InputError("The same question is asked twice.")
    return found


def _deadline_factor(text: str | float) -> float:
    """A positive factor of the least makespan, from a number or its text (``"1.2"``)."""
    try:
        factor = float(text) if isinstance(text, str) else text
    except ValueError:
        factor = None
    if isinstance(factor, bool) or not isinstance(factor, (int, float)) or not (math.isfinite(factor) and factor > 0):
        raise InputError(f"A deadline must be 'least' or a positive factor of it, got {text!r}.")
    return float(factor)


# ---------------------------------------------------------------- instances


def parse_spec(spec: str) -> list[Instance]:
    """Instances of a generator spec such as ``random:n=6..10:seeds=0..4``.

    Grammar: ``KIND(:KEY=VALUES)*`` with KIND one of ``random`` (keys ``n``,
    ``seeds``), ``graph`` (``n``, ``seeds``, ``virtual``), ``grid`` (``rows``,
    ``cols``), ``star`` (``n``); VALUES a whole number, a range ``A..B`` (inclusive)
    or a comma list. One instance per combination of values, in the order written
    (:mod:`parcover.generate`, seeds given explicitly).

    Raises
    ------
    InputError
        With one line naming what is wrong in the spec, or how much memory its
        instances would need when that is more than there is (before building any).
    """
    kind, values = _spec_values_by_key(spec)
    _check_spec_memory(spec, kind, values, 0)
    return _spec_instances(kind, values)


def _spec_values_by_key(spec: str) -> tuple[str, dict[str, Sequence[int]]]:
    """The generator of a spec and the values of each of its keys, defaults filled in."""
    kind, *parts = spec.strip().split(":")
    if kind not in _GENERATOR_KEYS:
        raise InputError(f"Unknown generator {kind!r} in {spec!r}; expected one of {', '.join(_GENERATOR_KEYS)}.")
    values: dict[str, Sequence[int]] = {}
    for part in parts:
        key, sep, text = part.partition("=")
        if not sep or key not in _GENERATOR_KEYS[kind]:
            raise InputError(
                f"Bad part {part!r} in {spec!r}; {kind} takes {', '.join(k + '=...' for k in _GENERATOR_KEYS[kind])}."
            )
        if key in values:
            raise InputError(f"{key!r} is given twice in {spec!r}.")
        values[key] = _spec_values(text, spec)
    for key, default in _GENERATOR_KEYS[kind].items():
        if key not in values:
            if default is None:
                raise InputError(f"{spec!r} lacks {key}=...; {kind} needs it.")
            values[key] = [default]
    return kind, values


def _spec_instances(kind: str, values: dict[str, Sequence[int]]) -> list[Instance]:
    """One generated instance per combination of ``values``, the first key varying slowest."""
    from parcover import generate

    build = {
        "random": lambda n, seeds: generate.random_points(n, seeds),
        "graph": lambda n, seeds, virtual: generate.random_graph(n, seeds, virtual=None if virtual < 0 else virtual),
        "grid": lambda rows, cols: generate.grid(rows, cols),
        "star": lambda n: generate.star(n),
    }[kind]
    keys = list(_GENERATOR_KEYS[kind])
    return [build(**dict(zip(keys, combo))) for combo in itertools.product(*(values[k] for k in keys))]


def _check_spec_memory(spec: str, kind: str, values: dict[str, Sequence[int]], kept: int) -> int:
    """Refuse a spec whose instances, on top of ``kept`` bytes of instances already
    loaded, need more memory than there is; else the bytes its instances keep.

    The instances are kept together, each built in turn (:func:`parcover.generate.footprint`).
    A first check with every instance as small as the smallest refuses a spec of
    billions of instances at once; then the sizes are summed (seeds do not change them).
    """
    from parcover import generate
    from parcover.memory import check_memory

    def footprint(sizes: dict[str, int]) -> Footprint:
        if kind == "graph" and sizes["virtual"] < 0:
            sizes = {**sizes, "virtual": 2 * sizes["n"]}
        return generate.footprint(kind, **sizes)

    keys = [k for k in _GENERATOR_KEYS[kind] if k != "seeds"]
    copies = len(values.get("seeds", [0]))
    count = copies * math.prod(len(values[k]) for k in keys)
    what = f"{spec!r} ({count} instance{'s' if count != 1 else ''})"
    least = footprint({k: values[k][0] if isinstance(values[k], range) else min(values[k]) for k in keys})
    check_memory(kept + count * least.kept + least.peak - least.kept, what)
    total, peak = kept, 0
    for combo in itertools.product(*(values[k] for k in keys)):
        each = footprint(dict(zip(keys, combo)))
        total += copies * each.kept
        peak = max(peak, each.peak - each.kept)
    check_memory(total + peak, what)
    return total - kept


def load_instances(instances: InstanceInput | Iterable[InstanceInput]) -> list[Instance]:
    """Instances from :class:`Instance` objects, files, folders (their ``.json`` and
    ``.tsp`` files, sorted) and generator specs (:func:`parse_spec`), in order.

    Raises
    ------
    InputError
        On a missing file, a bad spec, no instance at all, two instances with
        one name (rows are keyed by name), or more instances than memory holds
        (a spec is refused before any of its instances is built).
    """
    from parcover.io import read_instance
    from parcover.memory import check_memory, footprint_of

    items = [instances] if isinstance(instances, (Instance, str, os.PathLike)) else list(instances)
    found: list[Instance] = []
    kept = 0
    for item in items:
        loaded: Iterable[Instance]
        if isinstance(item, Instance):
            loaded = [item]
        elif Path(item).is_dir():
            files = sorted(p for p in Path(item).iterdir() if p.suffix.lower() in (".json", ".tsp"))
            loaded = (read_instance(p) for p in files)  # each counted before the next is read
        elif Path(item).is_file():
            loaded = [read_instance(item)]
        elif isinstance(item, str) and item.split(":")[0] in _GENERATOR_KEYS:
            kind, values = _spec_values_by_key(item)
            kept += _check_spec_memory(item, kind, values, kept)
            found += _spec_instances(kind, values)
            continue
        else:
            raise InputError(f"{str(item)!r} is neither a file, a folder nor a generator spec.")
        for instance in loaded:
            kept += footprint_of(instance).kept
            check_memory(kept, f"Loading the instances up to {instance.name!r}")
            found.append(instance)
    if not found:
        raise InputError("No instances given.")
    names = [inst.name for inst in found]
    twice = sorted({name for name in names if names.count(name) > 1})
    if twice:
        raise InputError(f"Two instances are named {twice[0]!r}; rows are keyed by instance name.")
    return found


# ---------------------------------------------------------------- one task


@dataclass(frozen=True)
class _Task:
    """Everything a worker needs for one instance x route kind (picklable)."""

    instance: dict[str, Any]  # parcover.io.instance_to_dict form: Instance itself does not pickle
    routes: RoutesKind
    questions: tuple[Question, ...]
    methods: tuple[MethodInfo, ...]
    reference: MethodInfo
    time_limit: float | None
    seed: int
    done: frozenset[tuple[str, str]]  # (question label, method) units already in the CSV

    def units(self) -> list[tuple[Question, MethodInfo]]:
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
    result: Result, question: Question, instance: Instance, routes: RoutesKind
) -> list[tuple[str, int | None, float | None]]:
    """The questions ``result`` is compared on: (compared, robot limit, deadline).

    One, as asked; two when the method dropped the deadline (module docstring).
    """
    if result.objective == "robots" and result.deadline is None and result.has_routes:
        return [(ROBOTS_AT_MAKESPAN, None, result.makespan), (MAKESPAN_AT_ROBOTS, result.robots, None)]
    return [(AS_ASKED, question.robots, question.deadline(instance, routes))]


def _row(
    task: _Task, instance: Instance, question: Question, result: Result, compared: str, reference: Result
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
        The exact method giving ``optimum`` (module docstring).
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
    grid: list[Question],
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
    from milp.orphans import exit_with_parent

    # Workers end with this process, whatever ends it (SIGKILL included): no orphans.
    context = multiprocessing.get_context()
    parent = None if context.get_start_method() == "forkserver" else os.getpid()
    pool = concurrent.futures.ProcessPoolExecutor(
        max_workers=workers, mp_context=context, initializer=exit_with_parent, initargs=(parent,)
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


def _progress_bar(total: int, progress: bool | None) -> Any:
    from tqdm import tqdm

    show = sys.stderr.isatty() if progress is None else progress
    return tqdm(total=total, disable=not show, file=sys.stderr, unit="question", desc="gaps")


# ---------------------------------------------------------------- rows and CSV


def _empty() -> pd.DataFrame:
    return _frame([])


def _frame(rows: list[dict[str, Any]]) -> pd.DataFrame:
    """Rows as a DataFrame with the dtypes of :data:`COLUMNS`."""
    frame = pd.DataFrame(rows, columns=list(COLUMNS))
    return _typed(frame)


def _typed(frame: pd.DataFrame) -> pd.DataFrame:
    """A copy of ``frame`` with the dtypes of :data:`COLUMNS`."""
    frame = frame.copy()
    for name, dtype in COLUMNS.items():
        if dtype == "float64":
            frame[name] = pd.to_numeric(frame[name], errors="coerce").astype("float64")
        elif dtype == "Int64":
            frame[name] = pd.to_numeric(frame[name], errors="coerce").astype("Int64")
        elif dtype == "bool":
            frame[name] = frame[name].map(lambda x: str(x) == "True").astype("bool")
        elif dtype == "str":
            frame[name] = frame[name].astype(_STRING_DTYPE)
        else:
            frame[name] = frame[name].astype(dtype)
    return frame


def read_gaps(path: str | os.PathLike[str]) -> pd.DataFrame:
    """Read a gaps.csv back, with the dtypes of :data:`COLUMNS`.

    Rows cut short by an interrupt (a missing ``seconds``) are dropped.
    """
    path = Path(path)
    try:
        frame = pd.read_csv(path, dtype={k: _STRING_DTYPE for k, v in COLUMNS.items() if v == "str"})
    except pd.errors.EmptyDataError:
        return _empty()
    except (OSError, pd.errors.ParserError) as exc:
        raise InputError(f"{path}: cannot be read as gaps.csv ({exc}).") from None
    if list(frame.columns) != list(COLUMNS):
        raise InputError(f"{path}: not a gaps.csv (columns differ).")
    frame = frame[frame["seconds"].notna()]
    return _typed(frame).reset_index(drop=True)


def _kept_rows(csv_path: str | os.PathLike[str], settings: dict[str, Any]) -> pd.DataFrame:
    """Rows of an earlier run to keep: those of complete (question, method) units.

    Raises InputError when the file was made with other settings.
    """
    path = Path(csv_path)
    if not path.exists():
        return _empty()
    frame = read_gaps(path)
    for key, value in settings.items():
        column = frame[key]
        wrong = column.notna() if value is None else (column.isna() | (column != value))
        if wrong.any():
            raise InputError(f"{path} holds rows made with another {key.replace('_', ' ')}; use a new file.")
    return frame[_complete_units(frame)].reset_index(drop=True)


def _complete_units(frame: pd.DataFrame) -> pd.Series:
    """Rows whose (question, method) unit has all its rows: the asked one, or both
    rows of a dropped deadline."""
    def complete(compared: pd.Series) -> bool:
        seen = set(compared)
        return AS_ASKED in seen or {ROBOTS_AT_MAKESPAN, MAKESPAN_AT_ROBOTS} <= seen

    if frame.empty:
        return pd.Series([], dtype="bool")
    return frame.groupby(_UNIT_KEY, sort=False)["compared"].transform(complete).astype("bool")


class _CsvSink:
    """Appends rows to the CSV as they come, flushed (an interrupt loses only rows in flight)."""

    def __init__(self, path: str | os.PathLike[str] | None, kept: pd.DataFrame) -> None:
        self.path = None if path is None else Path(path)
        self.rows: list[dict[str, Any]] = []
        if self.path is not None:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            _write_csv_atomically(kept, self.path)

    def write(self, rows: list[dict[str, Any]]) -> None:
        self.rows += rows
        if self.path is None or not rows:
            return
        text = _frame(rows).to_csv(index=False, header=False)
        with self.path.open("a", encoding="utf-8", newline="") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())


def _write_csv_atomically(frame: pd.DataFrame, path: Path) -> None:
    temporary = path.with_name(path.name + ".tmp")
    frame.to_csv(temporary, index=False)
    os.replace(temporary, path)


def _sort_order(
    insts: list[Instance], kinds: Sequence[str], grid: list[Question], infos: Sequence[MethodInfo]
) -> dict[str, dict[str, int]]:
    """Position of each key value in the request: the sort order of the rows."""
    return {
        "instance": {inst.name: i for i, inst in enumerate(insts)},
        "routes": {k: i for i, k in enumerate(kinds)},
        "question": {q.label: i for i, q in enumerate(grid)},
        "method": {m.name: i for i, m in enumerate(infos)},
        "compared": {c: i for i, c in enumerate((AS_ASKED, ROBOTS_AT_MAKESPAN, MAKESPAN_AT_ROBOTS))},
    }


def _sorted(frame: pd.DataFrame, order: dict[str, dict[str, int]]) -> pd.DataFrame:
    keys = pd.DataFrame({k: frame[k].map(pos).astype("float64") for k, pos in order.items()})
    index = keys.sort_values(list(order), kind="stable", na_position="last").index
    return frame.loc[index].reset_index(drop=True)


def _check_request(frame: pd.DataFrame, order: dict[str, dict[str, int]], path: Any) -> None:
    """Refuse a CSV holding rows of another request (they would be silently mixed in)."""
    for key, pos in order.items():
        stray = ~frame[key].isin(list(pos))
        if stray.any():
            first = frame[key][stray].iloc[0]
            raise InputError(f"{path} holds rows of another request ({key} {first!r}); use a new file.")


# ---------------------------------------------------------------- report.md


def summary_table(frame: pd.DataFrame) -> pd.DataFrame:
    """Per route kind, objective and method: rows, mean / median / max ``gap_to_optimum``
    (over rows that have one) and how often the method is at the optimum."""
    groups = frame.groupby(["routes", "objective", "method"], sort=False)
    table = groups.agg(
        rows=("gap_to_optimum", "size"),
        with_gap=("gap_to_optimum", "count"),
        mean_gap=("gap_to_optimum", "mean"),
        median_gap=("gap_to_optimum", "median"),
        max_gap=("gap_to_optimum", "max"),
        at_optimum=("at_optimum", "sum"),
    )
    return table.reset_index()


def render_report(
    frame: pd.DataFrame, meta: dict[str, Any], plots: Sequence[tuple[str, str]] = (), worst_cases: int = 3
) -> str:
    """The text of report.md: header with the run's metadata, summary tables, the
    worst cases, plots."""
    regenerate = ["Regenerate with:", "", f"    {meta['command']}", ""] if meta.get("command") else []
    lines = ["# Optimality gaps", "", *regenerate, *_header_lines(meta), "", "## Summary", ""]
    lines += [
        "Gap = (value - optimum) / optimum, in percent, against the reference's proven optimum",
        "(or its best bound when it did not prove one). *At optimum*: rows whose value meets a",
        "proven optimum. A method that dropped the deadline is compared twice: its robots at the",
        "makespan it reached, and its makespan with its robots (column `compared` of gaps.csv).",
        "",
    ]
    table = summary_table(frame)
    for (kind, objective), part in table.groupby(["routes", "objective"], sort=False):
        lines += [f"### {kind}, objective {objective}", "", *_markdown_table(part), ""]
    statuses = frame.groupby("reference_status").size()
    lines += ["Reference status counts: " + ", ".join(f"{s} {c}" for s, c in statuses.items()) + ".", ""]
    worst = worst_rows(frame, worst_cases)
    if not worst.empty:
        lines += [
            "## Worst cases",
            "",
            "| instance | routes | question | method | compared | value | optimum | gap % |",
            "|---|---|---|---|---|---:|---:|---:|",
        ]
        lines += [
            f"| {r.instance} | {r.routes} | {r.question} | {r.method} | {r.compared} | {r.value:.6g} "
            f"| {r.optimum:.6g} | {_percent(r.gap_to_optimum)} |"
            for r in worst.itertuples(index=False)
        ]
        lines.append("")
    if plots:
        lines += ["## Plots", ""]
        lines += [f"![{caption}]({name})" for caption, name in plots]
        lines.append("")
    return "\n".join(lines)


def _header_lines(meta: dict[str, Any]) -> list[str]:
    machine = meta["machine"]
    versions = ", ".join(f"{k} {v}" for k, v in meta["versions"].items())
    return [
        f"- parcover {meta['parcover']}; {versions}",
        f"- methods: {', '.join(meta['methods'])}; reference: {meta['reference']}",
        f"- instances: {', '.join(map(str, meta['instances']))}",
        f"- routes: {', '.join(meta['routes'])}; robots: {meta['robots']}; deadlines: {meta['deadlines']}",
        f"- time limit: {meta['time_limit']} s per solve; seed: {meta['seed']}",
        f"- machine: {machine['cpu']}, {machine['cores']} cores, {machine['memory_gb']} GB, {machine['platform']}",
    ]


def _markdown_table(part: pd.DataFrame) -> list[str]:
    head = "| method | rows | with gap | mean gap % | median gap % | max gap % | at optimum |"
    lines = [head, "|---|---:|---:|---:|---:|---:|---:|"]
    for r in part.itertuples(index=False):
        share = f"{r.at_optimum}/{r.rows} ({100 * r.at_optimum / r.rows:.0f}%)"
        lines.append(
            f"| {r.method} | {r.rows} | {r.with_gap} | {_percent(r.mean_gap)} | {_percent(r.median_gap)} "
            f"| {_percent(r.max_gap)} | {share} |"
        )
    return lines


def _percent(x: float) -> str:
    return "-" if pd.isna(x) else f"{100 * x:.2f}"


# ---------------------------------------------------------------- metadata


def run_metadata(**settings: Any) -> dict[str, Any]:
    """Versions of parcover and its solvers, the run's settings, and the machine."""
    import parcover

    return {
        "parcover": parcover.__version__,
        "versions": {name: package_version(name) for name in ("highspy", "cvxpy", "numpy", "scipy", "pandas")},
        **settings,
        "machine": machine_info(),
    }


def machine_info() -> dict[str, Any]:
    """CPU model (``/proc/cpuinfo``), cores, memory (``/proc/meminfo``), platform."""
    return {
        "cpu": _proc_field("/proc/cpuinfo", "model name") or platform.processor() or "unknown",
        "cores": os.cpu_count(),
        "memory_gb": _memory_gb(),
        "platform": platform.platform(),
        "python": platform.python_version(),
    }


def _proc_field(path: str, field: str) -> str | None:
    try:
        text = Path(path).read_text(encoding="utf-8", errors="replace")
    except OSError:
        return None
    for line in text.splitlines():
        key, sep, value = line.partition(":")
        if sep and key.strip() == field:
            return value.strip()
    return None


def _memory_gb() -> float | None:
    total = _proc_field("/proc/meminfo", "MemTotal")  # "16318420 kB"
    if not total:
        return None
    return round(int(total.split()[0]) / 2**20, 1)


def package_version(name: str) -> str | None:
    """The installed version of distribution ``name``, or None when it is not installed."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version(name)
    except PackageNotFoundError:
        return None


# ---------------------------------------------------------------- write_report


def write_report(
    instances_spec: InstanceInput | Iterable[InstanceInput],
    out_dir: str | os.PathLike[str],
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
    plots: bool = True,
    worst_cases: int = 3,
    command: str | None = None,
) -> Path:
    """Run :func:`gaps` into ``out_dir`` (resuming from its gaps.csv) and write
    ``report.md``, ``meta.json`` and PNG plots there.

    Parameters
    ----------
    instances_spec, methods
        As ``instances`` and ``methods`` of :func:`gaps`; so are the keywords up to
        ``progress``.
    out_dir
        The folder (created when missing). Its ``gaps.csv`` is resumed.
    plots
        Draw the PNGs with :mod:`parcover.plot` (:func:`draw_plots`).
    worst_cases
        How many of the largest gaps report.md lists and draws.
    command
        The command line that regenerates the report, shown at its top and kept in
        meta.json.

    Returns
    -------
    Path
        ``out_dir / "report.md"``.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    items = [instances_spec] if isinstance(instances_spec, (Instance, str, os.PathLike)) else list(instances_spec)
    names = [methods] if isinstance(methods, str) else list(methods)
    options = dict(
        routes=routes, robots=robots, deadlines=deadlines, reference=reference, time_limit=time_limit, seed=seed
    )
    frame = gaps(
        items, names, **options, workers=workers, scheduler=scheduler, progress=progress, csv_path=out / "gaps.csv"
    )
    meta = run_metadata(
        instances=[s.name if isinstance(s, Instance) else str(s) for s in items],
        instance_names=list(dict.fromkeys(frame["instance"])),
        methods=names,
        **{k: list(v) if isinstance(v, (list, tuple)) else v for k, v in options.items()},
    )
    if command:
        meta["command"] = command
    (out / "meta.json").write_text(json.dumps(meta, indent=2) + "\n", encoding="utf-8")
    drawn = []
    if plots:
        if sys.stderr.isatty() if progress is None else progress:
            print(f"report: drawing the plots (the largest instance's frontiers, solved by {reference}; "
                  f"the {worst_cases} largest gaps) ...", file=sys.stderr, flush=True)
        drawn = draw_plots(frame, load_instances(items), out, reference, time_limit, seed, worst_cases)
    path = out / "report.md"
    path.write_text(render_report(frame, meta, drawn, worst_cases), encoding="utf-8")
    return path


def worst_rows(frame: pd.DataFrame, count: int) -> pd.DataFrame:
    """The ``count`` rows farthest above a proven optimum (ties: table order)."""
    proven = frame[(frame["reference_status"] == "optimal") & frame["gap_to_optimum"].gt(0)]
    return proven.sort_values("gap_to_optimum", ascending=False, kind="stable").head(count)


def draw_plots(
    frame: pd.DataFrame,
    insts: list[Instance],
    out: Path,
    reference: str,
    time_limit: float | None,
    seed: int,
    worst_cases: int,
) -> list[tuple[str, str]]:
    """Draw the report's PNGs with :mod:`parcover.plot`; (caption, file name) pairs.

    Calls, each with the PNG's path last: ``plot_gap_distribution(frame, path)``;
    for each route kind, on the instance of its largest gap,
    ``plot_frontier(frontier, points, path)`` (the reference's
    :class:`~parcover.result.Frontier` and ``{method: [(robots, makespan), ...]}``
    from the rows); for each of the ``worst_cases`` largest gaps,
    ``plot_route_comparison(instance, method_result, reference_result, path)``.
    A function :mod:`parcover.plot` lacks, or one that fails, is skipped with a
    logged warning: the rows are already safe in gaps.csv.
    """
    plot = _plot_module()
    if plot is None:
        return []
    by_name = {inst.name: inst for inst in insts}
    drawn: list[tuple[str, str]] = []

    def draw(caption: str, name: str, render: Callable[[Path], None]) -> None:
        try:
            render(out / name)
        except Exception as exc:  # a drawing must not cost the report
            log.warning("Skipping %s: %s: %s.", name, type(exc).__name__, exc)
            return
        drawn.append((caption, name))

    draw("Gap distribution per method", "gaps.png", lambda path: plot.plot_gap_distribution(frame, path))
    for kind in dict.fromkeys(frame["routes"]):
        worst_of_kind = worst_rows(frame[frame["routes"] == kind], 1)
        if worst_of_kind.empty:
            continue
        name = worst_of_kind["instance"].iloc[0]

        def render_frontier(path: Path, name: str = name, kind: RoutesKind = kind) -> None:
            curve, points = _frontier_args(by_name[name], kind, frame, reference, time_limit, seed)
            plot.plot_frontier(curve, path, points=points, unit=plot.distance_unit(by_name[name]))

        draw(f"Frontier of {name} ({kind}) with each method's point", f"frontier-{name}-{kind}.png", render_frontier)
    worst = worst_rows(frame, worst_cases)
    for rank, row in enumerate(worst.itertuples(index=False), start=1):

        def render_comparison(path: Path, row: Any = row, rank: int = rank) -> None:
            instance, greedy, optimal = _comparison_args(by_name[row.instance], row, reference, time_limit, seed)
            captions = [f"worst case {rank}: {row.method}, {row.gap_to_optimum:.1%} above the optimum",
                        f"the reference, {reference}"]
            plot.plot_side_by_side(instance, [greedy, optimal], path, captions)

        draw(
            f"Worst case {rank}: {row.method} against {reference} on {row.instance} ({row.routes}, {row.question})",
            f"worst-{rank}.png",
            render_comparison,
        )
    return drawn


def _plot_module() -> Any:
    try:
        from parcover import plot
    except ImportError as exc:
        log.warning("No plots: %s.", exc)
        return None
    return plot


def _frontier_args(
    instance: Instance, kind: RoutesKind, frame: pd.DataFrame, reference: str, time_limit: float | None, seed: int
) -> tuple[Any, ...]:
    """(frontier by the reference, {method: [(robots, makespan), ...]}) for one instance."""
    from parcover.frontier import frontier

    curve = frontier(instance, kind, method=reference, time_limit=time_limit, seed=seed)
    rows = frame[(frame["instance"] == instance.name) & (frame["routes"] == kind) & frame["makespan"].notna()]
    points = {
        method: sorted({(int(r), float(m)) for r, m in zip(part["robots"], part["makespan"])})
        for method, part in rows.groupby("method", sort=False)
    }
    return curve, points


def _comparison_args(
    instance: Instance, row: Any, reference: str, time_limit: float | None, seed: int
) -> tuple[Any, ...]:
    """(instance, the method's result on its question, the reference's on the row's)."""
    from parcover.solve import solve

    asked = Question.from_label(row.question)
    greedy = solve(
        instance, row.routes, robots=asked.robots, deadline=asked.deadline(instance, row.routes),
        method=row.method, time_limit=time_limit, seed=seed,
    )
    robots = None if pd.isna(row.robots_limit) else int(row.robots_limit)
    deadline = None if row.objective == "makespan" else float(row.deadline)
    optimal = solve(
        instance, row.routes, robots=robots, deadline=deadline, method=reference, time_limit=time_limit, seed=seed
    )
    return instance, greedy, optimal


# ---------------------------------------------------------------- small helpers


def _spec_values(text: str, spec: str) -> Sequence[int]:
    """``7``, ``6..10`` (inclusive, a ``range``: not built) or ``1,3,5`` as whole numbers."""
    try:
        if ".." in text:
            low, high = (int(x) for x in text.split(".."))
            if high < low:
                raise ValueError
            return range(low, high + 1)
        return [int(x) for x in text.split(",")]
    except ValueError:
        raise InputError(f"Bad value {text!r} in {spec!r}; expected N, A..B or a list A,B,C.") from None


def _whole(value: Any, what: str, least: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < least:
        raise InputError(f"The {what} must be a whole number >= {least}, got {value!r}.")
    return value
