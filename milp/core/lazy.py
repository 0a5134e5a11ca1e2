"""A package's public names loaded on first use (PEP 562), from a table of where each lives.

A package that re-exports names of heavy modules (numba's labelling, matplotlib, cvxpy)
imports them only when one is first read: its ``__getattr__``, built here, looks the name
up in the table, imports the module and keeps the value in the package's namespace, so a
later read finds it there without calling ``__getattr__`` again.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from typing import Any

__all__ = ["lazy_getattr"]


def lazy_getattr(package: str, namespace: dict[str, Any], defined_in: Mapping[str, str],
                 modules: Mapping[str, str] | None = None) -> Callable[[str], Any]:
    """A module ``__getattr__`` for ``package`` (its ``namespace`` being its ``globals()``).

    A name of ``defined_in`` is read from the module it maps to; a name of ``modules`` is
    that module itself. Either is imported on the first read and stored in ``namespace``;
    any other name raises AttributeError with the message of a missing module attribute.
    """
    modules = modules or {}

    def __getattr__(name: str) -> Any:
        if name in modules:
            value = importlib.import_module(modules[name])
        elif name in defined_in:
            value = getattr(importlib.import_module(defined_in[name]), name)
        else:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        namespace[name] = value
        return value

    return __getattr__
