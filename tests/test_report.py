"""Gap reports: rows against a reference, the CSV, resume, executors, report.md."""

from __future__ import annotations

import itertools
import json
import math

import pandas as pd
import pytest

from parcover import InputError, MethodInfo, Solution, Status, generate, report
from parcover.problem import meets_deadline
from parcover.solve import METHODS, available_methods, register_method, solve

TIMING = list(report.TIMING_COLUMNS)


# ---------------------------------------------------------------- test-only methods
# Module-level, so worker processes (forked, or Dask's, which share sys.path) can
# unpickle them by reference.


def _best_route_costs(instance, tours):
    """Cheapest route over every subset of KPOI indices, by trying every order."""
    d = instance.distances
    best = {}
    for size in range(1, instance.n + 1):
        for subset in itertools.combinations(range(1, instance.n + 1), size):
            options = []
            for order in itertools.permutations(subset):
                cost = d[0, order[0]] + sum(d[a, b] for a, b in zip(order, order[1:]))
                options.append((cost + (d[order[-1], 0] if tours else 0.0), list(order)))
            best[frozenset(subset)] = min(options)
    return best


def _partitions(items):
    """Every partition of the list ``items`` into non-empty blocks."""
    if not items:
        yield []
        return
    first, rest = items[0], items[1:]
    for partition in _partitions(rest):
        yield [[first], *partition]
        for i in range(len(partition)):
            yield [*partition[:i], [first, *partition[i]], *partition[i + 1 :]]


def brute_force(instance, problem, *, time_limit=None, seed=0):
    """Proven optimum by trying every partition and every order (n <= 6)."""
    best = _best_route_costs(instance, problem.tours)
    deadline = problem.effective_deadline(instance)
    answers = []
    for partition in _partitions(list(range(1, instance.n + 1))):
        costs = [best[frozenset(block)][0] for block in partition]
        if problem.objective == "makespan" and len(partition) <= problem.robots:
            answers.append((max(costs), len(partition), partition))
        elif problem.objective == "robots" and all(meets_deadline(c, deadline) for c in costs):
            answers.append((len(partition), max(costs), partition))
    value, _, partition = min(answers, key=lambda a: (a[0], a[1]))
    routes = [best[frozenset(block)][1] for block in partition]
    return Solution(routes=routes, bound=value, status=Status.OPTIMAL)


def one_route_backwards(instance, problem, *, time_limit=None, seed=0):
    """One robot, KPOIs in reverse list order; drops the deadline like the paper's Alg. 2."""
    return Solution(routes=[list(range(instance.n, 0, -1))], drops_deadline=problem.objective == "robots")


@pytest.fixture(scope="module", autouse=True)
def test_methods():
    available_methods()  # load the built-ins first: the registry loads them only when empty
    register_method(MethodInfo("brute", brute_force, "test only: every partition, every order"))
    register_method(MethodInfo("backwards", one_route_backwards, "test only: one route, reversed"))
    yield
    METHODS.pop("brute", None)
    METHODS.pop("backwards", None)


def _small_run(**changes):
    """A run on tiny instances, fast enough for every test."""
    options = dict(
        methods=["trivial", "backwards"], routes=("paths", "tours"), robots=(2,), deadlines=("least", 1.5),
        reference="brute", time_limit=10, seed=0, workers=1, progress=False,
    )
    options.update(changes)
    return report.gaps(["random:n=4..5:seeds=0..1", "grid:rows=2:cols=2"], **options)


# ---------------------------------------------------------------- rows


