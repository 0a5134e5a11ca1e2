"""Exact scaling: time to a proven optimum, our exact methods against each other and peers.

On random Euclidean instances
(:func:`benchmarks.common.euclidean_points`) it runs, side by side in the same process
run, ``parcover``'s default ``exact`` (:func:`parcover.exact.exact`: above 20 KPOIs
branch-and-price, raced against branch-and-cut for the least makespan with 2-3 robots),
branch-and-price alone up to 20 KPOIs and the compact arc-flow model as ``parcover``'s
``branchprice`` and ``compact`` methods run them (warm start from ``best``,
:func:`parcover.exact.branch_and_price`, :func:`parcover.exact.compact`), set partitioning (:mod:`milp.setpart`,
small ``n``), the naive big-M MTZ and plain arc-flow models
(:mod:`benchmarks.naive_models`) and OR-Tools CP-SAT (:mod:`benchmarks.peers.cpsat`, in a
subprocess). Ratios: a peer's time over ours (:data:`OURS`); when the peer does not
prove within its limit ``L`` the ratio is a lower bound ``>= L / our time`` (shown
with ``>=``), and when ours does not prove either no ratio is given.
"""

from __future__ import annotations

import time

import numpy as np
import pandas as pd

from benchmarks import naive_models
from benchmarks.common import Config, Section, euclidean_points, markdown_table, run_peer
from milp import setpart
from milp.core.routes import least_makespan, makespan, route_cost, within
from parcover import Instance, Problem
from parcover import exact as parcover_exact
from parcover.problem import meets_bound

MODELS = ("exact", "branchprice", "compact", "setpart", "mtz", "plain", "cpsat")
#: The models run as parcover's methods run them (warm start from ``best`` included).
PARCOVER_MODELS = {"exact": parcover_exact.exact, "branchprice": parcover_exact.branch_and_price,
                   "compact": parcover_exact.compact}
#: Set partitioning enumerates 2^n subsets: only up to this many KPOIs.
SETPART_MAX = setpart.MAX_KPOIS
SIZES = (10, 15, 20, 25, 30, 40, 50)
SEEDS = (1, 2, 3)
#: (objective, k or deadline factor): least makespan with k robots, fewest robots within
#: factor x the least makespan.
PROBLEMS = (("makespan", 2), ("makespan", 3), ("makespan", 5), ("robots", 1.0), ("robots", 1.2))
#: Every seed for the cells the targets name (k = 3 paths, fewest robots on paths); seed 1
#: for the others.
TARGET_PROBLEMS = (("paths", "makespan", 3), ("tours", "makespan", 3), ("paths", "robots", 1.0),
                   ("paths", "robots", 1.2))
#: CP-SAT runs up to this many KPOIs (every seed to 20, seed 1 above).
CPSAT_MAX = 30
#: The naive models run on seed 1 at these sizes (they prove nothing beyond), on these
#: (routes, objective, k or factor) only: each runs to its limit where it cannot prove.
NAIVE_SIZES = (10, 15)
NAIVE_PROBLEMS = (("paths", "makespan", 3), ("tours", "makespan", 3), ("paths", "robots", 1.2))


def time_limit(n: int) -> float:
    """Seconds per model and cell: 60 at n = 30 (its target), 30 at n = 25, 20 otherwise."""
    return 60.0 if n == 30 else 30.0 if n == 25 else 20.0


#: Ours: ``parcover``'s default method at every size (it chooses among checks and models).
OURS = "exact"


