"""The coverage instance: start, KPOIs, and the metric between them.

An :class:`Instance` is validated once, on construction, and is read-only afterwards:
its arrays are not writeable and :meth:`Instance.replace` makes a modified copy.

The metric is the shortest-path distance (the metric closure, docs/format.md section 1)
between the start and the KPOIs:

- with ``edges``, shortest paths in that undirected graph, whose other nodes are the
  paper's *virtual nodes* (Definition 3); predecessor data is kept so that a route
  can be expanded into the physical walk through virtual nodes (:meth:`Instance.walk`);
- without ``edges``, the complete graph over ``coordinates`` with exact Euclidean
  weights, or TSPLIB's rounded ``nint`` weights when ``metric="tsplib"``.

Index convention used by every algorithm: index 0 is the start and index ``i`` (1..n)
is ``kpois[i - 1]``; :attr:`Instance.distances` is the ``(n + 1) x (n + 1)`` matrix.

Numbers are real numbers (Python's or numpy's, never booleans or strings) whose
float value is finite. The distances they give must be usable by every method: the
largest is at least :data:`MIN_SCALE` (costs are compared with an absolute tolerance
of 1e-9, docs/format.md section 1) or 0, and the cost of any route and its square are
finite floats (a route costs at most ``2 (n + 1)`` times the largest distance; the
heuristics combine costs, and ``best`` failed on coordinates near 1e200). An instance
whose distance matrix would not fit in the memory available is refused before it is
allocated (:mod:`parcover.memory`).
"""

from __future__ import annotations

import dataclasses
import math
import numbers
import warnings
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from parcover.errors import InputError
from parcover.memory import check_memory, instance_footprint

if TYPE_CHECKING:
    import scipy.sparse as sp

__all__ = ["Instance", "InstanceError", "MapInfo", "ShortEdgeWarning", "Metric", "MIN_SCALE"]

#: The largest distance of an instance, when not 0, must be at least this: costs are
#: compared with an absolute tolerance of 1e-9 (docs/format.md section 1), which must stay
#: below a millionth of them.
MIN_SCALE = 1e-3

Metric = Literal["euclidean", "tsplib"]
Point = tuple[float, float]


class InstanceError(InputError):
    """Bad instance data. The message is one sentence naming the problem."""


class ShortEdgeWarning(UserWarning):
    """An edge is shorter than the straight line between its end coordinates.

    docs/format.md section 2 says coordinates and weights share one unit, so this hints at
    mixed units; the instance is still usable.
    """


@dataclass(frozen=True)
class MapInfo:
    """A background image for drawings (docs/format.md section 2, the ``map`` block).

    Parameters
    ----------
    image
        Path of the bitmap, relative to the instance file when read from one.
    metres_per_pixel
        Scale of one pixel; a pair ``(x, y)`` when the axes differ (Stage stretches
        bitmaps per axis).
    origin
        World position of pixel (0, 0).
    """

    image: str
    metres_per_pixel: float | tuple[float, float] = 1.0
    origin: Point = (0.0, 0.0)


