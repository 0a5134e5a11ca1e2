"""OR-Tools routing (guided local search) for the least makespan with ``k`` robots.

Payload: ``{"distances": (n+1) x (n+1) list (row 0 = the start), "robots": k,
"routes": "paths" | "tours", "time_limit": seconds, "seed": int}``.
Answer: ``{"routes": [[KPOI indices 1..n in visiting order], ...] (start and dummy end
left out, empty routes dropped), "status": OR-Tools' search status, "solver":
"ortools X.Y", "objective": the integer objective}``.

The model is the textbook OR-Tools min-max VRP: every vehicle starts at node 0 and
ends at node 0 (tours) or at a dummy end node ``n + 1`` reached at cost 0 from every
node (paths: a robot stays where it finishes). Arc costs are integers: the float
distances times :data:`SCALE` (1000), rounded to the nearest integer, so a route's
integer cost is off by at most 0.5 per arc (the parent recomputes the makespan from
the float matrix and never trusts this peer's value). A distance dimension with a
global span cost coefficient of :data:`SPAN_COEFFICIENT` makes the objective
``total length + 100 x longest route`` (min-max, ties broken by total length); the
search is PATH_CHEAPEST_ARC then GUIDED_LOCAL_SEARCH until the time limit. The arc
costs go in as a matrix (``RegisterTransitMatrix``), not a Python callback, which
slows the search down (200 KPOIs, K = 5 paths, 5 s: makespan 807 with a callback,
546 with the matrix). OR-Tools routing takes no random seed: ``seed`` is accepted
and ignored (the search is deterministic up to its time limit).

Imports only json/numpy and ortools (never parcover, whose HiGHS clashes with
OR-Tools' own).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from benchmarks.common import peer_main

SCALE = 1000
SPAN_COEFFICIENT = 100


def integer_arcs(distances: list[list[float]], paths: bool) -> np.ndarray:
    """Arc costs in integers (``round(SCALE * d)``), with the dummy end node for paths.

    The dummy end (last row and column) is reached at cost 0 from every node and is
    never left (its outgoing arcs are not used: it ends every vehicle's route).
    """
    arcs = np.rint(np.asarray(distances, dtype=float) * SCALE).astype(np.int64)
    if not paths:
        return arcs
    m = len(arcs)
    out = np.zeros((m + 1, m + 1), dtype=np.int64)
    out[:m, :m] = arcs
    return out


def solve_min_max(payload: dict[str, Any]) -> dict[str, Any]:
    """Build and solve the routing model of ``payload`` (module docstring)."""
    import ortools
    from ortools.constraint_solver import pywrapcp, routing_enums_pb2

    paths = payload["routes"] == "paths"
    arcs = integer_arcs(payload["distances"], paths)
    n = len(payload["distances"]) - 1
    k = int(payload["robots"])
    end = n + 1 if paths else 0
    manager = pywrapcp.RoutingIndexManager(len(arcs), k, [0] * k, [end] * k)
    routing = pywrapcp.RoutingModel(manager)
    transit = routing.RegisterTransitMatrix(arcs.tolist())
    routing.SetArcCostEvaluatorOfAllVehicles(transit)
    routing.AddDimension(transit, 0, int(arcs.sum()) + 1, True, "Distance")
    routing.GetDimensionOrDie("Distance").SetGlobalSpanCostCoefficient(SPAN_COEFFICIENT)

    parameters = pywrapcp.DefaultRoutingSearchParameters()
    parameters.first_solution_strategy = routing_enums_pb2.FirstSolutionStrategy.PATH_CHEAPEST_ARC
    parameters.local_search_metaheuristic = routing_enums_pb2.LocalSearchMetaheuristic.GUIDED_LOCAL_SEARCH
    parameters.time_limit.FromMilliseconds(max(1, int(1000 * float(payload["time_limit"]))))
    solution = routing.SolveWithParameters(parameters)
    status = routing_enums_pb2.RoutingSearchStatus.Value.Name(routing.status())
    version = ".".join(ortools.__version__.split(".")[:2])
    answer: dict[str, Any] = {"status": status, "solver": f"ortools {version}", "routes": []}
    if solution is None:
        return answer
    for vehicle in range(k):
        index = routing.Start(vehicle)
        route = []
        while not routing.IsEnd(index):
            node = manager.IndexToNode(index)
            if node != 0:
                route.append(node)
            index = solution.Value(routing.NextVar(index))
        if route:
            answer["routes"].append(route)
    answer["objective"] = solution.ObjectiveValue()
    return answer


if __name__ == "__main__":
    peer_main(solve_min_max, "ortools")
