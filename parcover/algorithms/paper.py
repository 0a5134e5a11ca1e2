"""The paper's greedy algorithms: Algorithm 1, Algorithm 1-1 and Algorithm 2 (Section V).

Algorithm 1 (parallel path coverage at ``c_p = c_max``) sends the first robot along
the shortest path to the farthest KPOI ``v_max`` (steps 1-4), then starts every
further path at the remaining KPOI nearest the start and extends it greedily while
its cost stays within ``cost(pi_max) = c_max`` (steps 5a-5e). Algorithm 1-1 inserts
supplementary steps between 4 and 5 that extend the first path up to a deadline
``c_p > c_max``; every later path then uses the same threshold ``c_p``. Algorithm 2
(parallel tour coverage) pairs those paths into tours: the costliest path with the
path whose end minimises ``cost(pi_a) + w + cost(pi_b)``.

Readings
--------
The printed algorithms leave two choices open; each combination is a method:

``paper``
    The literal reading. Step 5d looks for the KPOI nearest to the path's *first*
    node ``v_m`` (the text never moves ``v_m``) and applies the printed test
    ``cost(pi_i) + w(v_m, v_j) <= threshold``; Algorithm 1-1 step 1 takes the KPOI
    nearest to the *start* (``m = argmin_l pi_sl``).
``paper-5d-end``
    Step 5d takes the KPOI nearest the path's current end, which then becomes the
    new end (the printed test then is the path's true cost).
``paper-1-1-end``
    Algorithm 1-1 step 1 takes the KPOI nearest the current end ``v_d`` (step 2
    measures ``w(v_d, v_m)`` and moves ``v_d``); step 5d literal.
``paper-nearest-end``
    Both: nearest-neighbour growth of every path.

Decisions common to all readings
--------------------------------
- ``cost(pi_i)`` is the true cost of the path as built: KPOIs are appended at its
  end, in the order they are inserted.
- Repair (``paper`` and ``paper-1-1-end``): after the first insertion of step 5d the path's end is no
  longer ``v_m``, so the printed test can accept a KPOI that takes the path past the
  threshold. Such a KPOI is refused and step 5d breaks, as for a failed test; the
  trace says "repair".
- Step 5c: ``P_i`` is the KPOIs of the instance's shortest path ``s -> v_m`` that are
  still in ``V`` (the printed ``pi_si ∩ V``); KPOIs already covered are passed
  through, not covered twice. Since ``v_m`` is the remaining KPOI nearest the
  start, every other KPOI on that path is nearer and so already covered, unless it
  lies at the same distance (zero-weight edges): the question whether ``P_i`` may
  hold covered KPOIs only arises then, so it gets no variant. In complete
  Euclidean instances ``P_i = {v_m}``.
- Step 6 prints ``k = i`` after step 5e has already increased ``i``: one more than
  the number of paths built. The robot count reported is the number of paths.
- Algorithm 1 uses the threshold ``cost(pi_max) = c_max``; Algorithm 1-1 uses
  ``c_p`` both for its supplementary steps and for step 5d of every later path.
  Algorithm 1 runs when ``c_p <= c_max``, Algorithm 1-1 when ``c_p > c_max``.
- Algorithm 2 step 3 ranges over the other paths only (``l != a``); an odd path out
  becomes a tour of its own. A tour ``pi_a + pi_b`` is ``s -> P_a -> reversed(P_b)
  -> s`` and costs ``cost(pi_a) + w(end_a, end_b) + cost(pi_b)``.
- Threshold tests use the contract's tolerance (:func:`parcover.problem.meets_deadline`).
- Ties go to the first KPOI in instance order (and to the first path built, in
  Algorithm 2).

Adaptations to the questions of :class:`parcover.problem.Problem`
-----------------------------------------------------------------
- Paths, robots objective: Algorithm 1 at ``c_max`` or Algorithm 1-1 at the deadline.
- Tours without a deadline: Algorithm 2 as published on Algorithm 1's paths; its
  tours may exceed ``2 c_max``, so the answer drops the deadline and reports the
  makespan reached (``Solution.drops_deadline``).
- Tours with a deadline ``c_t`` (``>= 2 c_max``): paths from Algorithm 1 / 1-1 at
  ``c_p = c_t / 2`` (``>= c_max``, the analogue of ``c_max`` against ``2 c_max``),
  so a path alone makes a tour of cost ``<= c_t / 2 + c_max <= c_t``; Algorithm 2
  pairs ``pi_a`` with its best partner ``pi_b`` only when that tour meets ``c_t``,
  else ``pi_a`` becomes a tour alone (``b`` minimises the pair cost, so no other
  partner would fit either).
- A robot limit ``K`` (makespan objective): the robot count need not be monotone
  in the threshold (a larger ``c_p`` lets an early path take a KPOI that would
  have anchored a better later path), so the thresholds are scanned upwards exactly. A run's decisions are a
  sequence of threshold tests; it stays the same for every threshold from its
  largest accepted test value up to (not including) its smallest rejected one. The
  scan runs Algorithm 1 at the least threshold, then Algorithm 1-1 just above it
  and at each run's smallest rejected value, so it meets every distinct
  run in increasing order and stops at the first with at most ``K`` routes:
  the least threshold at which the algorithm needs at most ``K`` robots. After
  ``max_scan_runs`` runs (or the time limit) it bisects between the last run scanned
  and the one-route run instead, and ``info["search"]["exact"]`` is ``False``: the
  threshold found is then one where ``K`` robots suffice and the run just below it
  needs more, not necessarily the least such. For tours the threshold is ``c_t``
  (paths at ``c_t / 2`` as above).
- ``Solution.info``: ``"algorithm"`` (which ran), ``"threshold"`` (``c_p``, or
  ``c_t`` for tours), ``"search"`` (``exact`` and ``runs``, under a robot limit) and,
  when asked for, ``"trace"`` (the steps as lines of text) with ``"steps"`` (the same
  steps as :class:`TraceStep` records, one per line, which :mod:`parcover.frames`
  draws).

References
----------
H. J. Min and N. Papanikolopoulos, "The Multi-robot Coverage Problem for Optimal Coordinated
Search with an Unknown Number of Robots", Section V: Algorithm 1, Algorithm 1-1,
Algorithm 2. ``docs/algorithms.md`` restates them step by step with these readings.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from parcover.instance import Instance
from parcover.problem import MethodInfo, Problem, Solution, meets_deadline
from parcover.result import Status

__all__ = [
    "TraceStep",
    "paper",
    "paper_5d_end",
    "paper_1_1_end",
    "paper_nearest_end",
    "Reading",
    "LITERAL",
    "NEAREST_END",
    "algorithm_1",
    "algorithm_2",
    "METHODS",
]

_MAX_SCAN_RUNS = 200
_MAX_BISECTIONS = 60


@dataclass(frozen=True)
class Reading:
    """Where the greedy extensions start (module docstring, Readings).

    Attributes
    ----------
    grow_from_end
        Step 5d takes the KPOI nearest the path's current end (which moves to each
        inserted KPOI) instead of the one nearest ``v_m``, the path's first node.
    supplement_from_end
        Algorithm 1-1 step 1 takes the KPOI nearest the current end ``v_d`` instead
        of the one nearest the start.
    """

    grow_from_end: bool = False
    supplement_from_end: bool = False


LITERAL = Reading()
_5D_END = Reading(grow_from_end=True)
_1_1_END = Reading(supplement_from_end=True)
NEAREST_END = Reading(grow_from_end=True, supplement_from_end=True)


@dataclass(frozen=True)
class TraceStep:
    """One recorded step of Algorithm 1, 1-1 or 2: its line of text and the state it leaves.

    Attributes
    ----------
    text
        The step as a readable line, led by the paper's step number ("Alg 1 step 5d: ...").
    paths
        Paths as KPOI ids in visiting order, the start implicit: in Algorithm 1 and 1-1
        the paths built so far (the last one possibly still growing); in Algorithm 2
        every path it pairs, numbered as in ``text`` (path 1 first).
    tours
        Algorithm 2: the tours formed so far, KPOI ids (the start implicit at both ends).
    current
        Index of the path this step grows (in ``paths``) or of the tour it forms (in ``tours``).
    candidate
        The KPOI the step considers (Algorithm 1 and 1-1).
    anchor
        The node the candidate's distance is measured from: the path's end, or ``v_m``
        (the path's first KPOI) in the literal step 5d, or the start.
    accepted
        Whether the candidate was taken (or, in Algorithm 2, a partner joined).
    cost
        Cost of the current path (or tour) once the step is done.
    threshold
        What ``cost`` is tested against: ``c_max`` (Algorithm 1), ``c_p`` (1-1) or
        the tour deadline ``c_t`` (Algorithm 2 under a deadline).
    joined
        Algorithm 2: indices in ``paths`` of the paths forming this step's tour.
    remaining
        Algorithm 2: indices in ``paths`` of the paths still to pair after this step.
    """

    text: str
    paths: tuple[tuple[str, ...], ...] = ()
    tours: tuple[tuple[str, ...], ...] = ()
    current: int | None = None
    candidate: str | None = None
    anchor: str | None = None
    accepted: bool | None = None
    cost: float | None = None
    threshold: float | None = None
    joined: tuple[int, ...] = ()
    remaining: tuple[int, ...] = ()

    @property
    def budget_left(self) -> float | None:
        """``threshold - cost``: how much the current path may still grow."""
        return None if self.cost is None or self.threshold is None else self.threshold - self.cost


Trace = list[TraceStep]


class _Recorder:
    """Appends :class:`TraceStep` records to a trace, naming KPOIs by id."""

    def __init__(self, trace: Trace, ids: tuple[str, ...]) -> None:
        self.trace = trace
        self.ids = ids

    def names(self, routes: Sequence[list[int]]) -> tuple[tuple[str, ...], ...]:
        return tuple(tuple(self.ids[i] for i in route) for route in routes)

    def add(self, text: str, paths: Sequence[list[int]] = (), tours: Sequence[list[int]] = (), *,
            candidate: int | None = None, anchor: int | None = None, **state: Any) -> None:
        self.trace.append(TraceStep(
            text, self.names(paths), self.names(tours),
            candidate=None if candidate is None else self.ids[candidate],
            anchor=None if anchor is None else self.ids[anchor], **state,
        ))


@dataclass
class _Tests:
    """The threshold tests of one run: the largest accepted and smallest rejected value.

    The run makes the same decisions for every threshold in ``[accepted, rejected)``.
    ``scale`` converts a tested value to the searched threshold (2 for paths built at
    ``c_t / 2``).
    """

    scale: float = 1.0
    accepted: float = -math.inf
    rejected: float = math.inf

    def passes(self, value: float, threshold: float) -> bool:
        ok = meets_deadline(value, threshold)
        if ok:
            self.accepted = max(self.accepted, value * self.scale)
        else:
            self.rejected = min(self.rejected, value * self.scale)
        return ok


@dataclass
class _Run:
    """Routes of one run and what the scan needs to know about it."""

    routes: list[list[int]]
    threshold: float
    algorithm: str
    tests: _Tests
    trace: Trace | None = field(default=None)


# -- Algorithm 1 and 1-1 -----------------------------------------------------------------


def algorithm_1(
    instance: Instance,
    c_p: float | None = None,
    *,
    reading: Reading = LITERAL,
    trace: Trace | None = None,
    tests: _Tests | None = None,
) -> list[list[int]]:
    """Paths of Algorithm 1 (``c_p <= c_max``) or Algorithm 1-1 (``c_p > c_max``).

    Parameters
    ----------
    instance
        The instance.
    c_p
        The deadline of every path; ``None`` means ``c_max`` (Algorithm 1).
    reading
        Where step 5d and Algorithm 1-1 step 1 look for the nearest KPOI; default
        the literal reading.
    trace
        When a list, the steps are appended to it as :class:`TraceStep` records.
    tests
        Records the threshold tests (for the robot-limit scan).

    Returns
    -------
    list[list[int]]
        Paths as KPOI indices in visiting order, start implicit; every path costs at
        most ``max(c_p, c_max)`` and the first exactly ``c_max`` (Prop. 1).

    Notes
    -----
    O(n^2) time: each insertion or refusal is one masked ``argmin`` over a row of
    the distance matrix, and new paths take the nearest remaining KPOI to the start
    from one sorted order.
    """
    tests = _Tests() if tests is None else tests
    d = instance.distances
    ids = instance.ids
    n = instance.n
    c_max = instance.c_max
    supplementary = c_p is not None and c_p > c_max
    threshold = c_p if supplementary else c_max
    label = "Alg 1-1" if supplementary else "Alg 1"
    record = _Recorder(trace, ids) if trace is not None else None
    # Step 1: shortest path costs from the start (row 0 of the metric closure).
    from_start = d[0]
    by_start = np.argsort(from_start[1:], kind="stable") + 1
    if record is not None:
        record.add(f"Alg 1 step 1: shortest paths from the start {ids[0]} to the {n} KPOIs")
    # `blocked` is 0 for KPOIs still in V and inf otherwise: argmin(row + blocked)
    # is the nearest remaining KPOI, ties to the first in instance order.
    blocked = np.zeros(n + 1)
    blocked[0] = math.inf
    left = n
    cursor = 0

    def cover(i: int) -> None:
        nonlocal left
        blocked[i] = math.inf
        left -= 1

    def nearest_to_start() -> int:
        nonlocal cursor
        while blocked[by_start[cursor]] != 0:
            cursor += 1
        return int(by_start[cursor])

    # Step 2: the destination v_d = v_max, the KPOI farthest from the start.
    v_d = int(np.argmax(from_start[1:])) + 1
    # Steps 3-4: P_1 = the KPOIs on the shortest path s -> v_d; V = V \ P_1.
    first = list(instance.kpoi_indices_on_shortest_path(v_d))
    paths = [first]
    cost = _path_cost(d, first)
    for i in first:
        cover(i)
    if record is not None:
        record.add(f"Alg 1 step 2: v_d = v_max = {ids[v_d]}, c_max = {c_max:g}",
                   candidate=v_d, anchor=0, accepted=True)
        state = dict(current=0, cost=cost, threshold=threshold)
        record.add(
            f"Alg 1 step 3: path 1 = shortest path s -> {ids[v_d]}, P_1 = {_names(ids, first)}, "
            f"cost {cost:g}, budget left {threshold - cost:g}", paths, **state
        )
        record.add(f"Alg 1 step 4: V = V \\ P_1, {left} KPOIs left", paths, **state)
    if supplementary:
        cost = _supplementary_steps(
            d, ids, first, cost, threshold, reading.supplement_from_end, nearest_to_start, blocked, cover, tests,
            record,
        )
    # Step 5: new paths until V is empty.
    i = 2
    while left:
        # 5a-5b: the remaining KPOI nearest the start is the end node v_m.
        v_m = nearest_to_start()
        # 5c: P_i = the KPOIs of the shortest path s -> v_m still in V.
        path = [j for j in instance.kpoi_indices_on_shortest_path(v_m) if blocked[j] == 0]
        paths.append(path)
        cost = _path_cost(d, path)
        for j in path:
            cover(j)
        if record is not None:
            record.add(
                f"{label} step 5a-5c: path {i}: nearest KPOI to the start v_m = {ids[v_m]}, "
                f"P_{i} = {_names(ids, path)}, cost {cost:g}, budget left {threshold - cost:g}",
                paths, current=len(paths) - 1, candidate=v_m, anchor=0, accepted=True, cost=cost, threshold=threshold,
            )
        _extend(d, ids, paths, cost, v_m, threshold, reading.grow_from_end, left, blocked, cover, tests, record,
                label)
        # 5e
        i += 1
    if record is not None:
        record.add(
            f"{label} step 6: k = i - 1 = {_plural(len(paths), 'robot')} "
            f"(the printed 'k = i' would count {i}: step 5e already moved i past the last path)", paths
        )
    return paths


def _supplementary_steps(
    d: np.ndarray,
    ids: tuple[str, ...],
    first: list[int],
    cost: float,
    c_p: float,
    from_end: bool,
    nearest_to_start: Callable[[], int],
    blocked: np.ndarray,
    cover: Callable[[int], None],
    tests: _Tests,
    record: _Recorder | None,
) -> float:
    """Algorithm 1-1 steps 1-4: extend the first path while it meets ``c_p``.

    Step 1 takes the KPOI nearest the start (literal) or nearest the end ``v_d``
    (``from_end``); step 2 appends it when ``cost(pi_s1) + w(v_d, v_m) <= c_p``
    and makes it the new ``v_d``, else breaks. Returns the new cost of the path.
    """
    while np.isfinite(blocked).any():
        v_d = first[-1]
        v_m = int(np.argmin(d[v_d] + blocked)) if from_end else nearest_to_start()
        new_cost = cost + float(d[v_d, v_m])
        ok = tests.passes(new_cost, c_p)
        if ok:
            first.append(v_m)
            cover(v_m)
        if record is not None:
            sign = "<=" if ok else ">"
            near = f"the end {ids[v_d]}" if from_end else "the start"
            record.add(
                f"Alg 1-1 step 1-2: nearest KPOI to {near}: {ids[v_m]}; "
                f"{cost:g} + {d[v_d, v_m]:g} = {new_cost:g} {sign} c_p = {c_p:g}, "
                + (f"add it (steps 3-4), budget left {c_p - new_cost:g}" if ok else "break"),
                [first], current=0, candidate=v_m, anchor=v_d, accepted=ok, cost=new_cost if ok else cost,
                threshold=c_p,
            )
        if not ok:
            break
        cost = new_cost
    return cost


def _extend(
    d: np.ndarray,
    ids: tuple[str, ...],
    paths: list[list[int]],
    cost: float,
    v_m: int,
    threshold: float,
    from_end: bool,
    left: int,
    blocked: np.ndarray,
    cover: Callable[[int], None],
    tests: _Tests,
    record: _Recorder | None,
    label: str,
) -> None:
    """Step 5d: append the nearest remaining KPOI to the last of ``paths`` while it meets the threshold.

    Literal reading: nearest to ``v_m`` and the printed test
    ``cost(pi_i) + w(v_m, v_j) <= threshold``, plus the repair that refuses a KPOI
    taking the path itself past the threshold. ``from_end``: nearest to the
    current end, which moves to each inserted KPOI.
    """
    path = paths[-1]
    while left > 0:
        end = path[-1]
        anchor = end if from_end else v_m
        v_j = int(np.argmin(d[anchor] + blocked))
        printed = cost + float(d[anchor, v_j])
        actual = cost + float(d[end, v_j])
        ok = tests.passes(printed, threshold)
        repaired = ok and anchor != end and not tests.passes(actual, threshold)
        inserted = ok and not repaired
        if inserted:
            path.append(v_j)
            cover(v_j)
        if record is not None:
            sign = "<=" if ok else ">"
            line = (
                f"{label} step 5d: nearest KPOI to {ids[anchor]}: {ids[v_j]}; {cost:g} + "
                f"{d[anchor, v_j]:g} = {printed:g} {sign} {threshold:g}, "
            )
            if repaired:
                line += f"but the path from {ids[end]} would cost {actual:g}: repair, break"
            elif ok:
                line += f"insert; path cost {actual:g}, budget left {threshold - actual:g}"
            else:
                line += "break"
            record.add(line, paths, current=len(paths) - 1, candidate=v_j, anchor=anchor, accepted=inserted,
                       cost=actual if inserted else cost, threshold=threshold)
        if not inserted:
            return
        cost = actual
        left -= 1


# -- Algorithm 2 -------------------------------------------------------------------------


def algorithm_2(
    instance: Instance,
    paths: list[list[int]],
    deadline: float | None = None,
    *,
    trace: Trace | None = None,
    tests: _Tests | None = None,
) -> list[list[int]]:
    """Tours of Algorithm 2: pair the costliest path with its best partner.

    Parameters
    ----------
    instance
        The instance.
    paths
        Paths as KPOI indices (e.g. from :func:`algorithm_1`).
    deadline
        ``None``: Algorithm 2 as published. Otherwise a pair is joined only when its
        tour meets ``deadline`` (else the costliest path is a tour alone).
    trace, tests
        As in :func:`algorithm_1`.

    Returns
    -------
    list[list[int]]
        Tours as KPOI indices, start implicit at both ends: ``P_a`` then ``P_b``
        reversed (steps 1-6), an odd path out alone.
    """
    tests = _Tests() if tests is None else tests
    d = instance.distances
    ids = instance.ids
    record = _Recorder(trace, ids) if trace is not None else None
    costs = np.array([_path_cost(d, p) for p in paths])
    ends = np.array([p[-1] for p in paths], dtype=np.int64)
    alive = np.ones(len(paths), dtype=bool)
    tours: list[list[int]] = []
    i = 1
    while alive.any():
        # Steps 1-2: the costliest remaining path pi_a and its end v_d.
        a = int(np.argmax(np.where(alive, costs, -math.inf)))
        alive[a] = False
        # Step 3: the partner b != a minimising cost(pi_a) + w(v_d, v_l) + cost(pi_l).
        pair = np.where(alive, costs[a] + d[ends[a], ends] + costs, math.inf)
        b = int(np.argmin(pair)) if alive.any() else None
        joined = b is not None and (deadline is None or tests.passes(float(pair[b]), deadline))
        if joined:
            assert b is not None
            alive[b] = False
            tours.append(paths[a] + paths[b][::-1])
        else:
            tours.append(list(paths[a]))
        if record is not None:
            alone = costs[a] + d[ends[a], 0]
            head = f"Alg 2 steps 1-5: tour {i}: costliest path {a + 1} (cost {costs[a]:g}, end {ids[ends[a]]})"
            if joined:
                assert b is not None
                line = (
                    f"{head} + path {b + 1} (end {ids[ends[b]]}): {costs[a]:g} + "
                    f"{d[ends[a], ends[b]]:g} + {costs[b]:g} = {pair[b]:g}"
                    + ("" if deadline is None else f", budget left {deadline - pair[b]:g}")
                )
            elif b is None:
                line = f"{head}: no path left to pair with, a tour alone ({alone:g})"
            else:
                line = f"{head}: best partner path {b + 1} gives {pair[b]:g} > {deadline:g}, a tour alone ({alone:g})"
            record.add(
                line, paths, tours, current=len(tours) - 1, accepted=joined, threshold=deadline,
                cost=float(pair[b]) if joined else float(alone),
                joined=(a, b) if joined else (a,), remaining=tuple(int(l) for l in np.flatnonzero(alive)),
            )
        # Step 6
        i += 1
    if record is not None:
        record.add(f"Alg 2 step 6: Phi is empty: {_plural(len(tours), 'tour')}", paths, tours)
    return tours


# -- the methods ------------------------------------------------------------------------


def paper(
    instance: Instance,
    problem: Problem,
    *,
    time_limit: float | None = None,
    seed: int = 0,
    trace: bool = False,
    max_scan_runs: int = _MAX_SCAN_RUNS,
) -> Solution:
    """The paper's Algorithms 1, 1-1 and 2, read literally (see the module docstring).

    ``trace=True`` puts every step, with the paper's step numbers, in
    ``Solution.info["trace"]``. ``seed`` is unused (the algorithms are deterministic).
    ``max_scan_runs`` (default 200) bounds the exact scan under a robot limit.

    Examples
    --------
    Start at 0 and KPOIs at 1, 2, 3 on a line: the first path goes to 3 (``c_max``),
    the second covers 1 then 2.

    >>> from parcover import Instance
    >>> line = Instance.from_points([[0, 0], [1, 0], [2, 0], [3, 0]], names="sabc")
    >>> paper(line, Problem()).routes
    [[3], [1, 2]]
    """
    return _answer(instance, problem, LITERAL, time_limit, trace, max_scan_runs)


def paper_5d_end(
    instance: Instance,
    problem: Problem,
    *,
    time_limit: float | None = None,
    seed: int = 0,
    trace: bool = False,
    max_scan_runs: int = _MAX_SCAN_RUNS,
) -> Solution:
    """As :func:`paper`, but step 5d grows each path from its current end."""
    return _answer(instance, problem, _5D_END, time_limit, trace, max_scan_runs)


def paper_1_1_end(
    instance: Instance,
    problem: Problem,
    *,
    time_limit: float | None = None,
    seed: int = 0,
    trace: bool = False,
    max_scan_runs: int = _MAX_SCAN_RUNS,
) -> Solution:
    """As :func:`paper`, but Algorithm 1-1 step 1 takes the KPOI nearest the end ``v_d``."""
    return _answer(instance, problem, _1_1_END, time_limit, trace, max_scan_runs)


def paper_nearest_end(
    instance: Instance,
    problem: Problem,
    *,
    time_limit: float | None = None,
    seed: int = 0,
    trace: bool = False,
    max_scan_runs: int = _MAX_SCAN_RUNS,
) -> Solution:
    """As :func:`paper`, but step 5d and Algorithm 1-1 step 1 both extend from the
    path's current end (nearest-neighbour growth)."""
    return _answer(instance, problem, NEAREST_END, time_limit, trace, max_scan_runs)


def _answer(
    instance: Instance,
    problem: Problem,
    reading: Reading,
    time_limit: float | None,
    trace: bool,
    max_scan_runs: int,
) -> Solution:
    """Dispatch a :class:`Problem` to the algorithms (module docstring, Adaptations)."""
    least = problem.least_makespan(instance)

    def run(threshold: float, supplementary: bool) -> _Run:
        steps: Trace | None = [] if trace else None
        if problem.tours:
            return _tour_run(instance, threshold, supplementary, reading, steps)
        return _path_run(instance, threshold, supplementary, reading, steps)

    if problem.objective == "makespan":
        assert problem.robots is not None
        best, search = _scan(run, least, problem.robots, time_limit, max_scan_runs)
        info: dict[str, Any] = {"algorithm": best.algorithm, "threshold": best.threshold, "search": search}
        lines = search.pop("lines")
        if trace:
            assert best.trace is not None
            info |= _trace_info([TraceStep(line) for line in lines] + best.trace, instance, problem, best.routes)
        return Solution(routes=best.routes, info=info)

    if problem.tours and problem.deadline is None:
        steps: Trace | None = [] if trace else None
        paths = algorithm_1(instance, reading=reading, trace=steps)
        tours = algorithm_2(instance, paths, trace=steps)
        info = {"algorithm": "1 + 2 (published)", "threshold": instance.c_max}
        if steps is not None:
            info |= _trace_info(steps, instance, problem, tours)
        return Solution(routes=tours, drops_deadline=True, info=info)

    deadline = problem.effective_deadline(instance)
    assert deadline is not None
    if not meets_deadline(least, deadline):
        return Solution(routes=[], status=Status.INFEASIBLE)
    result = run(deadline, deadline > least)
    info = {"algorithm": result.algorithm, "threshold": result.threshold}
    if trace:
        assert result.trace is not None
        info |= _trace_info(result.trace, instance, problem, result.routes)
    return Solution(routes=result.routes, info=info)


def _path_run(
    instance: Instance,
    c_p: float,
    supplementary: bool,
    reading: Reading,
    trace: Trace | None,
    tests: _Tests | None = None,
) -> _Run:
    """Algorithm 1 (``supplementary=False``) or Algorithm 1-1 at ``c_p``.

    Algorithm 1-1 at ``c_p = c_max`` is the limit of Algorithm 1-1 from above, which
    the robot-limit scan needs; :func:`algorithm_1` runs it for ``c_p > c_max`` only,
    so it is asked for at the next float up.
    """
    tests = _Tests() if tests is None else tests
    c_max = instance.c_max
    c_p = max(c_p, math.nextafter(c_max, math.inf)) if supplementary else c_max
    paths = algorithm_1(instance, c_p, reading=reading, trace=trace, tests=tests)
    return _Run(paths, c_p if supplementary else c_max, "1-1" if supplementary else "1", tests, trace)


def _tour_run(
    instance: Instance, c_t: float, supplementary: bool, reading: Reading, trace: Trace | None
) -> _Run:
    """Paths at ``c_p = c_t / 2`` (Algorithm 1 or 1-1) paired within ``c_t`` (Algorithm 2)."""
    path_tests = _Tests(scale=2.0)
    paths_run = _path_run(instance, c_t / 2, supplementary, reading, trace, path_tests)
    c_t = max(c_t, 2 * paths_run.threshold)
    if trace is not None:
        _Recorder(trace, instance.ids).add(
            f"Alg 2: pair the {len(paths_run.routes)} paths into tours within c_t = {c_t:g}", paths_run.routes,
            threshold=c_t, remaining=tuple(range(len(paths_run.routes))),
        )
    pair_tests = _Tests()
    tours = algorithm_2(instance, paths_run.routes, c_t, trace=trace, tests=pair_tests)
    tests = _Tests(
        accepted=max(path_tests.accepted, pair_tests.accepted),
        rejected=min(path_tests.rejected, pair_tests.rejected),
    )
    return _Run(tours, c_t, paths_run.algorithm + " + 2", tests, trace)


def _scan(
    run: Callable[[float, bool], _Run],
    least: float,
    robots: int,
    time_limit: float | None,
    max_runs: int,
) -> tuple[_Run, dict[str, Any]]:
    """The least threshold at which ``run`` gives at most ``robots`` routes.

    Exact scan over the distinct runs in increasing threshold (module docstring),
    then bisection when ``max_runs`` or ``time_limit`` is used up.
    """
    started = time.perf_counter()
    lines: list[str] = []
    runs = 0

    def note(result: _Run, threshold: float) -> None:
        above = " (just above)" if result.threshold > threshold else ""
        lines.append(
            f"Search: threshold {threshold:g}{above} (Alg {result.algorithm}): "
            f"{_plural(len(result.routes), 'route')}, limit {robots}"
        )

    def out_of_budget() -> bool:
        late = time_limit is not None and time.perf_counter() - started > time_limit
        return runs >= max_runs or late

    threshold, supplementary = least, False
    covered = least  # every threshold below `covered` (and `least`) needs too many robots
    while True:
        current = run(threshold, supplementary)
        runs += 1
        note(current, threshold)
        if len(current.routes) <= robots:
            return current, {"exact": True, "runs": runs, "lines": lines}
        if supplementary:
            covered = current.tests.rejected
        if not supplementary:
            supplementary = True
        elif math.isfinite(current.tests.rejected) and current.tests.rejected > threshold:
            threshold = current.tests.rejected
        else:
            break
        if out_of_budget():
            break
    # Bisection between the thresholds scanned and the one-route run (at infinity).
    # `high`: the least threshold of a run with few enough routes; `low`: one past
    # the last run found with too many.
    high = max(run(math.inf, True).tests.accepted, least)
    low = covered
    for _ in range(_MAX_BISECTIONS):
        if not low < high:
            break
        middle = (low + high) / 2
        current = run(middle, True)
        runs += 1
        note(current, middle)
        if len(current.routes) <= robots:
            high = max(current.tests.accepted, least)
        else:
            low = current.tests.rejected
    best = run(high, True)
    runs += 2
    lines.append(f"Search: scan budget used up; bisection settled at threshold {high:g}")
    return best, {"exact": False, "runs": runs, "lines": lines}


# -- helpers ----------------------------------------------------------------------------


def _path_cost(d: np.ndarray, path: list[int]) -> float:
    """Cost of the path start -> ``path`` (no return)."""
    stops = np.array([0, *path], dtype=np.int64)
    return float(d[stops[:-1], stops[1:]].sum())


def _names(ids: tuple[str, ...], indices: list[int]) -> str:
    return "[" + ", ".join(ids[i] for i in indices) + "]"


def _trace_info(steps: Trace, instance: Instance, problem: Problem, routes: list[list[int]]) -> dict[str, Any]:
    """``info["trace"]`` (the lines) and ``info["steps"]`` (the records), the result's step last."""
    kind = "tour" if problem.tours else "path"
    summary = f"Result: {_plural(len(routes), 'robot')} ({_plural(len(routes), kind)})"
    recorded = [*steps]
    _Recorder(recorded, instance.ids).add(summary, **{"tours" if problem.tours else "paths": routes})
    return {"trace": [step.text for step in recorded], "steps": tuple(recorded)}


def _plural(count: int, noun: str) -> str:
    return f"{count} {noun}{'' if count == 1 else 's'}"


METHODS = (
    MethodInfo(
        "paper",
        paper,
        "the paper's Algorithms 1, 1-1 and 2, read literally",
        options=("trace",),
    ),
    MethodInfo(
        "paper-5d-end",
        paper_5d_end,
        "as paper, step 5d grows each path from its current end",
        options=("trace",),
    ),
    MethodInfo(
        "paper-1-1-end",
        paper_1_1_end,
        "as paper, Algorithm 1-1 extends the first path from its end",
        options=("trace",),
    ),
    MethodInfo(
        "paper-nearest-end",
        paper_nearest_end,
        "as paper, every path grown from its current end (nearest neighbour)",
        options=("trace",),
    ),
)
