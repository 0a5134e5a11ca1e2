"""Drawings: parcover.plot writes readable PNG files."""

from pathlib import Path


import parcover as pc
from parcover.maps import instance_from_map
from parcover.plot import node_positions, plot_frontier, plot_routes, plot_side_by_side
from parcover.result import Frontier, FrontierPoint, Status

MAPS = Path(__file__).parent.parent / "instances" / "maps"
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def is_png(path):
    data = Path(path).read_bytes()
    return data[:8] == PNG_MAGIC and len(data) > 1000


def test_routes_over_a_map(tmp_path):
    inst = instance_from_map(MAPS / "simple_rooms.png", 0.05, kpois=8, seed=1)
    result = pc.solve(inst, robots=2, method="knn")
    plot_routes(inst, result, tmp_path / "map.png", title="knn on simple_rooms")
    assert is_png(tmp_path / "map.png")


def test_routes_over_the_plane(tmp_path, fig3_star):
    plot_routes(fig3_star, pc.solve(fig3_star, robots=2, method="knn"), tmp_path / "plane.png")
    assert is_png(tmp_path / "plane.png")


def test_instance_without_coordinates_gets_a_seeded_layout(tmp_path):
    # Two KPOIs on a path graph, no coordinates: spring_layout places every node,
    # and the same seed places them the same way.
    inst = pc.Instance("s", ("a", "b"), edges=(("s", "a", 1.0), ("a", "b", 2.0)))
    first, second = node_positions(inst, seed=3), node_positions(inst, seed=3)
    assert set(first) == {"s", "a", "b"}
    assert first == second
    plot_routes(inst, pc.solve(inst, method="trivial"), tmp_path / "layout.png")
    assert is_png(tmp_path / "layout.png")


def test_side_by_side(tmp_path, fig1_grid):
    results = [pc.solve(fig1_grid, robots=2, method=m) for m in ("knn", "nn")]
    plot_side_by_side(fig1_grid, results, tmp_path / "pair.png", ["knn", "nn"])
    assert is_png(tmp_path / "pair.png")


def test_frontier(tmp_path):
    points = [
        FrontierPoint(1, 10.0, Status.OPTIMAL, 10.0),
        FrontierPoint(2, 7.0, Status.FEASIBLE, 5.5),  # hollow, with its bound
        FrontierPoint(3, 5.0, Status.OPTIMAL, 5.0),
    ]
    plot_frontier(Frontier("toy", "paths", "exact", points), tmp_path / "frontier.png")
    assert is_png(tmp_path / "frontier.png")


