"""Verdicts on the paper's claims (parcover.props), checked against planted fakes.

The fakes are registered as methods: ``test-brute`` is a brute-force optimum over all
partitions x orders (n <= 6, an independent exact reference), ``test-split`` is that
optimum with one route split in two (one robot too many whenever some optimal route
covers two KPOIs), and ``test-weak`` one robot per KPOI reported as merely feasible
(an unproven reference).
"""

from __future__ import annotations

import itertools
import json
import math
import sys
import types
from pathlib import Path

import pytest
from hypothesis import HealthCheck, assume, given, settings

import parcover
from parcover import Instance, MethodInfo, Solution, Status, generate, props as P, shrinking
from parcover.problem import meets_deadline
from parcover.question import load as load_question
from parcover.solve import METHODS, register_method
from strategies import euclidean_instances


# -- fake methods -------------------------------------------------------------------


def _route_costs(instance: Instance, tours: bool) -> dict[int, tuple[float, tuple[int, ...]]]:
    """Cheapest order of every non-empty KPOI subset (bitmask over KPOIs 1..n)."""
    d = instance.distances
    best: dict[int, tuple[float, tuple[int, ...]]] = {}
    for mask in range(1, 1 << instance.n):
        members = [i + 1 for i in range(instance.n) if mask >> i & 1]
        for order in itertools.permutations(members):
            cost = d[0, order[0]] + sum(d[a, b] for a, b in zip(order, order[1:]))
            cost += d[order[-1], 0] if tours else 0.0
            if mask not in best or cost < best[mask][0]:
                best[mask] = (float(cost), order)
    return best


def _blocks(mask: int):
    """Submasks of ``mask`` holding its lowest bit (each partition once)."""
    low = mask & -mask
    sub = mask
    while sub:
        if sub & low:
            yield sub
        sub = (sub - 1) & mask


def brute_force(instance, problem, *, time_limit=None, seed=0):
    """Optimum over all partitions x orders; n <= 6."""
    if instance.n > 6:
        raise ValueError("brute force is for n <= 6")
    best = _route_costs(instance, problem.tours)
    full = (1 << instance.n) - 1
    if problem.objective == "robots":
        deadline = problem.effective_deadline(instance)
        fewest = {0: (0, [])}
        for mask in range(1, full + 1):
            options = [
                (fewest[mask ^ sub][0] + 1, fewest[mask ^ sub][1] + [sub])
                for sub in _blocks(mask)
                if meets_deadline(best[sub][0], deadline) and fewest.get(mask ^ sub, (math.inf,))[0] < math.inf
            ]
            fewest[mask] = min(options, key=lambda o: o[0]) if options else (math.inf, [])
        value, parts = fewest[full]
    else:
        layer = {0: (0.0, [])}
        for _ in range(min(problem.robots, instance.n)):
            nxt = dict(layer)
            for mask in range(1, full + 1):
                for sub in _blocks(mask):
                    if mask ^ sub in layer:
                        cost = max(best[sub][0], layer[mask ^ sub][0])
                        if mask not in nxt or cost < nxt[mask][0]:
                            nxt[mask] = (cost, layer[mask ^ sub][1] + [sub])
            layer = nxt
        value, parts = layer[full]
    return Solution([list(best[sub][1]) for sub in parts], bound=float(value), status=Status.OPTIMAL)


def split_one(instance, problem, *, time_limit=None, seed=0):
    """The optimum with the first multi-KPOI route split before its last KPOI (robots question)."""
    routes = brute_force(instance, problem).routes
    if problem.objective == "robots":
        for i, route in enumerate(routes):
            if len(route) >= 2:
                routes[i : i + 1] = [route[:-1], route[-1:]]
                break
    return Solution(routes)


def one_each_unproven(instance, problem, *, time_limit=None, seed=0):
    """One robot per KPOI, reported as feasible only (an unproven reference)."""
    return Solution([[i] for i in range(1, instance.n + 1)], status=Status.FEASIBLE)


