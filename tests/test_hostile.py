"""Hostile input: every user mistake is one line and exit status 2 on the
command line, an InputError in the API; never a traceback, never a silent answer.

Broken instance files are in ``tests/data/bad`` and read in ``test_io.py``; this module
covers what reaches the readers from elsewhere (arbitrary values, special files), the
command line's output files, the API's arguments and the start-up cost.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import warnings
from importlib.metadata import version
from pathlib import Path

import networkx as nx
import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

import parcover as pc
from parcover.cli import main
from parcover.io import instance_from_dict

ROOT = Path(__file__).resolve().parents[1]
GRID = str(ROOT / "instances" / "fig1_grid.json")
BAD = Path(__file__).parent / "data" / "bad"


def _run(capsys, argv: list[str]) -> tuple[int, str, str]:
    """main()'s status (whether it returns it or argparse exits with it), stdout, stderr."""
    try:
        code = main(argv)
    except SystemExit as exc:
        code = int(exc.code or 0)
    out, err = capsys.readouterr()
    return code, out, err


def _refused(capsys, argv: list[str], message: str) -> None:
    code, _, err = _run(capsys, argv)
    assert code == 2, err
    assert message in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err


# -- the command line ---------------------------------------------------------------


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["solve", GRID, "--plot", "{tmp}/missing/r.png"], "no folder"),  # matplotlib would raise deep inside
        (["solve", GRID, "--plot", "{tmp}/r.txt"], "must end in one of .png"),  # no such drawing format
        (["frontier", GRID, "--plot", "{tmp}/f.txt"], "must end in one of .png"),  # same for frontier
        (["solve", GRID, "--export-model", "{tmp}/missing/m.mps"], "no folder"),  # HiGHS said "None"
        (["solve", GRID, "--export-model", "{tmp}/m.txt"], "must end in .mps or .lp"),  # no such model format
        (["solve", GRID, "--out", "{tmp}"], "is a folder"),  # a result file, not a folder
        (["generate", "random", "--seed", "-1"], "--seed: must be >= 0"),  # numpy refuses negative seeds
        (["solve", GRID, "--seed", "-1"], "--seed: must be >= 0"),  # one rule for every seed
        (["solve", "{tmp}/x.tsp"], "is a directory"),  # a folder named like a TSPLIB file
        (["solve", "/dev/zero"], "not a regular file"),  # a device never ends: reading it fills memory
        (["verify", GRID, "/dev/zero"], "not a regular file"),  # same for solution files
        (["report", "grid:rows=2:cols=2", "--out", "{tmp}/report.md"], "needs a folder"),  # an existing file
    ],
)
def test_bad_command_lines_exit_2_with_one_line(capsys, tmp_path, argv, message):
    (tmp_path / "x.tsp").mkdir()
    (tmp_path / "report.md").write_text("keep me")
    _refused(capsys, [a.replace("{tmp}", str(tmp_path)) for a in argv], message)
    assert (tmp_path / "report.md").read_text() == "keep me"


def test_a_fifo_is_refused_without_blocking(tmp_path):
    # opening a FIFO for reading blocks until a writer comes: the reader must not open it
    fifo = tmp_path / "instance.json"
    os.mkfifo(fifo)
    done = subprocess.run(
        [sys.executable, "-m", "parcover", "solve", str(fifo)], capture_output=True, text=True, timeout=60
    )
    assert done.returncode == 2 and "not a regular file" in done.stderr and done.stderr.count("\n") == 1


def test_an_instance_too_large_for_memory_is_refused_before_allocating(capsys, tmp_path, monkeypatch):
    # 2000 points need 3 x 2001^2 x 8 bytes (96 MB) to build the distances; allow 1 MB
    monkeypatch.setenv("PARCOVER_MEMORY_LIMIT", "1MB")
    path = tmp_path / "big.json"
    points = {"s": [0, 0], **{f"k{i}": [i, i % 7] for i in range(1, 2001)}}
    path.write_text(json.dumps({"start": "s", "kpois": list(points)[1:], "coordinates": points}))
    _refused(capsys, ["solve", str(path)], "An instance of 2000 KPOIs needs about 98.1 MB of memory, more than the "
             "1.0 MB allowed by PARCOVER_MEMORY_LIMIT")


