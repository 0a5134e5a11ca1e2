"""Regenerate the pictures of docs/gallery.md: one plot of each kind parcover draws.

Run from the repository's root::

    python docs/make_gallery.py            # writes docs/gallery/*.png
    python docs/make_gallery.py OUT_DIR    # writes elsewhere (the tests do)

Every picture comes from a bundled instance and a fast method, so the whole gallery
takes seconds; the PNGs are drawn at :data:`DPI` to keep them small.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from pathlib import Path

import parcover as pc
from parcover import plot
from parcover.frames import draw_step, trace_steps
from parcover.report import gaps

ROOT = Path(__file__).resolve().parent.parent
INSTANCES = ROOT / "instances"
#: Resolution of every picture (dots per inch).
DPI = 80


def routes_on_points(path: Path) -> None:
    """Proven optimal paths of 3 robots over 12 random points."""
    inst = pc.read_instance(INSTANCES / "random12_s2.json")
    plot.save_routes_plot(inst, pc.solve(inst, robots=3, method="setpart"), path, dpi=DPI)


def routes_on_a_graph(path: Path) -> None:
    """The paper's Algorithm 1 on a sparse graph with virtual nodes (non-Euclidean weights)."""
    inst = pc.read_instance(INSTANCES / "graph10_s4.json")
    plot.save_routes_plot(inst, pc.solve(inst, method="paper"), path, dpi=DPI)


def routes_on_a_map(path: Path) -> None:
    """Tours of 3 robots over Stage's cave map, drawn along the corridors."""
    inst = pc.read_instance(INSTANCES / "cave12_s1.json")
    plot.save_routes_plot(inst, pc.solve(inst, "tours", robots=3, method="best"), path, dpi=DPI)


def greedy_beside_optimum(path: Path) -> None:
    """Fig. 1's grid: the literal Algorithm 1 needs 3 robots where 2 reach c_max."""
    inst = pc.generate.grid(3, 3)
    results = [pc.solve(inst, method=m) for m in ("paper", "setpart")]
    plot.plot_side_by_side(inst, results, path, ["the paper's greedy", "the optimum"], dpi=DPI)


def frontier(path: Path) -> None:
    """The least makespan for 1..n robots (setpart) with the nearest-neighbour greedy's answers."""
    inst = pc.read_instance(INSTANCES / "random8_s1.json")
    curve = pc.frontier(inst, "paths", "setpart")
    nn = [pc.solve(inst, robots=k, method="nn") for k in range(1, inst.n + 1)]
    points = {"nn": sorted({(r.robots, r.makespan) for r in nn})}
    plot.plot_frontier(curve, path, points=points, dpi=DPI)


def gap_distribution(path: Path) -> None:
    """Gaps of three greedy methods against setpart's optima on six small random instances."""
    frame = gaps("random:n=6..7:seeds=0..2", ["paper", "nn", "mst"], robots=(2,), reference="setpart",
                 time_limit=10, workers=1, progress=False)
    plot.plot_gap_distribution(frame, path, dpi=DPI)


def teaching_frame(path: Path) -> None:
    """Step 5d of the literal Algorithm 1 on Fig. 1's grid, as ``--trace --plot DIR/`` draws it."""
    inst = pc.generate.grid(3, 3)
    result = pc.solve(inst, method="paper", trace=True)
    steps = trace_steps(result)
    fig = plot.new_figure(figsize=(9.5, 6.5))
    fig.subplots_adjust(left=0.08, right=0.72, bottom=0.08, top=0.84)
    draw_step(fig.add_subplot(), inst, result, steps[7], 8, len(steps))
    plot.save_figure(fig, path, dpi=DPI, tight=False)


#: Each picture's file name and the function drawing it, in the order of docs/gallery.md.
PICTURES: dict[str, Callable[[Path], None]] = {
    "routes-points.png": routes_on_points,
    "routes-graph.png": routes_on_a_graph,
    "routes-map.png": routes_on_a_map,
    "greedy-vs-optimum.png": greedy_beside_optimum,
    "frontier.png": frontier,
    "gaps.png": gap_distribution,
    "teaching-frame.png": teaching_frame,
}


def main(out: Path) -> list[Path]:
    """Draw every picture of :data:`PICTURES` into ``out`` (made if missing); their paths."""
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for name, draw in PICTURES.items():
        draw(out / name)
        written.append(out / name)
    return written


if __name__ == "__main__":
    folder = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parent / "gallery"
    for picture in main(folder):
        print(f"wrote {picture}")
