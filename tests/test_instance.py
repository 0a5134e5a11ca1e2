"""The instance model: validation, read-only state, the metric and walks."""

from __future__ import annotations

import dataclasses
import time

import networkx as nx
import numpy as np
import pytest

from parcover import Instance, InstanceError, ShortEdgeWarning, generate


def test_arrays_are_read_only(fig1_grid):
    assert not fig1_grid.distances.flags.writeable
    with pytest.raises(ValueError):
        fig1_grid.distances[0, 1] = 5.0


def test_instance_is_frozen(fig1_grid):
    with pytest.raises(dataclasses.FrozenInstanceError):
        fig1_grid.start = "r1c1"  # type: ignore[misc]


def test_replace_validates_the_copy(tiny_line):
    renamed = tiny_line.replace(name="other")
    assert renamed.name == "other" and np.array_equal(renamed.distances, tiny_line.distances)
    with pytest.raises(InstanceError, match="Duplicate KPOI"):
        tiny_line.replace(kpois=("a", "a"))


def test_fig1_grid_c_max_is_4(fig1_grid):
    # Fig. 1: the farthest cell from the upper left corner of a 3x3 grid is the
    # opposite corner, 2 + 2 = 4 unit moves away.
    assert fig1_grid.c_max == 4
    assert fig1_grid.v_max == "r2c2"


def test_fig1_grid_P_max_is_a_shortest_path_of_kpois(fig1_grid):
    path = fig1_grid.P_max
    # every cell on a 4-move path from the corner is a KPOI: 4 KPOIs, ending at v_max
    assert len(path) == 4 and path[-1] == "r2c2"
    steps = [fig1_grid.distance(u, v) for u, v in zip(("r0c0", *path), path)]
    assert steps == [1, 1, 1, 1]


def test_fig3_star_kpois_are_equidistant(fig3_star):
    assert np.allclose(fig3_star.distances[0, 1:], 1.0)
    assert fig3_star.P_max == (fig3_star.v_max,)  # the straight edge meets no other KPOI


