"""Where ``best`` starts: the best of every registered construction and its own.

:func:`best_construction` runs every registered method that is a construction (all
but ``best``, ``trivial`` and the exact ones), each with a share of the time limit,
plus :func:`min_max_insertion`, and keeps the valid answer with the least objective key.
"""

from __future__ import annotations

import time

from parcover import exact
from parcover.algorithms.moves import Search
from parcover.instance import Instance
from parcover.problem import Problem

#: Methods that are not constructions: ourselves, the trivial one and every exact method.
_NOT_STARTS = frozenset({"best", "trivial", *(method.name for method in exact.METHODS)})
_CONSTRUCTION_SHARE = 0.025  # of the time limit, for each construction
_CONSTRUCTIONS_SHARE = 0.5  # of the time limit: no construction starts after it
_QUICK = "nn"  # the construction run when none answered in time and ours would not fit
_INSERTION_SECONDS = 1.5e-6  # min_max_insertion per KPOI pair (1.3 s at 1000 KPOIs, measured)


def best_construction(
    instance: Instance, problem: Problem, *, time_limit: float | None, seed: int
) -> tuple[str, list[list[int]]]:
    """The valid construction with the least objective key (name, routes).

    Every registered method except ``best``, ``trivial`` and the exact ones is tried
    (each gets :data:`_CONSTRUCTION_SHARE` of the time limit), then
    :func:`min_max_insertion`. Most constructions cannot be interrupted and some take
    a second at 1000 KPOIs, so under a time limit none starts once
    :data:`_CONSTRUCTIONS_SHARE` of it has passed, and ours (O(n^2)) only when its
    expected time (:data:`_INSERTION_SECONDS`) fits; when it does not and nothing else
    answered, :data:`_QUICK` (then ours if that fails). One that
    raises or answers invalid routes is skipped. Ties go to the construction listed
    first (registry order, then ours).
    """
    from parcover.solve import available_methods  # solve imports local_search, which imports this

    stop = None if time_limit is None else time.perf_counter() + _CONSTRUCTIONS_SHARE * time_limit
    search = Search(instance, problem)
    candidates: list[tuple[str, list[list[int]]]] = []
    share = None if time_limit is None else time_limit * _CONSTRUCTION_SHARE
    for name, info in available_methods().items():
        if name.split(":")[0] in _NOT_STARTS:  # a label such as best:iterations=5 is best
            continue
        if stop is not None and time.perf_counter() >= stop:
            break
        try:
            solution = info.function(instance, problem, time_limit=share, seed=seed)
        except Exception:  # a failing construction must not break `best`
            continue
        if not solution.drops_deadline and search.valid(solution.routes):
            candidates.append((name, [list(map(int, r)) for r in solution.routes if r]))
    ours_ends = time.perf_counter() + _INSERTION_SECONDS * instance.n**2
    if stop is None or ours_ends <= stop:
        candidates.append(("min_max_insertion", min_max_insertion(instance, problem)))
    elif not candidates:
        # Nothing answered before the stop and ours would not fit (14 s at 3000 KPOIs,
        # run anyway it held `exact --time-limit 3` 10 s): the nearest neighbour
        # answers at once (0.03 s at 3000 KPOIs), ours only if it fails.
        try:
            quick = available_methods()[_QUICK].function(instance, problem, time_limit=share, seed=seed)
            if not quick.drops_deadline and search.valid(quick.routes):
                candidates.append((_QUICK, [list(map(int, r)) for r in quick.routes if r]))
        except Exception:  # as above: a failing construction must not break `best`
            pass
        if not candidates:
            candidates.append(("min_max_insertion", min_max_insertion(instance, problem)))
    return min(candidates, key=lambda c: search.key(search.sequences(c[1])))


def min_max_insertion(instance: Instance, problem: Problem) -> list[list[int]]:
    """Our own construction: KPOIs farthest from the start first, each at the position
    that keeps the makespan least (then adds least length); under a deadline, the
    cheapest position within it, or a new route."""
    search = Search(instance, problem)
    seqs = search.empty_routes()
    search.insert_all(seqs, search.farthest_first(range(1, instance.n + 1)))
    return [s[1:-1] for s in seqs if len(s) > 2]
