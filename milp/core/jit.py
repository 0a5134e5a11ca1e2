"""numba's ``njit`` with an on-disk cache wherever parcover is installed.

``@njit(cache=True)`` functions (:mod:`milp.branchprice.ngroute`, :mod:`milp.branchprice.enumeration`,
:mod:`milp.branchprice.cuts`) are compiled once and loaded by later processes from numba's cache.
numba writes it to the first writable of: ``NUMBA_CACHE_DIR``; the ``__pycache__``
folder next to the source (a user's own install); the user's cache folder
(``$XDG_CACHE_HOME/numba`` or ``~/.cache/numba``; a system-wide install). When none of
them is writable numba refuses to define the functions at all; then this module points
``NUMBA_CACHE_DIR`` at :func:`fallback_folder` (a folder of this user's in the temporary
directory), and only when that is not writable either compiles in every process,
without a cache (:data:`CACHE_FOLDER` is None).

This module must be imported before numba compiles or caches anything: the modules
above take ``njit`` from here.
"""

from __future__ import annotations

import getpass
import os
import tempfile
from collections.abc import Callable, Iterable
from typing import Any

import numba
import numpy as np
from numba.misc.appdirs import AppDirs

__all__ = ["njit", "compiled_layout", "CACHE_FOLDER", "writable_folder", "numba_folders", "fallback_folder"]


def numba_folders() -> list[str]:
    """The folders numba would cache this package's functions in, in its order of preference."""
    folders = [numba.config.CACHE_DIR] if numba.config.CACHE_DIR else []
    return [*folders, os.path.join(os.path.dirname(os.path.abspath(__file__)), "__pycache__"),
            AppDirs(appname="numba", appauthor=False).user_cache_dir]


def fallback_folder() -> str:
    """This user's cache folder in the temporary directory, when numba has none."""
    return os.path.join(tempfile.gettempdir(), f"parcover-numba-{getpass.getuser()}")


def writable_folder(folders: Iterable[str]) -> str | None:
    """The first of ``folders`` that exists or can be made and takes a file, as numba tests it."""
    for folder in folders:
        try:
            os.makedirs(folder, exist_ok=True)
            tempfile.TemporaryFile(dir=folder).close()
        except OSError:
            continue
        return folder
    return None


def _choose_cache_folder() -> str | None:
    """Where the compiled functions are cached, setting ``NUMBA_CACHE_DIR`` (for numba and
    child processes) to :func:`fallback_folder` when numba has no writable folder."""
    folder = writable_folder(numba_folders())
    if folder is not None:
        return folder
    try:
        folder = writable_folder([fallback_folder()])
    except (KeyError, OSError):  # getpass found no user name
        folder = None
    if folder is not None:
        os.environ["NUMBA_CACHE_DIR"] = numba.config.CACHE_DIR = folder
    return folder


#: The folder numba caches compiled functions in (None: no writable folder, no cache).
CACHE_FOLDER = _choose_cache_folder()


def njit(*args: Any, **options: Any) -> Callable[..., Any]:
    """:func:`numba.njit`, its ``cache=True`` dropped when no folder takes a cache."""
    if CACHE_FOLDER is None:
        options["cache"] = False
    return numba.njit(*args, **options)


def compiled_layout(array: Any, dtype: Any) -> np.ndarray:
    """``array`` as the one kind of array the compiled functions take: C-contiguous,
    writable, of ``dtype``. numba compiles (and caches) a separate version of a function
    for each layout and for read-only arrays (an ``Instance``'s distances are read-only),
    so arguments of another kind would compile again inside a solve's time limit, after
    :mod:`milp.branchprice.compiling` found the function ready. Copies only when needed."""
    array = np.ascontiguousarray(array, dtype=dtype)
    return array if array.flags.writeable else array.copy()
