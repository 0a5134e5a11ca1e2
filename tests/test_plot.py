"""Drawings: parcover.plot draws plots that say what they show, and writes readable PNG files."""

import dataclasses
import doctest
import re
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import parcover as pc  # noqa: E402
from parcover import plot as P  # noqa: E402
from parcover.maps import instance_from_map  # noqa: E402
from parcover.plot import (node_positions, plot_frontier, plot_gap_distribution, plot_routes,  # noqa: E402
                           plot_side_by_side, save_routes_plot)
from parcover.result import Frontier, FrontierPoint, Status  # noqa: E402

MAPS = Path(__file__).parent.parent / "instances" / "maps"
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def is_png(path):
    data = Path(path).read_bytes()
    return data[:8] == PNG_MAGIC and len(data) > 1000


@pytest.fixture
def axes():
    fig, ax = plt.subplots()
    yield ax
    plt.close(fig)


@pytest.fixture(scope="module")
def rooms():
    """8 KPOIs on the simple_rooms floor plan, decomposition graph (walks through cell boundaries)."""
    return instance_from_map(MAPS / "simple_rooms.png", 0.05, kpois=8, seed=1)


def arrows(ax):
    """The direction arrows drawn on ``ax`` (annotations without text)."""
    return [t for t in ax.texts if t.get_text() == "" and t.arrow_patch is not None]


def test_plot_routes_is_exported_and_returns_the_axes_it_drew_on(axes, fig3_star):
    result = pc.solve(fig3_star, robots=2, method="knn")
    assert pc.plot_routes is plot_routes and "plot_routes" in pc.__all__
    assert plot_routes(fig3_star, result, axes) is axes


def test_plot_routes_makes_a_figure_when_given_no_axes(fig3_star):
    ax = plot_routes(fig3_star, pc.solve(fig3_star, robots=2, method="knn"))
    assert ax.figure is not None and ax.lines
    plt.close(ax.figure)


def test_title_names_instance_question_method_status_and_value(axes, fig3_star):
    # star of 6 unit spokes, tours with 2 robots: the optimum is 2 tours of 4 (out, 2 chords, back)
    plot_routes(fig3_star, pc.solve(fig3_star, "tours", robots=2, method="exact"), axes)
    assert axes.get_title() == ("star-6: tours, at most 2 robots: least makespan\n"
                                "exact: optimal, 2 robots, makespan 4 (distance units)")
    assert (axes.get_xlabel(), axes.get_ylabel()) == ("x (distance units)", "y (distance units)")


def test_title_of_a_deadline_question_with_an_unproven_answer(axes, fig1_grid):
    result = pc.solve(fig1_grid, deadline=5, method="paper")
    plot_routes(fig1_grid, result, axes, title="a caption")
    caption, question, answer = axes.get_title().split("\n")
    assert caption == "a caption"
    assert question == "grid-3x3: paths, deadline 5 (distance units): fewest robots"
    assert answer == (f"paper: feasible, {result.robots} robots, makespan {result.makespan:.4g}, "
                      f"proven bound {result.bound:.0f} robots (distance units)")


def test_every_leg_has_a_direction_arrow(axes, fig1_grid):
    result = pc.solve(fig1_grid, robots=2, method="exact")
    plot_routes(fig1_grid, result, axes)
    legs = sum(len(route) - 1 for route in result.routes)
    assert len(arrows(axes)) == legs


def test_out_and_back_arrows_sit_on_both_sides_of_the_line(axes):
    # s - a - b on a line, route s -> b -> a: the leg b -> a runs back over s -> b. The arrows are
    # drawn to the right of travel: one above the line, one below, so both directions show.
    inst = pc.Instance.from_points([[0, 0], [1, 0], [2, 0]], names="sab")
    back = dataclasses.replace(pc.solve(inst, method="exact"), routes=[["s", "b", "a"]], route_costs=[3.0])
    plot_routes(inst, back, axes)
    axes.figure.canvas.draw()
    ys = sorted(a.xycoords.transform(a.xy)[1] for a in arrows(axes))  # the arrow heads, in pixels
    line_y = axes.transData.transform((0, 0))[1]
    assert ys[0] < line_y - 1 and ys[-1] > line_y + 1


def test_kpoi_labels_are_drawn_above_the_start_marker(axes, fig1_grid):
    plot_routes(fig1_grid, pc.solve(fig1_grid, robots=2, method="knn"), axes)
    start = next(c for c in axes.collections if c.get_label() == "start")
    labels = [t for t in axes.texts if t.get_text() in fig1_grid.kpois]
    assert len(labels) == fig1_grid.n and min(t.get_zorder() for t in labels) > start.get_zorder()


def test_legend_holds_only_what_is_drawn(axes, fig1_grid):
    result = pc.solve(fig1_grid, robots=2, method="knn")
    plot_routes(fig1_grid, result, axes)
    labels = [t.get_text() for t in axes.get_legend().get_texts()]
    robots = [f"robot {r + 1}: {c:.4g}" for r, c in enumerate(result.route_costs)]
    assert labels == ["graph edge", *robots, "start", "KPOI"]  # the grid's edges are drawn in grey


