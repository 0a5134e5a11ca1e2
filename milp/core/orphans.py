"""Child processes that end with their parent: no orphans.

A child process calls :func:`exit_with_parent` first (``parcover report``'s pool workers
as their initializer, :mod:`milp.race`'s entrants on start). When its parent ends, by any
signal, SIGKILL included, the child ends too instead of running on under init:

- on Linux the kernel kills it at once (``prctl(PR_SET_PDEATHSIG, SIGKILL)``), even
  while it runs compiled code that holds the GIL;
- everywhere a daemon thread compares :func:`os.getppid` with the parent it started
  with every :data:`POLL_SECONDS` and ends the process (:func:`os._exit`) when it
  changed (the child was handed to init or a subreaper).
"""

from __future__ import annotations

import ctypes
import os
import signal
import sys
import threading
import time

__all__ = ["exit_with_parent", "watch_parent", "POLL_SECONDS", "ORPHAN_STATUS"]

#: Seconds between two looks at the parent process.
POLL_SECONDS = 0.5
#: Exit status of a child that ended because its parent was gone.
ORPHAN_STATUS = 70
_PR_SET_PDEATHSIG = 1


def exit_with_parent(parent: int | None = None) -> None:
    """End this process soon after its parent process ends.

    Parameters
    ----------
    parent
        The parent's process id as the parent saw it (its :func:`os.getpid`), to catch
        a parent that ended before this call; None when the process that started this
        one is not the one to follow (a forkserver's child follows the forkserver,
        which ends with its own parent).
    """
    _ask_the_kernel()
    if parent is not None and os.getppid() != parent:
        os._exit(ORPHAN_STATUS)
    watch_parent()


def watch_parent() -> threading.Thread:
    """Start the daemon thread that ends this process once :func:`os.getppid` changes
    (the portable half of :func:`exit_with_parent`)."""
    started_with = os.getppid()

    def watch() -> None:
        while os.getppid() == started_with:
            time.sleep(POLL_SECONDS)
        os._exit(ORPHAN_STATUS)

    thread = threading.Thread(target=watch, name="exit-with-parent", daemon=True)
    thread.start()
    return thread


def _ask_the_kernel() -> None:
    """On Linux, have the kernel send SIGKILL to this process when its parent ends."""
    if not sys.platform.startswith("linux"):
        return
    try:
        ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    except (OSError, AttributeError):  # no libc symbol: the watching thread remains
        pass