@dataclass(frozen=True, eq=False)
class Instance:
    """A parallel coverage instance, validated on construction and read-only after.

    Parameters
    ----------
    start
        Id of the start node ``s`` shared by every robot.
    kpois
        Ids of the key positions of interest, in a fixed order (ties in every
        algorithm are broken by this order). Listing the start is allowed: it is
        covered at time 0, so it is removed from :attr:`kpois` and
        :attr:`start_is_kpoi` is set.
    coordinates
        Optional positions by id (any node, virtual ones included). Required for the
        start and every KPOI when there are no ``edges``.
    edges
        Optional undirected edges ``(u, v, weight)``; ``(u, v)`` takes the Euclidean
        distance between the coordinates of ``u`` and ``v`` (rounded under the
        ``tsplib`` metric). Parallel edges keep the lightest.
    name
        Instance name, reported in results.
    map
        Optional background image for drawings.
    metric
        How coordinates become weights: ``"euclidean"`` (exact, the default) or
        ``"tsplib"`` (TSPLIB's ``nint`` rounding; the metric closure of the rounded
        complete graph is then used, since rounding can break the triangle
        inequality).
    start_is_kpoi
        Set when the start was listed among the KPOIs.

    Raises
    ------
    InstanceError
        On any inconsistency, with a one-line message.
    """

    start: str
    kpois: tuple[str, ...]
    coordinates: Mapping[str, Point] | None = None
    edges: tuple[tuple[str, str, float], ...] | None = None
    name: str = ""
    map: MapInfo | None = None
    metric: Metric = "euclidean"
    start_is_kpoi: bool = False

    distances: np.ndarray = field(init=False, repr=False)
    _index: Mapping[str, int] = field(init=False, repr=False)
    _nodes: tuple[str, ...] = field(init=False, repr=False)
    _key_nodes: np.ndarray = field(init=False, repr=False)
    _key_row_of_node: np.ndarray | None = field(init=False, repr=False)
    _predecessors: np.ndarray | None = field(init=False, repr=False)

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        start = _check_id(self.start, "start")
        kpois = _check_kpois(self.kpois, start)
        start_is_kpoi = self.start_is_kpoi or start in kpois
        kpois = tuple(k for k in kpois if k != start)
        if not kpois:
            raise InstanceError("Expected at least one KPOI other than the start.")
        if self.metric not in ("euclidean", "tsplib"):
            raise InstanceError(f"Unknown metric {self.metric!r}; expected 'euclidean' or 'tsplib'.")
        coordinates = _check_coordinates(self.coordinates)
        key = (start, *kpois)
        set_(self, "start", start)
        set_(self, "kpois", kpois)
        set_(self, "start_is_kpoi", start_is_kpoi)
        set_(self, "coordinates", coordinates)
        set_(self, "name", str(self.name or ""))
        set_(self, "_index", MappingProxyType({v: i for i, v in enumerate(key)}))

        if self.edges is None:
            missing = [v for v in key if coordinates is None or v not in coordinates]
            if missing:
                role = "start" if missing[0] == start else "KPOI"
                raise InstanceError(
                    f"Missing coordinates for {role} {missing[0]!r} (needed when there are no edges)."
                )
            xy = np.array([coordinates[v] for v in key], dtype=float)
            pairs = len(key) * (len(key) - 1) // 2 if self.metric == "tsplib" else 0  # rounded weights as edges
            check_memory(instance_footprint(len(kpois), edges=pairs).peak, f"An instance of {len(kpois)} KPOIs")
            if self.metric == "euclidean":
                set_(self, "edges", None)
                set_(self, "_nodes", key)
                set_(self, "_key_nodes", _readonly(np.arange(len(key))))
                set_(self, "_key_row_of_node", None)
                set_(self, "_predecessors", None)
                set_(self, "distances", _readonly(_check_scale(_euclidean_matrix(xy), len(kpois))))
                return
            # TSPLIB rounding: the complete graph of rounded weights, then its closure.
            i, j = np.triu_indices(len(key), k=1)
            with np.errstate(over="ignore"):
                weights = _check_scale(_tsplib_round(np.hypot(*(xy[i] - xy[j]).T)), len(kpois))
            edges = tuple(zip([key[a] for a in i], [key[b] for b in j], weights.tolist()))
        else:
            edges = _check_edges(self.edges, coordinates, self.metric)
            set_(self, "edges", edges)
        self._build_graph_metric(key, edges)

    # -- construction helpers ------------------------------------------------------

    def _build_graph_metric(
        self, key: tuple[str, ...], edges: tuple[tuple[str, str, float], ...]
    ) -> None:
        """Shortest paths from the start and every KPOI over the edge graph."""
        from scipy.sparse.csgraph import dijkstra  # scipy takes a while to load: only graphs need it

        nodes: dict[str, int] = {}
        for u, v, _ in edges:
            nodes.setdefault(u, len(nodes))
            nodes.setdefault(v, len(nodes))
        for v in key:
            if v not in nodes:
                role = "start" if v == self.start else "KPOI"
                raise InstanceError(f"The {role} {v!r} is in no edge.")
        m = len(edges)
        rows = np.fromiter((nodes[u] for u, _, _ in edges), dtype=np.int64, count=m)
        cols = np.fromiter((nodes[v] for _, v, _ in edges), dtype=np.int64, count=m)
        weights = np.fromiter((w for _, _, w in edges), dtype=float, count=m)
        _check_path_sums(weights, len(nodes))
        check_memory(instance_footprint(len(key) - 1, len(nodes), m).peak,
                     f"An instance of {len(key) - 1} KPOIs and {len(nodes)} nodes")
        graph = _lightest_edge_graph(rows, cols, weights, len(nodes))
        key_nodes = np.array([nodes[v] for v in key], dtype=np.int64)
        dist, pred = dijkstra(graph, directed=False, indices=key_nodes, return_predecessors=True)
        unreachable = np.flatnonzero(~np.isfinite(dist[0, key_nodes]))
        if unreachable.size:
            raise InstanceError(
                f"KPOI {key[unreachable[0]]!r} is unreachable from the start {self.start!r}."
            )
        d = dist[:, key_nodes]
        set_ = object.__setattr__
        set_(self, "distances", _readonly(_check_scale(np.minimum(d, d.T), len(key) - 1)))
        set_(self, "_nodes", tuple(nodes))
        key_row = np.full(len(nodes), -1, dtype=np.int64)
        key_row[key_nodes] = np.arange(len(key_nodes))
        set_(self, "_key_nodes", _readonly(key_nodes))
        set_(self, "_key_row_of_node", _readonly(key_row))
        set_(self, "_predecessors", _readonly(pred.astype(np.int32)))

    @classmethod
    def from_points(
        cls,
        points: Sequence[Sequence[float]] | np.ndarray,
        start: int = 0,
        *,
        names: Sequence[str] | None = None,
        name: str = "",
        metric: Metric = "euclidean",
    ) -> Instance:
        """A complete Euclidean instance from points in the plane.

        Row ``start`` of ``points`` is the start; every other row is a KPOI. Ids are
        ``names`` if given, else the row numbers as strings.

        Examples
        --------
        >>> inst = Instance.from_points([[0, 0], [3, 4], [0, 1]])
        >>> inst.kpois, float(inst.c_max)
        (('1', '2'), 5.0)
        """
        try:
            xy = np.asarray(points, dtype=float)
        except (TypeError, ValueError, OverflowError):
            raise InstanceError("Points must be numbers: an (m, 2) array of x, y.") from None
        if xy.ndim != 2 or xy.shape[1] != 2:
            raise InstanceError(f"Expected points of shape (m, 2), got shape {xy.shape}.")
        ids = [str(i) for i in range(len(xy))] if names is None else [str(v) for v in names]
        if len(ids) != len(xy):
            raise InstanceError(f"Expected {len(xy)} names, got {len(ids)}.")
        duplicate = _first_duplicate(ids)
        if duplicate is not None:
            raise InstanceError(f"Duplicate name {duplicate!r} in names.")
        if not is_whole(start):
            raise InstanceError(f"The start must be a row number, got {start!r}.")
        if not 0 <= start < len(xy):
            raise InstanceError(f"Start row {start} is out of range for {len(xy)} points.")
        coordinates = {v: (float(x), float(y)) for v, (x, y) in zip(ids, xy)}
        kpois = tuple(v for i, v in enumerate(ids) if i != start)
        return cls(ids[start], kpois, coordinates=coordinates, name=name, metric=metric)

    @classmethod
    def from_matrix(
        cls,
        matrix: Sequence[Sequence[float]] | np.ndarray,
        start: int = 0,
        kpois: Iterable[int] | None = None,
        ids: Sequence[str] | None = None,
        *,
        name: str = "",
    ) -> Instance:
        """An instance from a symmetric distance matrix, as OR-Tools and PyVRP take one.

        Parameters
        ----------
        matrix
            Square, symmetric, non-negative and finite, with a zero diagonal (a numpy
            array or nested lists). Entry ``[i, j]`` is the cost of travelling
            between nodes ``i`` and ``j`` directly; travel between two nodes takes
            the cheapest way, so a matrix breaking the triangle inequality is
            closed by shortest paths.
        start
            Index of the start node; default 0.
        kpois
            Indices of the KPOIs; default every node but the start. Nodes that are
            neither the start nor a KPOI are virtual nodes (paper, Definition 3):
            robots may pass through them.
        ids
            Node ids, one string per row; default the row numbers as strings (as
            :meth:`from_points`).
        name
            Instance name.

        Raises
        ------
        InstanceError
            One sentence naming the problem: a matrix that is not square, not
            numeric, not finite, negative, with a non-zero diagonal or not symmetric
            (parcover handles symmetric distances only); a start or KPOI index out of
            range; duplicate or missing ids.

        Examples
        --------
        >>> inst = Instance.from_matrix([[0, 2, 5], [2, 0, 1], [5, 1, 0]])
        >>> inst.kpois, float(inst.distance("0", "2"))
        (('1', '2'), 3.0)
        """
        m = _check_matrix(matrix)
        size = len(m)
        labels = [str(i) for i in range(size)] if ids is None else _check_ids(ids, size)
        start = _check_row(start, size, "start")
        if kpois is None:
            rows = [i for i in range(size) if i != start]
        elif isinstance(kpois, (str, bytes)) or not isinstance(kpois, Iterable):
            raise InstanceError(f"kpois must be a list of row numbers, got {short_repr(kpois)}.")
        else:
            rows = [_check_row(k, size, "KPOI") for k in kpois]
        i, j = np.triu_indices(size, k=1)
        edges = tuple(zip([labels[a] for a in i], [labels[b] for b in j], m[i, j].tolist()))
        return cls(labels[start], tuple(labels[k] for k in rows), edges=edges, name=name)

    @classmethod
    def from_networkx(
        cls,
        graph: Any,
        start: Any,
        kpois: Iterable[Any],
        weight: str = "weight",
        *,
        pos: str = "pos",
        name: str = "",
    ) -> Instance:
        """An instance over a networkx graph; its other nodes are virtual nodes.

        Node ids are converted to strings. Edge weights come from the ``weight``
        attribute (Euclidean between ``pos`` attributes when it is missing); node
        coordinates from the ``pos`` attribute where present. ``kpois`` may be any
        iterable (a generator too). A directed graph is accepted only when it is an
        undirected one written twice: every edge has its reverse, of the same weight.
        """
        import networkx as nx

        if not isinstance(graph, nx.Graph):
            raise InstanceError(f"Expected a networkx graph, got {type(graph).__name__}.")
        if isinstance(kpois, str) or not isinstance(kpois, Iterable):
            raise InstanceError(f"kpois must be an iterable of graph nodes, got {kpois!r}.")
        kpois = list(kpois)
        if graph.is_directed():
            _check_symmetric(graph, weight)
        label = {v: str(v) for v in graph.nodes}
        if len(set(label.values())) != len(label):
            raise InstanceError("Graph node ids collide when converted to strings.")
        for v in (start, *kpois):
            if not _hashable(v) or v not in label:
                raise InstanceError(f"Node {v!r} is not in the graph.")
        coordinates = {
            label[v]: data[pos] for v, data in graph.nodes(data=True) if pos in data
        }
        edges = tuple(
            (label[u], label[v], data[weight]) if weight in data else (label[u], label[v])
            for u, v, data in graph.edges(data=True)
        )
        return cls(
            label[start],
            tuple(label[v] for v in kpois),
            coordinates=coordinates or None,
            edges=edges,  # type: ignore[arg-type]
            name=name or str(graph.graph.get("name", "")),
        )

    def replace(self, **changes: Any) -> Instance:
        """A copy with some constructor fields changed, validated afresh."""
        return dataclasses.replace(self, **changes)

    # -- the metric ----------------------------------------------------------------

    @property
    def n(self) -> int:
        """Number of KPOIs (the start excluded)."""
        return len(self.kpois)

    @property
    def ids(self) -> tuple[str, ...]:
        """``(start, *kpois)``: the id of each row of :attr:`distances`."""
        return (self.start, *self.kpois)

    def index(self, node: str) -> int:
        """Row of ``node`` in :attr:`distances` (0 for the start).

        Raises
        ------
        KeyError
            If ``node`` is neither the start nor a KPOI.
        """
        return self._index[node]

    def distance(self, u: str, v: str) -> float:
        """Shortest travel cost between two key nodes (start or KPOIs)."""
        return float(self.distances[self._index[u], self._index[v]])

    @property
    def c_max(self) -> float:
        """Distance from the start to the farthest KPOI (paper, Prop. 1).

        No path solution has a smaller makespan; no tour solution one below
        ``2 * c_max``.
        """
        return float(self.distances[0, 1:].max())

    @property
    def v_max(self) -> str:
        """The KPOI farthest from the start (Alg. 1 step 2); ties go to the first listed."""
        return self.kpois[int(np.argmax(self.distances[0, 1:]))]

    @property
    def P_max(self) -> tuple[str, ...]:  # noqa: N802 - the paper's name
        """KPOIs on the shortest path from the start to :attr:`v_max` (paper, Prop. 2).

        In the order the path meets them, ending with ``v_max``.
        """
        indices = self.kpoi_indices_on_shortest_path(self._index[self.v_max])
        return tuple(self.kpois[i - 1] for i in indices)

    def kpoi_indices_on_shortest_path(self, target: int) -> tuple[int, ...]:
        """KPOI indices met by the shortest path from the start to KPOI ``target``.

        In travel order, ending with ``target`` (Alg. 1 steps 3 and 5c: ``P_i`` is
        every KPOI on the path ``pi_si``). In a complete Euclidean instance the
        shortest path is the straight segment, which meets the KPOIs lying on it.
        """
        if self._key_row_of_node is None:
            return self._kpois_on_segment(target)
        rows = self._key_row_of_node[self._node_walk(0, target)[1:]]
        return tuple(int(r) for r in rows if r > 0)

    def _kpois_on_segment(self, target: int) -> tuple[int, ...]:
        """KPOIs ``k`` with ``d(s, k) + d(k, target) = d(s, target)``, by distance from s."""
        d = self.distances
        through = d[0, 1:] + d[1:, target]
        on = np.flatnonzero(through <= d[0, target] * (1 + 1e-12) + 1e-12) + 1
        on = on[(on != target) & (d[0, on] > 0)]
        return (*(int(k) for k in on[np.argsort(d[0, on], kind="stable")]), target)

    def shortest_walk(self, u: str, v: str) -> list[str]:
        """The nodes (virtual ones included) of a shortest path from ``u`` to ``v``."""
        walk = self._node_walk(self._index[u], self._index[v])
        return [self._nodes[w] for w in walk]

    def walk(self, route: Sequence[str]) -> list[str]:
        """The physical walk of a route: every node passed, virtual nodes included.

        Its cost (sum of edge weights along it) equals the route's cost.
        """
        if not route:
            return []
        walk = [route[0]]
        for u, v in zip(route, route[1:]):
            walk.extend(self.shortest_walk(u, v)[1:])
        return walk

    def _node_walk(self, i: int, j: int) -> list[int]:
        """Graph node numbers of the shortest path from key row ``i`` to key row ``j``."""
        if self._predecessors is None:
            return [i, j] if i != j else [i]
        source, target = int(self._key_nodes[i]), int(self._key_nodes[j])
        pred = self._predecessors[i]
        walk = [target]
        while walk[-1] != source:
            walk.append(int(pred[walk[-1]]))
        return walk[::-1]

    # -- graph views ---------------------------------------------------------------

    @property
    def nodes(self) -> tuple[str, ...]:
        """Every node of the map: start, KPOIs and virtual nodes."""
        return self._nodes

    @property
    def virtual_nodes(self) -> tuple[str, ...]:
        """Nodes that are neither the start nor a KPOI (paper, Definition 3)."""
        return tuple(v for v in self._nodes if v not in self._index)

    def to_networkx(self) -> Any:
        """The map as a networkx Graph.

        Nodes carry ``kind`` (``"start"``, ``"kpoi"`` or ``"virtual"``) and ``pos``
        when coordinates are known; edges carry ``weight``. Without edges, the
        complete graph with the metric's weights.
        """
        import networkx as nx

        g = nx.Graph(name=self.name)
        for v in self._nodes:
            kind = "start" if v == self.start else "kpoi" if v in self._index else "virtual"
            g.add_node(v, kind=kind)
            if self.coordinates is not None and v in self.coordinates:
                g.nodes[v]["pos"] = self.coordinates[v]
        if self.edges is not None:
            for u, v, w in self.edges:
                if not g.has_edge(u, v) or g.edges[u, v]["weight"] > w:
                    g.add_edge(u, v, weight=w)
        else:
            ids = self.ids
            for a in range(len(ids)):
                for b in range(a + 1, len(ids)):
                    g.add_edge(ids[a], ids[b], weight=float(self.distances[a, b]))
        return g

    def __repr__(self) -> str:
        kind = "graph" if self.edges is not None else self.metric
        return (
            f"Instance(name={self.name!r}, start={self.start!r}, n={self.n}, "
            f"metric={kind}, virtual_nodes={len(self._nodes) - self.n - 1})"
        )