def test_map_routes_follow_the_corridors_in_metres(axes, rooms):
    result = pc.solve(rooms, robots=2, method="knn")
    plot_routes(rooms, result, axes)
    assert (axes.get_xlabel(), axes.get_ylabel()) == ("x (m)", "y (m)")
    assert re.search(r"makespan [\d.]+ m, proven bound [\d.]+ m$", axes.get_title())  # metres after each length
    # no virtual-node crosses by default; each leg is drawn through some of its walk's waypoints,
    # joined by straight lines over free pixels (or by the walk's own edge where none is free)
    assert not any(c.get_label() == "virtual node" for c in axes.collections)
    pos = node_positions(rooms)
    mask = P._corridors(rooms)
    walked = drawn = 0
    for route in result.routes:
        for (u, v), xy in zip(zip(route, route[1:]), P.leg_polylines(rooms, route, pos)):
            walk = [pos[w] for w in rooms.shortest_walk(u, v)]
            kept = [walk.index(tuple(p)) for p in xy]
            assert kept == sorted(kept) and kept[0] == 0 and kept[-1] == len(walk) - 1
            assert all(j == i + 1 or P._segment_free(xy[k], xy[k + 1], rooms, mask)
                       for k, (i, j) in enumerate(zip(kept, kept[1:])))
            walked, drawn = walked + len(walk), drawn + len(xy)
    assert drawn < walked  # cell-boundary waypoints were cut where a straight line is free


def test_virtual_nodes_only_when_asked(axes, rooms):
    plot_routes(rooms, pc.solve(rooms, robots=2, method="knn"), axes, show_virtual=True)
    assert any(c.get_label() == "virtual node" for c in axes.collections)


def test_shortcut_keeps_a_waypoint_the_straight_line_cannot_skip():
    # an L around a wall: the corner stays; a straight run loses its middle point
    corner = np.array([[0, 0], [1, 0], [1, 1]], dtype=float)
    assert P.shortcut(corner, lambda a, b: not (a[0] == 0 and b[1] == 1)).tolist() == corner.tolist()
    straight = np.array([[0, 0], [1, 0], [2, 0]], dtype=float)
    assert P.shortcut(straight, lambda a, b: True).tolist() == [[0, 0], [2, 0]]


def test_instance_without_coordinates_gets_a_seeded_layout_not_to_scale(axes):
    # Two KPOIs on a path graph, no coordinates: spring_layout places every node,
    # and the same seed places them the same way; the axes say the layout is not to scale.
    inst = pc.Instance("s", ("a", "b"), edges=(("s", "a", 1.0), ("a", "b", 2.0)))
    first, second = node_positions(inst, seed=3), node_positions(inst, seed=3)
    assert set(first) == {"s", "a", "b"}
    assert first == second
    plot_routes(inst, pc.solve(inst, method="trivial"), axes)
    assert "not to scale" in axes.get_xlabel() and not axes.get_xticks().size


def test_save_routes_plot_writes_a_png(tmp_path, rooms):
    save_routes_plot(rooms, pc.solve(rooms, robots=2, method="knn"), tmp_path / "map.png")
    assert is_png(tmp_path / "map.png")


def test_side_by_side(tmp_path, fig1_grid):
    results = [pc.solve(fig1_grid, robots=2, method=m) for m in ("knn", "nn")]
    plot_side_by_side(fig1_grid, results, tmp_path / "pair.png", ["knn", "nn"])
    assert is_png(tmp_path / "pair.png")


def test_frontier_legend_has_no_empty_entry(axes):
    # all points optimal: no "best found" or "bound" entry; one entry per method's points
    points = [FrontierPoint(1, 10.0, Status.OPTIMAL, 10.0), FrontierPoint(2, 6.0, Status.OPTIMAL, 6.0)]
    ax = P.draw_frontier(Frontier("toy", "paths", "exact", points), axes, points={"nn": [(2, 7.0)]})
    assert ax is axes
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["optimal (exact)", "nn"]
    assert ax.get_title() == "toy: least makespan per number of robots (paths)\nfrontier by exact"
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("robots", "makespan (distance units)")


def test_frontier_with_unproven_points_shows_their_bounds(tmp_path):
    points = [
        FrontierPoint(1, 10.0, Status.OPTIMAL, 10.0),
        FrontierPoint(2, 7.0, Status.FEASIBLE, 5.5),  # hollow, with its bound
        FrontierPoint(3, 5.0, Status.OPTIMAL, 5.0),
    ]
    plot_frontier(Frontier("toy", "paths", "exact", points), tmp_path / "frontier.png")
    assert is_png(tmp_path / "frontier.png")
    ax = P.draw_frontier(Frontier("toy", "paths", "exact", points), unit="m")
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == ["optimal (exact)", "best found (exact)", "proven lower bound"] and "(m)" in ax.get_ylabel()
    plt.close(ax.figure)


def test_gap_distribution_title_says_over_what(tmp_path):
    import pandas as pd

    frame = pd.DataFrame({"instance": ["a", "a", "b"], "routes": ["paths"] * 3, "question": ["robots<=2"] * 3,
                          "method": ["nn", "paper", "nn"], "reference": ["exact"] * 3,
                          "gap_to_optimum": [0.1, 0.0, float("nan")]})
    plot_gap_distribution(frame, tmp_path / "gaps.png")
    assert is_png(tmp_path / "gaps.png")
    ax = P.draw_gap_distribution(frame)
    assert ax.get_title().replace("\n", " ") == ("Gap to the optimum (exact) per method: 2 instances, paths, 1 question "
                              "(2 answers with a gap)")
    assert ax.get_ylabel() == "gap to optimum (%)"
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["median", "mean", "middle half (quartiles)"]
    plt.close(ax.figure)


def test_docstring_examples(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert doctest.testmod(P).failed == 0
    plt.close("all")


def test_importing_parcover_loads_no_matplotlib_until_a_drawing_is_asked_for():
    import subprocess
    import sys

    code = ("import sys, parcover; before = 'matplotlib' in sys.modules; parcover.plot_routes; "
            "print(before, 'matplotlib' in sys.modules, 'plot_routes' in dir(parcover))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True)
    assert done.stdout.split() == ["False", "True", "True"]