def grid(quick: bool) -> list[dict]:
    """The cells run: problem, n, seed, route kind, k or deadline factor, models, limit.

    Full run: n in :data:`SIZES`, paths and tours, every problem of
    :data:`PROBLEMS`; every seed of :data:`SEEDS` for :data:`TARGET_PROBLEMS`, seed 1 for
    the rest. Branch-and-price and the compact model everywhere, set partitioning to :data:`SETPART_MAX`,
    CP-SAT to :data:`CPSAT_MAX`, the naive models on seed 1 at :data:`NAIVE_SIZES` (and
    at n = 20 for k = 3 paths, the plain one with 120 s for the '>= 20x' target).
    Quick: n = 8 and 10, 3 s limits.
    """
    if quick:
        return [dict(n=n, seed=1, routes="paths", k=3, factor=None, models=MODELS, limit=3.0)
                for n in (8, 10)] + [
            dict(n=8, seed=1, routes="tours", k=None, factor=1.2, models=MODELS, limit=3.0)]
    cells = []
    for n in SIZES:
        for routes in ("paths", "tours"):
            for objective, value in PROBLEMS:
                seeds = SEEDS if (routes, objective, value) in TARGET_PROBLEMS else SEEDS[:1]
                for seed in seeds:
                    models = ["exact", "compact"]
                    if n <= SETPART_MAX:
                        models += ["branchprice", "setpart"]
                    if n <= 20 or (n <= CPSAT_MAX and seed == SEEDS[0]):
                        models.append("cpsat")
                    if n in NAIVE_SIZES and seed == SEEDS[0] and (routes, objective, value) in NAIVE_PROBLEMS:
                        models += ["mtz", "plain"]
                    k, factor = (value, None) if objective == "makespan" else (None, value)
                    cells.append(dict(n=n, seed=seed, routes=routes, k=k, factor=factor,
                                      models=tuple(models), limit=time_limit(n)))
    k3 = dict(seed=SEEDS[0], routes="paths", k=3, factor=None)
    cells.append(dict(n=20, models=("mtz",), limit=time_limit(20), **k3))
    cells.append(dict(n=20, models=("plain",), limit=120.0, **k3))
    return cells


def solve_cell(instance: Instance, model: str, *, tours: bool, k: int | None,
               deadline: float | None, limit: float) -> dict:
    """One model on one problem: status, objective, bound, seconds (routes re-checked) and
    the model's message (why it stopped; for branch-and-price unproven, the share of its last
    tree closed).

    The makespan (``k`` given) or robot count (``deadline`` given) is recomputed from
    ``D`` and the routes; a route over the deadline makes the status ``invalid``, one that
    meets the model's proven bound ``optimal``, as :func:`parcover.solve` calls it
    (:func:`parcover.problem.meets_bound`).
    """
    D = instance.distances
    kind = "paths" if not tours else "tours"
    if model == "cpsat":
        payload = {"distances": D.tolist(), "routes": kind, "time_limit": limit, "workers": 2}
        payload.update({"robots": k} if k is not None else {"deadline": deadline})
        answer = run_peer("cpsat", payload, timeout=limit + 120)
        if "status" not in answer:
            return {"status": "error", "objective": None, "bound": None,
                    "seconds": answer.get("seconds"), "message": answer.get("error") or answer.get("unavailable")}
        routes, status = answer["routes"], answer["status"]
        bound, seconds = answer["bound"], answer["seconds"]
        message = ""
    elif model in PARCOVER_MODELS:
        problem = Problem(kind, robots=k) if k is not None else Problem(kind, deadline=deadline)
        began = time.perf_counter()
        solution = PARCOVER_MODELS[model](instance, problem, time_limit=limit)
        seconds = time.perf_counter() - began
        routes, bound, message = solution.routes, solution.bound, solution.info.get("message") or ""
        status = solution.status.value if solution.status is not None else "feasible"
    else:
        solver = {
            "setpart": (setpart.min_makespan, setpart.min_robots),
            "mtz": (naive_models.mtz_min_makespan, naive_models.mtz_min_robots),
            "plain": (naive_models.arcflow_min_makespan, naive_models.arcflow_min_robots),
        }[model][0 if k is not None else 1]
        result = solver(D, k if k is not None else deadline, tours=tours, time_limit=limit)
        routes, status, bound, seconds = result.routes, result.status, result.bound, result.seconds
        message = result.message
    objective = None
    if routes:
        if k is not None:
            objective = makespan(D, routes, tours=tours)
            if len(routes) > k:
                status = "invalid"
        else:
            objective = float(len(routes))
            if not all(within(route_cost(D, r, tours=tours), deadline) for r in routes):
                status = "invalid"
    if status == "feasible" and objective is not None and bound is not None and meets_bound(objective, bound):
        status = "optimal"
    return {"status": status, "objective": objective, "bound": bound, "seconds": seconds, "message": message}


def proven_time(row: dict) -> float | None:
    """Seconds to the proof, or None when the model did not prove within its limit."""
    return row["seconds"] if row["status"] == "optimal" else None