@pytest.fixture(scope="module", autouse=True)
def fake_methods():
    parcover.available_methods()  # load the built-in methods first
    fakes = [
        MethodInfo("test-brute", brute_force, "brute force over partitions x orders (tests)"),
        MethodInfo("test-split", split_one, "brute force with one route split (tests)"),
        MethodInfo("test-weak", one_each_unproven, "one robot per KPOI, unproven (tests)"),
    ]
    for info in fakes:
        register_method(info)
    yield
    for info in fakes:
        METHODS.pop(info.name, None)


def _solver():
    return P.CachedSolver(time_limit=5.0, seed=0)


def _claim(claim_id, instances, *, reference="test-brute", greedy=("test-split",)):
    found = [c for c in P.claims(_solver(), reference=reference, greedy=greedy, general=instances,
                                 grids=instances, stars=instances) if c.id == claim_id]
    assert len(found) == 1
    return found[0]


def _alg1_refutes(inst: Instance) -> bool:
    return _claim("alg1-test-split", [inst]).check(inst).status == "refuted"


# -- the brute-force reference itself ------------------------------------------------


def test_brute_force_matches_hand_optima(tiny_line):
    # Line s=0, a=1, b=2, c=3: one path s-a-b-c of cost 3 = c_max.
    assert parcover.solve(tiny_line, method="test-brute").robots == 1
    # 2x3 grid, c_max 3: five cells cannot share one path of cost 3, two paths can
    # (r0c1-r0c2-r1c2 costs 3, r1c0-r1c1 costs 2).
    assert parcover.solve(generate.grid(2, 3), method="test-brute").robots == 2
    # Fig. 3 star with 4 KPOIs, tours with 2 robots: each robot covers 2 neighbours,
    # 1 + sqrt(2) + 1.
    res = parcover.solve(generate.star(4), routes="tours", robots=2, method="test-brute")
    assert res.makespan == pytest.approx(2 + math.sqrt(2))


@pytest.mark.skipif("exact" not in parcover.available_methods(), reason="exact method not available")
@pytest.mark.parametrize("seed", [0, 1])
def test_exact_agrees_with_brute_force(seed):
    inst = generate.random_points(5, seed)
    for kw in (dict(), dict(routes="tours"), dict(robots=2), dict(deadline=1.3 * inst.c_max)):
        ref = parcover.solve(inst, method="test-brute", **kw)
        got = parcover.solve(inst, method="exact", time_limit=10, **kw)
        assert got.value == pytest.approx(ref.value)


# -- verdict logic -----------------------------------------------------------------------


def test_prop1_holds_with_fake_exact(tiny_line):
    family = [tiny_line, generate.star(4), generate.grid(2, 3), generate.random_points(5, 3)]
    verdict, outcomes = P.evaluate(_claim("prop1-paths", family))
    assert (verdict.tried, verdict.holds, verdict.refuted, verdict.undecided) == (4, 4, 0, 0)
    assert verdict.counterexample is None
    assert verdict.text == "holds on 4 of 4"


def test_planted_refutation_names_the_smallest_counterexample(tiny_line):
    # Star: every optimal path covers one KPOI, so the split fake is optimal (holds).
    # Line (3 KPOIs) and 2x3 grid (5 KPOIs): one robot too many (refuted).
    family = [generate.grid(2, 3), generate.star(4), tiny_line]
    verdict, outcomes = P.evaluate(_claim("alg1-test-split", family))
    assert [o.status for _, o in outcomes] == ["refuted", "holds", "refuted"]
    assert verdict.is_refuted and verdict.text == "refuted on 2 of 3"
    assert verdict.counterexample is tiny_line
    assert "test-split: 2 paths," in verdict.numbers and "test-brute: 1 path," in verdict.numbers


def test_undecided_when_reference_not_proven(tiny_line):
    # The split fake uses 2 robots; the weak reference finds 3 and proves only 1:
    # the optimum may be 1 or 2, so the instance must be undecided, not refuted.
    verdict, outcomes = P.evaluate(_claim("alg1-test-split", [tiny_line], reference="test-weak"))
    assert outcomes[0][1].status == "undecided"
    assert not verdict.is_refuted and verdict.counterexample is None
    assert verdict.text == "holds on 0 of 1 (1 undecided)"


def _result(status, value, bound):
    return parcover.Result(instance="x", routes_kind="paths", objective="robots", robots_limit=None,
                           deadline=1.0, method="ref", status=status, robots=value, makespan=1.0,
                           bound=bound, gap=None, routes=[["s", "a"]], route_costs=[1.0], seconds=0.0)


