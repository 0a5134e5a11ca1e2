"""Every committed counterexample shows, through solve() and through its question block
(`parcover props --check`), a greedy worse than the optimum.

File names are ``<claim>-<method>.json`` as written by ``parcover props``; the claim
says which question to ask (paper, Section V).
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import parcover as pc

FOLDER = Path(__file__).resolve().parents[1] / "instances" / "counterexamples"
FILES = sorted(FOLDER.glob("*.json"))
#: The worst instances of `parcover worst` carry their question the same way.
CHECKED = FILES + sorted((FOLDER.parent / "worst").glob("*.json"))
NAME = re.compile(r"^(alg1|alg1-1-x(?P<factor>[\d.]+)|alg2-robots|alg2-makespan)-(?P<method>paper.*)$")


@pytest.mark.parametrize("path", FILES, ids=[p.stem for p in FILES])
def test_counterexample_refutes_its_claim(path):
    match = NAME.match(path.stem)
    assert match, f"unexpected counterexample file {path.name}"
    instance, method = pc.load(path), match["method"]
    if path.stem.startswith("alg2"):
        # Algorithm 2 as published: tours, no deadline; it reaches makespan M with R tours
        greedy = pc.solve(instance, "tours", method=method)
        if path.stem.startswith("alg2-robots"):
            exact = pc.solve(instance, "tours", deadline=greedy.makespan, method="setpart")
            assert exact.status is pc.Status.OPTIMAL and exact.robots < greedy.robots
        else:
            exact = pc.solve(instance, "tours", robots=greedy.robots, method="setpart")
            assert exact.status is pc.Status.OPTIMAL and exact.makespan < greedy.makespan * (1 - 1e-9)
        return
    deadline = instance.c_max * float(match["factor"] or 1)
    greedy = pc.solve(instance, deadline=deadline, method=method)
    exact = pc.solve(instance, deadline=deadline, method="setpart")
    assert exact.status is pc.Status.OPTIMAL and exact.robots < greedy.robots


@pytest.mark.parametrize("path", CHECKED, ids=[f"{p.parent.name}/{p.stem}" for p in CHECKED])
def test_props_check_reproduces_the_refutation(path, capsys):
    from parcover.cli import main
    from parcover.question import load

    _, question = load(path)
    assert question is not None and question.claim == path.stem  # the file answers its own claim's question
    code = main(["props", "--check", str(path)])
    out = capsys.readouterr().out
    assert code == 0 and "verdict: refuted" in out, out
