"""Instances from bitmaps: parcover.maps (paper, Section VI)."""

import math
from pathlib import Path

import numpy as np
import pytest
import shapely

import parcover as pc
from parcover.maps import MapError, _free_pixels_inside, distance_ratio, free_space, instance_from_map, read_free_mask

DATA = Path(__file__).parent / "data"
MAPS = Path(__file__).parent.parent / "instances" / "maps"

# wall_gap.png, 40x20 px at 1 m/px, origin (0, 0): the map covers [0, 40] x [0, 20].
# A wall fills pixel columns 18..21 and rows 0..11, i.e. x in [18, 22], y in [8, 20]
# (rows grow downwards, y upwards); below it a gap y in [0, 8] joins the two halves.
# Marching squares cuts each pixel corner of the wall by half a pixel: the wall's
# lower corners become the chamfers (18, 8.5)-(18.5, 8) and (21.5, 8)-(22, 8.5).
WALL_GAP = DATA / "wall_gap.png"
# two_rooms.png, 40x20 px: the same wall down to the bottom, no gap.
TWO_ROOMS = DATA / "two_rooms.png"
A, B = (10.0, 15.0), (30.0, 15.0)


def wall_gap(graph, **kw):
    """Start at A, one KPOI at B, walls traced exactly (no simplification)."""
    return instance_from_map(WALL_GAP, 1.0, kpois=[B], start=A, graph=graph, tolerance=0.0, **kw)


def test_visibility_distance_around_the_wall_by_hand():
    # The shortest way from A to B hugs the chamfered corners (18.5, 8) and (21.5, 8):
    # the line from A = (10, 15) to (18.5, 8) has y = 15 - 7 (x - 10) / 8.5, which at
    # x = 18 is 8.41 (< 8.5, x + y = 26.41 < 26.5) so it passes under the chamfer's
    # other vertex (18, 8.5). Length 2 * hypot(8.5, 7) + 3 = 25.0227...
    inst = wall_gap("visibility")
    assert inst.distance("s", "1") == pytest.approx(2 * math.hypot(8.5, 7) + 3, abs=1e-9)
    assert [inst.coordinates[v] for v in inst.shortest_walk("s", "1")[1:-1]] == [(18.5, 8.0), (21.5, 8.0)]


def test_decomposition_distance_by_hand_and_not_shorter():
    # Cells: x <= 18, the sliver 18..18.5 under the chamfer, 18.5..21.5 under the wall,
    # the mirror sliver and x >= 22. Virtual nodes at the middle of each shared cut:
    # (18, 4.25) (cut y in [0, 8.5]), (18.5, 4), (21.5, 4), (22, 4.25).
    # A -> (18, 4.25): hypot(8, 10.75); (18, 4.25) -> (18.5, 4): hypot(0.5, 0.25);
    # then 3, then the mirror image.
    dec, vis = wall_gap("decomposition"), wall_gap("visibility")
    expected = 2 * math.hypot(8, 10.75) + 2 * math.hypot(0.5, 0.25) + 3
    assert dec.distance("s", "1") == pytest.approx(expected, abs=1e-9)
    assert dec.distance("s", "1") >= vis.distance("s", "1")


def test_ids_coordinates_map_and_edges_meet_design_section_2():
    inst = wall_gap("decomposition")
    assert inst.start == "s" and inst.kpois == ("1",)
    assert set(inst.virtual_nodes) == {f"v{i}" for i in range(1, len(inst.virtual_nodes) + 1)}
    assert set(inst.coordinates) == set(inst.nodes)
    for u, v, w in inst.edges:
        assert w >= math.dist(inst.coordinates[u], inst.coordinates[v]) * (1 - 1e-12)
    assert inst.map == pc.MapInfo(image=str(WALL_GAP), metres_per_pixel=1.0, origin=(0.0, 0.0))


@pytest.mark.parametrize("graph", ["decomposition", "visibility"])
def test_every_edge_stays_in_the_free_space(graph):
    space = free_space(MAPS / "simple_rooms.png", 0.05)
    inst = instance_from_map(MAPS / "simple_rooms.png", 0.05, kpois=12, seed=3, graph=graph)
    c = inst.coordinates
    lines = shapely.linestrings([[c[u], c[v]] for u, v, _ in inst.edges])
    assert shapely.covers(space.polygon.buffer(1e-6), lines).all()


def test_decomposition_never_beats_visibility_on_a_stage_map():
    args = (MAPS / "simple_rooms.png", 0.05)
    dec = instance_from_map(*args, kpois=12, seed=4, graph="decomposition")
    vis = instance_from_map(*args, kpois=12, seed=4, graph="visibility")
    stats = distance_ratio(dec, vis)
    assert stats["pairs"] == 13 * 12 // 2
    assert stats["min"] >= 1 - 1e-9
    assert stats["min"] <= stats["median"] <= stats["max"]


def test_sampled_kpois_avoid_the_inflated_walls():
    radius = 0.3  # metres: 6 pixels at 0.05 m/px
    space = free_space(MAPS / "simple_rooms.png", 0.05, robot_radius=radius)
    inst = instance_from_map(MAPS / "simple_rooms.png", 0.05, kpois=40, seed=7, robot_radius=radius)
    plain = free_space(MAPS / "simple_rooms.png", 0.05)
    assert space.mask.sum() < plain.mask.sum()  # the radius did inflate the walls
    for v in inst.ids:
        row, col = space.to_pixel(inst.coordinates[v])
        assert space.mask[row, col], v