def test_out_is_never_the_instance(capsys, tmp_path):
    # the result would overwrite the instance it came from
    path = tmp_path / "grid.json"
    text = Path(GRID).read_text()
    path.write_text(text)
    _refused(capsys, ["solve", str(path), "--out", str(path)], "is the instance file")
    assert path.read_text() == text


def test_a_bad_plot_path_leaves_no_result_behind(capsys, tmp_path):
    # the plot path is checked before --out is written: nothing half done
    out = tmp_path / "r.json"
    _refused(capsys, ["solve", GRID, "--out", str(out), "--plot", str(tmp_path / "r.txt")], "must end in")
    assert not out.exists()


@pytest.mark.parametrize(("command", "drawing"), [("solve", "plot_routes"), ("frontier", "plot_frontier")])
def test_a_failing_drawing_is_one_line_and_leaves_no_result(capsys, tmp_path, monkeypatch, command, drawing):
    # the drawing comes before --out: a refused write (here: permission) leaves nothing half done
    import parcover.plot

    def denied(*args, **kwargs):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(parcover.plot, drawing, denied)
    out = tmp_path / "r.json"
    argv = [command, GRID, "--method", "trivial", "--out", str(out), "--plot", str(tmp_path / "r.png")]
    _refused(capsys, argv, "Permission denied")
    assert not out.exists()


def test_out_is_written_atomically(capsys, tmp_path, monkeypatch):
    # a failure while writing (here: os.replace, as on a full disk) leaves the old file whole
    out = tmp_path / "r.json"
    out.write_text("the good result")

    def full_disk(src, dst):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "replace", full_disk)
    _refused(capsys, ["solve", GRID, "--method", "trivial", "--out", str(out)], "No space left on device")
    assert out.read_text() == "the good result" and sorted(p.name for p in tmp_path.iterdir()) == ["r.json"]


def test_out_replaces_an_existing_file_whole(capsys, tmp_path):
    out = tmp_path / "r.json"
    out.write_text("x" * 100_000)  # longer than the result: an in-place write would leave a tail
    assert _run(capsys, ["solve", GRID, "--method", "trivial", "--out", str(out)])[0] == 0
    assert json.loads(out.read_text())["method"] == "trivial"


@pytest.mark.parametrize("method", ["nn", "paper", "best", "mst", "exact"])
def test_large_valid_numbers_give_strict_json(capsys, tmp_path, method):
    # the largest coordinates still accepted (1e140): results stay finite JSON (nn printed Infinity)
    path = tmp_path / "far.json"
    path.write_text(json.dumps({"start": "s", "kpois": ["a", "b", "c"], "coordinates": {
        "s": [0, 0], "a": [1e140, 0], "b": [0, 1e140], "c": [1e140, 1e140]}}))
    code, out, err = _run(capsys, ["solve", str(path), "--robots", "2", "--method", method, "--json"])
    assert code == 0, err
    result = json.loads(out, parse_constant=lambda name: pytest.fail(f"{name} in the result JSON"))
    # two robots: s-a-c and s-b (or mirrored) cost 2e140 each at best; no method can do better
    assert math.isfinite(result["makespan"]) and result["makespan"] >= 2e140 * (1 - 1e-9)


def test_a_deeply_nested_solution_file_is_refused(capsys, tmp_path):
    path = tmp_path / "deep.json"
    path.write_text("[" * 100_000 + "]" * 100_000)
    _refused(capsys, ["verify", GRID, str(path)], "nested too deeply")


def test_version_is_the_package_version(capsys):
    code, out, _ = _run(capsys, ["--version"])
    assert code == 0 and out.strip() == f"parcover {version('parcover')}"


# -- the readers: arbitrary JSON values in every field ------------------------------

_json_values = st.recursive(
    # integers beyond 2**1024 have no float (JSON allows them); floats from tiny to huge
    st.none() | st.booleans() | st.integers() | st.integers(min_value=2**1024) | st.floats() | st.text(max_size=5),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=3), inner, max_size=4),
    max_leaves=12,
)
_VALID = {
    "name": "ok",
    "start": "s",
    "kpois": ["a", "b"],
    "coordinates": {"s": [0, 0], "a": [3, 4], "b": [0, 1]},
    "edges": [["s", "a", 5], ["a", "b", 5], ["s", "b"]],
    "map": {"image": "m.png", "metres_per_pixel": 0.5, "origin": [0, 0]},
    "metric": "euclidean",
}