# -- validation ------------------------------------------------------------------


def _check_id(value: Any, what: str) -> str:
    if not isinstance(value, str) or not value:
        raise InstanceError(f"The {what} must be a non-empty string id, got {value!r}.")
    return value


def _check_kpois(kpois: Any, start: str) -> tuple[str, ...]:
    if isinstance(kpois, str) or not isinstance(kpois, Iterable):
        raise InstanceError(f"kpois must be a list of string ids, got {kpois!r}.")
    seen: set[str] = set()
    out = []
    for v in kpois:
        _check_id(v, "KPOI id")
        if v in seen:
            raise InstanceError(f"Duplicate KPOI {v!r}.")
        seen.add(v)
        out.append(v)
    return tuple(out)


def _check_coordinates(coordinates: Any) -> Mapping[str, Point] | None:
    if coordinates is None:
        return None
    if not isinstance(coordinates, Mapping):
        raise InstanceError("coordinates must map ids to [x, y] pairs.")
    out: dict[str, Point] = {}
    for v, xy in coordinates.items():
        _check_id(v, "coordinate id")
        pair = isinstance(xy, (Sequence, np.ndarray)) and not isinstance(xy, (str, bytes)) and len(xy) == 2
        if not (pair and all(is_number(c) for c in xy)):
            raise InstanceError(f"Coordinates of {v!r} must be two numbers, got {short_repr(xy)}.")
        x, y = (_float(c, f"Coordinates of {v!r} have a", "coordinate") for c in xy)
        out[v] = (x, y)
    return MappingProxyType(out)