def test_rows_on_the_line_derived_by_hand(tiny_line):
    # s=0, a=1, b=2, c=3 on a line; c_max = 3; paths only.
    frame = report.gaps(
        tiny_line, ["trivial", "backwards"], routes=("paths",), robots=(2,), reference="brute",
        workers=1, progress=False,
    )
    got = {
        (r.question, r.method, r.compared): (r.objective, r.value, r.optimum, r.gap_to_optimum, r.at_optimum)
        for r in frame.itertuples()
    }
    assert got == {
        # trivial with 2 robots: blocks [a, b], [c] -> costs 2 and 3; optimum 3 (c is 3 away)
        ("robots<=2", "trivial", "as asked"): ("makespan", 3.0, 3.0, 0.0, True),
        # backwards: s -> c -> b -> a costs 3 + 1 + 1 = 5 against 3: 2/3 worse
        ("robots<=2", "backwards", "as asked"): ("makespan", 5.0, 3.0, pytest.approx(2 / 3), False),
        # trivial within c_max = 3: 3 robots; one robot s -> a -> b -> c suffices: 200 % worse
        ("deadline=least", "trivial", "as asked"): ("robots", 3.0, 1.0, 2.0, False),
        # backwards drops the deadline: 1 robot at makespan 5 (optimal there: 1) ...
        ("deadline=least", "backwards", "robots at its makespan"): ("robots", 1.0, 1.0, 0.0, True),
        # ... and makespan 5 with its 1 robot, where 3 is best
        ("deadline=least", "backwards", "makespan at its robots"): ("makespan", 5.0, 3.0, pytest.approx(2 / 3), False),
    }
    by_key = frame.set_index(["question", "method", "compared"])
    assert by_key.loc[("deadline=least", "trivial", "as asked"), "gap"] == pytest.approx(2 / 3)  # (3 - 1) / 3
    assert by_key.loc[("deadline=least", "backwards", "robots at its makespan"), "deadline"] == 5.0
    assert by_key.loc[("deadline=least", "backwards", "makespan at its robots"), "robots_limit"] == 1
    assert set(frame["reference_status"]) == {"optimal"}


def test_a_method_without_an_answer_has_no_gap(tiny_line):
    # a deadline of half the least makespan is infeasible for every method and the reference
    frame = report.gaps(tiny_line, ["trivial"], routes=("paths",), robots=(), deadlines=(0.5,),
                        reference="brute", workers=1, progress=False)
    row = frame.iloc[0]
    assert row["status"] == "infeasible" and row["reference_status"] == "infeasible"
    assert math.isnan(row["value"]) and math.isnan(row["optimum"]) and math.isnan(row["gap_to_optimum"])
    assert not row["at_optimum"]


def test_gap_to_optimum_edge_cases():
    assert report.gap_to_optimum(3.0, 3.0 * (1 + 1e-12)) == 0.0
    assert report.gap_to_optimum(2.0, 0.0) == math.inf
    assert report.gap_to_optimum(None, 1.0) is None
    assert report.gap_to_optimum(1.5, 1.0) == 0.5


def test_unknown_method_is_refused_before_any_work(tmp_path):
    csv_path = tmp_path / "gaps.csv"
    with pytest.raises(InputError, match="Unknown method 'no-such'"):
        report.gaps("star:n=3", ["trivial", "no-such"], reference="brute", csv_path=csv_path)
    assert not csv_path.exists()


def test_a_method_label_may_fix_its_options():
    # best:iterations=5 is best with 5 rounds: its rows carry the label, and its value is the
    # one solve gives for best with iterations=5 (no time limit, so the seed alone decides).
    frame = report.gaps(
        "random:n=6:seeds=0", ["best:iterations=5"], routes=("paths",), robots=(2,), deadlines=(),
        reference="brute", time_limit=None, seed=0, workers=1, progress=False,
    )
    assert list(frame["method"]) == ["best:iterations=5"]
    instance = report.parse_spec("random:n=6:seeds=0")[0]
    direct = solve(instance, "paths", robots=2, method="best", iterations=5, seed=0)
    assert frame["value"].iloc[0] == pytest.approx(direct.makespan)


