"""Heuristic quality: ``best`` and the paper's method against OR-Tools and PyVRP.

On uniform random Euclidean instances (the start and ``n`` KPOIs
in a 100 x 100 square, :func:`benchmarks.common.euclidean_distances`), paths and tours:

- **Least makespan with K robots** (K = 3, 5): ``best`` (construction + iterated
  local search) with a time limit, the paper's method (``paper``: Algorithms 1 /
  1-1 / 2 with the exact threshold scan under a robot limit) and OR-Tools routing
  (guided local search, global span cost, :mod:`benchmarks.peers.ortools_routing`)
  with the *same* time limit. Reported: each makespan, the ratios to OR-Tools' and
  a certified lower bound: the larger of the one parcover attaches (``Result.bound``)
  and the column-generation bound (:func:`milp.branchprice.colgen.makespan_lower_bound`, at most
  :data:`BOUND_SECONDS`).
- **Fewest robots within a deadline** of 1.2 times the least possible makespan
  (``c_max`` for paths, ``2 c_max`` for tours; a deadline of the exact targets,
  :mod:`benchmarks.exact_targets`): ``best``, ``paper`` and PyVRP (max distance, large fixed vehicle cost,
  :mod:`benchmarks.peers.pyvrp_fleet`) with the same time limit; the bound likewise
  with :func:`milp.branchprice.colgen.robots_lower_bound`.

Every peer answer is checked by :func:`parcover.verify.verify` on the instance
(KPOIs covered once, robot limit or deadline met, costs recomputed from the float
distances) before its value is used; one that fails is reported, not used.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import pandas as pd

from benchmarks.common import Config, Section, euclidean_points, markdown_table, run_peer
from milp.branchprice import colgen
from parcover import Instance, solve
from parcover.verify import InvalidSolution, verify

SIZES = (50, 100, 200)
SEEDS = (0, 1)
ROBOTS = (3, 5)
ROUTES = ("paths", "tours")
TIME_LIMIT = 5.0
QUICK_SIZES = (50,)
QUICK_SEEDS = (0,)
QUICK_ROBOTS = (3,)
QUICK_TIME_LIMIT = 1.0
DEADLINE_FACTOR = 1.2
RATIO_RTOL = 1e-9
#: Seconds for the column-generation bound of each cell, run up to this many KPOIs (in a
#: probe at n = 100 and 200, K = 5 paths, it did not beat the trivial bounds in 10 s).
BOUND_SECONDS, BOUND_MAX_KPOIS = 10.0, 50  # equal values summed in another order (a reversed tour) are equal

Log = Callable[[str], None]


def run(config: Config) -> Section:
    """Measure both questions (module docstring) and write the section."""
    sizes, seeds, robots, limit = (
        (QUICK_SIZES, QUICK_SEEDS, QUICK_ROBOTS, QUICK_TIME_LIMIT) if config.quick
        else (SIZES, SEEDS, ROBOTS, TIME_LIMIT)
    )
    makespans = makespan_table(sizes, seeds, robots, limit, config.log)
    fleets = fleet_table(sizes, seeds, limit, config.log)
    return Section(
        title="Heuristic quality: best and the paper's method against OR-Tools and PyVRP",
        markdown=section_markdown(makespans, fleets, sizes, seeds, limit),
        tables={"heuristic_makespan": makespans, "heuristic_fleet": fleets},
        targets=[target_line(makespans), cap_target_line(makespans, fleets)],
    )


def random_instance(n: int, seed: int) -> Instance:
    """The instance of :func:`benchmarks.common.euclidean_points` (start = row 0).

    Built from the points, not the distances, so that parcover sees coordinates (some
    constructions of ``best`` use them).
    """
    return Instance.from_points(euclidean_points(n, seed), name=f"uniform-{n}-{seed}")


def checked_peer_routes(
    instance: Instance,
    answer: dict[str, Any],
    routes: str,
    *,
    robots: int | None = None,
    deadline: float | None = None,
) -> tuple[float, int] | str:
    """``(makespan, robots)`` of a peer's routes as the verifier recomputes them, or why not.

    The answer's routes (KPOI indices, start implicit) are mapped to ids and checked by
    :func:`parcover.verify.verify` against the robot limit or the deadline; a missing,
    invalid or infeasible answer gives a short reason instead.
    """
    if "unavailable" in answer:
        return "unavailable"
    if "error" in answer:
        return f"error: {answer['error']}"
    ids = instance.ids
    try:
        id_routes = [
            [instance.start, *(ids[int(i)] for i in route), *([instance.start] if routes == "tours" else [])]
            for route in answer.get("routes") or []
        ]
        verdict = verify(instance, id_routes, routes_kind=routes, robots_limit=robots, deadline=deadline)
    except (InvalidSolution, IndexError, ValueError, TypeError) as error:
        return f"invalid: {error}"[:120]
    if not verdict.feasible:
        return f"infeasible: {'; '.join(verdict.violations())}"[:120]
    return verdict.makespan, verdict.robots


def makespan_row(instance: Instance, seed: int, routes: str, robots: int, limit: float) -> dict[str, Any]:
    """One cell of the least-makespan comparison: best, paper and OR-Tools with ``robots``."""
    best = solve(instance, routes, robots=robots, method="best", time_limit=limit, seed=seed)
    spent = solve(instance, routes, robots=robots, method="best:until=limit", time_limit=limit, seed=seed)
    again = solve(instance, routes, robots=robots, method="best:until=limit", time_limit=limit, seed=seed)
    paper = solve(instance, routes, robots=robots, method="paper", time_limit=limit)
    payload = {
        "distances": instance.distances.tolist(), "robots": robots, "routes": routes,
        "time_limit": limit, "seed": seed,
    }
    answer = run_peer("ortools_routing", payload, timeout=3 * limit + 60)
    checked = checked_peer_routes(instance, answer, routes, robots=robots)
    ortools = checked[0] if isinstance(checked, tuple) else math.nan
    upper = min(best.makespan, paper.makespan, ortools if not math.isnan(ortools) else math.inf)
    certified = 0.0 if instance.n > BOUND_MAX_KPOIS else colgen.makespan_lower_bound(
        instance.distances, robots, tours=routes == "tours", upper=upper,
        time_limit=min(BOUND_SECONDS, 2 * limit))
    bound = max(best.bound or 0.0, paper.bound or 0.0, certified)
    return {
        "n": instance.n, "seed": seed, "routes": routes, "K": robots,
        "bound": bound,
        "best": best.makespan,
        "paper": paper.makespan,
        "ortools": ortools,
        "best/ortools": best.makespan / ortools,
        "paper/ortools": paper.makespan / ortools,
        "best/bound": best.makespan / bound,
        "best/spent": best.makespan / spent.makespan,
        "again/spent": again.makespan / spent.makespan,
        "best s": best.seconds,
        "spent s": spent.seconds,
        "paper s": paper.seconds,
        "ortools s": answer["seconds"],
        "best start": best.info.get("start", ""),
        "best rounds": best.info.get("iterations", 0),
        "ortools answer": answer.get("status", "") if isinstance(checked, tuple) else checked,
    }


def fleet_row(instance: Instance, seed: int, routes: str, limit: float) -> dict[str, Any]:
    """One cell of the fewest-robots comparison at ``DEADLINE_FACTOR`` x the least makespan."""
    least = 2 * instance.c_max if routes == "tours" else instance.c_max
    deadline = DEADLINE_FACTOR * least
    best = solve(instance, routes, deadline=deadline, method="best", time_limit=limit, seed=seed)
    spent = solve(instance, routes, deadline=deadline, method="best:until=limit", time_limit=limit, seed=seed)
    again = solve(instance, routes, deadline=deadline, method="best:until=limit", time_limit=limit, seed=seed)
    paper = solve(instance, routes, deadline=deadline, method="paper", time_limit=limit)
    payload = {
        "distances": instance.distances.tolist(), "deadline": deadline, "routes": routes,
        "time_limit": limit, "seed": seed,
    }
    answer = run_peer("pyvrp_fleet", payload, timeout=3 * limit + 60)
    checked = checked_peer_routes(instance, answer, routes, deadline=deadline)
    pyvrp = checked[1] if isinstance(checked, tuple) else math.nan
    certified = 0 if instance.n > BOUND_MAX_KPOIS else colgen.robots_lower_bound(
        instance.distances, deadline, tours=routes == "tours", time_limit=min(BOUND_SECONDS, 2 * limit))
    bound = max(best.bound or 0, paper.bound or 0, certified)
    return {
        "n": instance.n, "seed": seed, "routes": routes, "deadline": deadline,
        "bound": bound,
        "best": best.robots,
        "paper": paper.robots,
        "pyvrp": pyvrp,
        "best/pyvrp": best.robots / pyvrp,
        "best/spent": best.robots / spent.robots,
        "again/spent": again.robots / spent.robots,
        "spent s": spent.seconds,
        "paper/pyvrp": paper.robots / pyvrp,
        "best s": best.seconds,
        "pyvrp s": answer["seconds"],
        "pyvrp answer": answer.get("status", "") if isinstance(checked, tuple) else checked,
    }


def makespan_table(
    sizes: Sequence[int], seeds: Sequence[int], robots: Sequence[int], limit: float, log: Log
) -> pd.DataFrame:
    """:func:`makespan_row` for every size, seed, route kind and robot count."""
    rows = []
    for n in sizes:
        for seed in seeds:
            instance = random_instance(n, seed)
            for routes in ROUTES:
                for k in robots:
                    rows.append(makespan_row(instance, seed, routes, k, limit))
                    log(f"  makespan n={n} seed={seed} {routes} K={k}: "
                        f"best/ortools {rows[-1]['best/ortools']:.3f}")
    return pd.DataFrame(rows)


def fleet_table(sizes: Sequence[int], seeds: Sequence[int], limit: float, log: Log) -> pd.DataFrame:
    """:func:`fleet_row` for every size, seed and route kind."""
    rows = []
    for n in sizes:
        for seed in seeds:
            instance = random_instance(n, seed)
            for routes in ROUTES:
                rows.append(fleet_row(instance, seed, routes, limit))
                log(f"  fleet n={n} seed={seed} {routes}: best {rows[-1]['best']} pyvrp {rows[-1]['pyvrp']}")
    return pd.DataFrame(rows)


def ratio_summary(ratios: pd.Series) -> dict[str, float]:
    """Geometric mean, worst (largest) ratio and counts over the measured (non-NaN) ratios.

    A ratio counts as at most 1 within :data:`RATIO_RTOL`.
    """
    values = ratios.dropna().to_numpy(dtype=float)
    if values.size == 0:
        return {"cells": 0, "at most 1": 0, "geomean": math.nan, "worst": math.nan, "best": math.nan}
    return {
        "cells": int(values.size),
        "at most 1": int(np.count_nonzero(values <= 1.0 + RATIO_RTOL)),
        "geomean": float(np.exp(np.log(values).mean())),
        "worst": float(values.max()),
        "best": float(values.min()),
    }


def target_line(makespans: pd.DataFrame) -> str:
    """This section's target and the figure reached."""
    target = "best no worse than OR-Tools at equal time (ratio <= 1.00)"
    s = ratio_summary(makespans["best/ortools"])
    if s["cells"] == 0:
        reason = makespans["ortools answer"].iloc[0]
        return f"{target}: not measured (OR-Tools gave no verified answer: {reason})"
    verdict = "met" if s["worst"] <= 1.0 + RATIO_RTOL else "not met"
    return (
        f"{target}: {verdict}: best/OR-Tools geometric mean {s['geomean']:.3f}, worst {s['worst']:.3f}, "
        f"{s['at most 1']} of {s['cells']} cells <= 1.00"
    )


