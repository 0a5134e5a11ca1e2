"""Instance files: JSON (docs/format.md section 2) and TSPLIB."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from parcover import FileFormatError, Instance, generate, load, write_instance
from parcover.io import instance_from_dict, instance_to_dict

BAD = Path(__file__).parent / "data" / "bad"
TSPLIB = Path(__file__).resolve().parents[1] / "instances" / "tsplib"


@pytest.mark.parametrize(
    "instance",
    [generate.grid(2, 3), generate.star(5), generate.random_points(6, 3), generate.random_graph(5, 2)],
    ids=["grid", "star", "random", "graph"],
)
def test_json_round_trip(instance, tmp_path):
    path = tmp_path / "inst.json"
    write_instance(instance, path)
    again = load(path)
    assert again.name == instance.name and again.start == instance.start and again.kpois == instance.kpois
    assert again.edges == instance.edges
    assert np.array_equal(again.distances, instance.distances)


def test_the_design_example_reads():
    # docs/format.md section 2, verbatim (the map block points at an image we need not open)
    data = json.loads("""{
      "name": "fig1-grid-3x3", "start": "s", "kpois": ["a", "b", "c"],
      "coordinates": {"s": [0, 0], "a": [1, 0], "b": [1, 1], "c": [0, 1]},
      "edges": [["s", "a", 1], ["a", "b", 1], ["b", "c", 1], ["c", "s", 1]],
      "map": {"image": "maps/cave.png", "metres_per_pixel": 0.05, "origin": [0, 0]}}""")
    inst = instance_from_dict(data)
    assert inst.c_max == 2 and inst.map is not None and inst.map.metres_per_pixel == 0.05
    assert instance_to_dict(inst)["map"]["image"] == "maps/cave.png"


def test_tsplib_exact_euclidean_by_default():
    inst = load(TSPLIB / "eil51.tsp")
    # eil51 node 1 is (37, 52) and node 2 is (49, 49)
    assert inst.start == "1" and inst.n == 50 and inst.name == "eil51"
    assert inst.distance("1", "2") == pytest.approx(math.hypot(12, 3))


def test_tsplib_rounding_on_request():
    inst = load(TSPLIB / "eil51.tsp", metric="tsplib")
    assert inst.distance("1", "2") == 12  # nint(12.369...)


@pytest.mark.parametrize(
    ("name", "message"),
    [
        ("truncated.json", "malformed JSON at line 1"),  # the closing brace is missing
        ("not_an_object.json", "expected a JSON object"),  # an instance is an object
        ("no_start.json", "Missing required key 'start'"),  # start is required
        ("numeric_start.json", "start must be a non-empty string"),  # ids are strings
        ("duplicate_kpoi.json", "Duplicate KPOI 'a'"),  # each KPOI listed once
        ("no_kpois.json", "at least one KPOI"),  # nothing to cover
        ("missing_coordinates.json", "Missing coordinates for KPOI 'b'"),  # no edges, b has no position
        ("one_coordinate.json", "must be two numbers"),  # a position is [x, y]
        ("negative_weight.json", "negative weight"),  # travel costs are >= 0
        ("infinite_weight.json", "non-finite weight"),  # 1e999 parses as infinity
        ("nan_weight.json", "NaN is not a valid JSON number"),  # NaN is not JSON
        ("text_weight.json", "non-numeric weight"),  # a weight is a number
        ("unreachable_kpoi.json", "'b' is unreachable from the start"),  # b sits in another component
        ("kpoi_in_no_edge.json", "KPOI 'b' is in no edge"),  # with edges, every KPOI needs one
        ("unknown_start.json", "start 'x' is in no edge"),  # the start is not on the map
        ("weightless_edge_no_coordinates.json", "no weight"),  # a weight or coordinates are needed
        ("not_utf8.json", "not UTF-8"),  # the format is UTF-8
        ("geo.tsp", "GEO is not supported"),  # only EUC_2D TSPLIB files
        ("bad_coordinate.tsp", "Points must be numbers"),  # a coordinate reads 'zero'
        ("single_node.tsp", "at least 2 nodes"),  # a start and no KPOI
        ("missing.json", "no such file"),  # not there at all
        # hostile numbers: each must be refused, not overflow or underflow into an answer
        ("huge_integer_weight.json", "weight too large for a float"),  # 400 digits: no float holds it
        ("overflowing_coordinates.json", "Distances overflow"),  # +-1e308 apart: the distance is inf
        ("huge_coordinates.json", "are too large"),  # 1e200: finite, but squared route costs overflow
        ("overflowing_weights.json", "overflow when 3 of them are added"),  # 1e308 + 1e308 is inf, not unreachable
        ("tiny_coordinates.json", "below 0.001"),  # 1e-200: every cost is lost in the tolerance 1e-9
        # coordinates are a list of two numbers, nothing else
        ("string_coordinates.json", "Coordinates of 's' must be two numbers"),  # "00" is not (0, 0)
        ("digit_string_coordinates.json", "Coordinates of 'a' must be two numbers"),  # nor is "12" (1, 2)
        ("text_coordinates.json", "Coordinates of 's' must be two numbers"),  # ["1", "0"] holds strings
        ("boolean_coordinates.json", "Coordinates of 's' must be two numbers"),  # [true, false] is not (1, 0)
        ("duplicate_key.json", "duplicate key 'start'"),  # which start was meant? JSON would keep the last
        # TSPLIB headers must describe the nodes listed
        ("dimension_too_small.tsp", "DIMENSION 2 does not match the 4 nodes"),  # 4 nodes listed
        ("dimension_too_large.tsp", "DIMENSION 10 does not match the 4 nodes"),  # 4 nodes listed
        ("dimension_word.tsp", "DIMENSION 'four' does not match"),  # a dimension is a number
        ("cvrp.tsp", "TYPE CVRP is not supported"),  # demands and capacities would be ignored
        ("duplicate_node.tsp", "node 2 is listed twice"),  # renumbering would name a node not in the file
        ("no_node_one.tsp", "no node 1"),  # node 1 is the start
    ],
)
def test_bad_files_are_refused_with_one_line(name, message):
    with pytest.raises(FileFormatError, match=message) as info:
        load(BAD / name)
    assert str(info.value).startswith(str(BAD / name)) and "\n" not in str(info.value)


def test_tsplib_nodes_keep_their_numbers(tmp_path):
    # ids are the numbers written in the file, even when they skip some
    path = tmp_path / "gaps.tsp"
    path.write_text("NAME : gaps\nTYPE : TSP\nDIMENSION : 3\nEDGE_WEIGHT_TYPE : EUC_2D\n"
                    "NODE_COORD_SECTION\n1 0 0\n5 3 4\n7 0 1\nEOF\n")
    inst = load(path)
    assert inst.start == "1" and inst.kpois == ("5", "7") and inst.distance("1", "5") == 5


@pytest.mark.parametrize("where", ["instance", "kpois"])
def test_json_nested_100000_deep_is_refused(tmp_path, where):
    # Python's parser recurses once per level: 100,000 levels is a RecursionError unless caught
    deep = "[" * 100_000 + "]" * 100_000
    text = deep if where == "instance" else '{"start": "s", "kpois": ' + deep + "}"
    path = tmp_path / "deep.json"
    path.write_text(text)
    with pytest.raises(FileFormatError, match="nested too deeply"):
        load(path)


def test_bundled_instances_load():
    root = TSPLIB.parent
    files = sorted(root.glob("*.json")) + sorted(TSPLIB.glob("*.tsp"))
    assert len(files) >= 8
    for path in files:
        assert isinstance(load(path), Instance)


def test_an_instance_whose_distances_are_all_zero_is_accepted(tmp_path):
    # The smallest-distance rule (largest distance >= 1e-3) is about costs lost in the
    # tolerance; when every KPOI is at the start there is no cost to lose: every answer
    # is one robot, makespan 0 (docs/format.md says so).
    path = tmp_path / "zero.json"
    path.write_text(json.dumps({"start": "s", "kpois": ["a", "b"],
                                "coordinates": {"s": [1, 1], "a": [1, 1], "b": [1, 1]}}))
    from parcover import solve

    result = solve(load(path), "tours", robots=2)
    assert result.makespan == 0 and result.status.value == "optimal"
