"""The compact arc-flow MILP: two-index arcs plus distance flow.

- :mod:`~milp.compact.arcflow`: the model solved with HiGHS (arc pruning, warm start); the default
  for small instances.
- :mod:`~milp.compact.cvx`: the same model written in cvxpy, to be read (cvxpy takes most of a
  second to load: import it on demand).
- :mod:`~milp.compact.frontier`: the robots-vs-makespan frontier with the arc-flow model.
"""
