"""Reading and writing instances (docs/format.md section 2) and solution files.

- JSON instance files: :func:`read_instance` / :func:`write_instance`, and the dict
  forms :func:`instance_from_dict` / :func:`instance_to_dict`.
- TSPLIB ``.tsp`` files (TYPE TSP, EUC_2D), parsed by ``vrplib``: node 1 is the start,
  every other node a KPOI, each named by its number in the file; exact Euclidean
  distances unless ``metric="tsplib"``.
- :func:`write_text_atomic`: every file parcover writes appears whole or not at all.

Every problem with a file raises :class:`FileFormatError` (an
:class:`~parcover.errors.InputError`) with one line naming the file and the problem:
only regular files up to :data:`MAX_FILE_BYTES` whose parsing fits in memory
(:mod:`parcover.memory`) are read (a FIFO would block, a device never end), and JSON
with duplicate keys or nested deeper than Python can parse is refused rather than
half-read.
"""

from __future__ import annotations

import json
import math
import os
import stat
import tempfile
from pathlib import Path
from typing import Any

from parcover.errors import InputError
from parcover.instance import Instance, InstanceError, MapInfo, Metric, _first_duplicate
from parcover.memory import check_memory, file_bytes, format_bytes
from parcover.question_block import Question

__all__ = [
    "FileFormatError",
    "load",
    "read_instance",
    "write_instance",
    "instance_from_dict",
    "instance_to_dict",
    "read_tsplib",
    "read_json",
    "write_text_atomic",
    "MAX_FILE_BYTES",
]

_REQUIRED = ("start", "kpois")

#: Instance and solution files larger than this are refused before reading (256 MiB:
#: ten times a million-node TSPLIB file; JSON takes several times its size in memory).
MAX_FILE_BYTES = 256 * 2**20


class FileFormatError(InputError):
    """A file that cannot be read as what it should be."""


def read_instance(path: str | os.PathLike[str], *, metric: Metric | None = None) -> Instance:
    """Read an instance from a ``.json`` or TSPLIB ``.tsp`` file.

    Parameters
    ----------
    path
        The file. ``.tsp`` files are TSPLIB; anything else is read as JSON.
    metric
        Override how coordinates become distances: ``"euclidean"`` (exact) or
        ``"tsplib"`` (TSPLIB's ``nint`` rounding). ``None`` keeps the file's own
        (``"euclidean"`` for TSPLIB files, as in the min-max mTSP literature).
    """
    path = _as_path(path)
    if path.suffix.lower() == ".tsp":
        return read_tsplib(path, metric=metric or "euclidean")
    data = read_json(path)
    if not isinstance(data, dict):
        raise FileFormatError(f"{path}: expected a JSON object at the top level.")
    try:
        return instance_from_dict(data, base_dir=path.parent, metric=metric, default_name=path.stem)
    except InstanceError as exc:
        raise FileFormatError(f"{path}: {exc}") from None


load = read_instance


def read_json(path: str | os.PathLike[str]) -> Any:
    """Parse a JSON file, with one-line errors for missing or malformed files.

    Refused: ``NaN``/``Infinity`` (not JSON), duplicate keys in an object (which
    value was meant?), and nesting too deep for Python's parser.
    """
    path = _as_path(path)
    text = _read_text(path)
    try:
        return json.loads(text, parse_constant=_reject_constant, object_pairs_hook=_unique_keys)
    except json.JSONDecodeError as exc:
        raise FileFormatError(
            f"{path}: malformed JSON at line {exc.lineno} column {exc.colno}: {exc.msg}."
        ) from None
    except RecursionError:
        raise FileFormatError(f"{path}: JSON nested too deeply to read.") from None
    except ValueError as exc:
        raise FileFormatError(f"{path}: {exc}") from None


def _as_path(path: Any) -> Path:
    if not isinstance(path, (str, os.PathLike)):
        raise InputError(f"Expected a file path (str or os.PathLike), got {type(path).__name__} {path!r}.")
    return Path(path)


def _read_text(path: Path) -> str:
    """The UTF-8 text of a regular file of at most :data:`MAX_FILE_BYTES`."""
    try:
        info = path.stat()
    except FileNotFoundError:
        raise FileFormatError(f"{path}: no such file.") from None
    except OSError as exc:
        raise FileFormatError(f"{path}: cannot be read ({exc.strerror}).") from None
    if stat.S_ISDIR(info.st_mode):
        raise FileFormatError(f"{path}: is a directory, not a file.")
    if not stat.S_ISREG(info.st_mode):
        raise FileFormatError(f"{path}: not a regular file (a pipe or a device?).")
    if info.st_size > MAX_FILE_BYTES:
        raise FileFormatError(
            f"{path}: {info.st_size / 2**20:.0f} MiB is larger than the {MAX_FILE_BYTES // 2**20} MiB parcover reads."
        )
    check_memory(file_bytes(info.st_size), f"{path} ({format_bytes(info.st_size)} to parse)")
    try:
        return path.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise FileFormatError(f"{path}: not UTF-8 text.") from None
    except OSError as exc:
        raise FileFormatError(f"{path}: cannot be read ({exc.strerror}).") from None


