"""PyVRP for the fewest robots within a deadline (every route at most ``deadline`` long).

Payload: ``{"distances": (n+1) x (n+1) list (row 0 = the start), "deadline": float,
"routes": "paths" | "tours", "time_limit": seconds, "seed": int}``.
Answer: ``{"routes": [[KPOI indices 1..n in visiting order], ...] (start left out,
empty routes dropped), "status": "feasible" | "infeasible" (PyVRP's best solution
breaks the deadline or leaves a KPOI out), "solver": "pyvrp X.Y", "cost": PyVRP's
integer objective}``.

The model: one client per KPOI, ``n`` vehicles of one type (one per KPOI always
suffices when ``deadline`` is at least the least makespan), each with
``max_distance`` = the deadline and a fixed cost larger than any total distance, so
that PyVRP's cost minimisation (fixed costs + distance) minimises the robots first
and the total length second. The time limit is PyVRP's ``MaxRuntime``.

Open routes (paths): PyVRP routes run from a start depot to an end depot, and a
vehicle type may name a different end depot (``end_depot``). Paths end at a second,
dummy depot reached at distance 0 from every KPOI (and from the start, for an
unused vehicle); the edges leaving it are never used. The route distance PyVRP
checks against ``max_distance`` is then exactly the path's length.

Integer distances: PyVRP wants integers, so distances are scaled by :data:`SCALE`
(1000) and rounded *up*, and the deadline is scaled and rounded *down*. An integer
route length within the integer deadline then proves the float route within the
float deadline (ceilings only overestimate), so PyVRP never answers a route that
the float check rejects; the price is a deadline tighter by at most one
thousandth per arc. The parent recomputes everything from the float matrix.

Imports only json/numpy and pyvrp (never parcover).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from benchmarks.common import peer_main

SCALE = 1000


def solve_fleet(payload: dict[str, Any]) -> dict[str, Any]:
    """Build and solve the fleet-minimising model of ``payload`` (module docstring)."""
    from importlib.metadata import version

    from pyvrp import Model
    from pyvrp.stop import MaxRuntime

    paths = payload["routes"] == "paths"
    arcs = np.ceil(np.asarray(payload["distances"], dtype=float) * SCALE).astype(np.int64)
    np.fill_diagonal(arcs, 0)
    limit = math.floor(float(payload["deadline"]) * SCALE)
    n = len(arcs) - 1

    model = Model()
    points = [model.add_location(0, 0, name=str(i)) for i in range(n + 1)]
    start = model.add_depot(points[0], name="start")
    end = start
    if paths:
        finish = model.add_location(0, 0, name="end")
        end = model.add_depot(finish, name="end")
        for location in points:
            model.add_edge(location, finish, distance=0)
    for i in range(1, n + 1):
        model.add_client(points[i], name=str(i))
    model.add_vehicle_type(
        num_available=n,
        start_depot=start,
        end_depot=end,
        fixed_cost=int(2 * (n + 1) * arcs.max()) + 1,
        max_distance=limit,
    )
    for i in range(n + 1):
        for j in range(n + 1):
            if i != j:
                model.add_edge(points[i], points[j], distance=int(arcs[i, j]))

    result = model.solve(MaxRuntime(float(payload["time_limit"])), seed=int(payload["seed"]), display=False)
    best = result.best
    # Client activities count clients from 0 in the order added: KPOI i is client i - 1.
    routes = [[activity.idx + 1 for activity in route if activity.is_client()] for route in best.routes()]
    status = "feasible" if best.is_feasible() and best.is_complete() else "infeasible"
    return {
        "routes": [r for r in routes if r],
        "status": status,
        "solver": f"pyvrp {'.'.join(version('pyvrp').split('.')[:2])}",
        "cost": int(result.cost()) if best.is_feasible() else None,
    }


if __name__ == "__main__":
    peer_main(solve_fleet, "pyvrp")
