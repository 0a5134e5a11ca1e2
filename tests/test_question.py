"""The question block of an instance file (parcover.question): validation, writing, asking.

The instance used throughout is the hand-checkable one: start s = (0, 0), KPOIs
1 = (0, -1) and 2 = (1, -1), so c_max = d(s, 2) = sqrt(2). One path covers both only
as s-1-2 (cost 1 + 1 = 2; s-2-1 costs sqrt(2) + 1 = 2.414): so the fewest paths are
2 at c_max = 1.414 and 1 at 1.5 c_max = 2.121.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from parcover import Instance, solve
from parcover.cli import main
from parcover.errors import InputError
from parcover.io import read_instance, write_instance
from parcover.question import Answer, Question, load

ROOT = Path(__file__).resolve().parents[1]

SQRT2 = math.sqrt(2)
INSTANCE = Instance.from_points([[0, 0], [0, -1], [1, -1]], names=["s", "1", "2"], name="tiny")


def block(**changes) -> dict:
    """A valid question block (Alg. 1-1 at 1.5 c_max: 2 greedy paths, 1 optimal), with ``changes``."""
    base = {
        "claim": "alg1-1-x1.5-paper-1-1-end",
        "routes": "paths",
        "objective": "robots",
        "deadline": 1.5 * SQRT2,
        "deadline_factor": 1.5,
        "robots": None,
        "method": "paper-1-1-end",
        "reading": "1-1-end",
        "greedy": {"robots": 2, "makespan": SQRT2},
        "optimum": {"robots": 1, "makespan": 2.0, "status": "optimal", "method": "setpart"},
    }
    base.update(changes)
    return {k: v for k, v in base.items() if v is not ...}


def write(tmp_path, question: dict, name: str = "q.json") -> str:
    path = tmp_path / name
    data = json.loads(write_instance(INSTANCE))
    data["question"] = question
    path.write_text(json.dumps(data), encoding="utf-8")
    return str(path)


def run(capsys, *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


# -- validation: one bad entry per case ----------------------------------------------

BAD = [
    ("not-object", "question must be an object", 3),
    ("no-claim", "question.claim must be a non-empty string", block(claim=...)),
    ("routes", "question.routes must be 'paths' or 'tours'", block(routes="walks")),
    ("objective", "question.objective must be 'robots' or 'makespan'", block(objective="time")),
    ("deadline-text", "question.deadline must be a finite number", block(deadline="2")),
    ("deadline-negative", "question.deadline must be a finite number", block(deadline=-1, deadline_factor=None)),
    ("deadline-missing", "question.deadline must be a finite number", block(deadline=..., deadline_factor=None)),
    ("robots-with-deadline", "question.robots must be null", block(robots=2)),
    ("makespan-no-robots", "question.robots must be a whole number >= 1",
     block(objective="makespan", deadline=None, deadline_factor=None)),
    ("makespan-robots-zero", "question.robots must be a whole number >= 1",
     block(objective="makespan", deadline=None, deadline_factor=None, robots=0)),
    ("makespan-robots-bool", "question.robots must be a whole number >= 1",
     block(objective="makespan", deadline=None, deadline_factor=None, robots=True)),
    ("makespan-deadline", "must be null for the makespan objective", block(objective="makespan", robots=2)),
    ("factor-inconsistent", "question.deadline_factor 1.25 x c_max", block(deadline_factor=1.25)),
    ("factor-text", "question.deadline_factor must be a finite number", block(deadline_factor="1.5")),
    ("method-empty", "question.method must be a non-empty string", block(method="")),
    ("reading-wrong", "question.reading '5d-end' is not method 'paper-1-1-end'", block(reading="5d-end")),
    ("greedy-missing", "question.greedy must be an object", block(greedy=...)),
    ("greedy-robots-zero", "question.greedy.robots must be a whole number >= 1",
     block(greedy={"robots": 0, "makespan": 1.0})),
    ("greedy-makespan-text", "question.greedy.makespan must be a finite number",
     block(greedy={"robots": 2, "makespan": "x"})),
    ("greedy-limit", "question.greedy.limit must be 'question' or 'none'",
     block(greedy={"robots": 2, "makespan": SQRT2, "limit": "some"})),
    ("optimum-status", "question.optimum.status must be one of",
     block(optimum={"robots": 1, "makespan": 2.0, "status": "proven"})),
    ("optimum-method", "question.optimum.method must be a method name",
     block(optimum={"robots": 1, "makespan": 2.0, "method": 7})),
]


@pytest.mark.parametrize("question, message", [(q, m) for _, m, q in BAD], ids=[i for i, _, _ in BAD])
def test_a_bad_question_block_is_refused_with_one_line(tmp_path, question, message):
    path = write(tmp_path, question)
    with pytest.raises(InputError) as info:
        read_instance(path)
    assert message in str(info.value) and "\n" not in str(info.value)


def test_a_bad_question_block_exits_2_on_the_command_line(tmp_path, capsys):
    code, out, err = run(capsys, "solve", write(tmp_path, block(routes="walks")))
    assert code == 2 and out == "" and err.count("\n") == 1 and "question.routes" in err


def test_a_valid_block_reads_back_as_written(tmp_path):
    question = Question.from_dict(block(), INSTANCE)
    path = tmp_path / "q.json"
    write_instance(INSTANCE, path, question=question)
    instance, again = load(path)
    assert again == question and write_instance(instance) == write_instance(INSTANCE)
    assert question.greedy == Answer(2, SQRT2) and question.greedy_limit == "question"


def test_a_file_without_a_question_loads_with_none(tmp_path):
    path = tmp_path / "plain.json"
    write_instance(INSTANCE, path)
    instance, question = load(path)
    assert question is None and write_instance(instance) == write_instance(INSTANCE)


def test_from_results_records_the_question_the_optimum_answered():
    greedy = solve(INSTANCE, "tours", method="paper")  # Algorithm 2 as published: no limit
    optimum = solve(INSTANCE, "tours", robots=greedy.robots, method="setpart")
    question = Question.from_results("alg2-makespan-paper", greedy, optimum)
    assert (question.objective, question.robots, question.deadline) == ("makespan", greedy.robots, None)
    assert question.greedy_limit == "none" and question.reading == "literal"
    assert Question.from_dict(question.to_dict(), INSTANCE) == question


# -- solve FILE asks the file's question ---------------------------------------------


def test_solve_asks_the_files_question(tmp_path, capsys):
    path = write(tmp_path, block())
    code, out, _ = run(capsys, "solve", path, "--json")
    result = json.loads(out)  # the note goes to stderr, stdout stays one JSON object
    assert code == 0 and result["deadline"] == pytest.approx(1.5 * SQRT2)
    assert result["robots"] == 1 and result["status"] == "optimal"  # s-1-2 costs 2 <= 2.121 (docstring)
    code, out, _ = run(capsys, "solve", path)
    assert out.startswith("question from the file (alg1-1-x1.5-paper-1-1-end): paths, fewest robots within "
                          "deadline 2.12132 (1.5 c_max); method exact\n")


def test_solve_with_the_claims_unlimited_greedy_points_to_check(capsys):
    # the Alg. 2 claim runs the greedy without a limit; asked the file's question (3 tours)
    # paper's adaptation answers another question, so solve says where the refutation is
    path = str(ROOT / "instances" / "worst" / "alg2-makespan-paper.json")
    code, out, _ = run(capsys, "solve", path, "--method", "paper")
    assert code == 0 and "without a robot limit" in out and f"parcover props --check {path}" in out
    code, out, _ = run(capsys, "solve", path)  # the exact method: nothing to point at
    assert code == 0 and "without a robot limit" not in out


def test_explicit_flags_override_the_files_question(tmp_path, capsys):
    path = write(tmp_path, block())
    code, out, _ = run(capsys, "solve", path, "--routes", "paths", "--json")
    result = json.loads(out)
    assert code == 0 and result["robots"] == 2  # at c_max = sqrt(2) no path covers both KPOIs
    code, out, _ = run(capsys, "solve", path, "--deadline", "3", "--json")
    assert json.loads(out)["deadline"] == 3


# -- props --check --------------------------------------------------------------------


def test_check_exits_1_when_the_greedy_is_optimal_on_the_question(tmp_path, capsys):
    # at c_max both paper-1-1-end and the optimum need 2 paths (docstring): the claim holds here
    question = block(claim="alg1-paper-1-1-end", deadline=SQRT2, deadline_factor=1.0,
                     greedy={"robots": 2, "makespan": SQRT2},
                     optimum={"robots": 1, "makespan": 2.0, "status": "optimal", "method": "setpart"})
    code, out, _ = run(capsys, "props", "--check", write(tmp_path, question))
    assert code == 1 and "verdict: no longer refuted" in out


def test_check_exits_1_when_the_greedys_run_no_longer_gives_the_questions_limit(tmp_path, capsys):
    # no tour set here costs 100 (one tour over both costs 1 + 1 + sqrt(2) = 3.41): stale question
    question = block(claim="alg2-robots-paper", routes="tours", deadline=100.0, deadline_factor=None,
                     method="paper", reading="literal", greedy={"robots": 2, "makespan": 100.0, "limit": "none"})
    code, out, _ = run(capsys, "props", "--check", write(tmp_path, question))
    assert code == 1 and "now reaches makespan" in out


@pytest.mark.parametrize("flag", ["--reference", "--exact"])
def test_check_asks_the_reference_method_named(flag, tmp_path, capsys):
    # --exact is the former name of --reference; either names the method giving the optimum
    code, out, _ = run(capsys, "props", "--check", write(tmp_path, block()), flag, "branchprice")
    assert code == 0 and "branchprice" in out and "setpart" not in out.split("recorded")[0]


def test_check_exits_0_on_a_refuting_file_and_2_on_a_file_without_question(tmp_path, capsys):
    # paper-1-1-end at 1.5 c_max: path 1 goes to v_max = 2 (sqrt 2), extending it to 1 would cost
    # sqrt(2) + 1 = 2.414 > 2.121, so 1 gets a path of its own: 2 paths against the optimal 1
    code, out, _ = run(capsys, "props", "--check", write(tmp_path, block()))
    assert code == 0 and "verdict: refuted" in out
    plain = tmp_path / "plain.json"
    write_instance(INSTANCE, plain)
    code, out, err = run(capsys, "props", "--check", str(plain))
    assert code == 2 and "has no question block" in err