@pytest.mark.parametrize(
    "status, value, bound, relation, claimed, expected",
    [
        (Status.OPTIMAL, 3, 3, "eq", 3, "holds"),
        (Status.OPTIMAL, 3, 3, "eq", 2, "refuted"),       # proven optimum differs
        (Status.FEASIBLE, 3, 1, "eq", 2, "undecided"),    # 1 <= opt <= 3 straddles 2
        (Status.FEASIBLE, 3, 3, "eq", 3, "holds"),        # bound meets value
        (Status.FEASIBLE, 3, 1, "ge", 4, "refuted"),      # witness 3 beats greedy's 4
        (Status.FEASIBLE, 3, 1, "ge", 2, "undecided"),
        (Status.FEASIBLE, 3, 2, "ge", 2, "holds"),        # bound proves greedy's 2 optimal
        (Status.FEASIBLE, 5, 4, "le", 3, "refuted"),      # proven bound above the claimed maximum
        (Status.FEASIBLE, 5, 2, "le", 3, "undecided"),
        (Status.FEASIBLE, 3, 1, "le", 3, "holds"),
    ],
)
def test_compare_optimum_brackets(status, value, bound, relation, claimed, expected):
    assert P.compare_optimum(_result(status, value, bound), relation, claimed, "claim").status == expected


def test_failing_method_is_an_error_not_a_verdict():
    big = generate.random_points(7, 0)  # brute force refuses n > 6
    verdict, outcomes = P.evaluate(_claim("prop1-paths", [big]))
    assert outcomes[0][1].status == "error" and verdict.errors == 1
    assert verdict.text == "holds on 0 of 1 (1 errors)"


# -- shrinking -----------------------------------------------------------------------------


def test_shrink_planted_line_to_two_kpois(tiny_line):
    # On a line any two KPOIs share one path at c_max, which the fake splits; one
    # KPOI cannot be split. So the shrunk counterexample has exactly 2 KPOIs.
    small = P.shrink(tiny_line, _alg1_refutes)
    assert small.n == 2
    assert _alg1_refutes(small)
    assert all(a <= b for a, b in zip(P.instance_size(small), P.instance_size(tiny_line)))


def test_shrink_graph_instance_keeps_only_shortest_walks():
    # 2x3 grid, KPOIs r0c1 r0c2 r1c0 | r1c1 r1c2: ddmin first drops the first half;
    # r1c1, r1c2 still refute (one path s..r1c1-r1c2 of cost 3 = c_max, split by the
    # fake) and one KPOI cannot. Distances stay 2, 3 and 1; unused edges go.
    grid = generate.grid(2, 3)
    small = P.shrink(grid, _alg1_refutes)
    assert small.kpois == ("r1c1", "r1c2") and _alg1_refutes(small)
    assert small.distances.tolist() == [[0, 2, 3], [2, 0, 1], [3, 1, 0]]
    assert len(small.edges) < len(grid.edges) == 7


def test_shrunk_graph_keeps_key_distances():
    graph = generate.random_graph(6, 3)
    fewer = shrinking._keep(graph, graph.kpois[:3])
    rows = [0, 1, 2, 3]
    assert fewer.distances == pytest.approx(graph.distances[rows][:, rows])
    assert len(fewer.edges) < len(graph.edges)


def test_shrink_returns_input_when_it_does_not_refute():
    star = generate.star(4)
    assert P.shrink(star, _alg1_refutes) is star


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(euclidean_instances(min_n=2, max_n=5))
def test_shrink_keeps_refuting_and_never_grows(inst):
    assume(_alg1_refutes(inst))
    small = P.shrink(inst, _alg1_refutes)
    assert _alg1_refutes(small)
    assert all(a <= b for a, b in zip(P.instance_size(small), P.instance_size(inst)))


# -- rendering and the whole run -------------------------------------------------------------