@pytest.mark.parametrize("seed", range(5))
def test_graph_metric_equals_networkx_shortest_paths(seed):
    inst = generate.random_graph(8, seed, virtual=15)
    graph = inst.to_networkx()
    lengths = dict(nx.all_pairs_dijkstra_path_length(graph, weight="weight"))
    expected = np.array([[lengths[u][v] for v in inst.ids] for u in inst.ids])
    assert np.allclose(inst.distances, expected, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("seed", range(5))
def test_walk_costs_the_same_as_the_route(seed):
    inst = generate.random_graph(8, seed, virtual=15)
    graph = inst.to_networkx()
    route = [inst.start, *np.random.default_rng(seed).permutation(inst.kpois).tolist()]
    walk = inst.walk(route)
    assert walk[0] == route[0] and walk[-1] == route[-1]
    walk_cost = sum(graph.edges[u, v]["weight"] for u, v in zip(walk, walk[1:]))
    route_cost = sum(inst.distance(u, v) for u, v in zip(route, route[1:]))
    assert walk_cost == pytest.approx(route_cost, rel=1e-12)
    assert set(route) <= set(walk)


def test_walk_goes_through_virtual_nodes():
    inst = Instance("s", ("a", "b"), edges=(("s", "v", 1), ("v", "a", 1), ("v", "b", 2)))
    assert inst.walk(["s", "a", "b"]) == ["s", "v", "a", "v", "b"]
    assert inst.virtual_nodes == ("v",)
    assert inst.distance("a", "b") == 3


def test_P_max_lists_kpois_passed_on_the_way():
    # s - a - b in a line: the shortest path to b passes a
    inst = Instance("s", ("b", "a"), edges=(("s", "a", 1), ("a", "b", 1)))
    assert inst.v_max == "b" and inst.P_max == ("a", "b")


def test_P_max_in_the_plane_lists_kpois_on_the_straight_segment():
    # s at the origin, v_max = c at distance 3; a and b lie on the segment s-c, d does not
    inst = Instance.from_points([[0, 0], [0, -3], [0, -2], [1, 0], [0, -1]], names=["s", "c", "b", "d", "a"])
    assert inst.P_max == ("a", "b", "c")


def test_start_listed_as_kpoi_is_covered_at_time_zero():
    inst = Instance.from_points([[0, 0], [1, 0]], names=["s", "a"]).replace(kpois=("s", "a"))
    assert inst.kpois == ("a",) and inst.start_is_kpoi


def test_parallel_edges_keep_the_lightest():
    inst = Instance("s", ("a",), edges=(("s", "a", 5), ("a", "s", 2), ("s", "a", 3)))
    assert inst.distance("s", "a") == 2


def test_zero_weight_edges_are_edges():
    # scipy's sparse graphs would drop implicit zeros; an explicit 0 must stay an edge
    inst = Instance("s", ("a", "b"), edges=(("s", "a", 0), ("a", "b", 0)))
    assert inst.distance("s", "b") == 0


def test_weightless_edges_take_the_euclidean_length():
    inst = Instance("s", ("a",), coordinates={"s": (0, 0), "a": (3, 4)}, edges=(("s", "a"),))
    assert inst.distance("s", "a") == 5


def test_an_edge_shorter_than_its_straight_line_warns():
    with pytest.warns(ShortEdgeWarning):
        Instance("s", ("a",), coordinates={"s": (0, 0), "a": (3, 4)}, edges=(("s", "a", 1),))


def test_tsplib_metric_rounds_and_closes():
    # nint(0.4) = 0 and nint(0.6) = 1; the closure keeps d <= the rounded edge
    inst = Instance.from_points([[0, 0], [0.4, 0], [1.0, 0]], metric="tsplib")
    assert inst.distances[0, 1] == 0 and inst.distances[1, 2] == 1 and inst.distances[0, 2] == 1


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        (dict(start=3, kpois=("a",)), "start must be a non-empty string"),  # ids are strings
        (dict(start="s", kpois="ab"), "kpois must be a list"),  # a string is not a list of ids
        (dict(start="s", kpois=("a", "a")), "Duplicate KPOI 'a'"),  # each KPOI once
        (dict(start="s", kpois=("s",)), "at least one KPOI"),  # nothing to cover
        (dict(start="s", kpois=("a",)), "Missing coordinates for start 's'"),  # no edges, no positions
        (dict(start="s", kpois=("a",), coordinates={"s": (0, 0)}), "Missing coordinates for KPOI 'a'"),
        (dict(start="s", kpois=("a",), coordinates={"s": (0, 0), "a": (1, float("nan"))}), "finite"),
        (dict(start="s", kpois=("a",), edges=(("s", "a", -1),)), "negative weight"),  # no negative travel
        (dict(start="s", kpois=("a",), edges=(("s", "a", float("inf")),)), "non-finite"),  # inf is no edge
        (dict(start="s", kpois=("a",), edges=(("s", "a", "1"),)), "non-numeric"),  # weights are numbers
        (dict(start="s", kpois=("a",), edges=(("s", "s", 1), ("s", "a", 1))), "loop"),  # meaningless edge
        (dict(start="s", kpois=("a",), edges=(("s", "a", 1, 2),)), "must be \\[u, v, weight\\]"),
        (dict(start="s", kpois=("a",), edges=()), "edges is empty"),
        (dict(start="s", kpois=("a", "b"), edges=(("s", "a", 1),)), "KPOI 'b' is in no edge"),
        (dict(start="x", kpois=("a",), edges=(("s", "a", 1),)), "start 'x' is in no edge"),
        (dict(start="s", kpois=("a", "b"), edges=(("s", "a", 1), ("b", "c", 1))), "'b' is unreachable"),
        (dict(start="s", kpois=("a",), edges=(("s", "a"),)), "no weight and its ends have no coordinates"),
        (dict(start="s", kpois=("a",), coordinates={"s": (0, 0), "a": (1, 1)}, metric="manhattan"), "Unknown metric"),
    ],
)
def test_bad_instances_are_refused_with_one_line(kwargs, message):
    with pytest.raises(InstanceError, match=message) as info:
        Instance(**kwargs)
    assert "\n" not in str(info.value)


def test_from_networkx_and_back():
    g = nx.Graph()
    g.add_node(0, pos=(0.0, 0.0))
    g.add_node(1, pos=(1.0, 0.0))
    g.add_node(2, pos=(1.0, 1.0))
    g.add_edge(0, 1, weight=1.5)
    g.add_edge(1, 2)  # Euclidean from pos: 1
    inst = Instance.from_networkx(g, 0, [2])
    assert inst.start == "0" and inst.kpois == ("2",) and inst.virtual_nodes == ("1",)
    assert inst.distance("0", "2") == 2.5
    back = inst.to_networkx()
    assert back.nodes["1"]["kind"] == "virtual" and back.edges["0", "1"]["weight"] == 1.5


def test_from_networkx_refuses_a_missing_node():
    with pytest.raises(InstanceError, match="not in the graph"):
        Instance.from_networkx(nx.path_graph(3), 0, [7])


