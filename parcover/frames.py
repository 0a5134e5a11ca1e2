"""Teaching frames: one picture per recorded step of the paper's Algorithms 1, 1-1 and 2.

``parcover solve FILE --method paper --trace --plot DIR/`` (or :func:`save_frames`)
draws every :class:`~parcover.algorithms.paper.TraceStep` of a result's trace, so a
lecturer can page through the greedy's decisions:

- Algorithm 1 and 1-1: the paths built so far, the path being grown drawn wider,
  the KPOI the step considers ringed in green (taken) or red (refused) with a dashed
  line from the node its distance is measured from, KPOIs not yet covered hollow;
  the title gives the step as the trace prints it and the budget left, the threshold
  (``c_max`` or ``c_p``) minus the path's cost.
- Algorithm 2: the paths still to pair dashed and numbered, the tours formed so far,
  the tour of the step drawn wider.

Every frame is drawn from the trace the algorithm recorded (``Result.info["steps"]``),
never by running the greedy again.
"""

from __future__ import annotations

import os
import textwrap
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from matplotlib.axes import Axes

from parcover.algorithms.paper import TraceStep
from parcover.errors import InputError
from parcover.instance import Instance
from parcover.plot import (TITLE_WIDTH, distance_unit, draw_background, draw_kpois, draw_route, label_axes,
                           leg_polylines, legend_outside, new_figure, node_positions, question_text, route_colour,
                           save_figure)
from parcover.result import Result

__all__ = ["draw_step", "frame_title", "save_frames", "trace_steps", "animate"]

Point = tuple[float, float]

#: Seconds each frame shows in the animated GIF.
GIF_SECONDS = 1.5


def trace_steps(result: Result) -> tuple[TraceStep, ...]:
    """The recorded steps of a result solved with ``trace=True`` by a ``paper*`` method.

    Raises
    ------
    InputError
        When the result carries no recorded steps.
    """
    steps = result.info.get("steps")
    if steps:
        return tuple(steps)
    if not result.routes:
        raise InputError(f"No steps to draw: the answer is {result.status.value}, the algorithm ran no step.")
    raise InputError(
        f"The result of {result.method} has no recorded steps to draw; solve with a paper* method and trace=True."
    )


def draw_step(
    ax: Axes,
    instance: Instance,
    result: Result,
    step: TraceStep,
    number: int,
    count: int,
    pos: dict[str, Point] | None = None,
) -> Axes:
    """Draw frame ``number`` of ``count``: the state ``step`` leaves, titled with what it did."""
    pos = node_positions(instance) if pos is None else pos
    draw_background(ax, instance, pos, show_virtual=False)
    covered = _draw_routes_of(ax, instance, step, pos)
    if step.candidate is not None:
        _draw_candidate(ax, instance, step, pos)
    draw_kpois(ax, instance, pos, faded=[v for v in instance.kpois if v not in covered])
    label_axes(ax, instance)
    ax.set_title(frame_title(instance, result, step, number, count), fontsize=8.5, loc="left")
    legend_outside(ax)
    return ax


def frame_title(instance: Instance, result: Result, step: TraceStep, number: int, count: int) -> str:
    """Instance, question and method; the step as the trace prints it; the budget left."""
    head = (f"{instance.name or 'unnamed instance'}: {question_text(result, distance_unit(instance))}; "
            f"{result.method}, frame {number}/{count}")
    lines = [head, *textwrap.wrap(step.text, TITLE_WIDTH)]
    if step.budget_left is not None and step.current is not None:
        what = "tour" if _pairing(step) else "path"
        lines.append(f"{what} {step.current + 1}: cost {step.cost:.4g}, {_threshold_name(instance, step)} = "
                     f"{step.threshold:.4g}, budget left {step.budget_left:.4g}")
    return "\n".join(lines)


def _pairing(step: TraceStep) -> bool:
    """An Algorithm 2 step (pairing paths into tours) or a tours result."""
    return bool(step.tours or step.remaining or step.joined)


def _threshold_name(instance: Instance, step: TraceStep) -> str:
    if _pairing(step):
        return "c_t"
    return "c_max" if step.threshold == instance.c_max else "c_p"


