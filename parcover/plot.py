"""Drawings: routes over a map or the plane (paper, Figs. 5 and 7), frontiers and gaps.

Every drawing says what it shows: its title names the instance, the question (paths
or tours; at most k robots, or a deadline), the method, the status and the value
with its unit; axes carry units (metres on maps, "distance units" otherwise); an
arrow on each leg shows the direction of travel, drawn beside the line on the
robot's right so that an out-and-back leg shows both ways.

:func:`plot_routes`, :func:`draw_frontier` and :func:`draw_gap_distribution` draw on a
matplotlib ``Axes`` (a new pyplot figure when none is given) and return it, as PyVRP's
``plot_solution`` does; :func:`save_routes_plot`, :func:`plot_side_by_side`,
:func:`plot_frontier` and :func:`plot_gap_distribution` write files, drawn on
:class:`matplotlib.figure.Figure` objects of their own, outside pyplot, so that no
window opens and no backend is needed.
"""

from __future__ import annotations

import functools
import os
import textwrap
from collections.abc import Iterable, Sequence
from typing import Any

import matplotlib.pyplot as plt
import numpy as np
from matplotlib import patheffects
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.transforms import offset_copy

from parcover.instance import Instance
from parcover.result import Frontier, Result, Status, plural

__all__ = [
    "plot_routes",
    "save_routes_plot",
    "plot_side_by_side",
    "plot_frontier",
    "draw_frontier",
    "plot_gap_distribution",
    "draw_gap_distribution",
    "node_positions",
    "distance_unit",
    "route_title",
    "new_figure",
    "save_figure",
]

Point = tuple[float, float]

#: Colours of the methods' points on a frontier (blue is the frontier's, orange its bounds').
_METHOD_COLOURS = ("tab:red", "tab:green", "tab:purple", "tab:brown", "tab:pink", "tab:olive", "tab:cyan",
                   "tab:gray", "black")
#: Characters per title line before it wraps.
TITLE_WIDTH = 90
_LABEL_HALO = [patheffects.withStroke(linewidth=2.5, foreground="white")]


# -- what a drawing says -----------------------------------------------------------------


def distance_unit(instance: Instance) -> str:
    """``"m"`` for map instances (their coordinates are metres), else ``"distance units"``."""
    return "m" if instance.map is not None else "distance units"


def _amount(value: float, unit: str) -> str:
    """``12.3 m``, or ``12.3 (distance units)``."""
    return f"{value:.4g} m" if unit == "m" else f"{value:.4g} ({unit})"


def question_text(result: Result, unit: str) -> str:
    """The question a result answers, e.g. ``tours, at most 3 robots: least makespan``."""
    if result.objective == "makespan":
        return f"{result.routes_kind}, at most {result.robots_limit} robots: least makespan"
    if result.deadline is None:
        return f"{result.routes_kind}, fewest robots (no deadline given)"
    return f"{result.routes_kind}, deadline {_amount(result.deadline, unit)}: fewest robots"


def answer_text(result: Result, unit: str) -> str:
    """Method, status and value, e.g. ``paper: feasible, 3 robots, makespan 52.3 m, proven bound 40 m``.

    Metres follow each length; another unit is named once, at the end.
    """
    metres = " m" if unit == "m" else ""
    text = f"{result.method}: {result.status.value}"
    if result.makespan is not None:
        text += f", {plural(result.robots or 0, 'robot')}, makespan {result.makespan:.4g}{metres}"
    if result.status is Status.FEASIBLE and result.bound is not None:
        robots = result.objective == "robots"
        text += f", proven bound {plural(int(result.bound), 'robot') if robots else f'{result.bound:.4g}{metres}'}"
    return text if metres or result.makespan is None else f"{text} ({unit})"


def route_title(instance: Instance, result: Result, caption: str | None = None) -> str:
    """The title of a routes drawing: optional caption, instance and question, answer."""
    unit = distance_unit(instance)
    lines = [caption] if caption else []
    lines += [f"{instance.name or 'unnamed instance'}: {question_text(result, unit)}", answer_text(result, unit)]
    return "\n".join(textwrap.fill(line, TITLE_WIDTH) for line in lines)


# -- positions and legs ------------------------------------------------------------------


