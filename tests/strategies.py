"""Hypothesis strategies for random instances, shared by every test module.

Import as ``from strategies import euclidean_instances`` (pyproject puts tests/ on
the path).
"""

from __future__ import annotations

from hypothesis import strategies as st

from parcover import Instance, Problem
from parcover.generate import random_graph


@st.composite
def euclidean_instances(draw: st.DrawFn, min_n: int = 1, max_n: int = 8) -> Instance:
    """A start and ``min_n..max_n`` KPOIs at integer points of a 100 x 100 square.

    Coincident points (distance 0) can occur, on purpose.
    """
    n = draw(st.integers(min_n, max_n))
    coordinate = st.integers(0, 100)
    points = draw(st.lists(st.tuples(coordinate, coordinate), min_size=n + 1, max_size=n + 1))
    return Instance.from_points(points, name=f"hyp-euclid-{n}")


@st.composite
def graph_instances(draw: st.DrawFn, min_n: int = 1, max_n: int = 8) -> Instance:
    """A random sparse graph with virtual nodes (a non-Euclidean metric)."""
    n = draw(st.integers(min_n, max_n))
    virtual = draw(st.integers(0, 2 * n))
    seed = draw(st.integers(0, 2**16))
    return random_graph(n, seed, virtual=virtual)


def instances(min_n: int = 1, max_n: int = 8) -> st.SearchStrategy[Instance]:
    """Euclidean or graph instances."""
    return st.one_of(euclidean_instances(min_n, max_n), graph_instances(min_n, max_n))


def least_makespan_or_robots(max_robots: int = 4) -> st.SearchStrategy[Problem]:
    """Paths or tours; ``1..max_robots`` robots (least makespan) or none (fewest
    robots at the default deadline)."""
    return st.builds(
        Problem,
        st.sampled_from(["paths", "tours"]),
        robots=st.one_of(st.none(), st.integers(1, max_robots)),
    )