def _draw_routes_of(ax: Axes, instance: Instance, step: TraceStep, pos: dict[str, Point]) -> set[str]:
    """The step's paths and tours; the KPOIs they cover."""
    s = instance.start
    covered: set[str] = set()
    pairing = _pairing(step)
    count = max(len(step.paths), len(step.tours), 1)
    for t, tour in enumerate(step.tours):
        wide = t == step.current
        draw_route(ax, instance, [s, *tour, s], pos, route_colour(t, count), width=3.2 if wide else 1.4,
                   alpha=1.0 if wide else 0.55, label=f"tour {t + 1}" + (" (this step)" if wide else ""))
        covered.update(tour)
    for p, path in enumerate(step.paths):
        if pairing and p not in step.remaining:
            continue  # already in a tour
        wide = not pairing and p == step.current
        style: dict[str, Any] = dict(linestyle="--", alpha=0.8) if pairing else dict(alpha=1.0 if wide else 0.6)
        colour = "0.35" if pairing else route_colour(p, count)
        label = f"path {p + 1}" + (" (to pair)" if pairing else " (growing)" if wide else "")
        draw_route(ax, instance, [s, *path], pos, colour, width=3.2 if wide else 1.4, label=label, **style)
        if path:
            ax.annotate(f"path {p + 1}", pos[path[-1]], xytext=(5, -11), textcoords="offset points", fontsize=7,
                        color=colour, zorder=7)
        covered.update(path)
    return covered


def _draw_candidate(ax: Axes, instance: Instance, step: TraceStep, pos: dict[str, Point]) -> None:
    """The KPOI considered, ringed green (taken) or red (refused), and dotted along the shortest
    walk to it the distance the step's test measures."""
    assert step.candidate is not None
    colour = "tab:green" if step.accepted else "tab:red"
    if step.anchor is not None and step.anchor != step.candidate:
        [xy] = leg_polylines(instance, [step.anchor, step.candidate], pos)
        ax.plot(xy[:, 0], xy[:, 1], linestyle=":", color=colour, lw=1.8, zorder=6,
                label=f"distance measured from {step.anchor}")
    x, y = pos[step.candidate]
    ax.scatter([x], [y], s=260, facecolor="none", edgecolor=colour, lw=2.0, zorder=6,
               label=f"candidate {step.candidate}: " + ("taken" if step.accepted else "refused"))


def save_frames(
    instance: Instance,
    result: Result,
    folder: str | os.PathLike[str],
    *,
    gif: bool = True,
    dpi: int = 90,
) -> list[Path]:
    """Write one PNG per recorded step (``step-001.png``, ...) into ``folder``, made if missing.

    With ``gif``, also ``steps.gif``: the frames animated, :data:`GIF_SECONDS` each.
    Returns the PNG paths, in step order.

    Examples
    --------
    >>> import parcover as pc
    >>> from parcover.frames import save_frames
    >>> grid = pc.generate.grid(2, 2)
    >>> result = pc.solve(grid, method="paper", trace=True)
    >>> frames = save_frames(grid, result, "frames", gif=False)  # doctest: +SKIP
    >>> len(frames) == len(result.info["trace"])  # doctest: +SKIP
    True
    """
    steps = trace_steps(result)
    out = Path(folder)
    out.mkdir(exist_ok=True)
    pos = node_positions(instance)
    digits = max(3, len(str(len(steps))))
    paths = []
    for number, step in enumerate(steps, start=1):
        fig = new_figure(figsize=(9.5, 6.5))
        # One layout for every frame: the drawing stays put while paging or in the GIF.
        fig.subplots_adjust(left=0.08, right=0.72, bottom=0.08, top=0.84)
        draw_step(fig.add_subplot(), instance, result, step, number, len(steps), pos)
        path = out / f"step-{number:0{digits}d}.png"
        save_figure(fig, path, dpi=dpi, tight=False)
        paths.append(path)
    if gif:
        animate(paths, out / "steps.gif")
    return paths


def animate(frames: Sequence[Path], path: Path) -> None:
    """An animated GIF of PNG frames (Pillow, which matplotlib depends on), looping."""
    from PIL import Image

    images = [Image.open(frame).convert("RGB") for frame in frames]  # all of one size (save_frames)
    images[0].save(path, save_all=True, append_images=images[1:], duration=int(GIF_SECONDS * 1000), loop=0)
