"""``python -m parcover``: the command line."""

from parcover.cli import run

run()
