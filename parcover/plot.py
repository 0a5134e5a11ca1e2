"""Drawings: routes over a map or the plane (paper, Figs. 5 and 7), and frontiers.

Everything is drawn with matplotlib's Agg backend into files; nothing is shown.
"""

from __future__ import annotations

import os
from typing import Any, Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from parcover.instance import Instance  # noqa: E402
from parcover.result import Frontier, Result  # noqa: E402

__all__ = ["plot_routes", "plot_frontier", "plot_side_by_side", "plot_gap_distribution", "node_positions"]


def node_positions(instance: Instance, seed: int = 0) -> dict[str, tuple[float, float]]:
    """Drawing position of every node: its coordinates, else a seeded spring layout."""
    if instance.coordinates is not None and all(v in instance.coordinates for v in instance.nodes):
        return dict(instance.coordinates)
    import networkx as nx

    pos = nx.spring_layout(instance.to_networkx(), seed=seed)
    return {v: (float(x), float(y)) for v, (x, y) in pos.items()}


def _draw_map(ax: Any, instance: Instance) -> None:
    """The map image under the drawing, placed by its scale and origin (maps.py).

    A missing image file is skipped: the routes are still drawn.
    """
    m = instance.map
    if m is None or not os.path.exists(m.image):
        return
    import matplotlib.image as mpimg

    img = mpimg.imread(m.image)
    h, w = img.shape[:2]
    sx, sy = m.metres_per_pixel if isinstance(m.metres_per_pixel, tuple) else (m.metres_per_pixel,) * 2
    ox, oy = m.origin
    ax.imshow(img, cmap="gray", vmin=0, vmax=1, extent=(ox, ox + w * sx, oy, oy + h * sy), zorder=0)


def _draw_routes(ax: Any, instance: Instance, result: Result, title: str | None) -> None:
    """Map (or graph edges), virtual nodes, one walk per robot, numbered KPOIs, start."""
    pos = node_positions(instance)
    _draw_map(ax, instance)
    if instance.map is None and instance.edges is not None:
        for u, v, _ in instance.edges:
            (x1, y1), (x2, y2) = pos[u], pos[v]
            ax.plot([x1, x2], [y1, y2], color="0.85", lw=0.6, zorder=1)
    virtual = instance.virtual_nodes
    if virtual:
        vx, vy = np.array([pos[v] for v in virtual]).T
        ax.scatter(vx, vy, marker="x", s=12, color="tab:red", lw=0.8, zorder=2, label="virtual node")
    colours = plt.get_cmap("tab10" if len(result.routes) <= 10 else "tab20")
    for r, route in enumerate(result.routes):
        walk = instance.walk(route)
        xy = np.array([pos[v] for v in walk])
        cost = result.route_costs[r] if r < len(result.route_costs) else float("nan")
        # Earlier robots drawn wider, so shared corridors show every colour.
        width = 1.2 + 2.4 * (len(result.routes) - r) / len(result.routes)
        ax.plot(xy[:, 0], xy[:, 1], color=colours(r % colours.N), lw=width, alpha=0.9, zorder=3,
                solid_capstyle="round", label=f"robot {r + 1}: {cost:.4g}")
    kx, ky = np.array([pos[v] for v in instance.kpois]).T
    ax.scatter(kx, ky, marker="D", s=28, color="tab:blue", edgecolor="white", lw=0.5, zorder=4)
    for v in instance.kpois:
        ax.annotate(v, pos[v], xytext=(3, 3), textcoords="offset points", fontsize=7, zorder=5)
    sx, sy = pos[instance.start]
    ax.scatter([sx], [sy], marker="*", s=160, color="gold", edgecolor="black", zorder=5, label="start")
    ax.set_aspect("equal")
    if instance.map is None:
        ax.margins(0.08)
    head = title if title is not None else f"{instance.name or 'instance'}: {result.method}"
    if result.makespan is not None:
        head += f"\n{result.robots} robots, makespan {result.makespan:.4g}"
    ax.set_title(head, fontsize=9)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)


