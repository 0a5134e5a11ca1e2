"""How much memory an input will take, checked before it is allocated.

Every command estimates what its input will allocate (generator sizes, distance
matrices, image pixels and their working arrays, instance files, report grids) and
calls :func:`check_memory` first: above :func:`memory_limit` it raises
:class:`MemoryLimitError`, an :class:`~parcover.errors.InputError`, which the command
line prints as one line with exit status 2. The limit is the memory the machine has
available (Linux ``MemAvailable`` and the cgroup v2 limit) or the environment variable
:data:`LIMIT_VARIABLE`, whichever is smaller.

The byte counts below were measured with ``tracemalloc`` and peak RSS on worst cases
(an all-white image, a random instance, a graph of many virtual nodes) and rounded up;
docs/limits.md turns them into sizes per command.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass
from typing import Protocol

from parcover.errors import InputError

__all__ = [
    "LIMIT_VARIABLE",
    "MemoryLimitError",
    "Footprint",
    "instance_footprint",
    "footprint_of",
    "BuiltInstance",
    "map_bytes",
    "file_bytes",
    "report_rows_bytes",
    "available_memory",
    "memory_limit",
    "check_memory",
    "parse_size",
    "format_bytes",
]

#: Environment variable capping what one command may allocate: bytes, or a number with
#: a unit (``KB``, ``MB``, ``GB``, ``TB`` decimal, ``KiB``, ``MiB``, ``GiB``, ``TiB``
#: binary; ``K``, ``M``, ``G``, ``T`` alone are decimal), e.g. ``PARCOVER_MEMORY_LIMIT=2GB``.
LIMIT_VARIABLE = "PARCOVER_MEMORY_LIMIT"

#: Bytes per entry of a distance matrix between points while it is built: three float
#: arrays of its size at once (the x and y differences, their hypotenuse).
MATRIX_BYTES_PER_ENTRY = 24
#: Bytes per key node x graph node while a graph's metric is built: Dijkstra's float
#: distances, its int32 predecessors and their copy; and per key x key entry, the key
#: columns and their symmetric minimum (measured 83 MB for a 40 x 40 grid, 85 estimated).
GRAPH_BYTES_PER_ENTRY = 16
#: Python objects per node (name, coordinates, index entries, JSON text; 360 measured
#: for random points, rounded up for the graphs' Delaunay triangulation).
NODE_BYTES = 1024
#: Python objects per edge (its tuple, weight, sparse-graph arrays, JSON text; 160
#: measured for TSPLIB's complete graph, 1870 per node with 3 edges for random graphs).
EDGE_BYTES = 320
#: Parsed JSON or TSPLIB per byte of file text (numbers become floats in lists, names strings).
FILE_BYTES_PER_BYTE = 10
#: Per pixel of a map while free KPOI positions are sampled (the labelled areas away from the
#: outline and the free pixels' indices; 38 measured on an all-white image, 57 when every free
#: pixel's world coordinates were computed).
MAP_BYTES_PER_PIXEL = 64
#: Per pixel and colour band while a map is decoded (Pillow's bytes, matplotlib's
#: float32, parcover's float64 copy; 13 measured).
MAP_BYTES_PER_BAND = 16
#: Per pixel while a decoded map becomes a mask (grey mean, its temporary, the mask).
MAP_BYTES_PER_GREY_PIXEL = 24
#: A solver's working memory per entry of the distance matrix, beyond the instance: at
#: 3000 KPOIs ``exact`` peaked at 790 MB (88 bytes an entry), ``best`` at 540 MB (60) and
#: ``paper`` at 250 MB (28); the largest, rounded up, for every method.
SOLVE_BYTES_PER_ENTRY = 96
#: One row of a gap report (a dict of 25 columns, then its pandas copies).
ROW_BYTES = 4096

_UNITS = {"": 1, "k": 10**3, "m": 10**6, "g": 10**9, "t": 10**12,
          "ki": 2**10, "mi": 2**20, "gi": 2**30, "ti": 2**40}
_SIZE = re.compile(r"\s*(\d+(?:\.\d*)?(?:e\d+)?)\s*([kmgt]?i?)b?\s*", re.IGNORECASE)


class MemoryLimitError(InputError):
    """An input whose estimated memory exceeds :func:`memory_limit` (one-line message)."""


@dataclass(frozen=True)
class Footprint:
    """Bytes an instance takes: ``peak`` while it is built, ``kept`` once built."""

    peak: int
    kept: int


def instance_footprint(kpois: int, nodes: int | None = None, edges: int = 0) -> Footprint:
    """Memory of an :class:`~parcover.instance.Instance` of ``kpois`` KPOIs.

    Parameters
    ----------
    kpois
        KPOIs (the start comes on top).
    nodes
        Nodes of its graph, virtual ones included (None: no graph, the start and the KPOIs).
    edges
        Edges of its graph (0 without one).

    Returns
    -------
    Footprint
        ``peak``: building the distance matrix (:data:`MATRIX_BYTES_PER_ENTRY`, or
        :data:`GRAPH_BYTES_PER_ENTRY` with edges) plus the Python objects
        (:data:`NODE_BYTES`, :data:`EDGE_BYTES`); ``kept``: the float distance matrix,
        a graph's int32 predecessors and the Python objects.
    """
    key = max(kpois, 0) + 1
    nodes = key if nodes is None else max(nodes, key)
    objects = NODE_BYTES * nodes + EDGE_BYTES * max(edges, 0)
    if not edges:
        return Footprint(peak=MATRIX_BYTES_PER_ENTRY * key * key + objects, kept=8 * key * key + objects)
    return Footprint(peak=GRAPH_BYTES_PER_ENTRY * key * (nodes + key) + objects,
                     kept=8 * key * key + 4 * key * nodes + objects)


class BuiltInstance(Protocol):
    """The sizes :func:`footprint_of` reads of an :class:`~parcover.instance.Instance`
    (described here, not imported: the instance checks its memory with this module)."""

    @property
    def n(self) -> int: ...

    @property
    def nodes(self) -> tuple[str, ...]: ...

    @property
    def edges(self) -> tuple[tuple[str, str, float], ...] | None: ...


def footprint_of(instance: BuiltInstance) -> Footprint:
    """:func:`instance_footprint` of an instance already built (its graph's sizes)."""
    edges = len(instance.edges) if instance.edges is not None else 0
    return instance_footprint(instance.n, len(instance.nodes), edges)


def map_bytes(height: int, width: int, bands: int) -> int:
    """Peak bytes of turning a ``height x width`` bitmap of ``bands`` colour bands into an
    instance: the larger of decoding it (:data:`MAP_BYTES_PER_BAND` per band, then
    :data:`MAP_BYTES_PER_GREY_PIXEL`) and sampling its free pixels
    (:data:`MAP_BYTES_PER_PIXEL`), per pixel."""
    per_pixel = max(MAP_BYTES_PER_BAND * max(bands, 1) + MAP_BYTES_PER_GREY_PIXEL, MAP_BYTES_PER_PIXEL)
    return height * width * per_pixel


def file_bytes(size: int) -> int:
    """Peak bytes of parsing an instance or solution file of ``size`` bytes."""
    return FILE_BYTES_PER_BYTE * size


def report_rows_bytes(instances: int, route_kinds: int, questions: int, methods: int) -> int:
    """Bytes of a gap report's rows: at most two rows (a method that drops the deadline is
    compared twice) per instance x route kind x question x method."""
    return 2 * instances * route_kinds * questions * methods * ROW_BYTES


def available_memory() -> int | None:
    """Bytes of memory available to this process (Linux ``MemAvailable`` and the cgroup v2
    limit; elsewhere the free physical pages), or None when unknown."""
    limits = []
    try:
        with open("/proc/meminfo", encoding="ascii") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    limits.append(int(line.split()[1]) * 1024)
    except (OSError, ValueError):
        pass
    try:
        with open("/sys/fs/cgroup/memory.max", encoding="ascii") as f:
            text = f.read().strip()
        with open("/sys/fs/cgroup/memory.current", encoding="ascii") as f:
            limits.append(int(text) - int(f.read().strip()))
    except (OSError, ValueError):  # no cgroup v2 limit ("max" is not a number)
        pass
    if not limits and hasattr(os, "sysconf"):
        try:
            limits.append(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
        except (OSError, ValueError):
            pass
    return min(limits) if limits else None


def parse_size(text: str) -> int:
    """Bytes of a size such as ``2000000``, ``1.5GB`` or ``512MiB`` (:data:`LIMIT_VARIABLE`).

    Raises
    ------
    InputError
        When ``text`` is not such a size or is 0.
    """
    match = _SIZE.fullmatch(text)
    if match is None or not float(match.group(1)) > 0:
        raise InputError(f"{LIMIT_VARIABLE}={text!r} is not a size: expected bytes such as 2000000000, 2GB or 512MiB.")
    return int(float(match.group(1)) * _UNITS[match.group(2).lower()])


def memory_limit() -> tuple[int, str] | None:
    """The bytes one command may allocate and where that limit comes from (``"available"``
    or :data:`LIMIT_VARIABLE`), or None when neither is known."""
    limits = []
    available = available_memory()
    if available is not None:
        limits.append((available, "available"))
    cap = os.environ.get(LIMIT_VARIABLE)
    if cap:
        limits.append((parse_size(cap), f"allowed by {LIMIT_VARIABLE}"))
    return min(limits) if limits else None


def check_memory(needed: int, what: str) -> None:
    """Refuse, before allocating, ``needed`` bytes above :func:`memory_limit`.

    Parameters
    ----------
    needed
        The estimate (this module's functions).
    what
        What needs them, the start of the message: ``"A random instance of 10 KPOIs"``.

    Raises
    ------
    MemoryLimitError
        "{what} needs about 2.2 GB of memory, more than the 1.0 GB available."
    """
    limit = memory_limit()
    if limit is not None and needed > limit[0]:
        raise MemoryLimitError(f"{what} needs about {format_bytes(needed)} of memory, more than the "
                               f"{format_bytes(limit[0])} {limit[1]}.")


def format_bytes(size: float) -> str:
    """``size`` bytes in decimal units, as :data:`LIMIT_VARIABLE` reads them: ``"512 B"``,
    ``"1.5 GB"``, ``"2.4e+07 TB"``."""
    for unit in ("B", "kB", "MB", "GB"):
        if size < 1000:
            return f"{size:.0f} {unit}" if unit == "B" else f"{size:.1f} {unit}"
        size /= 1000
    return f"{size:.1f} TB" if size < 1e6 else f"{size:.1e} TB"
