"""A gap report's folder: :func:`write_report` runs :func:`~parcover.report.run.gaps`
into ``gaps.csv`` and writes ``meta.json``, the plots and ``report.md`` beside it.
"""

from __future__ import annotations

import json
import os
import sys
from collections.abc import Iterable, Sequence
from pathlib import Path

from parcover.instance import Instance
from parcover.report.machine import run_metadata
from parcover.report.plots import draw_plots
from parcover.report.render import render_report
from parcover.report.run import gaps
from parcover.report.spec import InstanceInput, load_instances
from parcover.result import RoutesKind


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
