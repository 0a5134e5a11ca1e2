"""Branch-and-price over ng-routes: fewest routes within a deadline, least makespan with k.

- :mod:`~milp.branchprice.search`: the search (:func:`min_robots`): column generation at each
  node, branching, enumeration.
- :mod:`~milp.branchprice.makespan`: the least makespan (:func:`min_makespan`) as a sequence of
  fewest-routes decisions, and its LP-bisection bound.
- :mod:`~milp.branchprice.tree`: the tree of one fewest-routes decision.
- :mod:`~milp.branchprice.ngroute`: the pricing, by labelling over ng-routes (numba).
- :mod:`~milp.branchprice.columns`: the column pool and the branching nodes.
- :mod:`~milp.branchprice.cuts`: separation of the subset-row cuts.
- :mod:`~milp.branchprice.enumeration`: every route that can still be in a solution, once the
  gap is small.
- :mod:`~milp.branchprice.colgen`: certified lower bounds from column generation alone, for
  instances too large to prove.
- :mod:`~milp.branchprice.compiling`: whether the compiled functions are ready, and compiling them.
"""

from milp.core.lazy import lazy_getattr

__all__ = ["min_robots", "min_makespan", "ready_within", "compile_pricing", "MAX_KPOIS", "COMPILE_SECONDS"]

# The search's public names, loaded on first use: importing :mod:`~milp.branchprice.colgen`
# alone does not load numba's labelling.
__getattr__ = lazy_getattr(__name__, globals(), {**dict.fromkeys(__all__, "milp.branchprice.search"),
                                                 "min_makespan": "milp.branchprice.makespan"})