def test_sampling_is_seeded():
    args = (MAPS / "simple_rooms.png", 0.05)
    one = instance_from_map(*args, kpois=5, seed=11)
    two = instance_from_map(*args, kpois=5, seed=11)
    other = instance_from_map(*args, kpois=5, seed=12)
    assert one.coordinates == two.coordinates
    assert one.coordinates != other.coordinates


def test_only_white_is_free():
    # Black wall, grey unknown (SRI-AIC-kwing.png uses 128), near-white, white.
    assert read_free_mask(np.array([[0, 128, 250, 255]])).tolist() == [[False, False, True, True]]


def test_anisotropic_scale_and_origin_place_pixels():
    # Pixel (row 19, col 0) is the bottom-left one: its centre is origin + half a pixel.
    space = free_space(WALL_GAP, (0.5, 2.0), origin=(100.0, -10.0))
    assert space.pixel_centres(np.array([19]), np.array([0])).tolist() == [[100.25, -9.0]]
    assert space.to_pixel((100.25, -9.0)) == (19, 0)


@pytest.mark.parametrize(
    "kpoi, message",
    [
        ((30.0, 15.0), "KPOI 1 at (30, 15) cannot be reached from the start."),  # other room
        ((20.0, 15.0), "KPOI 1 at (20, 15) is in a wall"),  # inside the wall
        ((50.0, 15.0), "KPOI 1 at (50, 15) is outside the map."),  # off the image
    ],
)
def test_bad_user_kpoi_is_refused_in_one_line(kpoi, message):
    with pytest.raises(pc.InputError) as err:
        instance_from_map(TWO_ROOMS, 1.0, kpois=[kpoi], start=A)
    assert message in str(err.value) and "\n" not in str(err.value)


def test_start_in_a_wall_is_refused():
    with pytest.raises(MapError, match="start at"):
        instance_from_map(TWO_ROOMS, 1.0, kpois=1, start=(20.0, 10.0))


def test_stage_map_instance_round_trips_and_solves(tmp_path):
    # cave.png is Stage's simple.world bitmap: 500 px over 16 m, 0.032 m/px.
    inst = instance_from_map(MAPS / "cave.png", 0.032, kpois=8, seed=2)
    path = tmp_path / "cave.json"
    pc.write_instance(inst, path)
    back = pc.read_instance(path)
    assert back.ids == inst.ids
    np.testing.assert_allclose(back.distances, inst.distances, rtol=1e-9)
    result = pc.solve(back, method="trivial")
    assert result.robots == 8
    assert result.makespan == pytest.approx(back.c_max)


def test_walls_inside_free_space_inside_walls_are_traced_as_shells_and_holes():
    # A 12x12 room (the image border is wall) holding a wall block (rows and columns
    # 2..9), in it a free island (4..7), in that a wall pillar (5..6): two pieces of
    # free space, the room with the block as its hole and the island with the pillar.
    image = np.full((12, 12), 255)
    image[2:10, 2:10] = 0
    image[4:8, 4:8] = 255
    image[5:7, 5:7] = 0
    space = free_space(image, 1.0, tolerance=0.0)
    room, island = sorted(space.polygon.geoms, key=lambda p: -p.area)
    assert (len(room.interiors), len(island.interiors)) == (1, 1)
    # pixel (row r, column c) has its centre at (c + 0.5, 11.5 - r)
    assert room.contains(shapely.Point(0.5, 11.5)) and not room.contains(shapely.Point(3.5, 8.5))
    assert island.contains(shapely.Point(4.5, 7.5)) and not island.contains(shapely.Point(5.5, 6.5))


def test_free_pixels_inside_a_piece_are_those_whose_centres_it_contains():
    # Only pixels near the outline are tested one by one; the rest by one pixel per
    # area: the same pixels as testing every free pixel (anisotropic scale, inflated walls).
    space = free_space(MAPS / "cave.png", (0.03, 0.04), robot_radius=0.1)
    rows, cols = np.nonzero(space.mask)
    xy = space.pixel_centres(rows, cols)
    for piece in space.polygon.geoms:
        expected = xy[shapely.contains_xy(piece, xy[:, 0], xy[:, 1])]
        np.testing.assert_array_equal(space.pixel_centres(*_free_pixels_inside(space, piece)), expected)


@pytest.mark.parametrize("graph", ["decomposition", "visibility"])
def test_a_convex_room_without_corners_joins_every_pair_straight(graph, tmp_path):
    # sal2.png's rooms have no doors: a start in one sees a convex piece of free space
    # with no obstacle corner, and the visibility graph had no corner to index (IndexError).
    from PIL import Image

    room = tmp_path / "room.png"
    Image.fromarray(np.full((10, 20), 255, dtype=np.uint8)).save(room)  # the image border is the wall
    inst = instance_from_map(room, 1.0, kpois=5, seed=0, graph=graph)
    assert not inst.virtual_nodes and len(inst.edges) == 6 * 5 // 2
    for u, v in zip(*np.triu_indices(6, k=1)):
        a, b = inst.ids[u], inst.ids[v]
        assert inst.distance(a, b) == pytest.approx(math.dist(inst.coordinates[a], inst.coordinates[b]))
