"""The text of a gap report, report.md, from its rows and metadata.

:func:`summary_table` aggregates the gaps per route kind, objective and method,
:func:`worst_rows` picks the largest gaps above a proven optimum, and
:func:`render_report` writes the Markdown: the run's metadata, the summary tables, the
worst cases and the plots.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import pandas as pd


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


def worst_rows(frame: pd.DataFrame, count: int) -> pd.DataFrame:
    """The ``count`` rows farthest above a proven optimum (ties: table order)."""
    proven = frame[(frame["reference_status"] == "optimal") & frame["gap_to_optimum"].gt(0)]
    return proven.sort_values("gap_to_optimum", ascending=False, kind="stable").head(count)
