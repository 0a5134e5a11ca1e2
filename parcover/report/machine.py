"""What a report records about its run: versions, settings and the machine.

:func:`run_metadata` is the content of a report's meta.json; :func:`machine_info` (CPU,
cores, memory, platform) and :func:`package_version` are also used by the benchmarks.
"""

from __future__ import annotations

import os
import platform
from pathlib import Path
from typing import Any


def run_metadata(**settings: Any) -> dict[str, Any]:
    """Versions of parcover and its solvers, the run's settings, and the machine."""
    import parcover

    return {
        "parcover": parcover.__version__,
        "versions": {name: package_version(name) for name in ("highspy", "cvxpy", "numpy", "scipy", "pandas")},
        **settings,
        "machine": machine_info(),
    }


def machine_info() -> dict[str, Any]:
    """CPU model (``/proc/cpuinfo``), cores, memory (``/proc/meminfo``), platform."""
    return {
        "cpu": _proc_field("/proc/cpuinfo", "model name") or platform.processor() or "unknown",
        "cores": os.cpu_count(),
        "memory_gb": _memory_gb(),
        "platform": platform.platform(),
        "python": platform.python_version(),
    }


def _proc_field(path: str, field: str) -> str | None:
    try:
        text = Path(path).read_text(encoding="utf-8", errors="replace")
    except OSError:
        return None
    for line in text.splitlines():
        key, sep, value = line.partition(":")
        if sep and key.strip() == field:
            return value.strip()
    return None


def _memory_gb() -> float | None:
    total = _proc_field("/proc/meminfo", "MemTotal")  # "16318420 kB"
    if not total:
        return None
    return round(int(total.split()[0]) / 2**20, 1)


def package_version(name: str) -> str | None:
    """The installed version of distribution ``name``, or None when it is not installed."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version(name)
    except PackageNotFoundError:
        return None
