"""The PNG plots of a gap report, drawn with :mod:`parcover.plot`.

:func:`draw_plots` draws the gap distribution, each route kind's frontier on the
instance of its largest gap, and the worst cases side by side with the reference; a
drawing that fails is skipped with a logged warning.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from pathlib import Path
from types import ModuleType
from typing import Any

import pandas as pd

from parcover.instance import Instance
from parcover.report.render import worst_rows
from parcover.report.spec import GridQuestion
from parcover.result import Frontier, Result, RoutesKind

log = logging.getLogger("parcover.report")  # the logger of the report, as before it was a package


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


def _plot_module() -> ModuleType | None:
    try:
        from parcover import plot
    except ImportError as exc:
        log.warning("No plots: %s.", exc)
        return None
    return plot


def _frontier_args(
    instance: Instance, kind: RoutesKind, frame: pd.DataFrame, reference: str, time_limit: float | None, seed: int
) -> tuple[Frontier, dict[str, list[tuple[int, float]]]]:
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
) -> tuple[Instance, Result, Result]:
    """(instance, the method's result on its question, the reference's on the row's)."""
    from parcover.solve import solve

    asked = GridQuestion.from_label(row.question)
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
