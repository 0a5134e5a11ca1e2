r"""OR-Tools CP-SAT model of the parallel coverage problem (a peer; JSON in, JSON out).

Run as ``python -m benchmarks.peers.cpsat`` with the payload on stdin (see
:func:`benchmarks.common.run_peer`)::

    {"distances": [[...], ...], "routes": "paths" | "tours",
     "robots": k  or  "deadline": U, "time_limit": seconds, "workers": 2}

Answer: ``{"status": "optimal" | "feasible" | "infeasible" | "unknown", "routes": [[i, ...],
...], "objective": float, "bound": float, "scale": S, "seconds": float}``; routes are KPOI
indices ``1..n`` (start not listed), ``objective`` the makespan (``robots`` given) or the
number of routes (``deadline`` given) recomputed with float distances, ``bound`` a lower
bound on the optimum of the real (float) problem, ``seconds`` CP-SAT's wall time.

Model
-----
CP-SAT needs integers. Distances are scaled by :math:`S` (default ``10_000``) and rounded
*down*: :math:`\delta_{ij} = \lfloor S d_{ij} \rfloor`. Node 0 is the start; a route leaves 0
and returns to 0 through an arc of cost :math:`c_{i0} = \delta_{i0}` (tours) or 0 (paths).
Literals :math:`\ell_{ij}` for every arc :math:`i \ne j`, integers :math:`a_i \in [0, H]` the
(scaled) distance on arrival at KPOI :math:`i`, :math:`H` the sum of every node's largest
outgoing :math:`\delta`, and the makespan :math:`T`:

.. math::

    (1)&\quad \text{AddMultipleCircuit}(\ell): \text{every KPOI on exactly one circuit
        through 0} \\
    (2)&\quad \sum_j \ell_{0j} \le k \ \text{(makespan)} \\
    (3)&\quad \ell_{0j} \Rightarrow a_j = \delta_{0j}, \qquad
        \ell_{ij} \Rightarrow a_j \ge a_i + \delta_{ij} \quad (i, j \ge 1) \\
    (4)&\quad \ell_{i0} \Rightarrow T \ge a_i + c_{i0} \\
    (5)&\quad T \le \lceil S U \rceil \ \text{(robots)} \\
    (6)&\quad a_j \ge \delta_{0j} && j \ge 1 \\
    (7)&\quad T \ge a_j + c_{j0} - n && j \ge 1

minimise :math:`T` (makespan) or :math:`\sum_j \ell_{0j}` (robots). (6) and (7) are
redundant cuts that give CP-SAT's LP relaxation the ``c_max`` bound: with exact arrivals,
(6) is the triangle inequality and so is (7), up to the at most ``n`` units lost by
rounding each of the remaining arcs down.

Exactness. Rounding down makes every route's scaled cost at most :math:`S` times its real
cost, so the integer problem is a relaxation of the real one: CP-SAT's best bound
:math:`B` gives the valid real bound :math:`B / S` (for the makespan; the robot count
needs no scaling), and every real solution within the deadline stays feasible. The
other way, a route of :math:`m` arcs loses less than :math:`m / S` to rounding, so the
routes CP-SAT returns have a real makespan below :math:`(\text{its value} + n + 1) / S`
and, for a deadline, may exceed :math:`U` by less than :math:`(n + 1) / S` (``2.5e-3`` for
``n = 50`` at the default scale): the caller re-checks them with float distances.
"Optimal" is CP-SAT's proof for the rounded problem: the routes' real makespan is then
within :math:`(n + 1) / S` of the real optimum (``bound`` is reported separately).
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from benchmarks.common import peer_main

#: Distances are multiplied by this and rounded down to integers.
SCALE = 10_000


def solve(payload: dict[str, Any]) -> dict[str, Any]:
    """Solve the payload's problem with CP-SAT (module docstring) and report it."""
    from ortools.sat.python import cp_model

    began = time.perf_counter()
    D = np.asarray(payload["distances"], dtype=np.float64)
    tours = payload["routes"] == "tours"
    robots = payload.get("robots")
    deadline = payload.get("deadline")
    scale = float(payload.get("scale", SCALE))
    n = len(D) - 1
    delta = np.floor(D * scale).astype(np.int64)
    closing = delta[:, 0] if tours else np.zeros(n + 1, dtype=np.int64)
    horizon = int(delta.max(axis=1).sum() + closing.max())

    model = cp_model.CpModel()
    arcs, literal = [], {}
    for i in range(n + 1):
        for j in range(n + 1):
            if i != j:
                literal[i, j] = model.NewBoolVar(f"l_{i}_{j}")
                arcs.append((i, j, literal[i, j]))
    model.AddMultipleCircuit(arcs)  # (1)
    arrival = [None] + [model.NewIntVar(int(delta[0, i]), horizon, f"a_{i}")
                        for i in range(1, n + 1)]  # (6) lower end
    T = model.NewIntVar(0, horizon, "T")
    leaving = [literal[0, j] for j in range(1, n + 1)]
    if robots is not None:  # (2)
        model.Add(sum(leaving) <= int(robots))
    for j in range(1, n + 1):  # (3)
        model.Add(arrival[j] == int(delta[0, j])).OnlyEnforceIf(literal[0, j])
        for i in range(1, n + 1):
            if i != j:
                model.Add(arrival[j] >= arrival[i] + int(delta[i, j])).OnlyEnforceIf(literal[i, j])
        model.Add(T >= arrival[j] + int(closing[j])).OnlyEnforceIf(literal[j, 0])  # (4)
        model.Add(T >= arrival[j] + int(closing[j]) - n)  # (7)
    if robots is not None:
        model.Minimize(T)
    else:
        model.Add(T <= int(np.ceil(float(deadline) * scale)))  # (5)
        model.Minimize(sum(leaving))

    solver = cp_model.CpSolver()
    solver.parameters.num_workers = int(payload.get("workers", 2))
    if payload.get("time_limit") is not None:
        solver.parameters.max_time_in_seconds = float(payload["time_limit"])
    code = solver.Solve(model)
    status = {cp_model.OPTIMAL: "optimal", cp_model.FEASIBLE: "feasible",
              cp_model.INFEASIBLE: "infeasible"}.get(code, "unknown")
    answer: dict[str, Any] = {"status": status, "routes": [], "objective": None, "bound": None,
                              "scale": scale}
    if status in ("optimal", "feasible"):
        successor = {i: j for (i, j), lit in literal.items() if i > 0 and solver.BooleanValue(lit)}
        routes = []
        for j in range(1, n + 1):
            if solver.BooleanValue(literal[0, j]):
                route = [j]
                while successor[route[-1]] != 0:
                    route.append(successor[route[-1]])
                routes.append(route)
        answer["routes"] = routes
        answer["objective"] = (float(len(routes)) if robots is None
                               else _makespan(D, routes, tours=tours))
    if status != "infeasible":
        best = float(solver.BestObjectiveBound())
        answer["bound"] = best if robots is None else best / scale
    answer["seconds"] = time.perf_counter() - began
    return answer


def _makespan(D: np.ndarray, routes: list[list[int]], *, tours: bool) -> float:
    """Largest real route cost (float distances)."""
    costs = []
    for route in routes:
        stops = [0, *route, 0] if tours else [0, *route]
        costs.append(float(D[stops[:-1], stops[1:]].sum()))
    return max(costs)


if __name__ == "__main__":
    peer_main(solve, "ortools")