def test_render_table(tiny_line):
    verdicts = [
        P.Verdict("prop1-paths", "Prop. 1", None, tried=3, holds=2, refuted=0, undecided=1, errors=0),
        P.Verdict("alg1-paper", "Alg. 1", "paper", tried=3, holds=2, refuted=1, undecided=0, errors=0,
                  counterexample=tiny_line, found_on="line", file="out/alg1-paper.json"),
    ]
    lines = P.render_table(verdicts).splitlines()
    assert lines[0].split() == ["claim", "tried", "verdict", "counterexample"]
    assert lines[2].split() == ["prop1-paths", "3", "holds", "on", "2", "of", "3", "(1", "undecided)", "-"]
    assert lines[3].split() == ["alg1-paper", "3", "refuted", "on", "1", "of", "3", "out/alg1-paper.json"]


@pytest.mark.skipif(not {"exact", "paper"} <= set(parcover.available_methods()), reason="real methods missing")
def test_quick_run_writes_refuting_files_and_report(tmp_path):
    verdicts = P.props(quick=True, greedy=["paper"], out_dir=tmp_path / "ce", report_path=tmp_path / "verdicts.md")
    by_id = {v.claim: v for v in verdicts}
    assert by_id["fig1"].text == "holds on 1 of 1"  # 8, 4, 4 on the 3x3 grid
    assert by_id["prop1-paths"].refuted == 0 and by_id["prop2-x1"].refuted == 0
    report = (tmp_path / "verdicts.md").read_text()
    assert "Regenerate with:" in report and "seed 0" in report and parcover.__version__ in report
    claims = {c.id: c for c in P.claims(P.CachedSolver(10.0, 0), greedy=["paper"])}
    for v in verdicts:
        if v.is_refuted and v.file:
            saved = parcover.read_instance(v.file)
            assert json.loads(Path(v.file).read_text())["kpois"]  # a readable instance file
            assert saved.n <= min(i.n for i in P.families(quick=True)["general"] if i.name == v.found_on)
            assert P.check_instance(claims[v.claim], saved).status == "refuted"
            if v.claim.startswith("alg"):  # greedy-versus-optimum claims carry their question
                _, question = load_question(v.file)
                assert question is not None and question.claim == v.claim and question.method == "paper"
                assert f"parcover props --check {v.file}" in report
            assert (v.picture and Path(v.picture).exists()) or any("drawing" in n for n in v.notes)
    again = P.props(quick=True, greedy=["paper"])  # same seed, same verdicts and counterexamples
    assert [(v.claim, v.text, v.numbers) for v in again] == [(v.claim, v.text, v.numbers) for v in verdicts]


def _refuted_verdict(tiny_line):
    verdict, _ = P.evaluate(_claim("alg1-test-split", [tiny_line]))
    return verdict


def test_draw_calls_plot_side_by_side(tiny_line, tmp_path, monkeypatch):
    calls = []
    fake = types.ModuleType("parcover.plot")
    fake.plot_side_by_side = lambda inst, results, path, titles: calls.append((inst, results, path, titles))
    monkeypatch.setitem(sys.modules, "parcover.plot", fake)
    verdict = P.draw_counterexample(_refuted_verdict(tiny_line), tmp_path)
    [(inst, results, path, titles)] = calls
    assert inst is tiny_line and [r.method for r in results] == ["test-split", "test-brute"]
    assert verdict.picture == str(path) == str(tmp_path / "alg1-test-split.png")
    # the panels' titles add instance, question, method, status and value; captions say the roles
    assert titles == ["claim alg1-test-split: the greedy", "claim alg1-test-split: the exact method"]


def test_draw_skipped_with_a_note_without_plot_module(tiny_line, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "parcover.plot", None)  # makes the import fail
    verdict = P.draw_counterexample(_refuted_verdict(tiny_line), tmp_path)
    assert verdict.picture is None
    assert "drawing skipped: parcover.plot is not available" in verdict.notes
    assert "drawing skipped" in P.render_verdicts([verdict])


def test_docstring_examples():  # shrink's, in parcover.shrinking
    import doctest

    outcome = doctest.testmod(shrinking)
    assert outcome.attempted > 0 and outcome.failed == 0


def test_the_old_name_of_render_verdicts_still_imports():
    from parcover.props import render_report

    assert render_report is P.render_verdicts


def test_props_keeps_the_shrinking_names():
    assert P.shrink is shrinking.shrink and P.instance_size is shrinking.instance_size
