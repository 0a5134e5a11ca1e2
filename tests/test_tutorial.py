"""docs/tutorial.md runs: every console command's output matches, every Python block passes.

Set PARCOVER_UPDATE_DOCS=1 to rewrite the shown outputs from a real run (then review
the diff): the page only ever shows what the tool printed.
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
TUTORIAL = ROOT / "docs" / "tutorial.md"
BLOCK = re.compile(r"```(console|python)\n(.*?)```", re.S)
VOLATILE = re.compile(r"^time\s+[\d.]+ s$")  # wall-clock times differ run to run


def _blocks() -> list[tuple[str, str]]:
    return BLOCK.findall(TUTORIAL.read_text())


def _run(command: str) -> str:
    argv = shlex.split(command)
    assert argv[0] == "parcover", command
    done = subprocess.run(
        [sys.executable, "-m", "parcover", *argv[1:]], cwd=ROOT, capture_output=True, text=True
    )
    assert done.returncode == 0, f"{command}: {done.stderr}"
    return done.stdout


ROUTE = re.compile(r"^\s*robot\s+\d+\s+cost\s+(\S+)\s")
EXACT = re.compile(r"^method\s+(exact|setpart|cvxpy)$", re.M)


def _comparable(text: str) -> list[str]:
    """Lines to compare: no wall-clock times; for exact methods, whose optimal routes can
    tie, route lines reduce to their sorted costs."""
    lines = [line.rstrip() for line in text.strip().splitlines() if not VOLATILE.match(line.strip())]
    if not EXACT.search(text):
        return lines
    costs = sorted(m.group(1) for line in lines if (m := ROUTE.match(line)))
    return [line for line in lines if not ROUTE.match(line)] + [f"route cost {c}" for c in costs]


@pytest.mark.parametrize("number", [i for i, (kind, _) in enumerate(_blocks()) if kind == "console"])
def test_console_block(number):
    body = _blocks()[number][1]
    command, _, shown = body.partition("\n")
    assert command.startswith("$ "), body
    printed = _run(command[2:])
    if os.environ.get("PARCOVER_UPDATE_DOCS"):
        text = TUTORIAL.read_text()
        TUTORIAL.write_text(text.replace(body, f"{command}\n{printed.rstrip()}\n", 1))
        return
    assert _comparable(printed) == _comparable(shown)


def test_python_blocks(monkeypatch):
    monkeypatch.chdir(ROOT)
    namespace: dict[str, object] = {}
    for kind, body in _blocks():
        if kind == "python":
            exec(compile(body, str(TUTORIAL), "exec"), namespace)
