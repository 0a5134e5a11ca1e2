"""Seeded, deterministic instance generators.

- :func:`grid`: the paper's Fig. 1, cells of a grid with unit 4-neighbour moves.
- :func:`star`: the paper's Fig. 3, KPOIs equidistant from the start.
- :func:`random_points`: uniform or clustered Euclidean points.
- :func:`random_graph`: a random connected sparse graph with virtual nodes, whose
  weights exceed the straight line (a non-Euclidean metric).

The same arguments always give the same instance (numpy's ``default_rng(seed)``).
Sizes whose instance would not fit in memory are refused before anything is built
(:mod:`parcover.memory`).
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np

from parcover.errors import InputError
from parcover.instance import Instance, check_whole, finite_float
from parcover.memory import Footprint, check_memory, instance_footprint

__all__ = ["grid", "star", "random_points", "random_graph", "footprint"]

Layout = Literal["uniform", "clustered"]
StartPlacement = Literal["random", "center", "corner"]


def grid(rows: int = 3, cols: int = 3) -> Instance:
    """Every cell of a ``rows x cols`` grid, start in the upper left corner (Fig. 1).

    Cells are ``r{row}c{col}``; moves between 4-neighbours cost 1, so distances are
    Manhattan distances. The start cell is covered at time 0; the other
    ``rows * cols - 1`` cells are the KPOIs. On the 3x3 grid ``c_max = 4`` and the
    paper reports coverage times 8, 4, 4 for 1, 2, 3 robots.
    """
    check_whole(rows, "rows", 1)
    check_whole(cols, "cols", 1)
    if rows * cols < 2:
        raise InputError("A grid needs at least 2 cells.")
    check_memory(footprint("grid", rows=rows, cols=cols).peak, f"A {rows} x {cols} grid")

    def cell(r: int, c: int) -> str:
        return f"r{r}c{c}"

    coordinates = {cell(r, c): (float(c), float(-r)) for r in range(rows) for c in range(cols)}
    edges = [(cell(r, c), cell(r, c + 1), 1.0) for r in range(rows) for c in range(cols - 1)]
    edges += [(cell(r, c), cell(r + 1, c), 1.0) for r in range(rows - 1) for c in range(cols)]
    kpois = tuple(v for v in coordinates if v != cell(0, 0))
    return Instance(
        cell(0, 0), kpois, coordinates=coordinates, edges=tuple(edges), name=f"grid-{rows}x{cols}"
    )


def star(n: int = 6, radius: float = 1.0) -> Instance:
    """``n`` KPOIs evenly spaced on a circle around the start (Fig. 3).

    Euclidean. Every KPOI is at distance ``radius`` from the start; neighbours on
    the circle are ``2 radius sin(pi / n)`` apart (``radius`` for n = 6, the
    paper's picture: 6 paths, 3 tours).
    """
    check_whole(n, "n", 1)
    if finite_float(radius) is None or radius <= 0:
        raise InputError(f"radius must be a positive number, got {radius!r}.")
    check_memory(footprint("star", n=n).peak, f"A star of {n} KPOIs")
    angles = 2 * np.pi * np.arange(n) / n
    points = np.vstack([[0.0, 0.0], radius * np.column_stack([np.cos(angles), np.sin(angles)])])
    names = ["s", *(str(k) for k in range(1, n + 1))]
    return Instance.from_points(np.round(points, 12), start=0, names=names, name=f"star-{n}")


def random_points(
    n: int,
    seed: int = 0,
    *,
    layout: Layout = "uniform",
    size: float = 100.0,
    clusters: int = 3,
    start: StartPlacement = "random",
) -> Instance:
    """``n`` random KPOIs in a ``size x size`` square, complete Euclidean graph.

    ``layout="clustered"`` draws points around ``clusters`` random centres (normal,
    standard deviation ``size / 15``, clipped to the square). The start is a random
    point, the centre, or the corner (0, 0). Coordinates are rounded to 2 decimals
    so files stay readable.
    """
    check_whole(n, "n", 1)
    check_whole(clusters, "clusters", 1)
    check_whole(seed, "seed", 0)
    if layout not in ("uniform", "clustered"):
        raise InputError(f"Unknown layout {layout!r}; expected 'uniform' or 'clustered'.")
    if start not in ("random", "center", "corner"):
        raise InputError(f"Unknown start placement {start!r}; expected random, center or corner.")
    if finite_float(size) is None or size <= 0:
        raise InputError(f"size must be a positive number, got {size!r}.")
    check_memory(footprint("random", n=n).peak, f"A random instance of {n} KPOIs")
    rng = np.random.default_rng(seed)
    if layout == "uniform":
        kpois = rng.uniform(0, size, (n, 2))
    else:
        centres = rng.uniform(0.15 * size, 0.85 * size, (clusters, 2))
        kpois = np.clip(centres[rng.integers(clusters, size=n)] + rng.normal(0, size / 15, (n, 2)), 0, size)
    origin = {
        "random": rng.uniform(0, size, 2),
        "center": np.array([size / 2, size / 2]),
        "corner": np.zeros(2),
    }[start]
    points = np.round(np.vstack([origin, kpois]), 2)
    names = ["s", *(str(k) for k in range(1, n + 1))]
    return Instance.from_points(points, start=0, names=names, name=f"random-{layout}-n{n}-s{seed}")


def random_graph(
    n: int,
    seed: int = 0,
    *,
    virtual: int | None = None,
    size: float = 100.0,
    detour: float = 0.5,
) -> Instance:
    """A random connected sparse graph: ``n`` KPOIs among ``virtual`` virtual nodes.

    Nodes are uniform points in a ``size x size`` square joined by their Delaunay
    triangulation (planar, connected, about 3 edges per node). Each edge weighs its
    straight length times a random factor in ``[1, 1 + detour]``, so the metric is
    not Euclidean and shortest paths bend through virtual nodes (weights are rounded
    up to 4 decimals, never below the straight line). The start is ``s``,
    KPOIs ``k1..kn``, virtual nodes ``v1..``; ``virtual`` defaults to ``2 n``.
    """
    from scipy.spatial import Delaunay

    check_whole(n, "n", 1)
    check_whole(seed, "seed", 0)
    virtual = 2 * n if virtual is None else virtual
    check_whole(virtual, "virtual", 0)
    if finite_float(size) is None or size <= 0:
        raise InputError(f"size must be a positive number, got {size!r}.")
    if finite_float(detour) is None or detour < 0:
        raise InputError(f"detour must be a number >= 0, got {detour!r}.")
    check_memory(footprint("graph", n=n, virtual=virtual).peak, f"A graph of {n} KPOIs and {virtual} virtual nodes")
    rng = np.random.default_rng(seed)
    total = n + virtual + 1
    points = np.round(rng.uniform(0, size, (total, 2)), 2)
    roles = rng.permutation(total)  # roles[0] is the start, the next n the KPOIs
    names = [""] * total
    names[roles[0]] = "s"
    for k, node in enumerate(roles[1 : n + 1], start=1):
        names[node] = f"k{k}"
    for k, node in enumerate(roles[n + 1 :], start=1):
        names[node] = f"v{k}"
    pairs = _delaunay_pairs(points, Delaunay) if total >= 4 else [(i, i + 1) for i in range(total - 1)]
    factors = rng.uniform(1.0, 1.0 + detour, len(pairs))
    edges = tuple(
        (names[a], names[b], math.ceil(float(np.hypot(*(points[a] - points[b])) * f) * 1e4) / 1e4)
        for (a, b), f in zip(pairs, factors)
    )
    coordinates = {names[i]: (float(x), float(y)) for i, (x, y) in enumerate(points)}
    return Instance(
        "s",
        tuple(f"k{k}" for k in range(1, n + 1)),
        coordinates=coordinates,
        edges=edges,
        name=f"graph-n{n}-v{virtual}-s{seed}",
    )


def footprint(kind: str, *, n: int = 0, rows: int = 0, cols: int = 0, virtual: int | None = None) -> Footprint:
    """Memory of the instance a generator builds from these sizes, known before building it.

    Parameters
    ----------
    kind
        ``"grid"`` (``rows``, ``cols``), ``"star"`` or ``"random"`` (``n``), ``"graph"``
        (``n``, ``virtual``, default ``2 n``).

    Returns
    -------
    parcover.memory.Footprint
        From :func:`parcover.memory.instance_footprint` with the generator's node and
        edge counts.
    """
    if kind == "grid":
        cells = rows * cols
        return instance_footprint(cells - 1, cells, rows * (cols - 1) + (rows - 1) * cols)
    if kind == "graph":
        total = n + (2 * n if virtual is None else virtual) + 1
        return instance_footprint(n, total, 3 * total)  # a planar triangulation: under 3 edges per node
    if kind in ("random", "star"):
        return instance_footprint(n)
    raise InputError(f"Unknown generator {kind!r}; expected grid, star, random or graph.")


def _delaunay_pairs(points: np.ndarray, delaunay: type) -> list[tuple[int, int]]:
    """Sorted unique edges of the Delaunay triangulation of ``points``."""
    tri = delaunay(points, qhull_options="QJ")
    pairs = {
        (min(a, b), max(a, b))
        for simplex in tri.simplices
        for a, b in ((simplex[0], simplex[1]), (simplex[1], simplex[2]), (simplex[0], simplex[2]))
    }
    return sorted((int(a), int(b)) for a, b in pairs)