def cap_target_line(makespans: pd.DataFrame, fleets: pd.DataFrame) -> str:
    """The time limit as a cap: ``best`` (stopping at a bound, at convergence or at the
    limit) within 0.1% of ``best:until=limit`` (spending the limit, as before) at equal or
    less time, on the makespan cells (geometric mean) and as many robots on every fleet cell."""
    target = "best within 0.1% of best:until=limit (the whole limit spent) at equal or less time"
    s = ratio_summary(makespans["best/spent"])
    time_ratio = float(makespans["best s"].sum() + fleets["best s"].sum()) / float(
        makespans["spent s"].sum() + fleets["spent s"].sum())
    fleet_worst = float(fleets["best/spent"].max())
    noise = ratio_summary(makespans["again/spent"])
    verdict = "met" if s["geomean"] <= 1.001 and fleet_worst <= 1.0 and time_ratio <= 1.0 else "not met"
    return (f"{target}: {verdict}: makespan best/spent geometric mean {s['geomean']:.4f} (worst {s['worst']:.4f}, "
            f"{s['at most 1']} of {s['cells']} cells <= 1), robots best/spent worst {fleet_worst:.3f}; "
            f"time best/spent {time_ratio:.2f}; run-to-run noise of until=limit itself (a second run, "
            f"again/spent): geometric mean {noise['geomean']:.4f}, worst {noise['worst']:.4f}, robots worst "
            f"{float(fleets['again/spent'].max()):.3f}")


