"""Small named instances that every test module can use."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import settings

from parcover import Instance, generate

settings.register_profile("ci", max_examples=40, deadline=None, derandomize=True)
settings.register_profile("dev", max_examples=40, deadline=None)
settings.load_profile("ci")

ROOT = Path(__file__).resolve().parent.parent
INSTANCES = ROOT / "instances"


@pytest.fixture(scope="session")
def fig1_grid() -> Instance:
    """The paper's Fig. 1: a 3x3 grid, start in the upper left corner; c_max = 4."""
    return generate.grid(3, 3)


@pytest.fixture(scope="session")
def fig3_star() -> Instance:
    """The paper's Fig. 3: 6 KPOIs on a unit circle around the start (a hexagon)."""
    return generate.star(6)


@pytest.fixture(scope="session")
def tiny_line() -> Instance:
    """Start at 0 and KPOIs at 1, 2 and 3 on a line: easy to reason about by hand."""
    return Instance.from_points([[0, 0], [1, 0], [2, 0], [3, 0]], names=["s", "a", "b", "c"], name="line")