def ratio(peer: dict, mine: dict) -> str:
    """Peer time over our time as text: ``"12.3"``, ``">= 40"``, ``"<= 0.5"`` or ``"-"``.

    An unproven run counts at its limit: ``>= peer limit / our seconds`` when only the
    peer did not prove (a lower bound on the true ratio), ``<= peer seconds / our limit``
    when only we did not (an upper bound, below 1: the peer was faster), ``"-"`` when
    neither proved or the peer failed.
    """
    ours, theirs = proven_time(mine), proven_time(peer)
    if peer.get("status") in (None, "error", "unavailable") or (ours is None and theirs is None):
        return "-"
    if ours is None:
        return f"<= {theirs / mine['limit']:.3g}"
    if theirs is None:
        return f">= {peer['limit'] / max(ours, 1e-3):.3g}"
    return f"{theirs / max(ours, 1e-3):.3g}"


def run(config: Config) -> Section:
    """Run the grid (:func:`grid`) and write the section: table, ratios, plot, targets."""
    rows = []
    cells = grid(config.quick)
    for number, cell in enumerate(cells, 1):
        instance = Instance.from_points(euclidean_points(cell["n"], cell["seed"]))
        D = instance.distances
        tours = cell["routes"] == "tours"
        deadline = None if cell["k"] is not None else cell["factor"] * least_makespan(D, tours=tours)
        problem = (f"makespan k={cell['k']}" if cell["k"] is not None
                   else f"robots U={cell['factor']:g} x least")
        for model in cell["models"]:
            if model == "setpart" and cell["n"] > SETPART_MAX:
                continue
            config.log(f"[exact_scaling] {number}/{len(cells)} n={cell['n']} seed={cell['seed']} "
                       f"{cell['routes']} {problem} {model}")
            out = solve_cell(instance, model, tours=tours, k=cell["k"], deadline=deadline, limit=cell["limit"])
            rows.append({"n": cell["n"], "seed": cell["seed"], "routes": cell["routes"],
                         "problem": problem, "model": model, "limit": cell["limit"], **out})
    frame = pd.DataFrame(rows)
    ratios = ratio_table(frame)
    link = plot(frame, config)
    targets = check_targets(frame, ratios)
    grid_text = ("Quick grid: n = 8, 10, k = 3 paths and fewest robots (tours, 1.2 x), 3 s limits."
                 if config.quick else
                 f"Grid: n = {', '.join(map(str, SIZES))}; paths and tours; least makespan with "
                 "k = 2, 3, 5 robots and fewest robots within U = 1.0 and 1.2 x the least makespan. "
                 f"Seeds {', '.join(map(str, SEEDS))} for k = 3 paths and fewest robots on paths (the "
                 f"targets' cells), seed {SEEDS[0]} for the rest. Branch-and-price and the compact model on every cell, `exact` and set "
                 f"partitioning up to n = {SETPART_MAX}, CP-SAT up to n = 20 (every seed) and n = "
                 f"{CPSAT_MAX} (seed {SEEDS[0]}), the naive models on seed {SEEDS[0]} at n = "
                 f"{', '.join(map(str, NAIVE_SIZES))} (k = 3 paths and tours, fewest robots on paths "
                 "within 1.2 x) and at n = 20 for k = 3 paths. Limits per model and cell: 60 s at "
                 "n = 30, 30 s at n = 25, 20 s otherwise; the plain "
                 "arc-flow model gets 120 s at n = 20 (k = 3 paths), for the '>= 20x' target.")
    markdown = "\n\n".join([
        "Random Euclidean instances (start and n KPOIs uniform in a 100 x 100 square, seeded), "
        "solved in the same run by `parcover`'s default `exact` (above 20 KPOIs branch-and-price over "
        "ng-routes, raced against branch-and-cut, `milp.branchcut`, for the least makespan with 2-3 "
        "robots), branch-and-price alone up to 20 KPOIs and the compact arc-flow model "
        "as `parcover solve --method branchprice` / `--method compact` run them (`milp.branchprice`; "
        "`milp.compact.arcflow`: pruning, column-generation bound, its own heuristics; both with "
        f"a warm start from `best`, {parcover_exact.WARM_ROUNDS['makespan']} rounds for the "
        f"makespan and {parcover_exact.WARM_ROUNDS['robots']} for robots within "
        f"{parcover_exact.WARM_SHARE:.0%} of the limit, for branch-and-price's fewest robots up to "
        f"{parcover_exact.ROOT_FIRST_MAX} KPOIs only when its root bound does not prove "
        "`best`'s construction; their seconds include all of these), set partitioning (`milp.setpart`: Held-Karp routes, then the fewest "
        "routes by inclusion-exclusion counting), a naive big-M MTZ model and the plain "
        "arc-flow model (Kara 2011 style) in HiGHS (no pruning, no warm start; "
        "`benchmarks/naive_models.py`), and OR-Tools CP-SAT (`benchmarks/peers/cpsat.py`, 2 "
        "workers, distances x 1e4 rounded down: its bound is valid for the real problem, its "
        "`optimal` is exact to (n+1)/1e4). Seconds are each solver's own wall time (CP-SAT's "
        "excludes its process start-up; branch-and-price's numba pricing is compiled, or loaded "
        "from its cache, before the first cell, `benchmarks.common.compile_pricing`).",
        f"`ours` is what `parcover`'s default `exact` method runs: up to {SETPART_MAX} KPOIs "
        "`exact` itself (for the least makespan from 14 KPOIs a check of `best`'s constructions against the trivial "
        f"bound, then set partitioning up to {parcover_exact.SETPART_FIRST['makespan']} KPOIs "
        f"({parcover_exact.SETPART_FIRST['robots']} for the fewest robots), branch-and-price "
        "for 2 s and set partitioning above), above that branch-and-price (raced against "
        "branch-and-cut as said above). The ratios are each model's time over "
        "ours; a model that does not prove within its limit L counts as L, shown as `>= L / our "
        "seconds` (a lower bound on the true ratio); a model that proves where ours does not "
        "shows `<= its seconds / our limit` (it was faster); no ratio where neither proved.",
        grid_text,
        "### Ratios (model seconds / our seconds)",
        markdown_table(ratios),
        f"![time to proven optimum vs n]({link})",
        "### Results",
        markdown_table(frame.drop(columns=["message"])),
    ])
    return Section("Exact scaling", markdown, tables={"exact_scaling": frame,
                                                      "exact_scaling_ratios": ratios},
                   targets=targets)