def test_large_graph_loads_in_seconds():
    # a large map: 10,000 nodes, 50,000 edges, 500 KPOIs must load in seconds
    rng = np.random.default_rng(1)
    nodes = 10_000
    tree = [(str(i), str(int(rng.integers(i))), 1.0 + float(rng.random())) for i in range(1, nodes)]
    extra = [
        (str(u), str(v), 1.0 + float(w))
        for u, v, w in zip(rng.integers(nodes, size=40_001), rng.integers(nodes, size=40_001), rng.random(40_001))
        if u != v
    ]
    started = time.perf_counter()
    inst = Instance("0", tuple(str(i) for i in range(1, 501)), edges=tuple(tree + extra))
    seconds = time.perf_counter() - started
    assert inst.distances.shape == (501, 501)
    assert seconds < 20, f"took {seconds:.1f} s"


# -- Instance.from_matrix -----------------------------------------------------------------

SQUARE = [[0, 2, 5, 1], [2, 0, 1, 1], [5, 1, 0, 1], [1, 1, 1, 0]]  # 3 KPOIs around a start; 0 -> 2 via 1 or 3


def test_from_matrix_defaults_every_other_row_to_a_kpoi():
    inst = Instance.from_matrix(np.array(SQUARE))
    assert inst.start == "0" and inst.kpois == ("1", "2", "3") and inst.virtual_nodes == ()
    # [0, 2] = 5 breaks the triangle inequality: travel takes 0 -> 3 -> 2 (cost 2)
    assert inst.distance("0", "2") == 2.0 and inst.walk(["0", "2"]) == ["0", "3", "2"]


def test_from_matrix_rows_outside_start_and_kpois_are_virtual():
    inst = Instance.from_matrix(SQUARE, start=1, kpois=[0, 2], ids=["a", "b", "c", "d"], name="sq")
    assert (inst.name, inst.start, inst.kpois, inst.virtual_nodes) == ("sq", "b", ("a", "c"), ("d",))
    assert inst.distance("a", "c") == 2.0 and inst.walk(["b", "a", "c"]) == ["b", "a", "d", "c"]


def test_from_matrix_matches_from_points():
    points = [[0, 0], [3, 4], [0, 1], [2, 2]]
    plane = Instance.from_points(points)
    matrix = Instance.from_matrix(np.hypot(*(np.array(points)[:, None] - np.array(points)[None]).T))
    assert plane.ids == matrix.ids and np.allclose(plane.distances, matrix.distances)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (([[0, 1], [1, 0, 2]],), "rows differ in length"),  # ragged nested lists
        (([["0", "1"], ["1", "0"]],), "must hold numbers"),  # strings are not distances
        (([[False, True], [True, False]],), "must hold numbers"),  # booleans are not distances
        (([[0, 1, 2], [1, 0, 2]],), "square distance matrix, got shape \\(2, 3\\)"),  # not square
        (([0, 1, 2],), "square distance matrix, got shape \\(3,\\)"),  # a vector, not a matrix
        (([[0, np.nan], [np.nan, 0]],), "non-finite entry nan at \\[0, 1\\]"),  # nan is no distance
        (([[0, np.inf], [np.inf, 0]],), "non-finite entry inf"),  # unreachable is not a distance either
        (([[0, -1], [-1, 0]],), "negative entry -1 at \\[0, 1\\]"),  # no negative travel
        (([[1, 1], [1, 0]],), "zero diagonal; entry \\[0, 0\\] is 1"),  # staying put costs nothing
        (([[0, 1], [2, 0]],), "symmetric distances only.*\\[0, 1\\] = 1 but \\[1, 0\\] = 2"),  # one-way costs
        (([[0]],), "at least one KPOI"),  # a start alone: nothing to cover
        ((SQUARE, 4), "start row 4 is out of range for a 4 x 4 matrix"),  # no such row
        ((SQUARE, 1.0), "start must be a row number"),  # rows are whole numbers
        ((SQUARE, 0, [1, 9]), "KPOI row 9 is out of range"),  # no such row
        ((SQUARE, 0, 1), "kpois must be a list of row numbers"),  # one index, not a list
        ((SQUARE, 0, [1, 1]), "Duplicate KPOI '1'"),  # each KPOI once
        ((SQUARE, 0, [0]), "at least one KPOI"),  # only the start: nothing to cover
        ((SQUARE, 0, None, ["a", "b"]), "Expected 4 ids \\(one per matrix row\\), got 2"),  # an id per row
        ((SQUARE, 0, None, ["a", "b", "a", "c"]), "Duplicate id 'a'"),  # ids name one node each
    ],
)
def test_from_matrix_refuses_bad_input_with_one_line(args, message):
    with pytest.raises(InstanceError, match=message) as info:
        Instance.from_matrix(*args)
    assert "\n" not in str(info.value) and isinstance(info.value, ValueError)