def plot_routes(
    instance: Instance, result: Result, path: str | os.PathLike[str], *, title: str | None = None
) -> None:
    """Draw the routes of ``result`` to ``path`` (PNG or any matplotlib format).

    Over the map image when ``instance.map`` is set, else over the plane; one colour
    per robot, each route drawn as its physical walk through virtual nodes
    (:meth:`Instance.walk`), KPOIs numbered (paper, Figs. 5 and 7). Without
    coordinates the nodes are placed by a seeded spring layout.
    """
    fig, ax = plt.subplots(figsize=(10, 6))
    _draw_routes(ax, instance, result, title)
    save_figure(fig, path, dpi=130)


def plot_side_by_side(
    instance: Instance,
    results: Sequence[Result],
    path: str | os.PathLike[str],
    titles: Sequence[str] | None = None,
) -> None:
    """Several solutions of one instance side by side (e.g. greedy beside optimal)."""
    titles = list(titles) if titles is not None else [None] * len(results)
    fig, axes = plt.subplots(1, len(results), figsize=(7.5 * len(results), 5), squeeze=False)
    for ax, result, title in zip(axes[0], results, titles):
        _draw_routes(ax, instance, result, title)
    save_figure(fig, path, dpi=110)


def plot_frontier(
    frontier: Frontier,
    path: str | os.PathLike[str],
    *,
    points: dict[str, list[tuple[int, float]]] | None = None,
) -> None:
    """Robots versus makespan as steps; optimal points filled, others hollow with their bound.

    ``points`` adds each method's (robots, makespan) answers beside the frontier.
    """
    pts = [p for p in frontier.points if p.makespan is not None]
    fig, ax = plt.subplots(figsize=(6, 4))
    if pts:
        k = [p.robots for p in pts]
        c = [p.makespan for p in pts]
        ax.step(k, c, where="post", color="0.5", lw=1)
        opt = [p for p in pts if p.status.value == "optimal"]
        other = [p for p in pts if p.status.value != "optimal"]
        ax.scatter([p.robots for p in opt], [p.makespan for p in opt], color="tab:blue", zorder=3,
                   label="optimal")
        ax.scatter([p.robots for p in other], [p.makespan for p in other], facecolor="none",
                   edgecolor="tab:blue", zorder=3, label="best found")
        for p in other:
            if p.bound is not None:
                ax.plot([p.robots, p.robots], [p.bound, p.makespan], color="tab:orange", lw=1)
                ax.scatter([p.robots], [p.bound], marker="_", s=120, color="tab:orange", zorder=3)
        if other:
            ax.plot([], [], color="tab:orange", label="proven bound")
        for (method, answers), marker in zip((points or {}).items(), "xv^<>sPD*"):
            ax.scatter([r for r, _ in answers], [m for _, m in answers], marker=marker, zorder=4, label=method)
            k = sorted(set(k) | {r for r, _ in answers})
        ax.set_xticks(k)
        ax.legend(fontsize=8)
    ax.set_xlabel("robots")
    ax.set_ylabel("makespan")
    name = frontier.instance or "instance"
    ax.set_title(f"{name}: {frontier.routes_kind} frontier ({frontier.method})", fontsize=9)
    ax.grid(alpha=0.3)
    save_figure(fig, path, dpi=130)


def plot_gap_distribution(frame: Any, path: str | os.PathLike[str]) -> None:
    """Box plot of each method's gap to the optimum, in percent (a gaps.csv frame)."""
    rows = frame[np.isfinite(frame["gap_to_optimum"].astype(float))]
    methods = list(dict.fromkeys(rows["method"]))
    fig, ax = plt.subplots(figsize=(1.2 * max(len(methods), 3) + 2, 4))
    if methods:
        data = [100 * rows.loc[rows["method"] == m, "gap_to_optimum"].astype(float) for m in methods]
        ax.boxplot(data, showmeans=True)
        ax.set_xticks(range(1, len(methods) + 1), methods, rotation=30, ha="right")
    ax.set_ylabel("gap to optimum (%)")
    ax.set_title("Gap to the optimum per method (all questions)", fontsize=9)
    ax.grid(alpha=0.3, axis="y")
    save_figure(fig, path, dpi=130)


def save_figure(fig: Any, path: str | os.PathLike[str], *, dpi: int) -> None:
    """Lay out, write and release a figure (every drawing of the package ends here)."""
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