def ratio_table(frame: pd.DataFrame) -> pd.DataFrame:
    """One row per cell where our model ran: its seconds, and each other model's ratio to it."""
    out = []
    for key, cell in frame.groupby(["n", "seed", "routes", "problem"], sort=False):
        by_model = {r["model"]: r for r in cell.to_dict("records")}
        mine = by_model.get(OURS)
        if mine is None:
            continue
        row = dict(zip(("n", "seed", "routes", "problem"), key))
        row["ours"] = mine["model"]
        row["our s"] = mine["seconds"] if mine["status"] == "optimal" else None
        for model in MODELS:
            row[f"{model} / ours"] = (ratio(by_model[model], mine)
                                      if model in by_model and model != mine["model"] else "-")
        out.append(row)
    return pd.DataFrame(out)


def plot(frame: pd.DataFrame, config: Config) -> str:
    """Log-scale time vs n per model (k = 3 paths, least makespan; median over seeds,
    unproven runs counted at their limit and marked x)."""
    from parcover.plot import plt, save_figure

    path, link = config.figure("exact_scaling.png")
    data = frame[(frame["problem"] == "makespan k=3") & (frame["routes"] == "paths")].copy()
    data["shown"] = np.where(data["status"] == "optimal", data["seconds"], data["limit"])
    fig, ax = plt.subplots(figsize=(6, 4))
    for model, part in data.groupby("model", sort=False):
        median = part.groupby("n")["shown"].median()
        line = ax.plot(median.index, median.values, marker="o", label=model)[0]
        unproven = part[part["status"] != "optimal"]
        ax.scatter(unproven["n"], unproven["limit"], marker="x", s=80, color=line.get_color())
    ax.set_yscale("log")
    ax.set_xlabel("KPOIs n")
    ax.set_ylabel("seconds to proven optimum (median; x: not proven)")
    ax.set_title("least makespan, k = 3 paths, random Euclidean")
    if not data.empty:
        ax.legend()
    save_figure(fig, path, dpi=100)
    return link


def check_targets(frame: pd.DataFrame, ratios: pd.DataFrame) -> list[str]:
    """One line per target with the figure reached."""
    return [_cpsat_target(ratios), _plain_target(ratios), _n30_target(frame), _n40_target(frame),
            _robots50_target(frame)]