def _check_edges(
    edges: Any, coordinates: Mapping[str, Point] | None, metric: Metric
) -> tuple[tuple[str, str, float], ...]:
    if isinstance(edges, (str, bytes)) or not isinstance(edges, Iterable):
        raise InstanceError("edges must be a list of [u, v, weight] triples.")
    out = []
    short = None
    for number, edge in enumerate(edges):
        if isinstance(edge, (str, bytes)) or not isinstance(edge, Sequence) or len(edge) not in (2, 3):
            raise InstanceError(f"Edge {number} must be [u, v, weight] or [u, v], got {edge!r}.")
        u = _check_id(edge[0], f"first end of edge {number}")
        v = _check_id(edge[1], f"second end of edge {number}")
        if u == v:
            raise InstanceError(f"Edge {number} is a loop at {u!r}.")
        straight = _straight_line(u, v, coordinates)
        if len(edge) == 2:
            if straight is None:
                raise InstanceError(
                    f"Edge {number} [{u!r}, {v!r}] has no weight and its ends have no coordinates."
                )
            w = float(_tsplib_round(straight)) if metric == "tsplib" else straight
        else:
            w = edge[2]
            if not is_number(w):
                raise InstanceError(f"Edge {number} [{u!r}, {v!r}] has a non-numeric weight {short_repr(w)}.")
            w = _float(w, f"Edge {number} [{u!r}, {v!r}] has a", "weight")
            if w < 0:
                raise InstanceError(f"Edge {number} [{u!r}, {v!r}] has a negative weight {w}.")
            if metric == "euclidean" and straight is not None and w < straight * (1 - 1e-9) - 1e-9:
                short = short or (number, u, v, w, straight)
        out.append((u, v, w))
    if not out:
        raise InstanceError("edges is empty.")
    if short is not None:
        number, u, v, w, straight = short
        warnings.warn(
            f"Edge {number} [{u!r}, {v!r}] weighs {w:g}, less than the straight line "
            f"{straight:g} between its coordinates (mixed units?).",
            ShortEdgeWarning,
            stacklevel=4,
        )
    return tuple(out)


