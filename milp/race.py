"""Exact methods side by side, one process each: the first to prove its answer wins.

Used where no method dominates: with 2-3 long routes branch-and-price
(:mod:`milp.branchprice`) and branch-and-cut (:mod:`milp.branchcut`) each prove some
questions in seconds that the other does not prove in minutes (``milp/README.md``).
Each entrant runs in a fresh interpreter (``python -m milp.race``, the question pickled
on its standard input, the answer on its standard output): unlike ``multiprocessing``
this never imports the caller's main script again, nor inherits the HiGHS thread pool
of the parent without its threads. An entrant ends with its parent (:mod:`milp.core.orphans`):
a killed solve leaves none running. Every entrant gets the same time limit; the race
ends when one proves its answer (the others are stopped), when every entrant has
answered, or when the time is up.
"""

from __future__ import annotations

import importlib
import logging
import os
import pickle
import selectors
import subprocess
import sys
import tempfile
import time
from typing import Any

from milp.core import progress
from milp.core.orphans import exit_with_parent
from milp.core.result import MilpResult

__all__ = ["race", "cores", "START_SECONDS"]

#: Seconds kept back from an entrant's time limit for starting its interpreter (imports:
#: 0.5-0.8 s measured) and sending its answer back.
START_SECONDS = 1.5
log = logging.getLogger(__name__)

#: Seconds the race waits past the time limit for an answer before stopping an entrant.
GRACE_SECONDS = 1.0


def cores() -> int:
    """Cores this process may run on."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)


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
    limit = None if time_limit is None else max(time_limit - START_SECONDS, 0.1)
    selector = selectors.DefaultSelector()
    running: dict[str, subprocess.Popen] = {}
    errors: dict[str, Any] = {}
    output: dict[str, bytes] = {}
    answers: dict[str, MilpResult] = {}
    try:
        for name, target in entrants.items():
            errors[name] = tempfile.TemporaryFile()
            environment, log_fd = progress.entrant_environment(name)
            try:
                process = subprocess.Popen([sys.executable, "-m", "milp.race", str(os.getpid())],
                                           stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=errors[name],
                                           env=environment, pass_fds=() if log_fd is None else (log_fd,))
            finally:
                if log_fd is not None:
                    os.close(log_fd)
            log.info("race: %s started (pid %d, %s)", name, process.pid,
                     "no time limit" if limit is None else f"{limit:.1f} s")
            process.stdin.write(pickle.dumps((target, args, {**kwargs, "time_limit": limit})))
            process.stdin.close()
            running[name] = process
            output[name] = b""
            selector.register(process.stdout, selectors.EVENT_READ, name)
        while selector.get_map():
            left = None if time_limit is None else time_limit + GRACE_SECONDS - (time.perf_counter() - began)
            if left is not None and left <= 0:
                break
            for key, _ in selector.select(timeout=left):
                name = key.data
                chunk = os.read(key.fd, 1 << 20)
                if chunk:
                    output[name] += chunk
                    continue
                selector.unregister(key.fileobj)
                process = running.pop(name)
                process.wait()
                if process.returncode != 0 or not output[name]:
                    errors[name].seek(0)
                    raise RuntimeError(f"{name} failed: {errors[name].read().decode(errors='replace')[-2000:]}")
                answer = pickle.loads(output[name])
                log.info("race: %s answered %s, value %s, bound %s", name, answer.status,
                         _number(answer.objective), _number(answer.bound))
                if answer.status in ("optimal", "infeasible"):
                    if running:
                        log.info("race: %s proved it; stopping %s", name, ", ".join(running))
                    return {name: answer}
                answers[name] = answer
    finally:
        selector.close()
        for process in running.values():
            process.kill()
            process.wait()
        for file in errors.values():
            file.close()
    return answers


def _number(value: float | None) -> str:
    return "none" if value is None else f"{value:.6g}"


def _main() -> None:
    """Entrant: read ``(target, args, kwargs)`` pickled from stdin, write the answer pickled
    to stdout (the solvers' own output, if any, goes to stderr). It ends with the process
    that started it, whose id is its argument (:func:`milp.core.orphans.exit_with_parent`)."""
    exit_with_parent(int(sys.argv[1]))
    target, args, kwargs = pickle.load(sys.stdin.buffer)
    progress.log_as_entrant()
    answer_fd = os.dup(1)
    os.dup2(2, 1)
    module, function = target.split(":")
    answer = getattr(importlib.import_module(module), function)(*args, **kwargs)
    with os.fdopen(answer_fd, "wb") as out:
        out.write(pickle.dumps(answer))


if __name__ == "__main__":
    _main()
