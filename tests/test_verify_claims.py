"""The verifier refuses every false claim of a solution file (docs/format.md section 4),
and ``--certify`` re-proves the status and bound with an independent exact method."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import parcover as pc
from parcover.certify import certifier_for
from parcover.cli import main


@pytest.fixture(scope="module")
def files(tmp_path_factory) -> dict[str, Path]:
    """An 8-KPOI instance, a greedy answer (nn, 3 robots, feasible) and the exact one."""
    folder = tmp_path_factory.mktemp("claims")
    instance = folder / "r8.json"
    pc.write_instance(pc.generate.random_points(8, 3), instance)
    out = {"instance": instance}
    for method in ("nn", "exact"):
        out[method] = folder / f"{method}.json"
        assert main(["solve", str(instance), "--robots", "3", "--method", method, "--json",
                     "--out", str(out[method])]) == 0
    return out


def run_verify(capsys, files, data: dict, *extra: str) -> tuple[int, str]:
    path = files["instance"].parent / "tampered.json"
    path.write_text(json.dumps(data))
    capsys.readouterr()
    code = main(["verify", str(files["instance"]), str(path), *extra])
    return code, capsys.readouterr().out


def genuine(files, method: str = "nn") -> dict:
    return json.loads(files[method].read_text())


def test_genuine_files_are_valid(capsys, files):
    for method in ("nn", "exact"):
        code, out = run_verify(capsys, files, genuine(files, method))
        assert code == 0 and out.startswith("valid:"), out


# One tampered claim per case (makespan, route costs, robots, status, bound, gap, objective, robot
# limit); each must be refused with its reason.
TAMPERED = [
    ("makespan", lambda d: d.update(makespan=50.0), "makespan claims 50"),
    ("route_costs", lambda d: d.update(route_costs=[1.0] * len(d["routes"])), "route_costs are false"),
    ("robots", lambda d: d.update(robots=1), "robots claims 1"),
    # 'optimal' with makespan = bound = 90: the makespan is false, and so is the status
    ("optimal 90", lambda d: d.update(status="optimal", makespan=90.0, bound=90.0, gap=0.0), "makespan claims 90"),
    ("bound above", lambda d: d.update(bound=d["makespan"] * 1.5, gap=0.0), "is above the value"),
    ("negative gap", lambda d: d.update(gap=-0.5), "gap claims -0.5"),
    ("infeasible with routes", lambda d: d.update(status="infeasible"), "status 'infeasible' with routes"),
    ("objective robots", lambda d: d.update(objective="robots"), "objective 'robots' with a robots_limit"),
    ("no robots_limit", lambda d: d.pop("robots_limit"), "objective 'makespan' without a robots_limit"),
    ("optimal below", lambda d: d.update(status="optimal"), "status 'optimal' with bound"),
]


@pytest.mark.parametrize("change,reason", [(c, r) for _, c, r in TAMPERED], ids=[n for n, _, _ in TAMPERED])
def test_false_claim_is_refused_with_its_reason(capsys, files, change, reason):
    data = genuine(files)
    change(data)
    code, out = run_verify(capsys, files, data)
    assert code == 1
    assert any(line.startswith("invalid:") and reason in line for line in out.splitlines()), out


@settings(max_examples=30, deadline=None)
@given(key=st.sampled_from(["makespan", "route_cost", "bound", "gap"]),
       factor=st.one_of(st.floats(0.0, 0.9999), st.floats(1.0001, 10.0)))
def test_any_tampered_number_is_caught(files, key, factor):
    data = genuine(files)
    if key == "route_cost":
        data["route_costs"][0] *= factor
    elif key == "gap":
        data["gap"] = data["gap"] * factor if data["gap"] else factor
    elif key == "bound":  # raising it above the value, or a gap that no longer matches
        data["bound"] *= factor
    else:
        data[key] *= factor
    verdict = pc.verify(pc.load(str(files["instance"])), data)
    assert not verdict.valid


def test_certify_confirms_an_exact_answer(capsys, files):
    code, out = run_verify(capsys, files, genuine(files, "exact"), "--certify", "--time-limit", "30")
    assert code == 0 and "certified by" in out, out


def test_certify_refutes_a_greedy_answer_claimed_optimal(capsys, files):
    data = genuine(files)
    exact = genuine(files, "exact")
    assert data["makespan"] > exact["makespan"] * 1.001  # nn is not optimal here
    data.update(status="optimal", bound=data["makespan"], gap=0.0)  # self-consistent, false
    code, out = run_verify(capsys, files, data)
    assert code == 0  # nothing the file says contradicts itself ...
    code, out = run_verify(capsys, files, data, "--certify")
    assert code == 1 and "proves the optimum is" in out, out  # ... but the optimum does


def test_certify_uses_a_method_other_than_the_files():
    """Files without ``model`` (written before it existed): every model ``exact`` may
    answer with at that size is left out (tests/test_certify_models.py: with ``model``)."""
    small, fifteen, middle, large = (pc.generate.random_points(n, 1) for n in (8, 15, 20, 25))
    for objective in ("makespan", "robots"):
        assert certifier_for(small, "exact", objective) == "branchprice"
        assert certifier_for(small, "nn", objective) == "setpart"
        assert certifier_for(middle, "branchprice", objective) == "setpart"
        assert certifier_for(large, "exact", objective) == "compact"
        assert certifier_for(large, "compact", objective) == "branchprice"
    # exact never answers with branch-and-cut up to 20 KPOIs; it answers only the makespan
    assert certifier_for(middle, "exact", "makespan") == "branchcut"
    assert certifier_for(middle, "exact", "robots") == "compact"
    assert certifier_for(large, "branchprice", "makespan") == "branchcut"
    assert certifier_for(large, "branchprice", "robots") == "compact"
    # at 15 KPOIs exact answers the makespan by setpart, the fewest robots by either
    assert certifier_for(fifteen, "exact", "makespan") == "branchprice"
    assert certifier_for(fifteen, "exact", "robots") == "compact"


def test_certify_says_when_it_cannot_decide(capsys, files, monkeypatch):
    """A certifier that proves nothing (here: answering with a heuristic) leaves the claim
    undecided: exit 3 and a line saying why."""
    solve_module = sys.modules["parcover.solve"]  # parcover.solve is also the function
    real = solve_module.solve
    monkeypatch.setattr(solve_module, "solve", lambda *a, **k: real(*a, **{**k, "method": "nn"}))
    code, out = run_verify(capsys, files, genuine(files, "exact"), "--certify")
    assert code == 3 and out.splitlines()[-1].startswith("undecided:"), out


def _solve_into(files, name: str, *args: str) -> dict:
    path = files["instance"].parent / f"{name}.json"
    assert main(["solve", str(files["instance"]), *args, "--json", "--out", str(path)]) == 0
    return json.loads(path.read_text())


@pytest.mark.parametrize("args", [["--method", "paper"], ["--routes", "tours", "--method", "paper"],
                                  ["--deadline", "1000"], ["--routes", "tours", "--deadline", "1"]])
def test_genuine_robots_and_infeasible_answers_are_valid(capsys, files, args):
    """The paper's Algorithm 2 answers a robots question without a deadline, and an
    infeasible answer (a deadline of 1 is below c_max, about 70 here) has no routes: both genuine."""
    answer = _solve_into(files, "answer", *args)
    code, out = run_verify(capsys, files, answer)
    assert code == 0 and out.startswith("valid:"), out


def test_a_deadline_on_a_makespan_answer_is_a_false_objective(capsys, files):
    code, out = run_verify(capsys, files, {**genuine(files), "deadline": 1000.0})
    assert code == 1 and "objective 'makespan' with a deadline" in out


def test_certify_confirms_a_genuine_infeasible_answer(capsys, files):
    answer = _solve_into(files, "infeasible", "--deadline", "1")
    assert answer["status"] == "infeasible" and answer["routes"] == []
    code, out = run_verify(capsys, files, answer, "--certify")
    assert code == 0 and "certified" in out, out


def test_certify_refutes_a_false_infeasible_claim_without_routes(capsys, files):
    """A feasible question (deadline 1000: one path of 8 legs, each at most the largest
    distance, about 97 here, meets it) with its routes removed and 'infeasible' claimed."""
    answer = _solve_into(files, "feasible", "--deadline", "1000")
    assert answer["status"] in ("optimal", "feasible")
    claimed = {**answer, "status": "infeasible", "routes": [], "route_costs": [], "makespan": None,
               "robots": None, "bound": None, "gap": None}
    assert run_verify(capsys, files, claimed)[0] == 0  # nothing to recompute without routes
    code, out = run_verify(capsys, files, claimed, "--certify")
    assert code == 1 and "claimed infeasible" in out, out


def test_the_api_verifies_an_answer_without_routes_as_the_cli_does():
    # A deadline of half c_max cannot be met (some KPOI is c_max away): infeasible, no routes.
    instance = pc.generate.random_points(6, 1)
    result = pc.solve(instance, "paths", deadline=0.5 * instance.c_max)
    assert result.status is pc.Status.INFEASIBLE and not result.routes
    for solution in (result, json.loads(result.to_json())):
        verdict = pc.verify(instance, solution)
        assert verdict.valid and verdict.robots == 0 and verdict.makespan is None
    certified = pc.verify(instance, json.loads(result.to_json()), certify=True, time_limit=10)
    assert certified.certificate.outcome == "certified"
    # routes missing from an answer that claims a makespan are still refused
    claimed = {**json.loads(result.to_json()), "status": "feasible", "makespan": 3.0}
    with pytest.raises(pc.InvalidSolution):
        pc.verify(instance, claimed)


def test_the_api_certifies_a_result_object():
    # a Result (not its JSON) with certify=True was not re-proved: certificate None
    instance = pc.generate.random_points(8, 3)
    for method, outcome in (("exact", "certified"), ("nn", "certified")):
        verdict = pc.verify(instance, pc.solve(instance, robots=3, method=method), certify=True, time_limit=30)
        assert verdict.valid and verdict.certificate is not None
        assert verdict.certificate.outcome == outcome