def is_number(x: Any) -> bool:
    """A real number, Python's or numpy's (``np.float32(2)``); booleans are not numbers here."""
    return isinstance(x, numbers.Real) and not isinstance(x, bool)


def is_whole(x: Any) -> bool:
    """An integer, Python's or numpy's (``np.int64(2)``); booleans are not."""
    return isinstance(x, numbers.Integral) and not isinstance(x, bool)


def finite_float(x: Any) -> float | None:
    """``float(x)`` for a real number ``x`` whose float is finite, else ``None``
    (``10**400`` has no float; ``nan`` and ``inf`` are not finite)."""
    if not is_number(x):
        return None
    try:
        value = float(x)
    except OverflowError:
        return None
    return value if math.isfinite(value) else None


def check_whole(value: Any, name: str, least: int) -> int:
    """``value`` as an ``int`` when it is a whole number >= ``least``, else :class:`InputError`."""
    if not is_whole(value) or value < least:
        raise InputError(f"{name} must be a whole number >= {least}, got {short_repr(value)}.")
    return int(value)


def _float(x: Any, subject: str, noun: str) -> float:
    """``float(x)`` for a real number ``x``, refusing what no finite float represents.

    Messages read "{subject} non-finite {noun} inf." and "{subject} {noun} too
    large for a float (...)."
    """
    try:
        value = float(x)
    except OverflowError:
        raise InstanceError(f"{subject} {noun} too large for a float ({short_repr(x)}).") from None
    if not math.isfinite(value):
        raise InstanceError(f"{subject} non-finite {noun} {value}.")
    return value


