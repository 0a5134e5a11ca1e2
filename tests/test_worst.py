"""The adversarial search and the halving-line family (parcover.worst)."""

import json

import parcover as pc
from parcover.io import read_instance
from parcover.worst import Target, halving_line, save_worst, score, search


def test_search_saves_instances_whose_ratio_recomputes(tmp_path):
    # Not tied to the search's numbers: the saved file is reread, the greedy rerun and
    # the optimum re-proven by setpart, and the ratio must match the question block.
    for target in (Target("alg1", "paper"), Target("alg2-makespan", "paper-nearest-end")):
        found = search(target, budget=1.0, seed=0, max_kpois=6)
        assert found.instance is not None and found.ratio >= 1.0
        path = save_worst(found.instance, target, found.score, tmp_path / f"{target.id}.json")
        question = json.loads(path.read_text())["question"]
        again = score(read_instance(path), target)
        assert question["claim"] == target.id
        mine, best = again.values
        key = "robots" if target.objective == "robots" else "makespan"
        assert abs(question["greedy"][key] - mine) < 1e-9 and abs(question["optimum"][key] - best) < 1e-9
        assert abs(again.ratio - found.ratio) < 1e-9


def test_halving_line_smallest_members():
    # length 3: KPOIs -3, 1, 2, 3; c_max = 3. Literal Alg. 1: path 1 = [-3]; path 2 starts
    # at 1 (cost 1), adds 2 (1 + d(1,2) = 2 <= 3), refuses 3 (printed 2 + d(1,3) = 4 > 3);
    # path 3 = [3]: 3 robots. Optimum 2: [-3] and [1, 2, 3] (cost 3); one path cannot hold
    # -3 and 1 within 3. Length 7: paths [-7], [1..4] (test for 5: 4 + 4 = 8 > 7),
    # [5, 6] (test for 7: 6 + 2 = 8 > 7), [7]: 4 robots, optimum 2.
    for length, greedy in ((3, 3), (7, 4)):
        inst = halving_line(length)
        assert pc.solve(inst, "paths", method="paper").robots == greedy
        best = pc.solve(inst, "paths", method="setpart")
        assert best.robots == 2 and best.status.value == "optimal"
