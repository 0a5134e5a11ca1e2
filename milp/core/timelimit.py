"""One time limit shared by every phase of a solve: the wall clock, by its own name.

A time limit is turned into a :class:`TimeLimit` once, where the work begins (the CLI's
``solve`` command before it reads the instance, or :func:`parcover.solve`), and that
object is handed down: the warm start, the bounds, column generation, model building,
HiGHS and the verifier all ask it how much time is :meth:`~TimeLimit.remaining`, so
their shares add up to the limit instead of each phase starting its own clock.

Functions that take ``time_limit`` accept a number of seconds (counted from the call)
or a :class:`TimeLimit` (shared with the caller); :meth:`TimeLimit.of` reads either. The
moment it ends is :attr:`TimeLimit.ends_at`; code that reads the clock itself (numba's
labelling) takes that number, under the same name. *Deadline* is kept for the problem's
coverage deadline (the paper's :math:`c_p`), never for the wall clock.

A solve can also be stopped before its time is up: :func:`stopping` hands the current
thread an event (set from another thread, e.g. when another entrant of a race has proved
the answer, :func:`milp.race.race_here`), and :func:`stop_requested` is true once it is
set. Code that reads its clock checks it there (:mod:`milp.branchprice`'s search); a
:class:`TimeLimit` of that thread then counts as :meth:`~TimeLimit.expired` with nothing
:meth:`~TimeLimit.remaining`. :func:`interrupt` asks every thread of the process at once:
``parcover solve`` calls it on the first Ctrl-C (:func:`interrupt_stops`), so the solve
ends as at its time limit, with the best routes found and the bound proven so far.
"""

from __future__ import annotations

import os
import signal
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Union

__all__ = ["TimeLimit", "TimeLimitLike", "stopping", "stop_requested", "interrupt", "interrupted",
           "interrupt_stops"]

_STOPS: dict[int, threading.Event] = {}
_INTERRUPTED = threading.Event()


@contextmanager
def stopping(event: threading.Event) -> Iterator[threading.Event]:
    """Within the block, the current thread's work stops once ``event`` is set
    (:func:`stop_requested`); blocks nest, the inner event counting."""
    thread = threading.get_ident()
    outer = _STOPS.get(thread)
    _STOPS[thread] = event
    try:
        yield event
    finally:
        if outer is None:
            _STOPS.pop(thread, None)
        else:
            _STOPS[thread] = outer


def stop_requested() -> bool:
    """Whether the current thread was asked to stop (:func:`stopping`), or the whole
    process (:func:`interrupt`)."""
    event = _STOPS.get(threading.get_ident())
    return _INTERRUPTED.is_set() or (event is not None and event.is_set())


def interrupt() -> None:
    """Ask every thread of this process to stop, as at the end of its time limit."""
    _INTERRUPTED.set()


def interrupted() -> bool:
    """Whether :func:`interrupt` was called (within :func:`interrupt_stops`, by a Ctrl-C)."""
    return _INTERRUPTED.is_set()


@contextmanager
def interrupt_stops(notice: str) -> Iterator[None]:
    """Within the block, the first Ctrl-C (SIGINT) calls :func:`interrupt` and writes
    ``notice`` on stderr, so the work ends as at its time limit with what it has found; a
    second one raises :class:`KeyboardInterrupt` as usual. The interrupt is cleared when
    the block ends. Outside the main thread (where Python runs signal handlers) Ctrl-C
    keeps its usual effect."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def first(signum: int, frame: object) -> None:
        if _INTERRUPTED.is_set():
            raise KeyboardInterrupt
        _INTERRUPTED.set()
        if notice:
            os.write(2, notice.encode() + b"\n")  # not print: the handler may run inside a print

    outer = signal.signal(signal.SIGINT, first)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, outer)
        _INTERRUPTED.clear()


class TimeLimit:
    """The moment (on :func:`time.perf_counter`'s clock) by which work must end.

    Parameters
    ----------
    seconds : float or None
        Time from now; ``None`` for no limit (:meth:`remaining` is then ``None`` and
        :meth:`expired` never true).
    """

    __slots__ = ("ends_at", "seconds")

    def __init__(self, seconds: float | None) -> None:
        self.seconds = None if seconds is None else float(seconds)
        self.ends_at = None if seconds is None else time.perf_counter() + float(seconds)

    @classmethod
    def of(cls, limit: TimeLimitLike) -> TimeLimit:
        """``limit`` itself when it is a TimeLimit, else a new one ``limit`` seconds from now."""
        return limit if isinstance(limit, TimeLimit) else cls(limit)

    @property
    def unlimited(self) -> bool:
        """Whether there is no limit at all."""
        return self.ends_at is None

    def remaining(self) -> float | None:
        """Seconds left (never negative), or ``None`` without a limit."""
        if stop_requested():
            return 0.0
        return None if self.ends_at is None else max(self.ends_at - time.perf_counter(), 0.0)

    def expired(self) -> bool:
        """Whether the time is spent (or the work asked to stop: :func:`stopping`)."""
        return stop_requested() or (self.ends_at is not None and time.perf_counter() >= self.ends_at)

    def fraction(self, share: float) -> TimeLimit:
        """A time limit ending after ``share`` (0 to 1) of the time now remaining."""
        left = self.remaining()
        return TimeLimit(None if left is None else share * left)

    def earlier(self, seconds: float) -> TimeLimit:
        """A time limit ending ``seconds`` before this one (for work that must follow)."""
        left = self.remaining()
        return TimeLimit(None if left is None else max(left - seconds, 0.0))

    def __repr__(self) -> str:
        left = self.remaining()
        return "TimeLimit(unlimited)" if left is None else f"TimeLimit({left:.3f} s left)"


#: What a ``time_limit`` parameter accepts: seconds from the call, a shared :class:`TimeLimit`, or none.
TimeLimitLike = Union[float, int, TimeLimit, None]

#: The former name of :class:`TimeLimit` (``milp.deadline.Deadline``), kept for old imports.
Deadline = TimeLimit
