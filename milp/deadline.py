"""One deadline shared by every phase of a solve.

A time limit is turned into a :class:`Deadline` once, where the work begins (the CLI's
``solve`` command before it reads the instance, or :func:`parcover.solve`), and that
object is handed down: the warm start, the bounds, column generation, model building,
HiGHS and the verifier all ask it how much time is :meth:`~Deadline.remaining`, so
their shares add up to the limit instead of each phase starting its own clock.

Functions that take ``time_limit`` accept a number of seconds (counted from the call)
or a :class:`Deadline` (shared with the caller); :meth:`Deadline.of` reads either.
"""

from __future__ import annotations

import time
from typing import Union

__all__ = ["Deadline", "TimeLimit"]


class Deadline:
    """The moment (on :func:`time.perf_counter`'s clock) by which work must end.

    Parameters
    ----------
    seconds : float or None
        Time from now; ``None`` for no limit (:meth:`remaining` is then ``None`` and
        :meth:`expired` never true).
    """

    __slots__ = ("at", "seconds")

    def __init__(self, seconds: float | None) -> None:
        self.seconds = None if seconds is None else float(seconds)
        self.at = None if seconds is None else time.perf_counter() + float(seconds)

    @classmethod
    def of(cls, limit: TimeLimit) -> Deadline:
        """``limit`` itself when it is a Deadline, else a new one ``limit`` seconds from now."""
        return limit if isinstance(limit, Deadline) else cls(limit)

    @property
    def unlimited(self) -> bool:
        """Whether there is no limit at all."""
        return self.at is None

    def remaining(self) -> float | None:
        """Seconds left (never negative), or ``None`` without a limit."""
        return None if self.at is None else max(self.at - time.perf_counter(), 0.0)

    def expired(self) -> bool:
        """Whether the time is spent."""
        return self.at is not None and time.perf_counter() >= self.at

    def fraction(self, share: float) -> Deadline:
        """A deadline ending after ``share`` (0 to 1) of the time now remaining."""
        left = self.remaining()
        return Deadline(None if left is None else share * left)

    def earlier(self, seconds: float) -> Deadline:
        """A deadline ``seconds`` before this one (for work that must follow)."""
        left = self.remaining()
        return Deadline(None if left is None else max(left - seconds, 0.0))

    def __repr__(self) -> str:
        left = self.remaining()
        return "Deadline(unlimited)" if left is None else f"Deadline({left:.3f} s left)"


#: What a ``time_limit`` parameter accepts: seconds from the call, a shared deadline, or none.
TimeLimit = Union[float, int, Deadline, None]
