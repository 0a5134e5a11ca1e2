"""The README's two set-up commands are the ones CI runs."""

from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_ci_runs_the_readme_commands():
    readme = (ROOT / "README.md").read_text().splitlines()
    commands = [line for line in readme[:20] if line.startswith("python3 -m venv")]
    ci = (ROOT / ".ci" / "run").read_text().splitlines()
    assert len(commands) == 2 and commands == [line for line in ci if line.startswith("python3 -m venv")]