@pytest.mark.parametrize(
    "label, message",
    [
        ("best:rounds=5", "has no option 'rounds'"),  # best's option is iterations
        ("best:iterations=many", "needs a number"),  # not a number
        ("mst:iterations=5", "has no option 'iterations'"),  # mst takes no options
        ("nope:iterations=5", "Unknown method 'nope'"),  # no such method
    ],
)
def test_bad_method_labels_are_one_line(label, message):
    with pytest.raises(InputError, match=message):
        report.gaps("star:n=3", [label], reference="brute", workers=1, progress=False)


# ---------------------------------------------------------------- CSV, resume, executors


def test_csv_round_trips(tmp_path):
    csv_path = tmp_path / "gaps.csv"
    frame = _small_run(csv_path=csv_path)
    back = report.read_gaps(csv_path)
    assert dict(back.dtypes.astype(str)) == dict(frame.dtypes.astype(str))
    assert [str(t) for t in frame.dtypes] == [str(pd.Series(dtype=t).dtype) for t in report.COLUMNS.values()]
    pd.testing.assert_frame_equal(back, frame, check_exact=True)
    # 5 instances x 2 route kinds x 3 questions x 2 methods, + 1 row for each dropped
    # deadline: backwards drops both robots questions, 5 x 2 x 2 times
    assert len(frame) == 5 * 2 * 3 * 2 + 5 * 2 * 2
    assert (frame["compared"] != "as asked").sum() == 2 * 5 * 2 * 2


def test_a_resumed_run_gives_the_same_rows(tmp_path):
    whole = _small_run(csv_path=tmp_path / "whole.csv")
    lines = (tmp_path / "whole.csv").read_text().splitlines(keepends=True)
    cut = tmp_path / "cut.csv"
    # header, 4 rows, a row cut mid-write; row 4 is the first of backwards' two rows for
    # the dropped deadline, so its (question, method) is incomplete and must be rerun
    cut.write_text("".join(lines[:5]) + lines[5][:20])
    assert list(report.read_gaps(cut)["compared"]) == ["as asked"] * 3 + ["robots at its makespan"]
    settings = {"reference": "brute", "seed": 0, "time_limit": 10.0}
    assert len(report.store._kept_rows(cut, settings)) == 3
    resumed = _small_run(csv_path=cut)
    pd.testing.assert_frame_equal(resumed.drop(columns=TIMING), whole.drop(columns=TIMING), check_exact=True)
    pd.testing.assert_frame_equal(report.read_gaps(cut), resumed, check_exact=True)
    # the first row was kept, not recomputed: its timing is the first run's
    assert resumed.loc[0, "seconds"] == whole.loc[0, "seconds"]


def test_an_interrupted_run_keeps_its_rows_and_resumes(tmp_path, monkeypatch):
    from parcover.algorithms.trivial import one_per_kpoi

    calls_left = [5]

    def interrupted_after_5_calls(instance, problem, *, time_limit=None, seed=0):
        if calls_left[0] == 0:
            raise KeyboardInterrupt
        calls_left[0] -= 1
        return one_per_kpoi(instance, problem)

    monkeypatch.setitem(METHODS, "flaky", MethodInfo("flaky", interrupted_after_5_calls, "test only"))
    csv_path = tmp_path / "gaps.csv"
    with pytest.raises(KeyboardInterrupt):
        _small_run(methods=["flaky"], csv_path=csv_path)
    assert len(report.read_gaps(csv_path)) == 5  # one row per question, written as computed
    calls_left[0] = 10**9
    resumed = _small_run(methods=["flaky"], csv_path=csv_path)
    assert calls_left[0] == 10**9 - (5 * 2 * 3 - 5)  # only the missing questions ran
    whole = _small_run(methods=["trivial"])
    pd.testing.assert_frame_equal(
        resumed.drop(columns=TIMING + ["method"]), whole.drop(columns=TIMING + ["method"]), check_exact=True
    )


