"""The min-max multiple-TSP literature: the Necula cells, our value and certified bound.

Instances eil51, berlin52, eil76 and rat99 (TSPLIB, ``instances/tsplib/``,
read with exact Euclidean distances, node 1 the start) with m = 2, 3, 5, 7 tours (Necula,
Breaban and Raschip, ICTAI 2015). Each cell gets 10 minutes:

- our value and the exact method's bound: ``parcover.solve(..., method=BEST)`` (:data:`BEST`) for
  :data:`BEST_SECONDS`, then ``parcover.solve(..., method="exact")`` from its tours (at
  these sizes branch-and-price, :mod:`milp.branchprice`, raced against branch-and-cut,
  :mod:`milp.branchcut`, with 2 and 3 tours) with :data:`EXACT_SECONDS`
  (exact's own warm start, 200 rounds of ``best``, is far weaker on routes of 25-50
  KPOIs: berlin52 m = 2 4342.6 against 4110.2 after 60 s of ``best``);
- our certified lower bound: the largest of that bound, ``2 c_max``, the spanning-tree
  and Held-Karp bounds (:func:`milp.bounds.makespan_lower_bound`) and, when the cell is
  not proven yet,
  the column-generation bound over q-routes (:func:`milp.branchprice.colgen.makespan_bound`, at most
  :data:`BOUND_SECONDS`), which stays cheap where branch-and-price's pricing of long
  routes (m = 2, 3) does not finish;
- proven optimal when the value is within 1e-6 relative of the bound;
- beside the published CPLEX lower / upper bounds (runs of up to 168 hours) and the best
  known value (``instances/mtsp/minmax_best_known_summary.csv``).
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pandas as pd

import parcover
from benchmarks.common import ROOT, Config, Section, markdown_table
from milp import bounds
from milp.branchprice import colgen
from parcover.io import read_instance

INSTANCES = ("eil51", "berlin52", "eil76", "rat99")
ROBOTS = (2, 3, 5, 7)
QUICK_CELLS = (("eil51", 5),)
#: The warm start's method: ``best`` spending all of :data:`BEST_SECONDS` (plain ``best``
#: stops at convergence, after 2-20 s on these cells, a weaker start: milp/README.md).
BEST = "best:until=limit"
#: Seconds per cell for ``best``, the exact method and the column-generation bound (full
#: run): 10 minutes a cell in all.
BEST_SECONDS, EXACT_SECONDS, BOUND_SECONDS = 60.0, 420.0, 120.0
QUICK_BEST_SECONDS, QUICK_EXACT_SECONDS, QUICK_BOUND_SECONDS = 1.0, 3.0, 3.0
#: Relative tolerance for "proven optimal".
PROVEN_TOL = 1e-6
REFERENCE = ROOT / "instances" / "mtsp" / "minmax_best_known_summary.csv"


def reference_values() -> pd.DataFrame:
    """Published CPLEX bounds and best-known values per (instance, m)."""
    table = pd.read_csv(REFERENCE)
    table = table.rename(columns={
        "necula_cplex_lower_bound": "cplex_lb", "necula_cplex_upper_bound": "cplex_ub",
        "best_verified_max_route_unrounded": "best_known"})
    return table[["instance", "m", "cplex_lb", "cplex_ub", "best_known"]]


def solve_cell(name: str, m: int, best_seconds: float, exact_seconds: float, bound_seconds: float,
               tours_dir: Path | None = None) -> dict:
    """Our value, bounds and times on one cell (tours, ``m`` robots); with ``tours_dir``,
    our verified tours are written there as ``<name>-m<m>.json`` (a result JSON that
    ``parcover verify instances/tsplib/<name>.tsp FILE`` checks)."""
    inst = read_instance(ROOT / "instances" / "tsplib" / f"{name}.tsp")
    D = np.array(inst.distances)
    began = time.perf_counter()
    start = parcover.solve(inst, routes="tours", robots=m, method=BEST, time_limit=best_seconds)
    best_time = time.perf_counter() - began
    result = parcover.solve(inst, routes="tours", robots=m, method="exact", time_limit=exact_seconds,
                            warm_start=start.routes)
    exact_time = time.perf_counter() - began - best_time
    if tours_dir is not None:
        tours_dir.mkdir(parents=True, exist_ok=True)
        (tours_dir / f"{name}-m{m}.json").write_text(result.to_json() + "\n")
    value = float(result.makespan)
    exact_bound = float(result.bound or 0.0)
    trivial = 2.0 * float(D[0, 1:].max())
    tree = bounds.makespan_lower_bound(D, m, tours=True)
    bound = max(trivial, tree, exact_bound)
    cg, cg_time = np.nan, 0.0
    if value > bound * (1 + PROVEN_TOL):
        info = colgen.makespan_bound(D, m, tours=True, upper=value, time_limit=bound_seconds)
        cg, cg_time = info.bound, info.seconds
        bound = max(bound, cg)
    return {"instance": name, "m": m, "kpois": inst.n, "value": value, "2 c_max": trivial,
            "tree bound": tree, "exact bound": exact_bound, "colgen bound": cg, "bound": bound,
            "proven": bool(value <= bound * (1 + PROVEN_TOL)),
            "model": result.info.get("model", ""), "best s": best_time, "exact s": exact_time,
            "bound s": cg_time}


def cells_table(rows: list[dict]) -> pd.DataFrame:
    """Our rows joined with the published values, with the comparisons."""
    frame = pd.DataFrame(rows).merge(reference_values(), on=["instance", "m"], how="left")
    frame["bound >= CPLEX"] = frame["bound"] >= frame["cplex_lb"]
    frame["value vs best %"] = 100.0 * (frame["value"] / frame["best_known"] - 1.0)
    return frame


def targets(frame: pd.DataFrame, cells: int) -> list[str]:
    """The three targets with the figures reached (out of all 16 cells)."""
    above = int(frame["bound >= CPLEX"].sum())
    close = int((frame["value vs best %"] <= 0.5).sum())
    proven = int(frame["proven"].sum())
    scope = "" if len(frame) == cells else f" (only {len(frame)} cell(s) run: quick mode)"
    return [
        f"mTSP literature: certified lower bound >= CPLEX's on all 16 cells: "
        f"{'met' if above == cells else 'not met'}, {above}/{cells}{scope}",
        f"mTSP literature: value within 0.5% of best known: "
        f"{'met' if close == cells else 'not met'}, {close}/{cells}{scope}",
        f"mTSP literature: 10 or more cells proven optimal: "
        f"{'met' if proven >= 10 else 'not met'}, {proven}{scope}",
    ]


def run(config: Config) -> Section:
    """Solve and bound the Necula cells (one small cell with ``config.quick``)."""
    cells = QUICK_CELLS if config.quick else tuple((i, m) for i in INSTANCES for m in ROBOTS)
    best_s = QUICK_BEST_SECONDS if config.quick else BEST_SECONDS
    exact_s = QUICK_EXACT_SECONDS if config.quick else EXACT_SECONDS
    bound_s = QUICK_BOUND_SECONDS if config.quick else BOUND_SECONDS
    tours_dir, tours_link = config.figure("mtsp_tours")
    rows = []
    for name, m in cells:
        config.log(f"[mtsp_literature] {name} m={m}")
        rows.append(solve_cell(name, m, best_s, exact_s, bound_s, tours_dir))
        config.log(f"[mtsp_literature] {name} m={m}: {rows[-1]['value']:.6g} >= {rows[-1]['bound']:.6g}")
    frame = cells_table(rows)
    shown = frame[["instance", "m", "value", "bound", "proven", "cplex_lb", "cplex_ub",
                   "best_known", "bound >= CPLEX", "value vs best %", "2 c_max", "tree bound",
                   "exact bound", "colgen bound", "model", "best s", "exact s", "bound s"]]
    markdown = "\n".join([
        "Min-max multiple TSP with tours (Necula et al. 2015 cells: TSPLIB instances with exact "
        "Euclidean distances, node 1 the start). `value` and `exact bound`: "
        f"`parcover.solve(method=\"exact\")` with {exact_s:g} s from the tours of "
        f"`parcover.solve(method=\"{BEST}\")` with {best_s:g} s, all of them spent (`model`: the method that "
        "answered: branch-and-price, or with 2 and 3 tours whichever of branch-and-price and "
        "branch-and-cut (`milp.branchcut`, raced on the two cores) proved first); `bound`: our "
        "certified lower bound, the largest of `2 c_max`, the `tree bound` (the spanning-tree and "
        "Held-Karp bounds of `milp.bounds.makespan_lower_bound`), the exact "
        "method's bound and, for a cell not yet proven, the column-generation bound "
        "(`milp.branchprice.colgen`: set covering over q-routes with 2-cycle elimination, Farley's bound, "
        f"bisection on the makespan; at most {bound_s:g} s). `proven`: value within 1e-6 "
        "relative of the bound. `cplex_lb` / `cplex_ub`: Necula's published CPLEX bounds (runs "
        "of up to 168 hours); `best_known`: best verified value in `instances/mtsp/` (LKH-3 and "
        "Necula tours, recomputed). The CPLEX bounds are published to 2 decimals.",
        "",
        "A negative `value vs best %` means our tours are shorter than every verified solution "
        "in `instances/mtsp/`: those come from Necula's runs and from LKH-3 runs that optimised "
        "rounded (TSPLIB `nint`) distances, recomputed with exact ones. Our tours are in "
        f"[`{tours_link}/`]({tours_link}/), one result JSON per cell; check one with "
        f"`parcover verify instances/tsplib/{cells[-1][0]}.tsp reports/{tours_link}/"
        f"{cells[-1][0]}-m{cells[-1][1]}.json`.",
        "",
        f"Time: at most {best_s + exact_s + bound_s:g} s per cell (the issue allows 10 minutes); "
        f"{len(cells)} cell(s) here, "
        f"{frame['best s'].sum() + frame['exact s'].sum() + frame['bound s'].sum():.0f} s in all.",
        "",
        markdown_table(shown, floatfmt=".5g"),
    ])
    return Section("The min-max multiple-TSP literature (Necula cells, tours)", markdown,
                   tables={"mtsp_literature": frame}, targets=targets(frame, 16))
