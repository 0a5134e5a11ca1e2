"""Compiled once: numba's cache lives in a folder the install can
write (a fallback when it cannot), and the first compile says so on stderr, once."""

from __future__ import annotations

import os
import subprocess
import sys
import time

import numba
import numpy as np
import pytest
from numba.core.dispatcher import Dispatcher

from milp.branchprice import compiling, cuts, enumeration, ngroute
from milp.core import jit


@pytest.fixture
def fresh_process(monkeypatch):
    """This process as if it had not yet looked at the compiled functions."""
    monkeypatch.setattr(compiling, "_announced", False)


@pytest.mark.parametrize(("cached", "said"), [(False, compiling.COMPILING_MESSAGE), (True, "")])
def test_the_compile_is_announced_once_on_stderr_and_only_when_it_happens(capsys, monkeypatch, fresh_process,
                                                                          cached, said):
    monkeypatch.setattr(compiling, "compiled", lambda function: cached)
    compiling.announce_compiling()
    compiling.announce_compiling()
    out, err = capsys.readouterr()
    assert out == "" and err == (said + "\n" if said else "")


def test_the_message_says_when_nothing_can_be_cached(capsys, monkeypatch, fresh_process):
    monkeypatch.setattr(compiling, "compiled", lambda function: False)
    monkeypatch.setattr(compiling, "CACHE_FOLDER", None)
    compiling.announce_compiling()
    assert capsys.readouterr().err == compiling.COMPILING_UNCACHED_MESSAGE + "\n"


@pytest.mark.parametrize("module", [ngroute, enumeration, cuts], ids=lambda module: module.__name__)
def test_each_module_lists_exactly_the_compiled_functions_it_defines(module):
    # the list is what compiling checks and compiles, so a new kernel left out of it would go unseen
    defined = [f for f in vars(module).values()
               if isinstance(f, Dispatcher) and f.py_func.__module__ == module.__name__]
    assert len(module.KERNELS) == len(set(module.KERNELS)) and set(module.KERNELS) == set(defined)


def test_every_compiled_function_of_the_three_modules_is_checked_once():
    found = {f for module in (ngroute, enumeration, cuts) for f in vars(module).values() if isinstance(f, Dispatcher)}
    assert sorted(f.__name__ for f in compiling.jitted()) == sorted(f.__name__ for f in found)


def test_the_rarely_used_functions_are_the_cut_and_enumeration_ones(monkeypatch):
    asked = []
    monkeypatch.setattr(compiling, "compiled", lambda function: asked.append(function) or True)
    compiling.compile_rarely_used()
    assert [f.__name__ for f in asked] == ["violated_triples", "_cut_counts", "_extend", "_first_shortest", "_row_hash", "_same_row", "_table_size",
                                                   "_extension_lengths"]


def test_the_first_writable_folder_is_chosen(tmp_path):
    assert jit.writable_folder(["/dev/null/cache", str(tmp_path / "a" / "b")]) == str(tmp_path / "a" / "b")
    assert jit.writable_folder(["/dev/null/cache"]) is None


def test_without_a_folder_numba_can_write_the_cache_goes_to_the_fallback(tmp_path, monkeypatch):
    # numba would raise "cannot cache function ...: no locator available" at import
    monkeypatch.setattr(jit, "numba_folders", lambda: ["/dev/null/numba", "/dev/null/pycache"])
    monkeypatch.setattr(jit, "fallback_folder", lambda: str(tmp_path / "fallback"))
    monkeypatch.setattr(numba.config, "CACHE_DIR", numba.config.CACHE_DIR)
    monkeypatch.setenv("NUMBA_CACHE_DIR", "")
    assert jit._choose_cache_folder() == str(tmp_path / "fallback")
    assert os.environ["NUMBA_CACHE_DIR"] == numba.config.CACHE_DIR == str(tmp_path / "fallback")
    monkeypatch.setattr(jit, "fallback_folder", lambda: "/dev/null/fallback")
    assert jit._choose_cache_folder() is None


def test_without_any_folder_functions_compile_uncached(monkeypatch):
    monkeypatch.setattr(jit, "CACHE_FOLDER", None)
    add = jit.njit(cache=True)(lambda x: x + 1)
    assert add(1) == 2 and type(add._cache).__name__ == "NullCache"


def _solve(instance: str, cache: str) -> tuple[subprocess.CompletedProcess, float]:
    began = time.monotonic()
    done = subprocess.run(
        [sys.executable, "-m", "parcover", "solve", instance, "--method", "branchprice", "--robots", "3"],
        env={**os.environ, "NUMBA_CACHE_DIR": cache}, capture_output=True, text=True, timeout=600, check=True,
    )
    return done, time.monotonic() - began


@pytest.mark.slow
def test_a_second_process_loads_the_compiled_pricing_from_the_cache(tmp_path):
    # measured on a shared 2-core machine: 39 s cold (load 4), 2.9 s warm
    instance = tmp_path / "r26.json"
    subprocess.run([sys.executable, "-m", "parcover", "generate", "random", "--n", "26", "--seed", "5",
                    "--out", str(instance)], check=True)
    cache = str(tmp_path / "numba")
    first, _ = _solve(str(instance), cache)
    assert first.stderr.count(compiling.COMPILING_MESSAGE) == 1 and compiling.COMPILING_MESSAGE not in first.stdout
    second, seconds = _solve(str(instance), cache)
    def answer(done: subprocess.CompletedProcess) -> list[str]:
        return [line for line in done.stdout.splitlines() if not line.startswith("time")]

    assert "compiling" not in second.stderr and answer(second) == answer(first)
    assert seconds < 10, seconds


def test_read_only_and_strided_arguments_reuse_the_compiled_functions():
    """An Instance's distances are read-only and a node's end column is a strided view;
    numba would compile a second version of each function for them, inside a solve's
    time limit and after ``ready_within`` found the functions ready."""
    from parcover.generate import random_points

    shared = random_points(10, 1).distances
    assert not shared.flags.writeable
    m1 = len(shared)
    prize = np.concatenate(([0.0], np.full(m1 - 1, 0.3)))
    budget = 2 * float(shared[0].max())

    def run(D: np.ndarray, allowed: np.ndarray, can_end: np.ndarray) -> None:
        ngroute.Pricing(D, tours=True, ng_size=4).price(prize, budget, allowed=allowed, can_end=can_end, exact=True)
        enumeration.routes_within_gap(D, D[:, 0], prize, budget, 0.5, allowed, can_end, max_states=1000)

    allowed = np.ones((m1, m1), dtype=bool)
    run(np.array(shared), allowed, np.ones(m1, dtype=bool))
    before = {function: set(function.signatures) for function in compiling.jitted()}
    run(shared, np.asfortranarray(allowed), allowed[:, 0])
    assert {function: set(function.signatures) for function in compiling.jitted()} == before