def _places(value: object, at: tuple = ()) -> list[tuple]:
    """Every place in a JSON value (keys and list positions down to each leaf)."""
    inside = value.items() if isinstance(value, dict) else enumerate(value) if isinstance(value, list) else ()
    return [at, *(p for key, child in inside for p in _places(child, (*at, key)))]


def _replaced(data: object, place: tuple, value: object) -> object:
    if not place:
        return value
    copy = dict(data) if isinstance(data, dict) else list(data)  # type: ignore[call-overload]
    copy[place[0]] = _replaced(copy[place[0]], place[1:], value)
    return copy


@given(place=st.sampled_from(_places(_VALID)[1:]), value=_json_values)
def test_any_json_value_anywhere_is_an_instance_or_one_line(place, value):
    # each field, coordinate, edge end and weight of a valid file replaced by any JSON value
    data = _replaced(_VALID, place, value)
    try:
        inst = instance_from_dict(data)
    except pc.InputError as exc:
        assert "\n" not in str(exc)
    else:
        assert np.all(np.isfinite(inst.distances))


def _accepted_coordinate(x: object) -> bool:
    """The rule, restated for a start at (0, 1) and one KPOI at (x, 0): a Python number
    with a finite float, whose longest route (2 (n + 1) = 4 distances) has a finite square."""
    if type(x) not in (int, float):
        return False
    try:
        route = 4 * math.hypot(float(x), 1)
    except OverflowError:
        return False
    return math.isfinite(route * route)


@given(x=st.one_of(st.integers(), st.floats(), st.text(max_size=4), st.booleans(), st.lists(st.integers(), max_size=3)))
def test_any_coordinate_value_is_a_number_or_refused(x):
    data = {"start": "s", "kpois": ["a"], "coordinates": {"s": [0, 1], "a": [x, 0]}}
    try:
        inst = instance_from_dict(data)
    except pc.InputError:
        assert not _accepted_coordinate(x)
    else:
        assert _accepted_coordinate(x) and inst.distance("s", "a") == math.hypot(x, 1)


@given(text=st.text(max_size=200))
def test_any_file_text_is_an_instance_or_one_line(tmp_path_factory, text):
    path = tmp_path_factory.mktemp("text") / "any.json"
    path.write_text(text, encoding="utf-8")
    try:
        pc.load(path)
    except pc.FileFormatError as exc:
        assert "\n" not in str(exc)


_OPTION_VALUES = st.one_of(
    st.text(max_size=6),
    st.integers(-10**400, 10**400).map(str),
    st.floats().map(repr),
    st.sampled_from(["", "-1", "0", "nan", "inf", "-inf", "1e308", "1e-320", "paths", "tours", "tsplib"]),
)


@settings(suppress_health_check=[HealthCheck.function_scoped_fixture], deadline=None, max_examples=60)
@given(options=st.lists(st.tuples(st.sampled_from(
    ["--robots", "--deadline", "--routes", "--time-limit", "--seed", "--distance"]), _OPTION_VALUES), max_size=3))
@example(options=[("--deadline", "1e308")])  # robots x deadline overflowed: a RuntimeWarning on stderr
def test_any_solve_options_give_an_answer_or_one_line(capsys, options):
    # any value, of any option, any number of times: an answer (0) or one line (2), no traceback
    argv = ["solve", GRID, "--method", "nn", *(word for pair in options for word in pair)]
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a warning is a line of noise on the user's screen
        code, _, err = _run(capsys, argv)
    assert "Traceback" not in err
    assert code in (0, 2), err
    if code == 2:
        assert len(err.strip().splitlines()) == 1, err


# -- the API ------------------------------------------------------------------------


