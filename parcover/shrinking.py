"""Shrinking an instance that refutes a claim to a smallest one that still does.

:func:`shrink` drops KPOIs by delta debugging (a graph instance keeps only the edges on
shortest walks between its remaining key nodes), then simplifies a Euclidean
instance's coordinates; :func:`instance_size` is what it never increases.
:mod:`parcover.props` shrinks its counterexamples with it.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Sequence

from parcover.instance import Instance

__all__ = ["shrink", "instance_size"]


def instance_size(instance: Instance) -> tuple[float, ...]:
    """``(KPOIs, edges, coordinate magnitude)``: what :func:`shrink` never increases.

    The magnitude is the sum of ``|x - x_s| + |y - y_s|`` over KPOIs (0 for pure
    graph instances without coordinates); edges count 0 for Euclidean instances.
    """
    edges = 0 if instance.edges is None else len(instance.edges)
    return (instance.n, edges, _magnitude(instance))


def _magnitude(instance: Instance) -> float:
    xy = instance.coordinates
    if xy is None or instance.start not in xy:
        return 0.0
    sx, sy = xy[instance.start]
    return float(sum(abs(xy[v][0] - sx) + abs(xy[v][1] - sy) for v in instance.kpois if v in xy))


def shrink(instance: Instance, refutes: Callable[[Instance], bool], *, max_checks: int = 400) -> Instance:
    """A smaller instance that still refutes: fewest KPOIs first, then simplest coordinates.

    Delta debugging (Zeller's ddmin) over the KPOIs: drop chunks of halving size,
    then single KPOIs, while ``refutes`` stays true. A dropped KPOI of a graph
    instance becomes a virtual node, and only the edges on shortest walks between
    the remaining start and KPOIs are kept (dangling parts go; the distances that
    matter are unchanged). For Euclidean instances the coordinates are then moved
    so the start is at the origin, truncated to integers, halved, and each KPOI
    coordinate moved toward the start's (to it, halfway, one unit), each step kept
    only if the claim stays refuted and no two positions coincide.

    Parameters
    ----------
    instance
        An instance that refutes the claim (returned unchanged otherwise).
    refutes
        ``refutes(candidate)`` is true when ``candidate`` still refutes the claim.
    max_checks
        At most this many calls of ``refutes``.

    Returns
    -------
    Instance
        An instance with ``refutes`` true whose :func:`instance_size` is no larger
        than the input's in every component.

    Examples
    --------
    With a "claim" refuted by any instance of two KPOIs or more, a line of three
    keeps two KPOIs; moving either toward the start would make two points coincide.

    >>> line = Instance.from_points([[0, 0], [1, 0], [2, 0], [3, 0]])
    >>> small = shrink(line, lambda inst: inst.n >= 2)
    >>> [small.coordinates[v] for v in small.kpois]
    [(1.0, 0.0), (2.0, 0.0)]
    """
    budget = [max_checks]

    def accept(candidate: Instance | None, current: Instance) -> bool:
        if candidate is None or budget[0] <= 0:
            return False
        if any(a > b for a, b in zip(instance_size(candidate), instance_size(current))):
            return False
        budget[0] -= 1
        return bool(refutes(candidate))

    if not refutes(instance):
        return instance
    current = _fewer_kpois(instance, accept)
    if current.edges is None and current.coordinates is not None:
        current = _simpler_coordinates(current, accept)
    return current


def _fewer_kpois(instance: Instance, accept: Callable[[Instance | None, Instance], bool]) -> Instance:
    """ddmin over the KPOIs: try dropping chunks, then complements' halves, down to one KPOI."""
    current = instance
    chunks = 2
    while current.n > 1:
        kpois = current.kpois
        size = math.ceil(len(kpois) / chunks)
        groups = [kpois[i : i + size] for i in range(0, len(kpois), size)]
        for group in groups:
            if len(group) == len(kpois):
                continue
            candidate = _keep(current, tuple(v for v in kpois if v not in group))
            if accept(candidate, current):
                current = candidate
                chunks = max(chunks - 1, 2)
                break
        else:
            if size == 1:
                return current
            chunks = min(2 * chunks, len(kpois))
    return current


def _keep(instance: Instance, kpois: tuple[str, ...]) -> Instance | None:
    """The instance with only ``kpois`` (in their order); ``None`` if that is invalid.

    A graph instance keeps only the edges on shortest walks between its remaining
    key nodes (the start and the kept KPOIs): the dropped KPOIs become virtual
    nodes or go, with every dangling part, and the distances between key nodes
    are unchanged.
    """
    try:
        keep = (instance.start, *kpois)
        if instance.edges is None:
            assert instance.coordinates is not None
            return instance.replace(kpois=kpois, coordinates={v: instance.coordinates[v] for v in keep})
        fewer = instance.replace(kpois=kpois)
        edges = _shortest_walk_edges(fewer, keep)
        coordinates = None
        if instance.coordinates is not None:
            used = {u for e in edges for u in e[:2]}
            coordinates = {v: p for v, p in instance.coordinates.items() if v in used} or None
        return fewer.replace(edges=edges, coordinates=coordinates)
    except Exception:  # noqa: BLE001 - an invalid candidate is just not taken
        return None


def _shortest_walk_edges(instance: Instance, keep: Sequence[str]) -> tuple[tuple[str, str, float], ...]:
    """The edges (lightest of parallel ones) on the shortest walks between nodes of ``keep``."""
    assert instance.edges is not None
    weight: dict[frozenset[str], float] = {}
    for u, v, w in instance.edges:
        pair = frozenset((u, v))
        weight[pair] = min(w, weight.get(pair, math.inf))
    used: dict[frozenset[str], tuple[str, str, float]] = {}
    for a, b in itertools.combinations(keep, 2):
        walk = instance.shortest_walk(a, b)
        for u, v in zip(walk, walk[1:]):
            used.setdefault(frozenset((u, v)), (u, v, weight[frozenset((u, v))]))
    return tuple(used.values())


def _simpler_coordinates(instance: Instance, accept: Callable[[Instance | None, Instance], bool]) -> Instance:
    """Start at the origin, integer offsets, halved magnitudes, then each KPOI coordinate
    moved toward the start's (to it, halfway, one unit) until nothing more is accepted."""
    current = instance

    def moved(inst: Instance, f: Callable[[str, float, float], tuple[float, float]]) -> Instance | None:
        assert inst.coordinates is not None
        sx, sy = inst.coordinates[inst.start]
        xy = {v: f(v, x - sx, y - sy) for v, (x, y) in inst.coordinates.items()}
        xy = {v: (float(x), float(y)) for v, (x, y) in xy.items()}
        if len(set(xy.values())) < len(xy):
            return None  # keep positions distinct: no degenerate zero distances
        try:
            return inst.replace(coordinates=xy)
        except Exception:  # noqa: BLE001 - an invalid candidate is just not taken
            return None

    def smaller(candidate: Instance | None) -> bool:
        return candidate is not None and _magnitude(candidate) < _magnitude(current) and accept(candidate, current)

    for step in (lambda v, x, y: (x, y), lambda v, x, y: (math.trunc(x), math.trunc(y))):
        candidate = moved(current, step)
        if accept(candidate, current):
            current = candidate  # type: ignore[assignment]
    while smaller(candidate := moved(current, lambda v, x, y: (math.trunc(x / 2), math.trunc(y / 2)))):
        current = candidate  # type: ignore[assignment]
    changed = True
    while changed:
        changed = False
        for kpoi, axis in itertools.product(current.kpois, (0, 1)):
            for target in (lambda t: 0, lambda t: math.trunc(t / 2), lambda t: t - math.copysign(1, t)):
                def step(v: str, x: float, y: float) -> tuple[float, float]:
                    if v != kpoi:
                        return (x, y)
                    return (target(x), y) if axis == 0 else (x, target(y))

                if smaller(candidate := moved(current, step)):
                    current = candidate  # type: ignore[assignment]
                    changed = True
                    break
    return current