def short_repr(x: Any) -> str:
    """``repr(x)``, cut to a readable length (a 400-digit integer is not)."""
    text = repr(x)
    return text if len(text) <= 40 else f"{text[:20]}...({len(text)} characters)"


def _hashable(x: Any) -> bool:
    try:
        hash(x)
    except TypeError:
        return False
    return True


def _first_duplicate(values: Iterable[str]) -> str | None:
    seen: set[str] = set()
    for v in values:
        if v in seen:
            return v
        seen.add(v)
    return None


def _check_matrix(matrix: Any) -> np.ndarray:
    """A distance matrix as a float array: square, finite, non-negative, zero diagonal, symmetric."""
    try:
        m = np.asarray(matrix)
    except ValueError:  # ragged nested lists
        raise InstanceError(
            "The distance matrix must be a square table of numbers; its rows differ in length."
        ) from None
    if m.dtype.kind not in "iuf":
        raise InstanceError(f"The distance matrix must hold numbers, got entries of type {m.dtype}.")
    if m.ndim != 2 or m.shape[0] != m.shape[1]:
        raise InstanceError(f"Expected a square distance matrix, got shape {m.shape}.")
    m = m.astype(float)
    bad = np.argwhere(~np.isfinite(m))
    if bad.size:
        i, j = bad[0]
        raise InstanceError(f"The distance matrix has a non-finite entry {m[i, j]} at [{i}, {j}].")
    bad = np.argwhere(m < 0)
    if bad.size:
        i, j = bad[0]
        raise InstanceError(f"The distance matrix has a negative entry {m[i, j]:g} at [{i}, {j}].")
    bad = np.flatnonzero(np.diag(m))
    if bad.size:
        i = bad[0]
        raise InstanceError(f"The distance matrix must have a zero diagonal; entry [{i}, {i}] is {m[i, i]:g}.")
    bad = np.argwhere(~np.isclose(m, m.T, rtol=1e-9, atol=1e-12))
    if bad.size:
        i, j = bad[0]
        raise InstanceError(
            f"parcover handles symmetric distances only; the matrix has [{i}, {j}] = {m[i, j]:g} but "
            f"[{j}, {i}] = {m[j, i]:g} (asymmetric travel costs are out of scope)."
        )
    return m


