"""What every exact method of :mod:`milp` shares.

- :mod:`~milp.core.result`: :class:`~milp.core.result.MilpResult`, the answer every solver returns.
- :mod:`~milp.core.routes`: route arithmetic (costs, the shared tolerance, validation).
- :mod:`~milp.core.merge`: KPOIs at distance 0 merged before modelling, split after.
- :mod:`~milp.core.highs`: HiGHS options, statuses, bounds and model export.
- :mod:`~milp.core.timelimit`: one time limit shared by every phase of a solve.
- :mod:`~milp.core.sizes`: the largest instance each exact method accepts.
- :mod:`~milp.core.jit`: numba's ``njit`` with an on-disk cache.
- :mod:`~milp.core.progress`: progress lines of a long solve, through :mod:`logging`.
- :mod:`~milp.core.orphans`: child processes that end with their parent.
- :mod:`~milp.core.lazy`: a package's public names imported on first read (PEP 562).
"""