def test_resume_refuses_a_csv_of_other_settings(tmp_path):
    csv_path = tmp_path / "gaps.csv"
    _small_run(csv_path=csv_path, routes=("paths",))
    with pytest.raises(InputError, match="another time limit") as info:
        _small_run(csv_path=csv_path, routes=("paths",), time_limit=20)
    assert "\n" not in str(info.value)


def test_executors_give_identical_rows():
    distributed = pytest.importorskip("dask.distributed")
    in_process = _small_run(workers=1).drop(columns=TIMING)
    pool = _small_run(workers=2).drop(columns=TIMING)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        on_dask = _small_run(scheduler=cluster.scheduler_address).drop(columns=TIMING)
    pd.testing.assert_frame_equal(pool, in_process, check_exact=True)
    pd.testing.assert_frame_equal(on_dask, in_process, check_exact=True)


def test_progress_bar_goes_to_stderr(capsys, tiny_line):
    report.gaps(tiny_line, ["trivial"], routes=("paths",), robots=(2,), deadlines=(), reference="brute",
                workers=1, progress=True)
    captured = capsys.readouterr()
    assert "gaps" in captured.err and "1/1" in captured.err and captured.out == ""


# ---------------------------------------------------------------- specs


def test_spec_expands_ranges_in_order():
    names = [inst.name for inst in report.parse_spec("random:n=4..5:seeds=0,2")]
    assert names == ["random-uniform-n4-s0", "random-uniform-n4-s2", "random-uniform-n5-s0", "random-uniform-n5-s2"]
    graph = report.parse_spec("graph:n=3:seeds=1:virtual=2")[0]
    assert graph.name == "graph-n3-v2-s1"
    assert (graph.distances == generate.random_graph(3, 1, virtual=2).distances).all()
    assert [i.name for i in report.parse_spec("grid:rows=2:cols=2..3")] == ["grid-2x2", "grid-2x3"]


@pytest.mark.parametrize(
    "spec, message",
    [
        ("hexagon:n=3", "Unknown generator 'hexagon'"),  # not a generator
        ("random", "lacks n="),  # n is required
        ("random:m=3", "Bad part 'm=3'"),  # unknown key
        ("random:n3", "Bad part 'n3'"),  # no '='
        ("random:n=6..x", "Bad value '6..x'"),  # not a number
        ("random:n=5..2", "Bad value '5..2'"),  # empty range
        ("random:n=3:n=4", "'n' is given twice"),  # repeated key
        ("grid:rows=3", "lacks cols="),  # a grid needs both sides
        ("star:n=0", "n must be a whole number >= 1"),  # the generator's own check
    ],
)
def test_bad_specs_are_one_line(spec, message):
    with pytest.raises(InputError, match=message) as info:
        report.parse_spec(spec)
    assert "\n" not in str(info.value)


def test_neither_file_nor_spec_is_refused():
    with pytest.raises(InputError, match="neither a file, a folder nor a generator spec"):
        report.load_instances("no/such/file.json")


# ---------------------------------------------------------------- report.md


def _planted() -> pd.DataFrame:
    """Method a: gaps 0, 0.1, 0.5 (one at the optimum); method b: 0.3 and no answer."""
    rows = []
    for method, gap, at_optimum in [("a", 0.0, True), ("a", 0.1, False), ("a", 0.5, False),
                                    ("b", 0.3, False), ("b", None, False)]:
        row = dict.fromkeys(report.COLUMNS)
        row.update(instance="i", n=3, routes="paths", question="robots<=2", method=method, compared="as asked",
                   objective="makespan", status="feasible", reference="exact", reference_status="optimal",
                   value=None if gap is None else 10 * (1 + gap), optimum=10.0,
                   gap_to_optimum=gap, at_optimum=at_optimum, seed=0, seconds=0.0)
        rows.append(row)
    return report.store._frame(rows)


