"""The greedy-scaling and maps-speed benchmark sections: quick paths on tiny inputs, the fit, the targets.

No test depends on how fast the machine is: the numbers checked are the fit on synthetic
times, the memory of a known allocation, and the consistency of the tables.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from benchmarks import greedy_scaling, maps_speed
from benchmarks.common import Config


def config(tmp_path) -> Config:
    return Config(quick=True, figures=tmp_path, figures_link="figs", log=lambda line: None)


def test_growth_exponent_of_power_laws():
    n = [500, 1000, 2000, 5000]
    assert greedy_scaling.growth_exponent(n, [3e-7 * x**2 for x in n]) == pytest.approx(2.0)
    assert greedy_scaling.growth_exponent(n, [0.01 * x for x in n]) == pytest.approx(1.0)


def test_growth_exponent_ignores_sizes_below_the_fit_range():
    # 100 and 200 are far off the n^2 trend but below 500, so the slope stays 2.
    n = [100, 200, 500, 1000, 5000]
    seconds = [1.0, 1.0, 0.25, 1.0, 25.0]  # (n / 1000)^2 from 500 on
    assert greedy_scaling.growth_exponent(n, seconds) == pytest.approx(2.0)
    assert greedy_scaling.growth_exponent(n, seconds, least=100) < 2.0


def test_growth_exponent_needs_two_sizes():
    assert math.isnan(greedy_scaling.growth_exponent([100, 200, 500], [1.0, 2.0, 3.0]))


def test_peak_memory_sees_a_numpy_allocation():
    # 2**20 float64 = 8 MiB, held until the call returns.
    assert greedy_scaling.peak_memory(lambda: np.ones(2**20).sum()) >= 8.0


def test_target_line_names_the_slowest_against_algorithm_1():
    frame = pd.DataFrame({
        "method": ["Alg 1 (paper)", "nn (c_max)", "kni (c_max)", greedy_scaling.BUILD],
        "n": [5000] * 4,
        "seconds": [0.1, 0.5, 3.0, 9.0],  # the build is not a method: not the slowest
    })
    line = greedy_scaling.target_line(frame)
    assert "not met" in line and "2 of 3" in line
    assert "slowest kni (c_max) 3.00 s (30x" in line
    frame.loc[2, "seconds"] = 1.5
    assert ": met" in greedy_scaling.target_line(frame)


def test_quick_path_on_tiny_sizes(tmp_path, monkeypatch):
    monkeypatch.setattr(greedy_scaling, "QUICK_SIZES", (6, 12))
    section = greedy_scaling.run(config(tmp_path))
    frame = section.tables["greedy_scaling"]
    names = [greedy_scaling.BUILD, *greedy_scaling.methods()]
    assert len(frame) == 2 * len(names)
    assert set(frame["method"]) == set(names)
    assert (frame["seconds"] > 0).all() and (frame["peak_mib"] >= 0).all()
    # Every route count is possible: 1..n robots, at most 10 with K = 10.
    routes = frame[frame["method"] != greedy_scaling.BUILD]
    assert ((routes["routes"] >= 1) & (routes["routes"] <= routes["n"])).all()
    assert (routes[routes["method"].str.endswith("(K=10)")]["routes"] <= 10).all()
    # The summary's exponent is the fit of the long table's times (all sizes in a quick run).
    wide = section.tables["greedy_scaling_summary"].set_index("method")
    for name in names:
        rows = frame[frame["method"] == name].sort_values("n")
        expected = math.log(rows["seconds"].iloc[1] / rows["seconds"].iloc[0]) / math.log(2)
        assert wide.loc[name, "exponent"] == pytest.approx(expected)
    assert (tmp_path / "greedy_scaling.png").is_file()
    assert "](figs/greedy_scaling.png)" in section.markdown
    assert section.targets == ["5,000 KPOIs under 2 s on one core: not measured (quick run, largest n = 12)"]


def test_maps_speed_quick_on_a_small_map(tmp_path, monkeypatch):
    monkeypatch.setattr(maps_speed, "QUICK", (("simple_rooms.png", 0.05),))
    monkeypatch.setattr(maps_speed, "QUICK_KPOIS", (4,))
    section = maps_speed.run(config(tmp_path))
    frame = section.tables["maps_speed"].set_index("graph")
    assert list(frame.index) == ["decomposition", "visibility"]
    assert (frame["kpois"] == 4).all() and (frame["seconds"] > 0).all()
    # Visibility distances are true shortest paths: the decomposition's are never shorter.
    assert frame.loc["decomposition", "ratio_median"] >= 1 - 1e-9
    assert frame.loc["decomposition", "ratio_max"] >= frame.loc["decomposition", "ratio_median"]
    assert frame.loc["visibility", "ratio_max"] == 1.0
    assert len(section.targets) == 1 and "quick run: 4 KPOIs" in section.targets[0]
