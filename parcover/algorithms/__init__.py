"""Solution methods: the paper's greedy algorithms, baselines and heuristics.

Each public function has the :class:`parcover.problem.Method` signature
``method(instance, problem, *, time_limit, seed) -> Solution``.
"""
