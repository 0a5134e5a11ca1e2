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

from parcover.report.machine import machine_info, run_metadata

# not in __all__, imported from here by the benchmarks
from parcover.report.machine import package_version as package_version
from parcover.report.plots import draw_plots
from parcover.report.render import render_report, summary_table, worst_rows
from parcover.report.run import gap_to_optimum, gaps
from parcover.report.spec import GridQuestion, load_instances, parse_spec, questions
from parcover.report.store import COLUMNS, TIMING_COLUMNS, read_gaps
from parcover.report.write import write_report

Question = GridQuestion  # the old name, kept importable (parcover.question.Question is the question block)

__all__ = [
    "COLUMNS",
    "TIMING_COLUMNS",
    "GridQuestion",
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
