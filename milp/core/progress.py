"""Progress lines of a long solve, through :mod:`logging`: quiet unless asked.

Every module logs to a logger under ``"milp"`` (and parcover's under ``"parcover"``) at
level INFO, one line an event: a phase starting, a new incumbent, a new bound with the
gap, nodes, the winner of a race. Nothing is printed until a handler is attached, by the
caller's own logging set-up (``logging.basicConfig(level=logging.INFO)``) or by
:func:`log_to_stderr`, which ``parcover solve --log`` calls. The entrants of
:mod:`milp.race` run in other processes; :func:`entrant_environment` passes them the
parent's stream and clock, so their lines arrive on the same stderr, in one time scale.
"""

from __future__ import annotations

import logging
import os
import sys
import time
from typing import TextIO

__all__ = ["log_to_stderr", "logging_enabled", "entrant_environment", "log_as_entrant", "Every",
           "PROGRESS_SECONDS"]

#: Environment variables an entrant reads: the parent's log file descriptor, its clock and
#: the entrant's name.
FD_VARIABLE, EPOCH_VARIABLE, NAME_VARIABLE = "MILP_LOG_FD", "MILP_LOG_EPOCH", "MILP_LOG_NAME"
#: The loggers :func:`log_to_stderr` opens by default.
LOGGERS = ("parcover", "milp")
#: Seconds between two progress lines of a long loop (a branching tree, a column generation).
PROGRESS_SECONDS = 10.0


class Every:
    """When the next progress line of a long loop is due: :data:`PROGRESS_SECONDS` after
    the loop began or after the last line, and only when ``logger`` prints INFO lines."""

    def __init__(self, logger: logging.Logger) -> None:
        self.logger = logger
        self.last = time.perf_counter()

    def due(self) -> bool:
        """Whether a line is due now (the next one is then counted from now)."""
        now = time.perf_counter()
        if now - self.last < PROGRESS_SECONDS or not self.logger.isEnabledFor(logging.INFO):
            return False
        self.last = now
        return True


class _ElapsedFormatter(logging.Formatter):
    """``  12.34 s  [prefix] message``: seconds since ``epoch`` (a :func:`time.time` value)."""

    def __init__(self, epoch: float, prefix: str = "") -> None:
        super().__init__()
        self.epoch, self.prefix = epoch, prefix

    def format(self, record: logging.LogRecord) -> str:
        return f"{record.created - self.epoch:8.2f} s  {self.prefix}{record.getMessage()}"


def log_to_stderr(names: tuple[str, ...] = LOGGERS, *, stream: TextIO | None = None,
                  epoch: float | None = None, prefix: str = "") -> None:
    """Print the INFO lines of the loggers ``names`` on ``stream`` (default stderr), each
    with the seconds since ``epoch`` (default now). Calling it again replaces the handler."""
    handler = logging.StreamHandler(sys.stderr if stream is None else stream)
    handler.setFormatter(_ElapsedFormatter(time.time() if epoch is None else epoch, prefix))
    handler.set_name("milp.core.progress")
    for name in names:
        logger = logging.getLogger(name)
        for old in [h for h in logger.handlers if h.get_name() == "milp.core.progress"]:
            logger.removeHandler(old)
        logger.addHandler(handler)
        logger.setLevel(logging.INFO)


def logging_enabled() -> bool:
    """Whether the ``milp`` loggers print INFO lines (a race then asks its entrants to)."""
    return logging.getLogger("milp").isEnabledFor(logging.INFO)


def entrant_environment(name: str) -> tuple[dict[str, str], int | None]:
    """The environment for an entrant process ``name`` that logs as this one does, its
    lines prefixed with its name, and the file descriptor it inherits (to be passed with
    ``pass_fds`` and closed after the start); this process's environment and None when
    nothing is logged."""
    if not logging_enabled():
        return dict(os.environ), None
    handler = next((h for name in LOGGERS for h in logging.getLogger(name).handlers
                    if isinstance(h, logging.StreamHandler) and isinstance(h.formatter, _ElapsedFormatter)), None)
    stream = sys.stderr if handler is None else handler.stream
    epoch = time.time() if handler is None else handler.formatter.epoch  # type: ignore[union-attr]
    stream.flush()
    fd = os.dup(stream.fileno())
    return {**os.environ, FD_VARIABLE: str(fd), EPOCH_VARIABLE: repr(epoch), NAME_VARIABLE: name}, fd


def log_as_entrant() -> None:
    """In an entrant: log as the parent asked (:func:`entrant_environment`), if it did."""
    fd = os.environ.get(FD_VARIABLE)
    if fd is None:
        return
    stream = os.fdopen(int(fd), "w", buffering=1)
    log_to_stderr(("milp",), stream=stream, epoch=float(os.environ[EPOCH_VARIABLE]),
                  prefix=f"[{os.environ.get(NAME_VARIABLE, 'entrant')}] ")