def test_report_md_summarises_a_planted_table():
    meta = report.run_metadata(instances=["i"], methods=["a", "b"], routes=["paths"], robots=[2],
                               deadlines=["least"], reference="exact", time_limit=60, seed=0)
    text = report.render_report(_planted(), meta)
    # a: mean (0 + 10 + 50) / 3 = 20 %, median 10 %, max 50 %, optimal once in 3
    assert "| a | 3 | 3 | 20.00 | 10.00 | 50.00 | 1/3 (33%) |" in text
    # b: one gap of 30 %; the row without an answer counts in rows only
    assert "| b | 2 | 1 | 30.00 | 30.00 | 30.00 | 0/2 (0%) |" in text
    assert "### paths, objective makespan" in text
    # worst cases, largest gap first: a's 15 against 10, b's 13, a's 11
    worst = [line for line in text.splitlines() if line.startswith("| i |")]
    assert worst == [
        "| i | paths | robots<=2 | a | as asked | 15 | 10 | 50.00 |",
        "| i | paths | robots<=2 | b | as asked | 13 | 10 | 30.00 |",
        "| i | paths | robots<=2 | a | as asked | 11 | 10 | 10.00 |",
    ]
    assert f"numpy {meta['versions']['numpy']}" in text and str(meta["machine"]["cores"]) in text


def test_write_report_writes_csv_meta_and_report(tmp_path, tiny_line):
    path = report.write_report(
        tiny_line, tmp_path / "out", ["trivial"], routes=("paths",), robots=(2,), reference="brute",
        time_limit=5, workers=1, progress=False,
    )
    assert path == tmp_path / "out" / "report.md"
    meta = json.loads((tmp_path / "out" / "meta.json").read_text())
    assert meta["reference"] == "brute" and meta["time_limit"] == 5 and meta["seed"] == 0
    assert set(meta["versions"]) == {"highspy", "cvxpy", "numpy", "scipy", "pandas"}
    assert meta["machine"]["cores"] >= 1 and meta["machine"]["cpu"]
    assert len(report.read_gaps(tmp_path / "out" / "gaps.csv")) == 2
    text = path.read_text()
    # makespan with 2 robots: 3 = optimum; fewest robots at c_max: 3 against 1, 200 % worse
    assert "| trivial | 1 | 1 | 0.00 | 0.00 | 0.00 | 1/1 (100%) |" in text
    assert "| trivial | 1 | 1 | 200.00 | 200.00 | 200.00 | 0/1 (0%) |" in text


class _PlotSpy:
    """Replaces parcover.plot's functions: records each call and writes an empty file."""

    def __init__(self, monkeypatch, functions):
        from parcover import plot

        self.calls = []
        for name in functions:
            monkeypatch.setattr(plot, name, self._recorder(name))

    def _recorder(self, name):
        def record(*args, **kwargs):
            self.calls.append((name, args, kwargs))
            path = args[2] if name == "plot_side_by_side" else args[1]
            path.write_bytes(b"")

        return record