def node_positions(instance: Instance, seed: int = 0) -> dict[str, Point]:
    """Drawing position of every node: its coordinates, else a seeded spring layout."""
    if has_coordinates(instance):
        return dict(instance.coordinates)  # type: ignore[arg-type]
    import networkx as nx

    pos = nx.spring_layout(instance.to_networkx(), seed=seed)
    return {v: (float(x), float(y)) for v, (x, y) in pos.items()}


def has_coordinates(instance: Instance) -> bool:
    """Every node has coordinates (else drawings use a layout that is not to scale)."""
    return instance.coordinates is not None and all(v in instance.coordinates for v in instance.nodes)


def _corridors(instance: Instance) -> np.ndarray | None:
    """The free pixels a drawn leg may cross: the map's free space reachable from the start,
    one pixel off the walls; None without a readable map image."""
    m = instance.map
    assert m is not None and instance.coordinates is not None
    pieces = _free_pieces(m.image)
    if pieces is None:
        return None
    rows, cols, inside = _pixels(instance, np.array([instance.coordinates[instance.start]]), pieces.shape)
    piece = int(pieces[rows[0], cols[0]]) if inside[0] else 0
    return _inside_piece(m.image, piece) if piece else None


@functools.lru_cache(maxsize=8)
def _free_pieces(image: str) -> np.ndarray | None:
    """The connected pieces of a map image's free pixels (:func:`parcover.maps.read_free_mask`),
    numbered from 1 (0: walls); None when the image is unreadable."""
    from scipy import ndimage

    from parcover.maps import MapError, read_free_mask

    try:
        free = read_free_mask(image)
    except MapError:
        return None
    return ndimage.label(free)[0]


@functools.lru_cache(maxsize=8)
def _inside_piece(image: str, piece: int) -> np.ndarray:
    """Piece ``piece`` of :func:`_free_pieces`, eroded by one pixel (drawn lines keep off the walls)."""
    from scipy import ndimage

    pieces = _free_pieces(image)
    assert pieces is not None
    inside = ndimage.binary_erosion(pieces == piece)
    inside.flags.writeable = False
    return inside