def _summary_by(frame: pd.DataFrame, columns: Sequence[str], ratios: Sequence[str]) -> pd.DataFrame:
    rows = []
    for key, group in frame.groupby(list(columns), sort=True):
        row = dict(zip(columns, key if isinstance(key, tuple) else (key,)))
        for ratio in ratios:
            s = ratio_summary(group[ratio])
            row[f"{ratio} geomean"] = s["geomean"]
            row[f"{ratio} worst"] = s["worst"]
        row["cells"] = int(group[ratios[0]].notna().sum())
        rows.append(row)
    return pd.DataFrame(rows)


def section_markdown(
    makespans: pd.DataFrame, fleets: pd.DataFrame, sizes: Sequence[int], seeds: Sequence[int], limit: float
) -> str:
    """The section's text: the setting, summaries, full tables, notes."""
    setting = (
        f"Uniform random Euclidean instances, n = {', '.join(map(str, sizes))} KPOIs, "
        f"seeds {', '.join(map(str, seeds))}, paths and tours. `best` and the peers get the same "
        f"time limit of {limit:g} s per solve (`paper` is deterministic and stops when its threshold "
        f"scan ends). Budget: the full run (n = 50, 100, 200; 2 seeds; 5 s) takes about 8 minutes, "
        f"`--quick` (n = 50, one seed, K = 3 only, 1 s) about 25 s; with more time every method may improve. "
        f"The peers' seconds include starting their Python process (1-2 s). All solves run one "
        f"after another on a shared machine. `spent`: `best:until=limit`, which spends the whole time "
        f"limit, as `best` did before its limit became a cap (it now stops at a proven bound or at "
        f"convergence); `best/spent` compares the two in the same run, and `again/spent` a second "
        f"`until=limit` run with the first: how much one method's answers move with the machine's load "
        f"at a time limit."
    )
    parts = [setting, "", "### Least makespan with K robots", ""]
    parts.append(_availability(makespans["ortools"], makespans["ortools answer"], "OR-Tools"))
    parts += [
        target_line(makespans) + ".",
        "",
        cap_target_line(makespans, fleets) + ".",
        "",
        markdown_table(_summary_by(makespans, ("n", "routes"),
                                   ("best/ortools", "paper/ortools", "best/spent", "again/spent")), ".4g"),
        "",
        "Every cell (`bound`: a certified lower bound, the largest of those parcover attaches to "
        "`best`'s and `paper`'s answers and, up to n = "
        f"{BOUND_MAX_KPOIS}, the column-generation bound of `milp.branchprice.colgen` (at most "
        f"{BOUND_SECONDS:g} s); `best start`: the construction `best` started from, `best rounds`: its "
        "ruin-and-recreate rounds):",
        "",
        markdown_table(makespans.drop(columns=["paper s"]), ".4g"),
        "",
        f"### Fewest robots within {DEADLINE_FACTOR:g} x the least makespan",
        "",
        f"The deadline is {DEADLINE_FACTOR:g} x `c_max` for paths and {DEADLINE_FACTOR:g} x `2 c_max` "
        "for tours (the least possible makespans), as in the exact section: at the least makespan "
        "itself every route is pinned to the farthest KPOI's distance, 20% more leaves room for the "
        "methods to differ. The question stays far from trivial: the answers found range from "
        f"{int(fleets['best'].min())} to {int(fleets['best'].max())} robots (`best`), between "
        "the certified lower bound (`bound`, as above: `milp.branchprice.colgen.robots_lower_bound`) and one "
        "robot per KPOI.",
        "",
        _availability(fleets["pyvrp"], fleets["pyvrp answer"], "PyVRP"),
        _fleet_tally(fleets),
        "",
        markdown_table(_summary_by(fleets, ("n", "routes"), ("best/pyvrp", "paper/pyvrp")), ".4g"),
        "",
        markdown_table(fleets, ".4g"),
        "",
        "### Notes",
        "",
        "- Makespans and robot counts of the peers are recomputed from the float distances by "
        "`parcover.verify` (the peers work on integer arc costs: distances x 1000, rounded for "
        "OR-Tools, rounded up for PyVRP with the deadline rounded down, so PyVRP's routes always "
        "meet the float deadline). A peer answer that fails verification shows the reason in its "
        "`answer` column and is not used.",
        "- OR-Tools: depot 0 as start of every vehicle, a dummy end node at distance 0 from every "
        "node for paths (tours end at the depot), a distance dimension with global span cost "
        "coefficient 100 (objective: total length + 100 x longest route), PATH_CHEAPEST_ARC then "
        "guided local search. OR-Tools routing has no seed parameter. From n = 100 it stops at "
        "the time limit before a local optimum (`ROUTING_PARTIAL_SUCCESS_LOCAL_OPTIMUM_NOT_REACHED`): "
        "it is still improving, but slowly. A probe outside this table (n = 200, seed 0, K = 5 "
        "paths) gave makespans 546 in 5 s, 553 with span coefficient 1000, 521 with "
        "PARALLEL_CHEAPEST_INSERTION as first solution and 441 in 20 s, against about 250 for `best` "
        "in 5 s.",
        "- PyVRP: n vehicles with the deadline as maximum distance and a fixed cost above any total "
        "length (so it minimises vehicles, then length); paths end at a second, dummy depot at "
        "distance 0 from every KPOI (a vehicle type's `end_depot`).",
        "- No exact optimum is shown: the exact method does not prove these sizes in seconds. "
        "`best/bound` is an upper bound on `best`'s true gap (the bound is certified, not the "
        "optimum). Beyond n = 50 the bound is parcover's trivial one (spanning tree, `c_max`): "
        "in a probe (n = 100 and 200, K = 5 paths) column generation did not beat it within 10 s.",
    ]
    return "\n".join(parts)


def _availability(values: pd.Series, answers: pd.Series, peer: str) -> str:
    """A sentence when the peer gave no verified answer somewhere (its value is NaN)."""
    failed = answers[values.isna()]
    if failed.empty:
        return ""
    return f"{peer} gave no verified answer in {len(failed)} of {len(answers)} cells ({failed.iloc[0]}).\n"


def _fleet_tally(fleets: pd.DataFrame) -> str:
    """In how many cells ``best`` needs fewer, as many or more robots than PyVRP."""
    measured = fleets[fleets["pyvrp"].notna()]
    fewer = int((measured["best"] < measured["pyvrp"]).sum())
    more = int((measured["best"] > measured["pyvrp"]).sum())
    return (
        f"`best` needs fewer robots than PyVRP in {fewer}, as many in {len(measured) - fewer - more} "
        f"and more in {more} of {len(measured)} cells; `paper` needs more than PyVRP in "
        f"{int((measured['paper'] > measured['pyvrp']).sum())}."
    )
