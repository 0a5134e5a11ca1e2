"""Exact targets: the exact methods' scale targets on the grid's seeds and on seeds never tuned on.

The cells the targets name (least makespan for n = 30, k = 3 and n = 40, k = 5
within 60 s; fewest robots for n = 50 within 1.0 and 1.2 x the least makespan within
10 s; paths and tours), each on the seeds of the exact-scaling grid (1-3, used while
designing branch-and-price) and on unseen seeds (11-13), solved in the same run by
``parcover``'s default ``exact`` (branch-and-price at these sizes, raced against
branch-and-cut for the least makespan with 3 robots when it has not proved it within
2 s) and by the compact model as the peer (ratio: compact's
seconds over ours, :func:`benchmarks.exact_scaling.ratio`). Quick: n = 12-16, 3 s.
"""

from __future__ import annotations

import pandas as pd

from benchmarks.common import Config, Section, euclidean_points, markdown_table
from benchmarks.exact_scaling import _cells_target, ratio, solve_cell
from milp.core.routes import least_makespan
from parcover import Instance

GRID_SEEDS = (1, 2, 3)
UNSEEN_SEEDS = (11, 12, 13)
#: (n, objective, k or deadline factor, limit in seconds), each for paths and tours.
TARGETS = ((30, "makespan", 3, 60.0), (40, "makespan", 5, 60.0),
           (50, "robots", 1.0, 10.0), (50, "robots", 1.2, 10.0))
QUICK = ((12, "makespan", 3, 3.0), (16, "robots", 1.2, 3.0))
MODELS = ("exact", "compact")


def run(config: Config) -> Section:
    """Every target cell on both seed sets, both models; the table and the target lines."""
    rows = []
    targets = QUICK if config.quick else TARGETS
    seeds = ((1,), ()) if config.quick else (GRID_SEEDS, UNSEEN_SEEDS)
    cells = [(n, objective, value, limit, seed, routes, "grid" if seed in seeds[0] else "unseen")
             for n, objective, value, limit in targets for seed in seeds[0] + seeds[1]
             for routes in ("paths", "tours")]
    for number, (n, objective, value, limit, seed, routes, kind) in enumerate(cells, 1):
        instance = Instance.from_points(euclidean_points(n, seed))
        tours = routes == "tours"
        k = value if objective == "makespan" else None
        deadline = None if k is not None else value * least_makespan(instance.distances, tours=tours)
        problem = f"makespan k={k}" if k is not None else f"robots U={value:g} x least"
        for model in MODELS:
            config.log(f"[exact_targets] {number}/{len(cells)} n={n} seed={seed} {routes} {problem} {model}")
            out = solve_cell(instance, model, tours=tours, k=k, deadline=deadline, limit=limit)
            rows.append({"n": n, "seeds": kind, "seed": seed, "routes": routes, "problem": problem,
                         "model": model, "limit": limit, **out})
    frame = pd.DataFrame(rows)
    table = _table(frame)
    lines = _target_lines(frame)
    markdown = "\n\n".join([
        "The cells the exact issue sets targets on, each on the exact-scaling grid's seeds "
        f"({', '.join(map(str, GRID_SEEDS))}, used while designing branch-and-price) and on seeds "
        f"never used for tuning ({', '.join(map(str, UNSEEN_SEEDS))}); random Euclidean instances "
        "as in the exact-scaling section. Ours: `parcover solve`'s default `exact` (branch-and-price "
        "here, raced against branch-and-cut for the least makespan with 3 robots when it has not "
        "proved it in 2 s; warm start from `best` included in its seconds); peer in the same "
        "run: the compact arc-flow model (`--method compact`). The ratio is compact's seconds "
        "over ours (`>= L / ours` when compact did not prove within its limit L).",
        "### Targets by seed set",
        "\n".join(f"- {line}" for line in lines),
        "### Results",
        markdown_table(table),
    ])
    return Section("Exact targets", markdown, tables={"exact_targets": frame}, targets=lines)


def _table(frame: pd.DataFrame) -> pd.DataFrame:
    """One row per cell: our status and seconds, compact's, and the ratio."""
    out = []
    for key, cell in frame.groupby(["n", "problem", "seeds", "seed", "routes"], sort=False):
        by_model = {r["model"]: r for r in cell.to_dict("records")}
        mine, peer = by_model["exact"], by_model["compact"]
        out.append({**dict(zip(("n", "problem", "seeds", "seed", "routes"), key)),
                    "ours": _short(mine), "compact": _short(peer), "compact / ours": ratio(peer, mine)})
    return pd.DataFrame(out)


def _short(row: dict) -> str:
    """``optimal 3.2 s`` or ``feasible 118.4 (bound 112.4)``."""
    if row["status"] == "optimal":
        return f"optimal {row['seconds']:.1f} s"
    if row["objective"] is None or row["bound"] is None or pd.isna(row["objective"]) or pd.isna(row["bound"]):
        return str(row["status"])
    return f"{row['status']} {row['objective']:.6g} (bound {row['bound']:.6g})"


def _target_lines(frame: pd.DataFrame) -> list[str]:
    """One line per target and seed set, with every cell's outcome."""
    ours = frame[frame["model"] == "exact"]
    lines = []
    for (n, problem, limit), part in ours.groupby(["n", "problem", "limit"], sort=False):
        for kind, cells in part.groupby("seeds", sort=False):
            title = f"{problem}, n = {n}, {kind} seeds: proven within {limit:g} s"
            lines.append(_cells_target(cells, title, limit, lambda r: f"{r.routes} seed {r.seed}"))
    return lines
