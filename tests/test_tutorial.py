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


# -- the prose quotes the outputs ---------------------------------------------------------------

QUOTE = re.compile(r"`([^`\n]+)`")


def _sections() -> list[str]:
    return re.split(r"^## ", TUTORIAL.read_text(), flags=re.M)[1:]


def _quoted_numbers(section: str) -> list[str]:
    """Quotes in the prose (outside code blocks) that hold a digit, file names and command
    lines aside: what the page says the commands printed."""
    prose = re.sub(r"```.*?```", "", section, flags=re.S)
    quotes = QUOTE.findall(prose)
    return [q for q in quotes if re.search(r"\d", q) and "/" not in q and not q.startswith(("parcover ", "--"))]


def _collapsed(text: str) -> str:
    return " ".join(text.split())


def test_the_check_of_quotes_can_fail():
    assert _quoted_numbers("## x\nwe got `robots 3` from `parcover solve a.json` in `instances/x1.json`\n") == [
        "robots 3"]


@pytest.mark.parametrize("number", range(len(_sections())))
def test_quoted_numbers_are_what_the_commands_print(number):
    section = _sections()[number]
    quotes = _quoted_numbers(section)
    commands = [body.partition("\n")[0][2:] for kind, body in BLOCK.findall(section) if kind == "console"]
    if not quotes:
        return
    assert commands, f"section {section.splitlines()[0]!r} quotes {quotes} but runs no command"
    printed = _collapsed("\n".join(_run(command) for command in commands))
    missing = [q for q in quotes if _collapsed(q) not in printed]
    assert not missing, f"section {section.splitlines()[0]!r}: not printed by its commands: {missing}"
