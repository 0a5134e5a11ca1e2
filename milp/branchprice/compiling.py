"""Whether branch-and-price's compiled functions are ready, and compiling them.

The pricing (:mod:`milp.branchprice.ngroute`), the route listing (:mod:`milp.branchprice.enumeration`) and the
cut separation (:mod:`milp.branchprice.cuts`) are numba functions, compiled on their first call and
cached on disk (``cache=True``, in a folder :mod:`milp.core.jit` found writable) for later
processes. A process about to compile them says so once on stderr
(:func:`announce_compiling`).
"""

from __future__ import annotations

import sys

import numpy as np
from numba.core.dispatcher import Dispatcher

from milp.branchprice import cuts, enumeration, ngroute
from milp.core.jit import CACHE_FOLDER

__all__ = ["COMPILE_SECONDS", "ready_within", "compile_rarely_used", "jitted", "compiled", "announce_compiling",
           "COMPILING_MESSAGE"]

#: Seconds to allow for compiling the pricing on its first use, when numba's on-disk cache
#: does not hold it yet (measured 9.9 s on a shared 2-core EPYC, 7.1 s of it the
#: labelling; twice that for slower machines). Later runs load it from the cache in a
#: fraction of a second.
COMPILE_SECONDS = 20.0

#: What :func:`announce_compiling` prints when numba's cache does not hold the functions.
COMPILING_MESSAGE = ("parcover: compiling the branch-and-price pricing code once (about 10-20 s); "
                     "later runs load it from the cache")
#: The same when no folder takes numba's cache (:data:`milp.core.jit.CACHE_FOLDER` is None).
COMPILING_UNCACHED_MESSAGE = ("parcover: compiling the branch-and-price pricing code (about 10-20 s); no "
                              "folder is writable for numba's cache, so every run compiles it (set NUMBA_CACHE_DIR)")
_announced = False


def ready_within(seconds: float | None) -> bool:
    """Whether a solve can start within ``seconds`` (None: no limit): the compiled pricing
    is loaded in this process or held by numba's on-disk cache for the current source,
    or ``seconds`` leaves room to compile it (:data:`COMPILE_SECONDS`)."""
    return seconds is None or seconds >= COMPILE_SECONDS or all(map(compiled, jitted()))


def compile_rarely_used() -> None:
    """Compile the subset-row cut and enumeration functions, which a search may never
    call, on toy arguments of the types a search passes: so that after one solve the
    on-disk cache holds every compiled function and :func:`ready_within` holds."""
    if not all(map(compiled, cuts.KERNELS)):
        cuts.violated_triples(np.zeros((1, 3)), np.zeros(1), 0.05)
    if not all(map(compiled, ngroute.CUT_KERNELS)):
        bits = np.zeros(2, dtype=np.uint64)
        ngroute.cut_coefficients([np.array([1])], bits, bits, 1)
    if not all(map(compiled, enumeration.KERNELS)):
        D = np.array([[0.0, 1.0], [1.0, 0.0]])
        enumeration.routes_within_gap(D, D[:, 0].copy(), np.array([0.0, 1.0]), 2.0, 0.5,
                                      np.ones((2, 2), dtype=bool), np.ones(2, dtype=bool), max_states=10)


def jitted() -> list[Dispatcher]:
    """The compiled functions of the pricing, the route listing and the cut separation,
    as each module lists them (its ``KERNELS``)."""
    return [*ngroute.KERNELS, *enumeration.KERNELS, *cuts.KERNELS]


def compiled(function: Dispatcher) -> bool:
    """Compiled in this process, or in the on-disk cache with the current source's stamp
    (numba's index file is read as numba reads it; any error counts as not cached)."""
    if function.signatures:
        return True
    try:
        return bool(function._cache._cache_file._load_index())
    except Exception:  # numba's cache internals: when they change, assume a compile
        return False


def announce_compiling() -> None:
    """Say on stderr, once per process, that the compiled functions are about to be
    compiled, when some are neither loaded nor in numba's on-disk cache (:func:`compiled`);
    nothing when they are."""
    global _announced
    if _announced:
        return
    _announced = True
    if not all(map(compiled, jitted())):
        print(COMPILING_MESSAGE if CACHE_FOLDER is not None else COMPILING_UNCACHED_MESSAGE, file=sys.stderr,
              flush=True)
