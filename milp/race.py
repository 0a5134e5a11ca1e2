"""Exact methods side by side: the first to prove its answer wins.

Used where no method dominates: with 2-3 long routes branch-and-price
(:mod:`milp.branchprice`) and branch-and-cut (:mod:`milp.branchcut`) each prove some
questions in seconds that the other does not prove in minutes (``milp/README.md``).

:func:`race` runs every entrant in a fresh interpreter (``python -m milp.race``, the
question pickled on its standard input, the answer on its standard output): unlike
``multiprocessing`` this never imports the caller's main script again, nor inherits the
HiGHS thread pool of the parent without its threads. An entrant ends with its parent
(:mod:`milp.core.orphans`): a killed solve leaves none running. Every entrant gets the
same time limit; the race ends when one proves its answer (the others are stopped), when
every entrant has answered, or when the time is up. Entrants run in a session of their
own, out of reach of the terminal's Ctrl-C; when the parent is interrupted
(:func:`milp.core.timelimit.interrupt`) it tells each one on its standard input, and
each answers with what it has, as at its time limit.

:func:`race_here` runs one entrant in the caller's process and thread, from the first
second to the last (it is never restarted), and the others as :func:`race` does, started
after ``others_after`` seconds unless the first has answered by then. A watching thread
reads the others' answers; when one proves, it sets the stop of
:func:`milp.core.timelimit.stopping`, which the entrant here reads where it reads its
clock (branch-and-price between pricing rounds and nodes), so it ends within a round.
"""

from __future__ import annotations

import importlib
import json
import logging
import os
import pickle
import selectors
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import IO, Any

from milp.core import progress
from milp.core.orphans import exit_with_parent
from milp.core.result import MilpResult
from milp.core.timelimit import interrupt, interrupted, stopping

__all__ = ["race", "race_here", "Entrant", "cores", "share_cores", "hand_over", "handed_reader", "START_SECONDS"]

#: Seconds kept back from an entrant's time limit for starting its interpreter (imports:
#: 0.5-0.8 s measured) and sending its answer back.
START_SECONDS = 1.5
log = logging.getLogger(__name__)

#: Seconds the race waits past the time limit for an answer before stopping an entrant.
GRACE_SECONDS = 1.0
#: Seconds between two looks at whether this process was interrupted, while it waits.
INTERRUPT_POLL_SECONDS = 0.25