def test_numpy_scalars_are_numbers_everywhere():
    inst = pc.Instance("s", ("a", "b"), edges=(("s", "a", np.float64(1.5)), ("a", "b", np.float32(0.5)),
                                              ("s", "b", np.int64(3))))
    # s-a 1.5 then a-b 0.5: b is 2 away through a, less than the 3 of the direct edge
    assert inst.distance("s", "b") == 2.0
    xy = pc.Instance("s", ("a",), coordinates={"s": np.array([0, 0]), "a": (np.int64(3), np.float32(4))})
    assert xy.c_max == 5.0
    # one robot covers a then b: makespan 2 (by hand above); the robot limit is a numpy integer
    assert pc.solve(inst, robots=np.int64(1), time_limit=np.float64(5), seed=np.int64(0)).makespan == 2.0
    assert pc.solve(inst, deadline=np.float32(2.0)).robots == 1


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda g: pc.solve(g, robots=2, seed="a"), "seed must be a whole number"),  # a seed is a number
        (lambda g: pc.solve(g, robots=2, seed=-1), "seed must be a whole number >= 0"),  # numpy refuses it
        (lambda g: pc.solve(g, robots=2, time_limit="3"), "time limit must be a positive number"),  # text
        (lambda g: pc.solve(g, robots=2, time_limit=math.inf), "time limit must be a positive number"),  # no limit is None
        (lambda g: pc.solve(g, robots=True), "robot limit must be a whole number"),  # a bool is not a count
        (lambda g: pc.solve(g, deadline=10**400), "deadline must be finite"),  # no float holds it
        (lambda g: pc.solve(g, robots=2, time_limit=10**400), "time limit must be a positive number"),  # same
        (lambda g: pc.solve(g, method=["exact"]), "Unknown method"),  # a name, not a list
        (lambda g: pc.solve(GRID), "read a file with pc.load"),  # a path, not an instance
        (lambda g: pc.solve(5), "Expected an Instance"),  # not an instance at all
        (lambda g: pc.load(5), "Expected a file path"),  # not a path
        (lambda g: pc.verify(5, [["s"]]), "Expected an Instance"),  # was AttributeError: no .start
        (lambda g: pc.solve(g, robots=2, export_model="no/such/m.mps"), "no folder no/such"),  # said "None"
        (lambda g: pc.generate.random_points(3, seed=-1), "seed must be a whole number >= 0"),  # numpy refuses it
        (lambda g: pc.generate.star(3, radius="1"), "radius must be a positive number"),  # text, not a number
        (lambda g: pc.generate.random_graph(3, size=-1), "size must be a positive number"),  # was not checked
        (lambda g: pc.Instance.from_points([[0, 0], [1, 0], [0, 1]], names=["a", "a", "b"]),
         "Duplicate name 'a'"),  # the start would move and a point vanish
        (lambda g: pc.Instance.from_points([[0, 0], [1, 0]], start=True), "must be a row number"),  # not a row
        (lambda g: pc.Instance.from_networkx([(0, 1)], 0, [1]), "Expected a networkx graph"),  # an edge list
        (lambda g: pc.Instance.from_networkx(nx.Graph([(0, 1, {"weight": 1})]), 0, 1), "iterable of graph nodes"),
        (lambda g: pc.Instance.from_points([[10**400, 0], [0, 0]]), "Points must be numbers"),  # no float holds it
        (lambda g: pc.Instance("s", ("a",), edges=(("s", "a", 10**400),)), "too large for a float"),  # no float
        (lambda g: pc.Instance("s", ("a",), edges=(("s", "a", np.bool_(True)),)), "non-numeric weight"),  # a flag
    ],
)
def test_bad_api_arguments_raise_input_error(fig1_grid, call, message):
    with pytest.raises(pc.InputError, match=message):
        call(fig1_grid)


@pytest.mark.parametrize("method", ["best", "paper", "nn", "exact"])
def test_more_robots_than_kpois_is_the_question_with_n_robots(fig1_grid, method):
    # `best` laid out one route per robot: robots=10**9 never finished. A robot more than
    # KPOIs covers nothing, so the answer is the one with n robots (checked by exact).
    many = pc.solve(fig1_grid, robots=10**9, method=method)
    assert many.robots_limit == 10**9
    assert many.makespan == pc.solve(fig1_grid, robots=fig1_grid.n, method="exact").makespan


