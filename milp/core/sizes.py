"""The largest instance, in KPOIs, each exact model accepts.

The limits live in this module, which imports nothing, so that a caller choosing a
model by size (``parcover``'s ``exact`` answers larger instances with the compact model
alone) reads them without loading the models (HiGHS, numba). Each model's module
exposes its own as ``MAX_KPOIS``.
"""

__all__ = ["SETPART_MAX_KPOIS", "BRANCHPRICE_MAX_KPOIS", "BRANCHCUT_MAX_KPOIS"]

#: Set partitioning (:mod:`milp.setpart`): 2^20 subsets x 20 end KPOIs is ~21 M DP
#: states (170 MB of costs, 21 MB of parents, about 2 s); each extra KPOI doubles time
#: and memory.
SETPART_MAX_KPOIS = 20
#: Branch-and-price (:mod:`milp.branchprice`): the number of (merged) KPOIs the
#: pricing's bit masks are tested with.
BRANCHPRICE_MAX_KPOIS = 200
#: Branch-and-cut (:mod:`milp.branchcut`; the model has k x n^2 / 2 edge columns). The
#: time limit holds to it (TSPLIB kroA100 and rat99, 2 and 3 tours, 10 and 30 s: at most
#: 2.4% over); above, HiGHS's own cut separation at the root node ignores its time limit
#: for seconds (ch150 with 3 tours, 10 s: 15.7 s, 10 s of it in one root separation round).
BRANCHCUT_MAX_KPOIS = 100