def _check_row(value: Any, size: int, what: str) -> int:
    """``value`` as a row number of a ``size``-row matrix, else :class:`InstanceError`."""
    if not is_whole(value):
        raise InstanceError(f"The {what} must be a row number of the matrix, got {short_repr(value)}.")
    if not 0 <= value < size:
        raise InstanceError(f"The {what} row {value} is out of range for a {size} x {size} matrix.")
    return int(value)


def _check_ids(ids: Any, size: int) -> list[str]:
    """One distinct string id per matrix row (any iterable, as ``names`` of :meth:`Instance.from_points`)."""
    if not isinstance(ids, Iterable):
        raise InstanceError(f"ids must be a list of {size} strings, got {short_repr(ids)}.")
    labels = [str(v) for v in ids]
    if len(labels) != size:
        raise InstanceError(f"Expected {size} ids (one per matrix row), got {len(labels)}.")
    duplicate = _first_duplicate(labels)
    if duplicate is not None:
        raise InstanceError(f"Duplicate id {duplicate!r} in ids.")
    return labels


def _check_symmetric(graph: Any, weight: str) -> None:
    """A directed networkx graph must be an undirected one: each edge and its reverse, same weight."""
    if graph.is_multigraph():
        raise InstanceError("A directed multigraph is not a map; give an undirected networkx Graph.")
    for u, v, data in graph.edges(data=True):
        if not graph.has_edge(v, u):
            raise InstanceError(
                f"Directed edge {u!r} -> {v!r} has no reverse edge; parcover's maps are undirected."
            )
        back = graph.edges[v, u].get(weight)
        if back != data.get(weight):
            raise InstanceError(
                f"Edge {u!r} -> {v!r} weighs {data.get(weight)!r} but {v!r} -> {u!r} weighs {back!r}; "
                "parcover's maps are undirected."
            )