def test_a_blinked_insertion_keeps_the_robot_limit():
    # ruin and recreate skips each slot with probability 1 %: with few slots all could be
    # skipped, and the KPOI went to a new route. `best --time-limit 1 --robots 2` on 3
    # KPOIs ran enough rounds to meet it: 3 routes, a SolverError traceback.
    from parcover.algorithms.moves import Search
    from parcover.problem import Problem

    class Blink:  # every slot skipped
        def random(self) -> float:
            return 0.0

    square = pc.Instance.from_points([[0, 0], [1, 0], [0, 1], [1, 1]])
    search = Search(square, Problem("paths", robots=2))
    seqs = [[0, 1, 4], [0, 4]]  # KPOI 1 on route 1, route 2 empty (4 is the path end)
    assert search.insert(seqs, 2, allow_new=True, rng=Blink())
    assert len(seqs) == 2 and sorted(v for s in seqs for v in s[1:-1]) == [1, 2]


def test_best_answers_at_once_when_no_construction_fits(monkeypatch):
    # no construction started before the stop and ours (O(n^2)) would not fit: at 3000
    # KPOIs ours then ran 14 s inside `exact --time-limit 3`; the nearest neighbour answers
    from parcover.algorithms import starts
    from parcover.problem import Problem

    def too_slow(*args, **kwargs):
        raise AssertionError("min_max_insertion ran although it does not fit")

    monkeypatch.setattr(starts, "min_max_insertion", too_slow)
    monkeypatch.setattr(starts, "_INSERTION_SECONDS", 1e6)  # never fits
    inst = pc.generate.random_points(30, seed=1)
    for problem in (Problem("paths", robots=3), Problem("tours")):
        name, routes = starts.best_construction(inst, problem, time_limit=1e-9, seed=0)
        assert name == "nn" and sorted(v for r in routes for v in r) == list(range(1, 31))


def test_from_networkx_takes_a_generator_of_kpois():
    # the KPOIs were read twice, the second time from an exhausted generator: "no KPOI"
    g = nx.path_graph(4)
    nx.set_edge_attributes(g, 1, "weight")
    inst = pc.Instance.from_networkx(g, 0, (v for v in (1, 2, 3)))
    assert inst.kpois == ("1", "2", "3") and inst.c_max == 3


def _digraph(weights: dict[tuple[int, int], float]) -> nx.DiGraph:
    g = nx.DiGraph()
    for (u, v), w in weights.items():
        g.add_edge(u, v, weight=w)
    return g


@pytest.mark.parametrize(
    ("weights", "message"),
    [
        ({(0, 1): 1, (1, 0): 5}, "weighs 1 but 1 -> 0 weighs 5"),  # which way is the map?
        ({(0, 1): 1}, "has no reverse edge"),  # a one-way street in an undirected world
    ],
)
def test_asymmetric_digraphs_are_refused(weights, message):
    with pytest.raises(pc.InstanceError, match=message):
        pc.Instance.from_networkx(_digraph(weights), 0, [1])


def test_a_symmetric_digraph_is_its_undirected_graph():
    inst = pc.Instance.from_networkx(_digraph({(0, 1): 2, (1, 0): 2}), 0, [1])
    assert inst.distance("0", "1") == 2


# -- start-up -----------------------------------------------------------------------

_HEAVY = ("cvxpy", "matplotlib", "pandas", "skimage", "shapely", "dask", "numba")


def test_a_small_solve_loads_no_heavy_optional_package():
    # `import milp` loaded cvxpy (1 s) and parcover.instance scipy: `parcover solve` of a
    # tiny instance took 2 s for a 0.004 s solve. Only the methods that need them may import them.
    code = (
        "import sys\n"
        "from parcover.cli import main\n"
        f"main(['solve', {GRID!r}, '--robots', '2'])\n"
        f"print(sorted(m for m in {_HEAVY!r} if m in sys.modules))\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True)
    assert done.stdout.strip().splitlines()[-1] == "[]"


def test_import_parcover_loads_no_solver():
    # the command line's --help, --version, generate and verify need no MILP solver
    code = "import sys, parcover.cli; print(sorted(m for m in ('cvxpy', 'highspy', 'scipy') if m in sys.modules))"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True)
    assert done.stdout.strip() == "[]"
