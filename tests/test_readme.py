"""The README's set-up commands are the ones CI runs, and its examples run.

- The two set-up commands at the top are the ones ``.ci/run`` runs.
- Every ``console`` block's command prints what the README shows (as in
  ``tests/test_tutorial.py``: wall-clock times aside, and for exact methods the choice
  among tied optimal routes).
- The Python example runs (its assertions check the values it states).
"""

import re
import subprocess
import sys
from pathlib import Path

import pytest

from test_tutorial import _comparable, _run

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
BLOCK = re.compile(r"```(console|python)\n(.*?)```", re.S)


def test_ci_runs_the_readme_commands():
    readme = README.read_text().splitlines()
    commands = [line for line in readme[:20] if line.startswith("python3 -m venv")]
    ci = (ROOT / ".ci" / "run").read_text().splitlines()
    assert len(commands) == 2 and commands == [line for line in ci if line.startswith("python3 -m venv")]


def _blocks(kind: str) -> list[str]:
    return [body for k, body in BLOCK.findall(README.read_text()) if k == kind]


def test_the_readme_has_its_examples():
    assert len(_blocks("console")) >= 2 and len(_blocks("python")) == 1


@pytest.mark.parametrize("number", range(len(_blocks("console"))))
def test_console_block(number):
    command, _, shown = _blocks("console")[number].partition("\n")
    assert command.startswith("$ parcover "), command
    assert _comparable(_run(command[2:])) == _comparable(shown)


def test_python_example_runs():
    done = subprocess.run([sys.executable, "-c", _blocks("python")[0]], cwd=ROOT, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