def _check_path_sums(weights: np.ndarray, nodes: int) -> None:
    """A shortest path adds at most ``nodes - 1`` weights: their sum must be finite."""
    heaviest = float(weights.max())
    if not math.isfinite(heaviest * nodes):
        raise InstanceError(
            f"Edge weights up to {heaviest:g} overflow when {nodes} of them are added along a path."
        )


def _check_scale(distances: np.ndarray, n: int) -> np.ndarray:
    """Refuse distances that overflow, whose route sums (or their squares) overflow, or that
    drown in the tolerance."""
    if not np.all(np.isfinite(distances)):
        raise InstanceError("Distances overflow: the coordinates are too far apart for a float.")
    largest = float(distances.max()) if distances.size else 0.0
    longest_route = largest * 2 * (n + 1)
    if not math.isfinite(longest_route * longest_route):
        raise InstanceError(
            f"Distances up to {largest:g} are too large: route costs over {n} KPOIs and their squares "
            "must be finite floats."
        )
    if 0 < largest < MIN_SCALE:
        raise InstanceError(
            f"The largest distance is {largest:g}, below {MIN_SCALE:g}: costs this small are lost in the "
            "tolerance of 1e-9; use a smaller unit."
        )
    return distances


def _straight_line(u: str, v: str, coordinates: Mapping[str, Point] | None) -> float | None:
    if coordinates is None or u not in coordinates or v not in coordinates:
        return None
    (x1, y1), (x2, y2) = coordinates[u], coordinates[v]
    return math.hypot(x1 - x2, y1 - y2)


def _euclidean_matrix(xy: np.ndarray) -> np.ndarray:
    """Pairwise straight-line distances between the rows of ``xy`` (``inf`` on overflow)."""
    with np.errstate(over="ignore"):
        return np.hypot(xy[:, None, 0] - xy[None, :, 0], xy[:, None, 1] - xy[None, :, 1])


def _tsplib_round(x: Any) -> Any:
    """TSPLIB's ``nint``: round half up (Reinelt 1995, EUC_2D)."""
    return np.floor(np.asarray(x, dtype=float) + 0.5)


def _lightest_edge_graph(
    rows: np.ndarray, cols: np.ndarray, weights: np.ndarray, size: int
) -> sp.csr_array:
    """A sparse graph keeping the lightest of parallel edges (scipy would sum them)."""
    import scipy.sparse as sp

    lo, hi = np.minimum(rows, cols), np.maximum(rows, cols)
    order = np.lexsort((weights, hi, lo))
    lo, hi, weights = lo[order], hi[order], weights[order]
    first = np.ones(len(lo), dtype=bool)
    first[1:] = (lo[1:] != lo[:-1]) | (hi[1:] != hi[:-1])
    return sp.csr_array((weights[first], (lo[first], hi[first])), shape=(size, size))


def _readonly(a: np.ndarray) -> np.ndarray:
    a = np.ascontiguousarray(a)
    a.flags.writeable = False
    return a
