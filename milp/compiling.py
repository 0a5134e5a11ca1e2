"""Whether branch-and-price's compiled functions are ready, and compiling them.

The pricing (:mod:`milp.ngroute`), the route listing (:mod:`milp.enumeration`) and the
cut separation (:mod:`milp.cuts`) are numba functions, compiled on their first call and
cached on disk (``cache=True``) for later processes.
"""

from __future__ import annotations

import numpy as np
from numba.core.dispatcher import Dispatcher

from milp import cuts, enumeration, ngroute

__all__ = ["COMPILE_SECONDS", "ready_within", "compile_rarely_used", "jitted", "compiled"]

#: Seconds to allow for compiling the pricing on its first use, when numba's on-disk cache
#: does not hold it yet (measured 9.9 s on a shared 2-core EPYC, 7.1 s of it the
#: labelling; twice that for slower machines). Later runs load it from the cache in a
#: fraction of a second.
COMPILE_SECONDS = 20.0


def ready_within(seconds: float | None) -> bool:
    """Whether a solve can start within ``seconds`` (None: no limit): the compiled pricing
    is loaded in this process or held by numba's on-disk cache for the current source,
    or ``seconds`` leaves room to compile it (:data:`COMPILE_SECONDS`)."""
    return seconds is None or seconds >= COMPILE_SECONDS or all(map(compiled, jitted()))


def compile_rarely_used() -> None:
    """Compile the subset-row cut and enumeration functions, which a search may never
    call, on toy arguments of the types a search passes: so that after one solve the
    on-disk cache holds every compiled function and :func:`ready_within` holds."""
    if not compiled(cuts.violated_triples):
        cuts.violated_triples(np.zeros((1, 3)), np.zeros(1), 0.05)
    if not compiled(ngroute._cut_counts):
        bits = np.zeros(2, dtype=np.uint64)
        ngroute.cut_coefficients([np.array([1])], bits, bits, 1)
    if not compiled(enumeration._extend):
        D = np.array([[0.0, 1.0], [1.0, 0.0]])
        enumeration.routes_within_gap(D, D[:, 0].copy(), np.array([0.0, 1.0]), 2.0, 0.5,
                                      np.ones((2, 2), dtype=bool), np.ones(2, dtype=bool), max_states=10)


def jitted() -> list[Dispatcher]:
    """The compiled functions of the pricing, the route listing and the cut separation."""
    return [f for module in (ngroute, enumeration, cuts) for f in vars(module).values()
            if isinstance(f, Dispatcher)]


def compiled(function: Dispatcher) -> bool:
    """Compiled in this process, or in the on-disk cache with the current source's stamp
    (numba's index file is read as numba reads it; any error counts as not cached)."""
    if function.signatures:
        return True
    try:
        return bool(function._cache._cache_file._load_index())
    except Exception:  # numba's cache internals: when they change, assume a compile
        return False