def _pixels(instance: Instance, xy: np.ndarray, shape: tuple[int, ...]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rows and columns of the map pixels holding world points ``xy`` (``(m, 2)``, metres), and
    which of them lie on the image (maps.py's axis convention: rows grow downwards)."""
    m = instance.map
    assert m is not None
    sx, sy = _scale(m.metres_per_pixel)
    cols = np.floor((xy[:, 0] - m.origin[0]) / sx).astype(int)
    rows = shape[0] - 1 - np.floor((xy[:, 1] - m.origin[1]) / sy).astype(int)
    inside = (rows >= 0) & (rows < shape[0]) & (cols >= 0) & (cols < shape[1])
    return rows, cols, inside


def _segment_free(a: np.ndarray, b: np.ndarray, instance: Instance, mask: np.ndarray) -> bool:
    """Whether the straight segment ``a``-``b`` (metres) crosses only pixels of ``mask``,
    sampled at least twice per pixel."""
    m = instance.map
    assert m is not None
    sx, sy = _scale(m.metres_per_pixel)
    steps = max(2, int(2 * max(abs(b[0] - a[0]) / sx, abs(b[1] - a[1]) / sy)) + 1)
    rows, cols, inside = _pixels(instance, a + np.linspace(0.0, 1.0, steps)[:, None] * (b - a), mask.shape)
    return bool(inside.all() and mask[rows, cols].all())


def _scale(metres_per_pixel: float | tuple[float, float]) -> tuple[float, float]:
    return metres_per_pixel if isinstance(metres_per_pixel, tuple) else (metres_per_pixel, metres_per_pixel)


def shortcut(xy: np.ndarray, free: Any) -> np.ndarray:
    """Drop waypoints of a polyline while the straight line that replaces them stays free.

    From each kept point, the next kept point is the farthest one reachable by a
    straight line ``free(a, b)`` accepts (string pulling); the first and last points
    are kept. A walk through the cell-boundary nodes of a decomposition graph then
    follows the corridor instead of zigzagging between cell boundaries.
    """
    kept = [0]
    while kept[-1] < len(xy) - 1:
        i = kept[-1]
        j = next((j for j in range(len(xy) - 1, i + 1, -1) if free(xy[i], xy[j])), i + 1)
        kept.append(j)
    return xy[kept]


def leg_polylines(instance: Instance, route: Sequence[str], pos: dict[str, Point]) -> list[np.ndarray]:
    """The drawn line of each leg of a route (between consecutive stops), as ``(m, 2)`` arrays.

    Each leg is its physical walk through virtual nodes (:meth:`Instance.shortest_walk`);
    on a map it is smoothed by :func:`shortcut` against the map image, so it follows
    the free corridors (a drawing: its length may be below the leg's graph cost).
    """
    mask = _corridors(instance) if instance.map is not None and has_coordinates(instance) else None
    legs = []
    for u, v in zip(route, route[1:]):
        xy = np.array([pos[w] for w in instance.shortest_walk(u, v)], dtype=float)
        if mask is not None and len(xy) > 2:
            xy = shortcut(xy, lambda a, b: _segment_free(a, b, instance, mask))
        legs.append(xy)
    return legs


# -- drawing pieces ----------------------------------------------------------------------


def route_colour(r: int, count: int) -> Any:
    """The colour of robot ``r`` (0-based) among ``count`` robots."""
    colours = plt.get_cmap("tab10" if count <= 10 else "tab20")
    return colours(r % colours.N)


def draw_background(ax: Axes, instance: Instance, pos: dict[str, Point], *, show_virtual: bool) -> None:
    """The map image (or the graph's edges in light grey), and virtual nodes when asked."""
    if instance.map is not None:
        _draw_map(ax, instance)
    elif instance.edges is not None:
        for i, (u, v, _) in enumerate(instance.edges):
            (x1, y1), (x2, y2) = pos[u], pos[v]
            ax.plot([x1, x2], [y1, y2], color="0.82", lw=0.7, zorder=1, label="graph edge" if i == 0 else None)
    virtual = instance.virtual_nodes
    if show_virtual and virtual:
        vx, vy = np.array([pos[v] for v in virtual]).T
        ax.scatter(vx, vy, marker="x", s=12, color="tab:red", lw=0.8, zorder=2, label="virtual node")


def _draw_map(ax: Axes, instance: Instance) -> None:
    """The map image under the drawing, placed by its scale and origin (maps.py).

    A missing image file is skipped: the routes are still drawn.
    """
    m = instance.map
    assert m is not None
    if not os.path.exists(m.image):
        return
    import matplotlib.image as mpimg

    img = mpimg.imread(m.image)
    h, w = img.shape[:2]
    sx, sy = _scale(m.metres_per_pixel)
    ox, oy = m.origin
    ax.imshow(img, cmap="gray", vmin=0, vmax=1, extent=(ox, ox + w * sx, oy, oy + h * sy), zorder=0)


def draw_route(
    ax: Axes,
    instance: Instance,
    route: Sequence[str],
    pos: dict[str, Point],
    colour: Any,
    *,
    width: float = 2.0,
    label: str | None = None,
    **line: Any,
) -> None:
    """One route as its legs, with an arrow per leg beside the line (the robot's right)."""
    for i, xy in enumerate(leg_polylines(instance, route, pos)):
        ax.plot(xy[:, 0], xy[:, 1], color=colour, lw=width, zorder=3, solid_capstyle="round",
                label=label if i == 0 else None, **line)
        _leg_arrow(ax, xy, colour, offset=width / 2 + 2.5)


def _leg_arrow(ax: Axes, xy: np.ndarray, colour: Any, *, offset: float) -> None:
    """An arrow at half the length of a leg, pointing along it, ``offset`` points to its right."""
    steps = np.diff(xy, axis=0)
    lengths = np.hypot(steps[:, 0], steps[:, 1])
    total = float(lengths.sum())
    if total == 0:
        return
    k = int(np.searchsorted(np.cumsum(lengths), total / 2))
    before = float(lengths[:k].sum())
    direction = steps[k] / lengths[k]
    middle = xy[k] + direction * (total / 2 - before)
    ux, uy = float(direction[0]), float(direction[1])
    shifted = offset_copy(ax.transData, fig=ax.figure, x=uy * offset, y=-ux * offset, units="points")
    ax.annotate("", xy=(middle[0], middle[1]), xycoords=shifted, xytext=(-9 * ux, -9 * uy),
                textcoords="offset points", zorder=4,
                arrowprops=dict(arrowstyle="-|>", color=colour, lw=1.0, mutation_scale=9, shrinkA=0, shrinkB=0))


def draw_kpois(ax: Axes, instance: Instance, pos: dict[str, Point], *, faded: Iterable[str] = ()) -> None:
    """The start (a star) under the KPOIs (diamonds) and their ids, haloed so lines never hide them.

    KPOIs in ``faded`` are drawn hollow (e.g. not yet covered, in a teaching frame).
    """
    sx, sy = pos[instance.start]
    ax.scatter([sx], [sy], marker="*", s=220, color="gold", edgecolor="black", lw=0.8, zorder=5, label="start")
    faded = set(faded)
    solid = [v for v in instance.kpois if v not in faded]
    hollow = [v for v in instance.kpois if v in faded]
    if solid:
        kx, ky = np.array([pos[v] for v in solid]).T
        ax.scatter(kx, ky, marker="D", s=26, color="tab:blue", edgecolor="white", lw=0.5, zorder=6, label="KPOI")
    if hollow:
        kx, ky = np.array([pos[v] for v in hollow]).T
        ax.scatter(kx, ky, marker="D", s=26, facecolor="white", edgecolor="tab:blue", lw=1.0, zorder=6,
                   label="KPOI not yet covered")
    for v in instance.kpois:
        ax.annotate(v, pos[v], xytext=(4, 4), textcoords="offset points", fontsize=7, zorder=7,
                    path_effects=_LABEL_HALO)


def label_axes(ax: Axes, instance: Instance) -> None:
    """Axis labels with units; a spring layout (no coordinates) says it is not to scale."""
    ax.set_aspect("equal")
    if not has_coordinates(instance):
        ax.set_xticks([])
        ax.set_yticks([])
        ax.set_xlabel("graph drawn by a spring layout: positions are not to scale, edge weights are the distances",
                      fontsize=7)
        ax.margins(0.08)
        return
    unit = distance_unit(instance)
    ax.set_xlabel(f"x ({unit})")
    ax.set_ylabel(f"y ({unit})")
    if instance.map is None:
        ax.margins(0.08)


def legend_outside(ax: Axes) -> None:
    """The legend right of the axes, with only what is drawn (entries with a label)."""
    handles, labels = ax.get_legend_handles_labels()
    if handles:
        ax.legend(handles, labels, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)


# -- public drawings ---------------------------------------------------------------------


def plot_routes(
    instance: Instance,
    result: Result,
    ax: Axes | None = None,
    *,
    title: str | None = None,
    show_virtual: bool = False,
) -> Axes:
    """Draw the routes of ``result`` on ``ax`` (a new figure when None) and return the axes.

    Over the map image when ``instance.map`` is set, else over the plane (a graph's
    edges in light grey); one colour per robot, each leg drawn as its physical walk
    (through virtual nodes, smoothed along the map's free corridors) with an arrow
    showing the direction of travel; the start as a star, KPOIs as labelled diamonds
    (paper, Figs. 5 and 7). Without coordinates the nodes are placed by a seeded
    spring layout. The title names the instance, the question, the method, the
    status and the makespan with its unit.

    Parameters
    ----------
    instance
        The instance the routes cover.
    result
        A result of :func:`parcover.solve` with routes.
    ax
        Axes to draw on; default a new figure of pyplot's.
    title
        A caption put above the generated title.
    show_virtual
        Also mark the virtual nodes (default False: on maps they clutter the plan).

    Returns
    -------
    matplotlib.axes.Axes
        The axes drawn on.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import parcover as pc
    >>> inst = pc.Instance.from_points([[0, 0], [3, 4], [0, 1], [2, 2]], name="four")
    >>> result = pc.solve(inst, robots=2, method="exact")
    >>> ax = pc.plot_routes(inst, result)
    >>> print(ax.get_title())
    four: paths, at most 2 robots: least makespan
    exact: optimal, 2 robots, makespan 5 (distance units)
    >>> ax.figure.savefig("four.png")  # doctest: +SKIP
    """
    if ax is None:
        _, ax = plt.subplots(figsize=(9, 6))
    pos = node_positions(instance)
    draw_background(ax, instance, pos, show_virtual=show_virtual)
    unit = "m" if instance.map is not None else ""
    count = len(result.routes)
    for r, (route, cost) in enumerate(zip(result.routes, result.route_costs)):
        # Earlier robots drawn wider, so shared corridors show every colour.
        width = 1.2 + 2.4 * (count - r) / count
        draw_route(ax, instance, route, pos, route_colour(r, count), width=width, alpha=0.9,
                   label=f"robot {r + 1}: {cost:.4g} {unit}".rstrip())
    draw_kpois(ax, instance, pos)
    label_axes(ax, instance)
    ax.set_title(route_title(instance, result, title), fontsize=9)
    legend_outside(ax)
    return ax


def save_routes_plot(
    instance: Instance,
    result: Result,
    path: str | os.PathLike[str],
    *,
    title: str | None = None,
    show_virtual: bool = False,
    dpi: int = 130,
) -> None:
    """:func:`plot_routes` into a file (PNG, PDF or SVG by its suffix); what ``--plot FILE`` writes."""
    fig = new_figure(figsize=(9, 6))
    plot_routes(instance, result, fig.add_subplot(), title=title, show_virtual=show_virtual)
    save_figure(fig, path, dpi=dpi)


def plot_side_by_side(
    instance: Instance,
    results: Sequence[Result],
    path: str | os.PathLike[str],
    titles: Sequence[str | None] | None = None,
    *,
    dpi: int = 110,
) -> None:
    """Several solutions of one instance side by side (e.g. greedy beside optimal).

    ``titles`` are captions put above each panel's generated title.
    """
    captions = list(titles) if titles is not None else [None] * len(results)
    fig = new_figure(figsize=(7.5 * len(results), 5.5))
    axes = fig.subplots(1, len(results), squeeze=False)[0]
    for ax, result, caption in zip(axes, results, captions):
        plot_routes(instance, result, ax, title=caption)
    save_figure(fig, path, dpi=dpi)


def plot_frontier(
    frontier: Frontier,
    path: str | os.PathLike[str],
    *,
    points: dict[str, list[tuple[int, float]]] | None = None,
    unit: str = "distance units",
    dpi: int = 130,
) -> None:
    """:func:`draw_frontier` into a file (what ``parcover frontier --plot`` writes)."""
    fig = new_figure(figsize=(6.5, 4.2))
    draw_frontier(frontier, fig.add_subplot(), points=points, unit=unit)
    save_figure(fig, path, dpi=dpi)


def draw_frontier(
    frontier: Frontier,
    ax: Axes | None = None,
    *,
    points: dict[str, list[tuple[int, float]]] | None = None,
    unit: str = "distance units",
) -> Axes:
    """Robots versus makespan as steps on ``ax`` (a new figure when None); optimal points
    filled, others hollow with their proven bound.

    ``points`` adds each method's (robots, makespan) answers beside the frontier;
    ``unit`` is the makespan's (``"m"`` on maps). Returns the axes.
    """
    if ax is None:
        _, ax = plt.subplots(figsize=(6.5, 4.2))
    pts = [p for p in frontier.points if p.makespan is not None]
    robots = sorted({p.robots for p in pts} | {r for answers in (points or {}).values() for r, _ in answers})
    if pts:
        ax.step([p.robots for p in pts], [p.makespan for p in pts], where="post", color="0.6", lw=1, zorder=1)
        _scatter_if_any(ax, [p for p in pts if p.status is Status.OPTIMAL], color="tab:blue",
                        label=f"optimal ({frontier.method})")
        other = [p for p in pts if p.status is not Status.OPTIMAL]
        _scatter_if_any(ax, other, facecolor="none", edgecolor="tab:blue", label=f"best found ({frontier.method})")
        bounded = [p for p in other if p.bound is not None]
        for i, p in enumerate(bounded):
            ax.plot([p.robots, p.robots], [p.bound, p.makespan], color="tab:orange", lw=1,
                    label="proven lower bound" if i == 0 else None)
            ax.scatter([p.robots], [p.bound], marker="_", s=120, color="tab:orange", zorder=3)
    for (method, answers), marker, colour in zip((points or {}).items(), "xv^<>sPD*", _METHOD_COLOURS):
        if answers:
            ax.scatter([r for r, _ in answers], [m for _, m in answers], marker=marker, color=colour, zorder=4,
                       label=method)
    if robots:
        ax.set_xticks(robots)
    handles, _ = ax.get_legend_handles_labels()
    if handles:
        ax.legend(fontsize=8)
    ax.set_xlabel("robots")
    ax.set_ylabel(f"makespan ({unit})")
    name = frontier.instance or "unnamed instance"
    ended = f"; stopped by Ctrl-C at {plural(frontier.points[-1].robots, 'robot')}" if frontier.note else ""
    ax.set_title(f"{name}: least makespan per number of robots ({frontier.routes_kind})\n"
                 f"frontier by {frontier.method}{ended}", fontsize=9)
    ax.grid(alpha=0.3)
    return ax


def _scatter_if_any(ax: Axes, points: Sequence[Any], **style: Any) -> None:
    """Scatter frontier points; nothing (and no legend entry) when there are none."""
    if points:
        ax.scatter([p.robots for p in points], [p.makespan for p in points], zorder=3, **style)


def plot_gap_distribution(frame: Any, path: str | os.PathLike[str], *, dpi: int = 130) -> None:
    """:func:`draw_gap_distribution` into a file (``gaps.png`` of ``parcover report``)."""
    methods = frame["method"].nunique()
    fig = new_figure(figsize=(1.2 * max(methods, 3) + 4.5, 4.2))
    draw_gap_distribution(frame, fig.add_subplot())
    save_figure(fig, path, dpi=dpi)


def draw_gap_distribution(frame: Any, ax: Axes | None = None) -> Axes:
    """Box plot of each method's gap to the optimum, in percent, on ``ax`` (a new figure when
    None), from a frame of :func:`parcover.report.gaps` (or gaps.csv); returns the axes.

    The title says over what: the reference, the instances, route kinds and questions.
    """
    rows = frame[np.isfinite(frame["gap_to_optimum"].astype(float))]
    methods = list(dict.fromkeys(rows["method"]))
    if ax is None:
        _, ax = plt.subplots(figsize=(1.2 * max(len(methods), 3) + 4.5, 4.2))
    if methods:
        data = [100 * rows.loc[rows["method"] == m, "gap_to_optimum"].astype(float) for m in methods]
        box = ax.boxplot(data, showmeans=True)
        ax.set_xticks(range(1, len(methods) + 1), methods, rotation=30, ha="right")
        _explain_boxes(ax, box)
    ax.set_xlabel("method")
    ax.set_ylabel("gap to optimum (%)")
    references = ", ".join(dict.fromkeys(frame["reference"].astype(str))) or "-"
    kinds = " and ".join(dict.fromkeys(frame["routes"].astype(str)))
    title = (f"Gap to the optimum ({references}) per method: {plural(frame['instance'].nunique(), 'instance')}, "
             f"{kinds}, {plural(frame['question'].nunique(), 'question')} ({len(rows)} answers with a gap)")
    ax.set_title(textwrap.fill(title, TITLE_WIDTH), fontsize=9)
    ax.grid(alpha=0.3, axis="y")
    return ax


def _explain_boxes(ax: Axes, box: dict[str, list[Any]]) -> None:
    """A legend for the parts of a box plot that are drawn: median, mean, quartile box, outliers."""
    parts = [(box["medians"], "median"), (box["means"], "mean"), (box["boxes"], "middle half (quartiles)"),
             ([f for f in box["fliers"] if len(f.get_xdata())], "outlier (beyond 1.5 box heights)")]
    drawn = [(artists[0], label) for artists, label in parts if artists]
    ax.legend([a for a, _ in drawn], [label for _, label in drawn], fontsize=7, loc="upper left",
              bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)


def new_figure(**kwargs: Any) -> Figure:
    """A figure outside pyplot (no window, no backend needed), for drawings written to files."""
    return Figure(**kwargs)


def save_figure(fig: Any, path: str | os.PathLike[str], *, dpi: int, tight: bool = True) -> None:
    """Lay out (unless ``tight`` is False: a layout fixed by the caller), write and release a
    figure (every drawing of the package ends here)."""
    if tight:
        fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    plt.close(fig)

