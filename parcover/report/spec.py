"""The questions and instances of a gap report.

:class:`GridQuestion` is one question of the grid (a robot limit or a deadline factor),
:func:`questions` the grid. :func:`parse_spec` builds the instances of a generator spec
such as ``random:n=6..10:seeds=0..4``; :func:`load_instances` gathers instances from
objects, files, folders and specs, refusing more than memory holds.
"""

from __future__ import annotations

import itertools
import math
import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Union

from parcover.errors import InputError
from parcover.instance import Instance
from parcover.memory import Footprint
from parcover.problem import Problem
from parcover.result import RoutesKind

InstanceInput = Union[Instance, str, os.PathLike]

_GENERATOR_KEYS = {
    "random": {"n": None, "seeds": 0},
    "graph": {"n": None, "seeds": 0, "virtual": -1},
    "grid": {"rows": None, "cols": None},
    "star": {"n": None},
}


# ---------------------------------------------------------------- questions


@dataclass(frozen=True)
class GridQuestion:
    """One coverage question of the grid: a robot limit, or a deadline factor.

    ``factor`` None with ``robots`` None is the paper's question (no deadline: the
    least possible makespan).
    """

    robots: int | None = None
    factor: float | None = None

    @property
    def label(self) -> str:
        if self.robots is not None:
            return f"robots<={self.robots}"
        return "deadline=least" if self.factor is None else f"deadline={self.factor!r}*least"

    @classmethod
    def from_label(cls, label: str) -> GridQuestion:
        """The question whose :attr:`label` is ``label``."""
        if label.startswith("robots<="):
            return cls(robots=int(label.removeprefix("robots<=")))
        if label == "deadline=least":
            return cls()
        return cls(factor=float(label.removeprefix("deadline=").removesuffix("*least")))

    def deadline(self, instance: Instance, routes: RoutesKind) -> float | None:
        """The deadline passed to :func:`parcover.solve` (None: the paper's question)."""
        if self.factor is None:
            return None
        return self.factor * Problem(routes).least_makespan(instance)


def questions(robots: Iterable[int], deadlines: Iterable[str | float]) -> list[GridQuestion]:
    """The grid's questions: one per robot limit, one per deadline (``"least"`` or a factor)."""
    found = [GridQuestion(robots=_whole(k, "robot limit", 1)) for k in robots]
    found += [GridQuestion() if d == "least" else GridQuestion(factor=_deadline_factor(d)) for d in deadlines]
    if not found:
        raise InputError("No questions: give robot limits or deadlines.")
    if len({q.label for q in found}) != len(found):
        raise InputError("The same question is asked twice.")
    return found


def _deadline_factor(text: str | float) -> float:
    """A positive factor of the least makespan, from a number or its text (``"1.2"``)."""
    try:
        factor = float(text) if isinstance(text, str) else text
    except ValueError:
        factor = None
    if isinstance(factor, bool) or not isinstance(factor, (int, float)) or not (math.isfinite(factor) and factor > 0):
        raise InputError(f"A deadline must be 'least' or a positive factor of it, got {text!r}.")
    return float(factor)


# ---------------------------------------------------------------- instances


def parse_spec(spec: str) -> list[Instance]:
    """Instances of a generator spec such as ``random:n=6..10:seeds=0..4``.

    Grammar: ``KIND(:KEY=VALUES)*`` with KIND one of ``random`` (keys ``n``,
    ``seeds``), ``graph`` (``n``, ``seeds``, ``virtual``), ``grid`` (``rows``,
    ``cols``), ``star`` (``n``); VALUES a whole number, a range ``A..B`` (inclusive)
    or a comma list. One instance per combination of values, in the order written
    (:mod:`parcover.generate`, seeds given explicitly).

    Raises
    ------
    InputError
        With one line naming what is wrong in the spec, or how much memory its
        instances would need when that is more than there is (before building any).
    """
    kind, values = _spec_values_by_key(spec)
    _check_spec_memory(spec, kind, values, 0)
    return _spec_instances(kind, values)


def _spec_values_by_key(spec: str) -> tuple[str, dict[str, Sequence[int]]]:
    """The generator of a spec and the values of each of its keys, defaults filled in."""
    kind, *parts = spec.strip().split(":")
    if kind not in _GENERATOR_KEYS:
        raise InputError(f"Unknown generator {kind!r} in {spec!r}; expected one of {', '.join(_GENERATOR_KEYS)}.")
    values: dict[str, Sequence[int]] = {}
    for part in parts:
        key, sep, text = part.partition("=")
        if not sep or key not in _GENERATOR_KEYS[kind]:
            raise InputError(
                f"Bad part {part!r} in {spec!r}; {kind} takes {', '.join(k + '=...' for k in _GENERATOR_KEYS[kind])}."
            )
        if key in values:
            raise InputError(f"{key!r} is given twice in {spec!r}.")
        values[key] = _spec_values(text, spec)
    for key, default in _GENERATOR_KEYS[kind].items():
        if key not in values:
            if default is None:
                raise InputError(f"{spec!r} lacks {key}=...; {kind} needs it.")
            values[key] = [default]
    return kind, values