def _reject_constant(name: str) -> Any:
    raise ValueError(f"{name} is not a valid JSON number.")


def _unique_keys(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    data: dict[str, Any] = {}
    for key, value in pairs:
        if key in data:
            raise ValueError(f"duplicate key {key!r} in a JSON object.")
        data[key] = value
    return data


def instance_from_dict(
    data: dict[str, Any],
    *,
    base_dir: str | os.PathLike[str] | None = None,
    metric: Metric | None = None,
    default_name: str = "",
) -> Instance:
    """An :class:`Instance` from the JSON object of docs/format.md section 2.

    Unknown keys are ignored (files may carry extensions); an optional ``question``
    block is validated (:class:`parcover.question_block.Question`). ``base_dir`` is where a
    relative ``map.image`` is resolved from, for drawings.
    """
    for key in _REQUIRED:
        if key not in data:
            raise InstanceError(f"Missing required key {key!r}.")
    if not isinstance(data["kpois"], list):
        raise InstanceError(f"kpois must be a list of string ids, got {data['kpois']!r}.")
    edges = data.get("edges")
    if edges is not None and not isinstance(edges, list):
        raise InstanceError("edges must be a list of [u, v, weight] triples.")
    name = data.get("name", default_name)
    if not isinstance(name, str):
        raise InstanceError(f"name must be a string, got {name!r}.")
    instance = Instance(
        start=data["start"],
        kpois=tuple(data["kpois"]),
        coordinates=data.get("coordinates"),
        edges=tuple(tuple(e) if isinstance(e, list) else e for e in edges) if edges is not None else None,
        name=name,
        map=_map_from_dict(data.get("map"), base_dir),
        metric=metric or data.get("metric", "euclidean"),
    )
    if data.get("question") is not None:
        Question.from_dict(data["question"], instance)  # refuse a bad block now (parcover.question_block)
    return instance


def instance_to_dict(instance: Instance) -> dict[str, Any]:
    """The JSON object of docs/format.md section 2 (keys without a value are left out)."""
    kpois = ([instance.start] if instance.start_is_kpoi else []) + list(instance.kpois)
    data: dict[str, Any] = {"name": instance.name, "start": instance.start, "kpois": kpois}
    if instance.metric != "euclidean":
        data["metric"] = instance.metric
    if instance.coordinates is not None:
        data["coordinates"] = {v: [_plain(x), _plain(y)] for v, (x, y) in instance.coordinates.items()}
    if instance.edges is not None:
        data["edges"] = [[u, v, _plain(w)] for u, v, w in instance.edges]
    if instance.map is not None:
        m = instance.map
        scale = m.metres_per_pixel
        data["map"] = {
            "image": m.image,
            "metres_per_pixel": list(scale) if isinstance(scale, tuple) else scale,
            "origin": list(m.origin),
        }
    return data


def write_instance(
    instance: Instance, path: str | os.PathLike[str] | None = None, *, question: Question | None = None
) -> str:
    """Write the instance as JSON to ``path`` (or just return the text).

    A map image is stored relative to the file's folder, as :func:`read_instance`
    resolves it. ``question`` adds the file's ``"question"`` block.
    """
    data = instance_to_dict(instance)
    if question is not None:
        data["question"] = question.to_dict()
    if path is not None and "map" in data and os.path.isabs(data["map"]["image"]):
        data["map"]["image"] = os.path.relpath(data["map"]["image"], Path(path).resolve().parent)
    text = _readable_json(data)
    if path is not None:
        write_text_atomic(path, text)
    return text


def write_text_atomic(path: str | os.PathLike[str], text: str) -> None:
    """Write ``text`` to ``path`` whole or not at all.

    The text goes to a temporary file in the same folder, which then replaces
    ``path`` in one step (``os.replace``): a full disk or an interruption leaves the
    old file in place, never a truncated one.

    Raises
    ------
    InputError
        When the folder is missing or not writable, or the write fails.
    """
    path = Path(path)
    folder = path.parent
    try:
        handle, temporary = tempfile.mkstemp(dir=folder, prefix=f".{path.name}.", suffix=".tmp")
    except OSError as exc:
        raise InputError(f"Cannot write {path}: {exc.strerror} ({folder}).") from None
    try:
        with os.fdopen(handle, "w", encoding="utf-8") as f:
            f.write(text)
        os.chmod(temporary, 0o666 & ~_umask())
        os.replace(temporary, path)
    except OSError as exc:
        os.unlink(temporary)
        raise InputError(f"Cannot write {path}: {exc.strerror}.") from None
    except BaseException:
        os.unlink(temporary)
        raise


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def read_tsplib(path: str | os.PathLike[str], *, metric: Metric = "euclidean") -> Instance:
    """A TSPLIB ``TYPE: TSP``, EUC_2D ``.tsp`` file: node 1 is the start, the others KPOIs.

    Ids are the node numbers as written in the file (each once; ``DIMENSION`` must
    count them). ``metric="euclidean"`` gives exact distances (the min-max mTSP
    literature's convention), ``"tsplib"`` TSPLIB's ``nint`` rounding (Reinelt 1991).
    """
    from vrplib.parse import parse_vrplib

    path = _as_path(path)
    text = _read_text(path)
    try:
        data = parse_vrplib(text, compute_edge_weights=False)
    except Exception as exc:  # vrplib raises many kinds on malformed files
        raise FileFormatError(f"{path}: not a readable TSPLIB file ({type(exc).__name__}: {exc}).") from None
    problem = str(data.get("type", "")).upper()
    if problem != "TSP":
        raise FileFormatError(f"{path}: TYPE {problem or '(missing)'} is not supported; expected TSP.")
    kind = str(data.get("edge_weight_type", "")).upper()
    if kind != "EUC_2D":
        raise FileFormatError(
            f"{path}: EDGE_WEIGHT_TYPE {kind or '(missing)'} is not supported; expected EUC_2D."
        )
    coords = data.get("node_coord")
    if coords is None or len(coords) < 2:
        raise FileFormatError(f"{path}: expected a NODE_COORD_SECTION with at least 2 nodes.")
    ids = _tsplib_node_ids(text)
    dimension = data.get("dimension")
    if isinstance(dimension, bool) or not isinstance(dimension, int) or dimension != len(ids):
        raise FileFormatError(f"{path}: DIMENSION {dimension!r} does not match the {len(ids)} nodes listed.")
    duplicate = _first_duplicate(ids)
    if duplicate is not None:
        raise FileFormatError(f"{path}: node {duplicate} is listed twice in NODE_COORD_SECTION.")
    if "1" not in ids:
        raise FileFormatError(f"{path}: no node 1, the start.")
    try:
        return Instance.from_points(
            coords, start=ids.index("1"), names=ids, name=str(data.get("name", path.stem)), metric=metric
        )
    except InstanceError as exc:
        raise FileFormatError(f"{path}: {exc}") from None


def _tsplib_node_ids(text: str) -> list[str]:
    """The node numbers heading the lines of NODE_COORD_SECTION, as written."""
    ids: list[str] = []
    inside = False
    for line in text.splitlines():
        if "EOF" in line or (inside and "_SECTION" in line):
            if inside:
                break
        elif "NODE_COORD_SECTION" in line:
            inside = True
        elif inside and line.split():
            ids.append(line.split()[0])
    return ids


def _readable_json(data: dict[str, Any]) -> str:
    """JSON with one top-level key per line and one coordinate, edge or question entry per line."""
    parts = []
    for key, value in data.items():
        if key in ("coordinates", "question"):
            body = ",\n".join(f"    {json.dumps(k)}: {json.dumps(v, allow_nan=False)}" for k, v in value.items())
            text = "{\n" + body + "\n  }"
        elif key == "edges":
            text = "[\n" + ",\n".join(f"    {json.dumps(e, allow_nan=False)}" for e in value) + "\n  ]"
        else:
            text = json.dumps(value, allow_nan=False)
        parts.append(f"  {json.dumps(key)}: {text}")
    return "{\n" + ",\n".join(parts) + "\n}\n"


def _map_from_dict(block: Any, base_dir: str | os.PathLike[str] | None) -> MapInfo | None:
    if block is None:
        return None
    if not isinstance(block, dict) or not isinstance(block.get("image"), str):
        raise InstanceError("map must be an object with an 'image' path.")
    scale = block.get("metres_per_pixel", 1.0)
    if isinstance(scale, list) and len(scale) == 2:
        scale = tuple(scale)
    values = scale if isinstance(scale, tuple) else (scale,)
    if not all(_positive_number(s) for s in values):
        raise InstanceError(f"map.metres_per_pixel must be a positive number or pair, got {scale!r}.")
    origin = block.get("origin", [0, 0])
    if not (isinstance(origin, list) and len(origin) == 2 and all(_finite_number(c) for c in origin)):
        raise InstanceError(f"map.origin must be [x, y], got {origin!r}.")
    image = block["image"]
    if base_dir is not None and not os.path.isabs(image):
        image = os.path.normpath(os.path.join(base_dir, image))
    return MapInfo(image=image, metres_per_pixel=scale, origin=(float(origin[0]), float(origin[1])))


def _finite_number(x: Any) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def _positive_number(x: Any) -> bool:
    return _finite_number(x) and x > 0


def _plain(x: float) -> int | float:
    """Whole numbers as ints, so files stay short and readable."""
    return int(x) if float(x).is_integer() and abs(x) < 2**53 else float(x)
