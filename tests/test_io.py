"""Instance files: JSON (design.md section 2) and TSPLIB."""

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
    # design.md section 2, verbatim (the map block points at an image we need not open)
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
    ],
)
def test_bad_files_are_refused_with_one_line(name, message):
    with pytest.raises(FileFormatError, match=message) as info:
        load(BAD / name)
    assert str(info.value).startswith(str(BAD / name)) and "\n" not in str(info.value)


def test_bundled_instances_load():
    root = TSPLIB.parent
    files = sorted(root.glob("*.json")) + sorted(TSPLIB.glob("*.tsp"))
    assert len(files) >= 8
    for path in files:
        assert isinstance(load(path), Instance)