def _spec_instances(kind: str, values: dict[str, Sequence[int]]) -> list[Instance]:
    """One generated instance per combination of ``values``, the first key varying slowest."""
    from parcover import generate

    build = {
        "random": lambda n, seeds: generate.random_points(n, seeds),
        "graph": lambda n, seeds, virtual: generate.random_graph(n, seeds, virtual=None if virtual < 0 else virtual),
        "grid": lambda rows, cols: generate.grid(rows, cols),
        "star": lambda n: generate.star(n),
    }[kind]
    keys = list(_GENERATOR_KEYS[kind])
    return [build(**dict(zip(keys, combo))) for combo in itertools.product(*(values[k] for k in keys))]


def _check_spec_memory(spec: str, kind: str, values: dict[str, Sequence[int]], kept: int) -> int:
    """Refuse a spec whose instances, on top of ``kept`` bytes of instances already
    loaded, need more memory than there is; else the bytes its instances keep.

    The instances are kept together, each built in turn (:func:`parcover.generate.footprint`).
    A first check with every instance as small as the smallest refuses a spec of
    billions of instances at once; then the sizes are summed (seeds do not change them).
    """
    from parcover import generate
    from parcover.memory import check_memory

    def footprint(sizes: dict[str, int]) -> Footprint:
        if kind == "graph" and sizes["virtual"] < 0:
            sizes = {**sizes, "virtual": 2 * sizes["n"]}
        return generate.footprint(kind, **sizes)

    keys = [k for k in _GENERATOR_KEYS[kind] if k != "seeds"]
    copies = len(values.get("seeds", [0]))
    count = copies * math.prod(len(values[k]) for k in keys)
    what = f"{spec!r} ({count} instance{'s' if count != 1 else ''})"
    least = footprint({k: values[k][0] if isinstance(values[k], range) else min(values[k]) for k in keys})
    check_memory(kept + count * least.kept + least.peak - least.kept, what)
    total, peak = kept, 0
    for combo in itertools.product(*(values[k] for k in keys)):
        each = footprint(dict(zip(keys, combo)))
        total += copies * each.kept
        peak = max(peak, each.peak - each.kept)
    check_memory(total + peak, what)
    return total - kept


def load_instances(instances: InstanceInput | Iterable[InstanceInput]) -> list[Instance]:
    """Instances from :class:`Instance` objects, files, folders (their ``.json`` and
    ``.tsp`` files, sorted) and generator specs (:func:`parse_spec`), in order.

    Raises
    ------
    InputError
        On a missing file, a bad spec, no instance at all, two instances with
        one name (rows are keyed by name), or more instances than memory holds
        (a spec is refused before any of its instances is built).
    """
    from parcover.io import read_instance
    from parcover.memory import check_memory, footprint_of

    items = [instances] if isinstance(instances, (Instance, str, os.PathLike)) else list(instances)
    found: list[Instance] = []
    kept = 0
    for item in items:
        loaded: Iterable[Instance]
        if isinstance(item, Instance):
            loaded = [item]
        elif Path(item).is_dir():
            files = sorted(p for p in Path(item).iterdir() if p.suffix.lower() in (".json", ".tsp"))
            loaded = (read_instance(p) for p in files)  # each counted before the next is read
        elif Path(item).is_file():
            loaded = [read_instance(item)]
        elif isinstance(item, str) and item.split(":")[0] in _GENERATOR_KEYS:
            kind, values = _spec_values_by_key(item)
            kept += _check_spec_memory(item, kind, values, kept)
            found += _spec_instances(kind, values)
            continue
        else:
            raise InputError(f"{str(item)!r} is neither a file, a folder nor a generator spec.")
        for instance in loaded:
            kept += footprint_of(instance).kept
            check_memory(kept, f"Loading the instances up to {instance.name!r}")
            found.append(instance)
    if not found:
        raise InputError("No instances given.")
    names = [inst.name for inst in found]
    twice = sorted({name for name in names if names.count(name) > 1})
    if twice:
        raise InputError(f"Two instances are named {twice[0]!r}; rows are keyed by instance name.")
    return found


# ---------------------------------------------------------------- small helpers


def _spec_values(text: str, spec: str) -> Sequence[int]:
    """``7``, ``6..10`` (inclusive, a ``range``: not built) or ``1,3,5`` as whole numbers."""
    try:
        if ".." in text:
            low, high = (int(x) for x in text.split(".."))
            if high < low:
                raise ValueError
            return range(low, high + 1)
        return [int(x) for x in text.split(",")]
    except ValueError:
        raise InputError(f"Bad value {text!r} in {spec!r}; expected N, A..B or a list A,B,C.") from None


def _whole(value: Any, what: str, least: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < least:
        raise InputError(f"The {what} must be a whole number >= {least}, got {value!r}.")
    return value