def _cpsat_target(ratios: pd.DataFrame) -> str:
    """Faster than CP-SAT at every n: the smallest CP-SAT / ours ratio at each n."""
    compared = ratios[ratios["cpsat / ours"] != "-"]
    if compared.empty:
        return "exact: faster than CP-SAT at every n: not measured"
    per_n, slower = [], []
    for n, part in compared.groupby("n"):
        values = [float(r.removeprefix(">= ").removeprefix("<= ")) for r in part["cpsat / ours"]]
        least = min(values)
        per_n.append(f"n={n}: min {least:.3g} over {len(values)} cells")
        slower += [f"n={n} seed {r.seed} {r.routes} {r.problem} ({v:.3g})"
                   for r, v in zip(part.itertuples(), values) if v < 1.0]
    verdict = "met" if not slower else f"not met on {len(slower)} cells: {', '.join(slower)}"
    return f"exact: faster than CP-SAT at every n: {verdict} (CP-SAT / ours: {'; '.join(per_n)})"


def _plain_target(ratios: pd.DataFrame) -> str:
    """>= 20x faster than the plain arc-flow model at n = 18-20 (k = 3 paths)."""
    plain = ratios[(ratios["n"].between(18, 20)) & (ratios["problem"] == "makespan k=3")
                   & (ratios["routes"] == "paths")]["plain / ours"]
    plain = [r for r in plain if r != "-"]
    values = [float(r.removeprefix(">= ").removeprefix("<= ")) for r in plain]
    verdict = "met" if values and min(values) >= 20 else "not met"
    return (f"exact: >= 20x faster than plain arc-flow at n = 18-20 (k = 3 paths): "
            f"{verdict} (ratio {', '.join(plain) or 'not measured'})")


def _n30_target(frame: pd.DataFrame) -> str:
    """n = 30, k = 3, paths and tours, proven within 60 s on every seed (the target);
    then, for information, how many of all n = 30 cells were."""
    ours30 = frame[(frame["n"] == 30) & (frame["model"] == OURS)]
    if ours30.empty:
        return "exact: n = 30, k = 3 proven within 60 s: not measured"
    k3 = ours30[ours30["problem"] == "makespan k=3"]
    parts = [f"{r.routes} seed {r.seed}: {_outcome(r)}" for r in k3.itertuples()]
    fast = k3[(k3["status"] == "optimal") & (k3["seconds"] <= 60)]
    verdict = "met" if len(fast) == len(k3) else f"not met ({len(fast)}/{len(k3)} cells)"
    proven = ours30[(ours30["status"] == "optimal") & (ours30["seconds"] <= 60)]
    return (f"exact: n = 30, k = 3 proven within 60 s: {verdict}: {'; '.join(parts)}; "
            f"all n = 30 cells (k = 2, 3, 5, fewest robots): {len(proven)}/{len(ours30)} proven within 60 s")


def _n40_target(frame: pd.DataFrame) -> str:
    """n = 40, k = 5, paths and tours, proven within 60 s."""
    cells = frame[(frame["n"] == 40) & (frame["problem"] == "makespan k=5") & (frame["model"] == OURS)]
    return _cells_target(cells, "n = 40, k = 5 proven within 60 s", 60,
                         lambda r: f"{r.routes} seed {r.seed}")


def _robots50_target(frame: pd.DataFrame) -> str:
    """Fewest robots for n = 50 within 10 s, on every n = 50 robots cell."""
    cells = frame[(frame["n"] == 50) & frame["problem"].str.startswith("robots") & (frame["model"] == OURS)]
    return _cells_target(cells, "fewest robots for n = 50 within 10 s", 10,
                         lambda r: f"{r.routes} {r.problem.removeprefix('robots ')} seed {r.seed}")


def _cells_target(cells: pd.DataFrame, title: str, seconds: float, label) -> str:
    """``exact: TITLE: met`` when every cell is proven within ``seconds``, else how many
    were, then each cell's outcome."""
    if cells.empty:
        return f"exact: {title}: not measured"
    fast = cells[(cells["status"] == "optimal") & (cells["seconds"] <= seconds)]
    parts = [f"{label(r)}: {_outcome(r)}" for r in cells.itertuples()]
    verdict = "met" if len(fast) == len(cells) else f"not met ({len(fast)}/{len(cells)} cells)"
    return f"exact: {title}: {verdict}: {'; '.join(parts)}"


def _outcome(row) -> str:
    """``optimal in 3.4 s`` or ``feasible 13 vs bound 10 at 30 s``."""
    if row.status == "optimal":
        return f"optimal in {row.seconds:.1f} s"
    if row.objective is None or row.bound is None or pd.isna(row.objective) or pd.isna(row.bound):
        return f"{row.status} at {row.seconds:.0f} s"
    return f"{row.status} {row.objective:.4g} vs bound {row.bound:.4g} at {row.seconds:.0f} s"