def test_plots_are_drawn_for_the_worst_cases(tmp_path, tiny_line, monkeypatch):
    spy = _PlotSpy(monkeypatch, ["plot_gap_distribution", "plot_frontier", "plot_side_by_side"])
    path = report.write_report(tiny_line, tmp_path, ["trivial", "backwards"], routes=("paths",), robots=(2,),
                               reference="brute", workers=1, progress=False, worst_cases=2)
    assert [name for name, _, _ in spy.calls] == [
        "plot_gap_distribution", "plot_frontier", "plot_side_by_side", "plot_side_by_side"
    ]
    assert len(spy.calls[0][1][0]) == 5  # the rows of test_rows_on_the_line_derived_by_hand
    curve, points = spy.calls[1][1][0], spy.calls[1][2]["points"]
    # the line: 1 robot already reaches c_max = 3, so the frontier is the single point (1, 3)
    assert [(p.robots, p.makespan) for p in curve.points] == [(1, 3.0)]
    assert points == {"trivial": [(2, 3.0), (3, 3.0)], "backwards": [(1, 5.0)]}
    # worst case: trivial's 3 robots against 1 at c_max (200 %); the instance, its result, the reference's
    instance, (greedy, optimal) = spy.calls[2][1][0], spy.calls[2][1][1]
    assert instance is tiny_line and (greedy.robots, optimal.robots) == (3, 1)
    # next: backwards' makespan 5 against 3 with 2 robots (2/3 worse; first of the two such rows)
    greedy, optimal = spy.calls[3][1][1]
    assert (greedy.makespan, optimal.makespan, optimal.robots_limit) == (5.0, 3.0, 2)
    text = path.read_text()
    assert "![Gap distribution per method](gaps.png)" in text and "(worst-2.png)" in text
    assert all((tmp_path / name).exists() for name in ("gaps.png", "frontier-line-paths.png", "worst-1.png"))


def test_a_failing_plot_is_skipped_with_a_note(tmp_path, tiny_line, monkeypatch, caplog):
    from parcover import plot

    def broken(*args, **kwargs):
        raise TypeError("wrong arguments")

    spy = _PlotSpy(monkeypatch, ["plot_gap_distribution"])
    monkeypatch.setattr(plot, "plot_frontier", broken)
    monkeypatch.setattr(plot, "plot_side_by_side", broken)
    path = report.write_report(tiny_line, tmp_path, ["trivial"], routes=("paths",), robots=(2,),
                               reference="brute", workers=1, progress=False)
    assert [name for name, _, _ in spy.calls] == ["plot_gap_distribution"]
    assert "TypeError: wrong arguments" in caplog.text
    text = path.read_text()
    assert "(gaps.png)" in text and "frontier-line-paths.png" not in text and "worst-1.png" not in text


@pytest.mark.parametrize(
    "robots, deadlines, message",
    [
        ((0,), (), "robot limit must be a whole number >= 1"),  # no robots
        ((), ("soon",), "got 'soon'"),  # neither 'least' nor a number
        ((), (-1.0,), "got -1.0"),  # a negative factor
        ((), (), "No questions"),  # nothing to ask
        ((2, 2), (), "asked twice"),  # one question twice
    ],
)
def test_bad_questions_are_one_line(robots, deadlines, message):
    with pytest.raises(InputError, match=message) as info:
        report.gaps("star:n=3", ["trivial"], robots=robots, deadlines=deadlines, reference="brute", workers=1)
    assert "\n" not in str(info.value)


def test_deadline_factors_may_be_text_as_from_a_command_line():
    labels = [q.label for q in report.questions([2], ["least", "1.2"])]
    assert labels == ["robots<=2", "deadline=least", "deadline=1.2*least"]


def test_two_instances_with_one_name_are_refused():
    with pytest.raises(InputError, match="Two instances are named 'star-3'"):
        report.load_instances(["star:n=3", "star:n=2..3"])


def test_the_package_keeps_the_names_of_the_module_it_was():
    from parcover.report import (  # noqa: F401 - importing them is the test
        COLUMNS, TIMING_COLUMNS, Question, draw_plots, gap_to_optimum, gaps, load_instances, machine_info,
        package_version, parse_spec, questions, read_gaps, render_report, run_metadata, summary_table, worst_rows,
        write_report,
    )

    assert Question is report.GridQuestion  # the old name of the grid's question
    assert set(report.__all__) <= set(dir(report))


def test_the_pools_workers_share_the_cores_so_none_races_on_all_of_them():
    import concurrent.futures

    from milp import race
    from parcover.report.run import _start_worker

    with concurrent.futures.ProcessPoolExecutor(2, initializer=_start_worker, initargs=(None, 2)) as pool:
        seen = pool.submit(race.cores).result()
    assert seen == max(1, race.cores() // 2)
