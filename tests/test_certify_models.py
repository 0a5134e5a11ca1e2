"""``verify --certify`` re-proves with a model other than the one that proved the file
(its ``model``, docs/format.md section 4), chosen among those that reach the question."""

from __future__ import annotations

import json

import pytest

import parcover as pc
from parcover.certify import certifier_for, certify, reaching
from parcover.exact import RACE_MAX_KPOIS, RACE_ROUTES


class Sized:
    """An instance stand-in: certifier_for reads only ``n``."""

    def __init__(self, n: int) -> None:
        self.n = n


# (KPOIs, objective, robot limit, the file's model) -> the certifier
CHOICES = [
    # set partitioning's range: setpart unless it made the proof
    (15, "makespan", 3, "setpart", "branchprice"),
    (15, "makespan", 3, "bounds", "setpart"),
    (18, "robots", None, "branchprice", "setpart"),
    (20, "makespan", 2, "setpart", "branchprice"),
    (20, "robots", None, "setpart", "branchprice"),
    (20, "makespan", 2, "branchcut", "setpart"),
    # few long routes: branch-and-cut and branch-and-price certify each other
    (50, "makespan", 3, "branchprice", "branchcut"),   # Necula's eil51 with 3 tours
    (50, "makespan", 2, "branchcut", "branchprice"),   # eil51 with 2 tours
    (RACE_MAX_KPOIS, "makespan", RACE_ROUTES, "branchprice", "branchcut"),
    (50, "makespan", 3, "compact", "branchcut"),
    # more routes, or the fewest robots: branch-and-price, then branch-and-cut for the makespan
    (50, "makespan", 5, "compact", "branchprice"),
    (50, "makespan", 5, "branchprice", "branchcut"),
    (50, "robots", None, "branchprice", "compact"),
    (50, "robots", None, "compact", "branchprice"),
    # above branch-and-cut's and branch-and-price's sizes
    (RACE_MAX_KPOIS + 1, "makespan", 2, "branchprice", "compact"),
    (150, "makespan", 2, "compact", "branchprice"),
    (300, "makespan", 2, "compact", "compact"),   # nothing else reaches it: undecided at worst
]


@pytest.mark.parametrize("n,objective,robots,model,expected", CHOICES)
def test_the_certifier_is_not_the_files_model_and_reaches_the_question(n, objective, robots, model, expected):
    chosen = certifier_for(Sized(n), "exact", objective, model=model, robots=robots)
    assert chosen == expected
    assert chosen != model or reaching(n, objective, robots) == ("compact",)
    assert chosen in reaching(n, objective, robots)


def test_a_file_without_model_leaves_out_every_model_exact_may_use():
    # old files: at race sizes exact may have answered with either, so neither certifies
    assert certifier_for(Sized(50), "exact", "makespan", robots=3) == "compact"
    assert certifier_for(Sized(50), "exact", "makespan", robots=5) == "branchcut"  # exact does not race k = 5
    assert certifier_for(Sized(50), "branchprice", "makespan", robots=3) == "branchcut"
    assert certifier_for(Sized(50), "branchcut", "makespan", robots=3) == "branchprice"
    # an unknown model name counts as none
    assert certifier_for(Sized(50), "exact", "makespan", model="magic", robots=3) == "compact"


def test_results_name_their_model_in_json():
    instance = pc.generate.random_points(8, 3)
    exact = pc.solve(instance, robots=2)
    assert exact.model in ("setpart", "bounds") and exact.to_dict()["model"] == exact.model
    keys = list(exact.to_dict())
    assert keys.index("model") == keys.index("method") + 1
    assert "model" not in pc.solve(instance, robots=2, method="nn").to_dict()
    assert pc.solve(instance, robots=2, method="branchprice").to_dict()["model"] == "branchprice"


ROBOTS = 2


@pytest.fixture(scope="module")
def twenty_one():
    """21 KPOIs, 2 tours: above set partitioning's range, where exact races (each model
    proves it in seconds on a quiet machine, in 20-75 s with 5-10 processes on 2 cores)."""
    instance = pc.generate.random_points(21, 26)
    answers = {model: pc.solve(instance, "tours", robots=ROBOTS, method=model, time_limit=300)
               for model in ("branchprice", "branchcut")}
    for answer in answers.values():
        assert answer.status is pc.Status.OPTIMAL
    return instance, answers


@pytest.mark.parametrize("model,certifier", [("branchprice", "branchcut"), ("branchcut", "branchprice")])
def test_certify_end_to_end_with_the_other_model(twenty_one, model, certifier):
    instance, answers = twenty_one
    fields = {**json.loads(answers[model].to_json()), "method": "exact", "model": model}
    verdict = pc.verify(instance, fields, certify=True, time_limit=300)
    assert verdict.certificate.method == certifier
    assert verdict.certificate.outcome == "certified", verdict.certificate.reasons


def test_certify_end_to_end_setpart_proof():
    instance = pc.generate.random_points(12, 4)
    answer = pc.solve(instance, "tours", robots=2, method="setpart")
    fields = {**json.loads(answer.to_json()), "method": "exact", "model": "setpart"}
    verdict = pc.verify(instance, fields, certify=True, time_limit=60)
    assert verdict.certificate.method == "branchprice" and verdict.certificate.outcome == "certified"
    # the same file without its model (as written before the key existed) still certifies
    fields.pop("model")
    verdict = pc.verify(instance, fields, certify=True, time_limit=60)
    assert verdict.certificate.method == "branchprice" and verdict.certificate.outcome == "certified"


def test_certify_refutes_a_false_optimum_even_from_its_routes(twenty_one):
    """The certifier starts from the file's routes; a worse solution claimed optimal (its
    status, bound and gap rewritten) is still refuted."""
    instance, answers = twenty_one
    worse = pc.solve(instance, "tours", robots=ROBOTS, method="nn")
    assert worse.makespan > answers["branchprice"].makespan * 1.001
    fields = {**json.loads(worse.to_json()), "status": "optimal", "bound": worse.makespan, "gap": 0.0,
              "method": "exact", "model": "branchprice"}
    certificate = certify(instance, fields, time_limit=300)
    assert certificate.method == "branchcut" and certificate.outcome == "refuted", certificate
