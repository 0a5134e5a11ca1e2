"""Instances from floor-plan bitmaps (paper, Section VI and Fig. 4).

A bitmap is read as free space (white) and walls (black; grey "unknown" pixels count
as walls), the walls are inflated by the robot radius, the free space is traced into
a polygon, KPOIs are sampled in it (or given), and a graph is built over it in one of
two ways:

``"decomposition"``
    The paper's construction: the corners of the obstacles, a vertical cell
    decomposition from every corner, one virtual node in the middle of each boundary
    between two cells, and straight edges inside each cell (cells are convex).
``"visibility"``
    The visibility graph over the reflex corners of the free space: its shortest
    paths are the true shortest paths among the (polygonal) obstacles.

Axis convention (as ROS ``map_server`` and Stage): world ``x`` grows to the right and
world ``y`` upwards, while image rows grow downwards. ``origin`` is the world position
of the lower-left corner of the bitmap, i.e. of the outer corner of the bottom-left
pixel, so the map covers ``[ox, ox + W sx] x [oy, oy + H sy]``. Pixel ``(row, col)``
has its centre at ``(ox + (col + 0.5) sx, oy + (H - row - 0.5) sy)``.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from typing import Literal, Sequence

import numpy as np
import shapely
from scipy import ndimage
from shapely.geometry import LinearRing, LineString, MultiPolygon, Point, Polygon
from shapely.geometry.polygon import orient
from shapely.ops import polygonize, unary_union

from parcover.instance import Instance, InstanceError, MapInfo, check_whole
from parcover.memory import check_memory, instance_footprint, map_bytes

__all__ = [
    "FreeSpace",
    "MapError",
    "read_free_mask",
    "free_space",
    "sample_kpois",
    "decomposition_edges",
    "visibility_edges",
    "instance_from_map",
    "distance_ratio",
]

GraphMethod = Literal["decomposition", "visibility"]
XY = tuple[float, float]


class MapError(InstanceError):
    """A map, or a position on it, that cannot make an instance (one-line message)."""


@dataclass(frozen=True)
class FreeSpace:
    """The free space of a map, in world coordinates.

    Attributes
    ----------
    mask
        Boolean image, True where a robot centre may be (walls inflated).
    polygon
        The traced free space (walls simplified to polygons), every piece.
    scale
        Metres per pixel ``(sx, sy)``.
    origin
        World position of the lower-left corner of the bitmap.
    """

    mask: np.ndarray
    polygon: Polygon | MultiPolygon
    scale: XY
    origin: XY

    def to_pixel(self, xy: Sequence[float]) -> tuple[int, int]:
        """``(row, col)`` of the pixel holding world point ``xy`` (may be off the image)."""
        (sx, sy), (ox, oy) = self.scale, self.origin
        col = math.floor((xy[0] - ox) / sx)
        row = self.mask.shape[0] - 1 - math.floor((xy[1] - oy) / sy)
        return row, col

    def pixel_centres(self, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
        """World coordinates of pixel centres, an ``(m, 2)`` array."""
        (sx, sy), (ox, oy) = self.scale, self.origin
        h = self.mask.shape[0]
        return np.column_stack([ox + (cols + 0.5) * sx, oy + (h - rows - 0.5) * sy])

    def piece_containing(self, xy: Sequence[float]) -> Polygon | None:
        """The connected piece of :attr:`polygon` that contains ``xy``, if any."""
        p = Point(xy)
        for piece in getattr(self.polygon, "geoms", [self.polygon]):
            if piece.covers(p):
                return piece
        return None


def read_free_mask(image: str | os.PathLike[str] | np.ndarray) -> np.ndarray:
    """Free pixels of a bitmap: True for white, False for black and grey (unknown).

    ``image`` is a file (read with matplotlib, any colour mode) or an array of grey
    levels in ``[0, 1]`` or ``[0, 255]``.

    Raises
    ------
    MapError
        For a missing or unreadable file, or more pixels than Pillow decodes
        (``PIL.Image.MAX_IMAGE_PIXELS``: a possible decompression bomb).
    parcover.memory.MemoryLimitError
        Before decoding, when turning the image into an instance would take more
        memory than there is (:func:`parcover.memory.map_bytes`, from the file's header).
    """
    if isinstance(image, np.ndarray):
        if image.ndim not in (2, 3) or not image.size:
            raise MapError(f"An image array has rows, columns and maybe colour bands, not shape {image.shape}.")
        height, width, bands = *image.shape[:2], image.shape[2] if image.ndim == 3 else 1
        check_memory(map_bytes(height, width, bands), f"A map of {width} x {height} pixels")
        a = image.astype(float)
        if a.max() > 1.0:
            a = a / 255.0
    else:
        import matplotlib.image as mpimg

        height, width, bands = _image_header(image)
        check_memory(map_bytes(height, width, bands), f"{image} ({width} x {height} pixels)")
        try:
            a = np.asarray(mpimg.imread(os.fspath(image)), dtype=float)
        except (OSError, ValueError) as exc:  # PIL's UnidentifiedImageError is an OSError
            raise MapError(f"{image}: not a readable image ({exc}).") from None
    if a.ndim == 3:
        a = a[..., :3].mean(axis=2)
    return a > 0.9


def _image_header(image: str | os.PathLike[str]) -> tuple[int, int, int]:
    """Height, width and colour bands (after matplotlib's conversion) of an image file,
    from its header: Pillow opens lazily, nothing is decoded."""
    import warnings

    from PIL import Image

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", Image.DecompressionBombWarning)
            with Image.open(os.fspath(image)) as im:
                width, height = im.size
                bands = 4 if im.mode == "P" else len(im.getbands())  # palettes become RGBA
    except FileNotFoundError:
        raise MapError(f"{image}: no such image file.") from None
    except (Image.DecompressionBombError, Image.DecompressionBombWarning) as exc:
        raise MapError(f"{image}: refused as a possible decompression bomb: {exc}") from None
    except (OSError, ValueError) as exc:  # PIL's UnidentifiedImageError is an OSError
        raise MapError(f"{image}: not a readable image ({exc}).") from None
    return height, width, bands


def _scale_pair(metres_per_pixel: float | Sequence[float]) -> XY:
    if isinstance(metres_per_pixel, (int, float)):
        sx = sy = float(metres_per_pixel)
    else:
        sx, sy = (float(v) for v in metres_per_pixel)
    if not (sx > 0 and sy > 0 and math.isfinite(sx) and math.isfinite(sy)):
        raise MapError(f"metres_per_pixel must be positive, got {metres_per_pixel!r}.")
    return sx, sy


def _scale_value(scale: XY) -> float | XY:
    """One number when both axes share the scale, else the pair."""
    return scale[0] if scale[0] == scale[1] else scale


def free_space(
    image: str | os.PathLike[str] | np.ndarray,
    metres_per_pixel: float | Sequence[float],
    *,
    robot_radius: float = 0.0,
    origin: Sequence[float] = (0.0, 0.0),
    tolerance: float = 0.75,
) -> FreeSpace:
    """Free space of a bitmap: inflated wall mask and its polygon in world coordinates.

    Walls are inflated by ``robot_radius`` (metres; a pixel is free when its centre is
    farther than that from every wall pixel centre and the image border). The free
    pixels are traced with marching squares (``skimage.measure.find_contours``) along
    pixel edges, and the rings simplified (Douglas-Peucker, ``tolerance`` pixels).
    """
    from skimage import measure

    sx, sy = _scale_pair(metres_per_pixel)
    ox, oy = float(origin[0]), float(origin[1])
    free = read_free_mask(image)
    if robot_radius < 0:
        raise MapError(f"robot_radius must be non-negative, got {robot_radius!r}.")
    padded = np.pad(free, 1, constant_values=False)
    if robot_radius > 0:
        clearance = ndimage.distance_transform_edt(padded, sampling=(sy, sx))
        padded = clearance > robot_radius
    mask = padded[1:-1, 1:-1].copy()
    mask.flags.writeable = False
    h = mask.shape[0]
    rings = []
    for contour in measure.find_contours(padded.astype(float), 0.5, fully_connected="low"):
        rows, cols = contour[:, 0] - 1, contour[:, 1] - 1
        xy = np.column_stack([ox + (cols + 0.5) * sx, oy + (h - rows - 0.5) * sy])
        if len(xy) >= 4:
            ring = Polygon(xy)
            if ring.area > 0:
                rings.append(ring)
    region = _even_odd_region(rings)
    region = shapely.make_valid(region.simplify(tolerance * min(sx, sy), preserve_topology=True))
    polys = [g for g in getattr(region, "geoms", [region]) if isinstance(g, Polygon) and g.area > 0]
    polygon = MultiPolygon([orient(p) for p in polys])
    return FreeSpace(mask=mask, polygon=polygon, scale=(sx, sy), origin=(ox, oy))


def _even_odd_region(rings: list[Polygon]) -> MultiPolygon:
    """The region inside an odd number of ``rings``, which neither cross nor touch.

    A ring inside an even number of others (0, 2, ...) is a shell, and a ring inside
    an odd number is a hole of the ring just around it: one spatial-index query
    (prepared rings against a vertex of each ring) instead of an overlay per ring.
    """
    if not rings:
        return MultiPolygon()
    tree = shapely.STRtree(shapely.points([r.exterior.coords[0] for r in rings]))
    outer, inner = tree.query(rings, predicate="contains")
    depth = np.bincount(inner, minlength=len(rings))
    holes: dict[int, list[LinearRing]] = {i: [] for i in np.flatnonzero(depth % 2 == 0).tolist()}
    for i, j in zip(inner.tolist(), outer.tolist()):
        if depth[i] % 2 == 1 and depth[j] == depth[i] - 1:
            holes[j].append(rings[i].exterior)
    return MultiPolygon([Polygon(rings[i].exterior, h) for i, h in holes.items()])


def _check_position(space: FreeSpace, piece: Polygon | None, xy: Sequence[float], what: str) -> None:
    """Refuse a user-given position in a wall or out of the start's reach."""
    row, col = space.to_pixel(xy)
    h, w = space.mask.shape
    where = f"({xy[0]:g}, {xy[1]:g})"
    if not (0 <= row < h and 0 <= col < w):
        raise MapError(f"The {what} at {where} is outside the map.")
    if not space.mask[row, col] or space.piece_containing(xy) is None:
        raise MapError(f"The {what} at {where} is in a wall (or closer to one than the robot radius).")
    if piece is not None and not piece.covers(Point(xy)):
        raise MapError(f"The {what} at {where} cannot be reached from the start.")


def _free_pixels_inside(space: FreeSpace, piece: Polygon) -> tuple[np.ndarray, np.ndarray]:
    """Rows and columns of the free pixels whose centres lie inside ``piece``, in row-major order.

    Only the pixels within two of the piece's boundary are tested one by one
    (``shapely.contains_xy``). The others form 4-connected areas that the boundary
    does not cross (it passes no closer than a pixel to their centres), so one pixel
    decides for each area.
    """
    (sx, sy), (ox, oy) = space.scale, space.origin
    h, w = space.mask.shape
    # Boundary points at most a pixel apart on each axis: every boundary point is within
    # half a pixel of one, so a pixel whose centre is within a pixel of the boundary is
    # within two rows and two columns of a sample's pixel.
    samples = shapely.get_coordinates(shapely.segmentize(piece.boundary, min(sx, sy)))
    rows = np.clip(np.floor(h - (samples[:, 1] - oy) / sy).astype(int), 0, h - 1)
    cols = np.clip(np.floor((samples[:, 0] - ox) / sx).astype(int), 0, w - 1)
    top, left = rows.min(), cols.min()  # the piece lies in the boundary's bounding box
    near = np.zeros((rows.max() - top + 1, cols.max() - left + 1), dtype=bool)
    near[rows - top, cols - left] = True
    near = ndimage.maximum_filter(near, size=5)
    free = space.mask[top : top + near.shape[0], left : left + near.shape[1]]
    inside = np.zeros_like(free)
    rows, cols = np.nonzero(free & near)
    xy = space.pixel_centres(rows + top, cols + left)
    inside[rows, cols] = shapely.contains_xy(piece, xy[:, 0], xy[:, 1])
    areas, count = ndimage.label(free & ~near)
    one_pixel = np.empty(count + 1, dtype=np.intp)  # of each area (whichever write lands last)
    one_pixel[areas.ravel()] = np.arange(areas.size)
    rows, cols = np.divmod(one_pixel[1:], free.shape[1])
    xy = space.pixel_centres(rows + top, cols + left)
    area_inside = np.zeros(count + 1, dtype=bool)
    area_inside[1:] = shapely.contains_xy(piece, xy[:, 0], xy[:, 1])
    inside |= area_inside[areas]
    rows, cols = np.nonzero(inside)
    return rows + top, cols + left


def sample_kpois(space: FreeSpace, n: int, start: XY, *, seed: int = 0) -> list[XY]:
    """``n`` distinct random pixel centres in the free space reachable from ``start``.

    The start's own position is never drawn.

    As in the paper (Section VI), positions outside the layout, in a wall, or in a
    part the start cannot reach are discarded.
    """
    piece = space.piece_containing(start)
    if piece is None:
        raise MapError(f"The start at ({start[0]:g}, {start[1]:g}) is in a wall.")
    rows, cols = _free_pixels_inside(space, piece)
    row, col = space.to_pixel(start)
    if (space.pixel_centres(np.array([row]), np.array([col])) == start).all():  # the start's own pixel
        keep = (rows != row) | (cols != col)
        rows, cols = rows[keep], cols[keep]
    if len(rows) < n:
        raise MapError(f"Only {len(rows)} free pixels are reachable from the start; asked for {n} KPOIs.")
    rng = np.random.default_rng(seed)
    chosen = rng.choice(len(rows), size=n, replace=False)
    return [(float(x), float(y)) for x, y in space.pixel_centres(rows[chosen], cols[chosen])]


def _random_start(space: FreeSpace, seed: int) -> XY:
    """A random free pixel centre in the largest piece of free space."""
    if not space.polygon.geoms:
        raise MapError("The map has no free space.")
    largest = max(space.polygon.geoms, key=lambda p: p.area)
    rows, cols = _free_pixels_inside(space, largest)
    if not len(rows):  # a free area of a pixel or two, whose traced outline holds no pixel centre
        raise MapError("The map's free space is too small to stand in: no free pixel lies inside its traced outline.")
    rng = np.random.default_rng([seed, 1])
    i = rng.integers(len(rows))
    x, y = space.pixel_centres(rows[i : i + 1], cols[i : i + 1])[0]
    return float(x), float(y)


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """z component of the cross product of rows of two ``(m, 2)`` arrays."""
    return a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]


def _reflex_corners(piece: Polygon) -> np.ndarray:
    """Reflex vertices of the free space (the corners of the obstacles), ``(m, 6)``.

    Each row is the vertex then its previous and next vertex along the ring. The piece
    is oriented with the free space on the left of every ring, so a reflex vertex is a
    right turn.
    """
    out = []
    for ring in (piece.exterior, *piece.interiors):
        pts = np.asarray(ring.coords)[:-1]
        prev, nxt = np.roll(pts, 1, axis=0), np.roll(pts, -1, axis=0)
        turn = _cross(pts - prev, nxt - pts)
        keep = turn < 0
        out.append(np.hstack([pts[keep], prev[keep], nxt[keep]]))
    return np.vstack(out) if out else np.empty((0, 6))


def _segments_free(piece: Polygon, a: np.ndarray, b: np.ndarray, eps: float) -> np.ndarray:
    """Which straight segments ``a[i] -> b[i]`` lie in the free space (within ``eps``).

    A segment in the free space has every point in it: points along each segment
    (halves, quarters, eighths) are tested first, cheaply, and only the segments
    that pass are tested whole.
    """
    if len(a) == 0:
        return np.zeros(0, dtype=bool)
    grown = piece.buffer(eps)
    shapely.prepare(grown)
    free = np.ones(len(a), dtype=bool)
    for t in (0.5, 0.25, 0.75, 0.125, 0.375, 0.625, 0.875):
        p = a[free] + t * (b[free] - a[free])
        free[free] = shapely.intersects_xy(grown, p[:, 0], p[:, 1])
    free[free] = shapely.covers(grown, shapely.linestrings(np.stack([a[free], b[free]], axis=1)))
    return free


def visibility_edges(
    piece: Polygon, points: Sequence[XY], eps: float
) -> tuple[list[XY], list[tuple[int, int]]]:
    """Visibility graph over the reflex corners of ``piece`` and ``points``.

    Returns the corner coordinates and edges as index pairs over
    ``points + corners`` (points first). Corner-to-corner segments are kept only when
    they are tangent to the walls at both ends (the only ones a shortest path uses).

    Notes
    -----
    :math:`O(m^2)` candidate segments for :math:`m` corners, each tested against the
    prepared free polygon.
    """
    corners = _reflex_corners(piece)
    k, m = len(points), len(corners)
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    cxy = corners[:, :2]
    allxy = np.vstack([pts, cxy])
    pairs_i, pairs_j = np.triu_indices(k + m, k=1)
    # Tangency at corner ends: both neighbours on the same side of the line.
    ok = np.ones(len(pairs_i), dtype=bool)
    for end, other in ((pairs_i, pairs_j), (pairs_j, pairs_i)):
        is_corner = end >= k
        c = corners[end[is_corner] - k]
        d = allxy[other[is_corner]] - c[:, :2]
        s1 = _cross(d, c[:, 2:4] - c[:, :2])
        s2 = _cross(d, c[:, 4:6] - c[:, :2])
        ok[is_corner] &= s1 * s2 >= -1e-12
    pairs_i, pairs_j = pairs_i[ok], pairs_j[ok]
    free = _segments_free(piece, allxy[pairs_i], allxy[pairs_j], eps)
    edges = list(zip(pairs_i[free].tolist(), pairs_j[free].tolist()))
    return [(float(x), float(y)) for x, y in cxy], edges


def _vertical_cells(piece: Polygon) -> list[Polygon]:
    """Vertical cell decomposition of ``piece`` from every obstacle corner (convex cells).

    From each reflex vertex a vertical line is drawn up and down through the free
    space until it meets a wall (paper, Fig. 4, dashed lines).
    """
    corners = _reflex_corners(piece)
    miny, maxy = piece.bounds[1] - 1.0, piece.bounds[3] + 1.0
    overshoot = 1e-7 * (maxy - miny)
    cuts = []
    shapely.prepare(piece)
    for x, y in corners[:, :2]:
        chord = piece.intersection(LineString([(x, miny), (x, maxy)]))
        p = Point(x, y)
        for part in getattr(chord, "geoms", [chord]):
            if isinstance(part, LineString) and part.length > 0 and part.distance(p) < 1e-9 * (1 + abs(y)):
                # Ends computed by the intersection are only nearly on the walls: run
                # them a hair past so that noding splits the walls there.
                (_, y0), (_, y1) = sorted((part.coords[0], part.coords[-1]), key=lambda c: c[1])
                cuts.append(LineString([(x, y0 - overshoot), (x, y1 + overshoot)]))
    noded = unary_union([piece.boundary, *cuts])
    cells = [c for c in polygonize(noded) if piece.covers(c.representative_point())]
    return cells


def decomposition_edges(
    piece: Polygon, points: Sequence[XY]
) -> tuple[list[XY], list[tuple[int, int]], list[Polygon]]:
    """The paper's graph (Section VI, Fig. 4) over ``piece`` and ``points``.

    Virtual nodes sit at the midpoints of the boundaries shared by two cells; inside
    each (convex) cell its virtual nodes and the points in it are joined pairwise.

    Returns
    -------
    virtual, edges, cells
        Virtual node coordinates, edges as index pairs over ``points + virtual``, and
        the cells (for drawings).
    """
    cells = _vertical_cells(piece)
    tree = shapely.STRtree(cells)
    members: list[list[int]] = [[] for _ in cells]
    virtual: list[XY] = []
    k = len(points)
    left, right = tree.query(cells, predicate="touches")
    for a, b in zip(left.tolist(), right.tolist()):
        if a >= b:
            continue
        shared = cells[a].intersection(cells[b])
        shared = shapely.line_merge(shared) if not isinstance(shared, (Point, LineString)) else shared
        if isinstance(shared, LineString) and shared.length > 0:
            mid = shared.interpolate(0.5, normalized=True)
            members[a].append(k + len(virtual))
            members[b].append(k + len(virtual))
            virtual.append((mid.x, mid.y))
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    idx_pt, idx_cell = tree.query(shapely.points(pts), predicate="intersects")
    seen = set()
    for p, c in zip(idx_pt.tolist(), idx_cell.tolist()):
        if p not in seen:  # a point on a cell boundary joins the first cell found
            seen.add(p)
            members[c].append(p)
    missing = sorted(set(range(k)) - seen)
    if missing:
        raise MapError(f"Position {missing[0]} lies in no cell of the decomposition.")
    edges = sorted({(min(u, v), max(u, v)) for group in members for u in group for v in group if u != v})
    return virtual, edges, cells


def instance_from_map(
    image: str | os.PathLike[str],
    metres_per_pixel: float | Sequence[float],
    *,
    kpois: int | Sequence[Sequence[float]] = 10,
    seed: int = 0,
    start: Sequence[float] | None = None,
    graph: GraphMethod = "decomposition",
    robot_radius: float = 0.0,
    origin: Sequence[float] = (0.0, 0.0),
    name: str | None = None,
    tolerance: float = 0.75,
) -> Instance:
    """An instance over a floor-plan bitmap (paper, Section VI).

    Parameters
    ----------
    image
        Bitmap file: black walls, white free space, grey unknown (treated as wall).
    metres_per_pixel
        Scale, a number or an ``(x, y)`` pair.
    kpois
        Number of KPOIs to sample (seeded, uniform over the free pixels reachable
        from the start), or their world coordinates.
    seed
        Seed of the sampling (the start too when ``start`` is None).
    start
        World coordinates of the start; default a random free position in the
        largest part of the free space.
    graph
        ``"decomposition"`` (the paper's) or ``"visibility"`` (true shortest paths).
    robot_radius
        Metres by which the walls are inflated.
    origin
        World position of the lower-left corner of the bitmap (module docstring).
    name
        Instance name; default ``"<image stem>-<graph>"``.
    tolerance
        Simplification of the traced walls, in pixels.

    Returns
    -------
    Instance
        Start ``"s"``, KPOIs ``"1"``..``"N"``, virtual nodes ``"v1"``.., every node
        with coordinates, Euclidean edge weights in metres, and ``map`` set (its
        ``image`` is the absolute path of the bitmap).

    Raises
    ------
    MapError
        For a position in a wall, outside the map or unreachable from the start.
    """
    if graph not in ("decomposition", "visibility"):
        raise MapError(f"Unknown graph method {graph!r}; expected 'decomposition' or 'visibility'.")
    check_whole(seed, "seed", 0)
    space = free_space(image, metres_per_pixel, robot_radius=robot_radius, origin=origin, tolerance=tolerance)
    s: XY = _random_start(space, seed) if start is None else (float(start[0]), float(start[1]))
    if start is not None:
        _check_position(space, None, s, "start")
    piece = space.piece_containing(s)
    assert piece is not None
    if isinstance(kpois, (int, np.integer)):
        if kpois < 1:
            raise MapError(f"Expected at least one KPOI, got {kpois}.")
        positions = sample_kpois(space, int(kpois), s, seed=seed)
    else:
        positions = [(float(p[0]), float(p[1])) for p in kpois]
        for i, p in enumerate(positions, 1):
            _check_position(space, piece, p, f"KPOI {i}")
    points = [s, *positions]
    # at worst the free space is one convex cell and every pair of points is an edge
    check_memory(instance_footprint(len(positions), len(points), len(points) * len(positions) // 2).peak,
                 f"A map instance of {len(positions)} KPOIs")
    if graph == "visibility":
        extra, pairs = visibility_edges(piece, points, eps=1e-6 * min(space.scale))
    else:
        extra, pairs, _ = decomposition_edges(piece, points)
    ids = ["s", *(str(i) for i in range(1, len(positions) + 1))]
    ids += [f"v{i}" for i in range(1, len(extra) + 1)]
    xy = [*points, *extra]
    coordinates = {v: p for v, p in zip(ids, xy)}
    edges = tuple((ids[u], ids[v], math.dist(xy[u], xy[v])) for u, v in pairs)
    stem = os.path.splitext(os.path.basename(os.fspath(image)))[0]
    return Instance(
        "s",
        tuple(ids[1 : len(points)]),
        coordinates=coordinates,
        edges=edges,
        name=name if name is not None else f"{stem}-{graph}",
        map=MapInfo(
            image=os.path.abspath(image), metres_per_pixel=_scale_value(space.scale), origin=space.origin
        ),
    )


def distance_ratio(longer: Instance, shorter: Instance) -> dict[str, float]:
    """How much longer one instance's distances are than another's, over the same KPOIs.

    Typically ``longer`` is the ``"decomposition"`` instance and ``shorter`` the
    ``"visibility"`` one built with the same seed. Pairs at distance 0 in ``shorter``
    are skipped.

    Returns
    -------
    dict
        ``pairs`` (count), ``min``, ``mean``, ``median``, ``p95``, ``max`` of
        ``d_longer / d_shorter`` over all pairs of key nodes (start included).
    """
    if longer.ids != shorter.ids:
        raise InstanceError("The two instances must have the same start and KPOIs.")
    i, j = np.triu_indices(len(longer.ids), k=1)
    a, b = longer.distances[i, j], shorter.distances[i, j]
    keep = b > 0
    r = a[keep] / b[keep]
    if r.size == 0:
        return {"pairs": 0, "min": 1.0, "mean": 1.0, "median": 1.0, "p95": 1.0, "max": 1.0}
    return {
        "pairs": int(r.size),
        "min": float(r.min()),
        "mean": float(r.mean()),
        "median": float(np.median(r)),
        "p95": float(np.percentile(r, 95)),
        "max": float(r.max()),
    }