def cores() -> int:
    """Cores this process may run on: its CPU affinity, divided among the sibling
    processes that share it (:func:`share_cores`), at least 1."""
    available = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    return max(1, available // _sharing)


#: Processes sharing this process's cores (:func:`share_cores`).
_sharing = 1


def share_cores(processes: int) -> None:
    """Count this process as one of ``processes`` that share its cores (a pool's workers,
    each solving its own question): :func:`cores` divides them, so that the workers do not
    each start a race on every core."""
    global _sharing
    _sharing = max(1, processes)


class Entrant:
    """One method answering in a fresh interpreter (``python -m milp.race``).

    Parameters
    ----------
    name : str
        The entrant's name, for the log and the answers.
    target : str
        ``"module:function"`` returning a :class:`~milp.core.result.MilpResult`.
    args, kwargs
        Passed to the function (picklable); ``time_limit`` is added.
    time_limit : float or None
        The function's time limit (seconds).
    """

    def __init__(self, name: str, target: str, args: tuple, kwargs: dict[str, Any], time_limit: float | None) -> None:
        self.name = name
        self.answer: MilpResult | None = None
        self._output = b""
        self._errors = tempfile.TemporaryFile()
        environment, log_fd = progress.entrant_environment(name)
        try:
            self.process = subprocess.Popen([sys.executable, "-m", "milp.race", str(os.getpid())],
                                            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=self._errors,
                                            env=environment, pass_fds=() if log_fd is None else (log_fd,),
                                            start_new_session=True)
        except BaseException:
            self._errors.close()
            raise
        finally:
            if log_fd is not None:
                os.close(log_fd)
        log.info("race: %s started (pid %d, %s)", name, self.process.pid,
                 "no time limit" if time_limit is None else f"{time_limit:.1f} s")
        # stdin stays open: its end asks the entrant to stop (interrupt)
        self.process.stdin.write(pickle.dumps((target, args, {**kwargs, "time_limit": time_limit})))
        self.process.stdin.flush()

    @property
    def running(self) -> bool:
        """Whether its answer is still to come."""
        return self.process.returncode is None

    def read(self) -> MilpResult | None:
        """Read what its standard output holds (call when it is readable); the answer once
        the entrant has ended, else None.

        Raises
        ------
        RuntimeError
            If the entrant failed (its error output is in the message).
        """
        chunk = os.read(self.process.stdout.fileno(), 1 << 20)
        if chunk:
            self._output += chunk
            return None
        self.process.stdout.close()
        self.process.wait()
        if self.process.returncode != 0 or not self._output:
            self._errors.seek(0)
            raise RuntimeError(f"{self.name} failed (exit status {self.process.returncode}): {self._errors.read().decode(errors='replace')[-2000:]}")
        self.answer = pickle.loads(self._output)
        log.info("race: %s answered %s, value %s, bound %s", self.name, self.answer.status,
                 _number(self.answer.objective), _number(self.answer.bound))
        return self.answer

    def interrupt(self) -> None:
        """Ask it to stop and answer with what it has: close its standard input."""
        _close(self.process.stdin)

    def stop(self) -> None:
        """End it (if it runs) and release its files."""
        if self.process.returncode is None:
            self.process.kill()
            self.process.wait()
        _close(self.process.stdin)
        _close(self.process.stdout)
        self._errors.close()


def hand_over(path: str | Path, value: Any) -> None:
    """Hand ``value`` (routes, a proven bound: anything JSON writes) to the entrant that
    reads ``path`` (:func:`handed_reader`): written beside it first and then put in its
    place, so a reader never sees half."""
    written = Path(f"{path}.part")
    written.write_text(json.dumps(value))
    os.replace(written, path)


def handed_reader(path: str | Path) -> Callable[[], Any | None]:
    """What reads the values another entrant hands over at ``path`` (:func:`hand_over`):
    each call returns the last one when it was written since the last call, else None
    (nothing written yet, or nothing new). Cheap enough to call between two pricing
    rounds: a ``stat`` when nothing is new."""
    path, seen = Path(path), {"stamp": None}

    def read() -> Any | None:
        try:
            stat = path.stat()
        except FileNotFoundError:
            return None
        stamp = (stat.st_mtime_ns, stat.st_size, stat.st_ino)
        if stamp == seen["stamp"]:
            return None
        seen["stamp"] = stamp
        return json.loads(path.read_text())

    return read


def _close(stream: IO[bytes]) -> None:
    """Close a pipe to or from an entrant, which may have ended."""
    if not stream.closed:
        try:
            stream.close()
        except BrokenPipeError:  # the entrant has ended: nothing was waiting to be read
            pass


def race(entrants: dict[str, str], args: tuple, kwargs: dict[str, Any],
         time_limit: float | None) -> dict[str, MilpResult]:
    """Run ``function(*args, time_limit=..., **kwargs)`` for each entrant, side by side.

    Parameters
    ----------
    entrants : dict
        Name -> ``"module:function"`` (a function returning a
        :class:`~milp.core.result.MilpResult`, e.g. ``"milp.branchcut:min_makespan"``).
    args, kwargs
        Passed to every entrant (picklable).
    time_limit : float or None
        Seconds for the whole race; each entrant gets this less :data:`START_SECONDS`.

    Returns
    -------
    dict
        Name -> answer, for the entrants that answered in time: only the winner's when
        one proved its answer (status ``optimal`` or ``infeasible``).

    Raises
    ------
    RuntimeError
        If an entrant failed (its error output is in the message).
    """
    began = time.perf_counter()
    limit = _entrant_limit(time_limit)
    started: list[Entrant] = []
    try:
        for name, target in entrants.items():
            started.append(Entrant(name, target, args, kwargs, limit))
        ends_at = None if time_limit is None else began + time_limit + GRACE_SECONDS
        return _answers(started, ends_at)
    finally:
        for entrant in started:
            entrant.stop()


def _entrant_limit(time_limit: float | None) -> float | None:
    """An entrant's time limit in a race of ``time_limit`` seconds."""
    return None if time_limit is None else max(time_limit - START_SECONDS, 0.1)


def _answers(entrants: list[Entrant], ends_at: float | None, until: threading.Event | None = None,
             poll: float | None = None) -> dict[str, MilpResult]:
    """The entrants' answers as they arrive, until one proves (then its answer alone),
    every one has answered, ``ends_at`` (a :func:`time.perf_counter` value) passes, or
    ``until`` is set (looked at every ``poll`` seconds). Once this process is
    interrupted, so is every entrant."""
    answers: dict[str, MilpResult] = {}
    poll = INTERRUPT_POLL_SECONDS if poll is None else min(poll, INTERRUPT_POLL_SECONDS)
    with selectors.DefaultSelector() as selector:
        for entrant in entrants:
            if entrant.running:
                selector.register(entrant.process.stdout, selectors.EVENT_READ, entrant)
        while selector.get_map() and not (until is not None and until.is_set()):
            if interrupted():
                for entrant in entrants:
                    entrant.interrupt()
            left = None if ends_at is None else ends_at - time.perf_counter()
            if left is not None and left <= 0:
                break
            wait = poll if left is None else min(poll, left)
            for key, _ in selector.select(timeout=wait):
                entrant = key.data
                answer = entrant.read()
                if answer is None:
                    continue
                selector.unregister(key.fileobj)
                if answer.status in ("optimal", "infeasible"):
                    others = [e.name for e in entrants if e.running]
                    if others:
                        log.info("race: %s proved it; stopping %s", entrant.name, ", ".join(others))
                    return {entrant.name: answer}
                answers[entrant.name] = answer
    return answers


#: Seconds between two looks of :func:`race_here`'s watching thread at the entrant here.
WATCH_SECONDS = 0.1


def race_here(name: str, function: Callable[..., MilpResult], others: dict[str, str], args: tuple,
              kwargs: dict[str, Any], time_limit: float | None, *, others_after: float = 0.0,
              others_kwargs: dict[str, Any] | None = None) -> dict[str, MilpResult]:
    """Run ``function(*args, time_limit=..., **kwargs)`` here, against ``others`` elsewhere.

    Parameters
    ----------
    name, function
        The entrant run in this process and thread, for the whole ``time_limit``; it
        must read :func:`milp.core.timelimit.stop_requested` where it reads its clock
        (:mod:`milp.branchprice` does).
    others : dict
        Name -> ``"module:function"``, each run as in :func:`race`, started
        ``others_after`` seconds from now unless ``function`` has returned by then, with
        the time then left (less :data:`START_SECONDS`).
    args, kwargs
        Passed to every entrant; ``others_kwargs`` (default ``kwargs``) to the others.
    time_limit : float or None
        Seconds for the whole race.

    Returns
    -------
    dict
        Name -> answer, as :func:`race`: only the winner's when one proved its answer.

    Raises
    ------
    RuntimeError
        If an entrant failed.
    """
    began = time.perf_counter()
    ends_at = None if time_limit is None else began + time_limit
    # done: the entrant here returned; parked: the watcher reads no more; released: the
    # watcher may end. It outlives its entrants: on Linux they are killed when the thread
    # that started them ends (milp.core.orphans' PR_SET_PDEATHSIG follows the thread).
    proved, done, parked, released = (threading.Event() for _ in range(4))
    started: list[Entrant] = []
    found: dict[str, MilpResult] = {}
    failed: list[BaseException] = []

    def watch() -> None:
        try:
            if done.wait(others_after):
                return
            left = None if ends_at is None else ends_at - time.perf_counter()
            if interrupted() or (left is not None and left <= START_SECONDS + 1.0):
                return
            for other, target in others.items():
                started.append(Entrant(other, target, args, {**(others_kwargs or kwargs)}, _entrant_limit(left)))
            answers = _answers(started, None, until=done, poll=WATCH_SECONDS)
            found.update(answers)
            if any(a.status in ("optimal", "infeasible") for a in answers.values()):
                log.info("race: %s proved it; stopping %s here", next(iter(answers)), name)
                proved.set()
        except BaseException as exc:  # noqa: BLE001 - handed to the caller's thread
            failed.append(exc)
            proved.set()
        finally:
            parked.set()
            released.wait()

    watcher = threading.Thread(target=watch, name="milp-race-watch", daemon=True)
    try:
        with stopping(proved):
            watcher.start()
            answer = function(*args, time_limit=time_limit, **kwargs)
        done.set()
        parked.wait()
        if failed:
            raise RuntimeError(str(failed[0])) from failed[0]
        if answer.status in ("optimal", "infeasible") and not proved.is_set():
            if any(e.running for e in started):
                log.info("race: %s proved it; stopping %s", name, ", ".join(e.name for e in started if e.running))
            return {name: answer}
        if any(a.status in ("optimal", "infeasible") for a in found.values()):
            return dict(found)
        rest = _answers([e for e in started if e.running],
                        None if ends_at is None else ends_at + GRACE_SECONDS)
        if any(a.status in ("optimal", "infeasible") for a in rest.values()):
            return rest
        return {name: answer, **found, **rest}
    finally:
        done.set()
        if watcher.is_alive():
            parked.wait(timeout=5.0)
        for entrant in started:
            entrant.stop()
        released.set()
        if watcher.is_alive():
            watcher.join(timeout=5.0)


def _number(value: float | None) -> str:
    return "none" if value is None else f"{value:.6g}"


def _main() -> None:
    """Entrant: read ``(target, args, kwargs)`` pickled from stdin, write the answer pickled
    to stdout (the solvers' own output, if any, goes to stderr). It ends with the process
    that started it, whose id is its argument (:func:`milp.core.orphans.exit_with_parent`)."""
    exit_with_parent(int(sys.argv[1]))
    target, args, kwargs = pickle.load(sys.stdin.buffer)
    threading.Thread(target=_interrupt_on_input, name="milp-race-interrupt", daemon=True).start()
    progress.log_as_entrant()
    answer_fd = os.dup(1)
    os.dup2(2, 1)
    module, function = target.split(":")
    answer = getattr(importlib.import_module(module), function)(*args, **kwargs)
    with os.fdopen(answer_fd, "wb") as out:
        out.write(pickle.dumps(answer))


def _interrupt_on_input() -> None:
    """Entrant: stop the work (:func:`milp.core.timelimit.interrupt`) once the parent
    closes its standard input (:meth:`Entrant.interrupt`)."""
    os.read(sys.stdin.fileno(), 1)  # the file descriptor: a buffered read's lock would stall the exit
    interrupt()


if __name__ == "__main__":
    _main()
