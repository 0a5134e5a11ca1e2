"""The adversarial search and the halving-line family (parcover.worst)."""

import json

import pytest

import parcover as pc
from parcover.cli import main
from parcover.instance import Instance
from parcover.io import read_instance
from parcover.worst import (Found, Target, family, family_table, found_row, growth, grows, halving_line,
                            save_found, save_worst, score, search)


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


def test_family_drawing_is_written_and_in_the_report_text(tmp_path):
    # The family is drawn (literal Alg. 1's paths beside the optimum), and report() links it.
    import inspect

    from parcover import worst

    path = worst.draw_family(7, tmp_path / "halving_line.png")
    assert path.exists() and path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "halving_line.png" in inspect.getsource(worst.report)


def test_a_ratio_of_one_saves_no_file_and_says_so(tmp_path):
    # One KPOI at distance 1: Alg. 1 uses 1 robot, the optimum too (ratio 1). Its file would
    # fail props --check (shown by saving it anyway), so save_found writes none, removes a
    # stale one of that name, and the report row says so. The halving line L = 3 (ratio 3 / 2)
    # is saved and passes the check.
    target = Target("alg1", "paper")
    one = Instance.from_points([(0.0, 0.0), (1.0, 0.0)], name="one")
    even = Found(target)
    even.offer(one, score(one, target), "plane")
    forced = save_worst(even.instance, target, even.score, tmp_path / "forced" / "f.json")
    assert main(["props", "--check", str(forced)]) == 1
    stale = tmp_path / f"{target.id}.json"
    stale.write_text("{}")
    assert save_found(even, tmp_path) is None and not stale.exists()
    assert "none saved: no ratio above 1 found" in found_row(even, None)
    worse = Found(target)
    worse.offer(halving_line(3), score(halving_line(3), target), "plane")
    path = save_found(worse, tmp_path)
    assert path == stale and main(["props", "--check", str(path)]) == 0
    assert f"`{path}`" in found_row(worse, path)


def test_halving_line_at_alg1_1_deadlines_stops_growing():
    # Literal test at deadline D: a path started at a takes j while (j - 1) + (j - a) <= D.
    # L = 1023, D = 1.25 L = 1278.75: [1..640] (2j - 2 <= D), [641..960] (2j - 642 <= D),
    # [961..1023]: with [-1023], 4 robots, as at L = 31 (D = 38.75: [1..20], [21..30], [31]).
    # D = 1.5 L = 1534.5: [1..768], [769..1023]: 3 robots (L = 31, D = 46.5: [1..24], [25..31]).
    def xs(route):
        return [-length if v == "1" else int(v) - 1 for v in route[1:]]

    length = 1023
    inst = halving_line(length)
    routes = pc.solve(inst, "paths", deadline=1.25 * length, method="paper").routes
    assert [(xs(r)[0], xs(r)[-1]) for r in routes] == [(-1023, -1023), (1, 640), (641, 960), (961, 1023)]
    routes = pc.solve(inst, "paths", deadline=1.5 * length, method="paper").routes
    assert [(xs(r)[0], xs(r)[-1]) for r in routes] == [(-1023, -1023), (1, 768), (769, 1023)]
    for factor, robots in ((1.25, 4), (1.5, 3)):
        assert pc.solve(halving_line(31), "paths", deadline=factor * 31, method="paper").robots == robots


def test_family_growth_verdicts_from_hand_counted_members():
    # At c_max, L = 3, 7, 15: literal Alg. 1 uses 3, 4, 5 robots (test above), optimum 2:
    # ratios 1.5, 2, 2.5 rise at each member, so it grows. At 1.25 c_max: L = 3 (D = 3.75):
    # [-3], [1, 2], [3]; L = 7 (D = 8.75): [-7], [1..5], [6, 7]; L = 15 (D = 18.75): [-15],
    # [1..10], [11..15]: 3 robots each, ratio 1.5 throughout: bounded, and the search's
    # larger ratio is the one reported. paper-5d-end sweeps the line: ratio 1, no growth.
    members = family((3, 7, 15), (1.0, 1.25), reference="setpart")
    assert [m.greedy["paper"] for m in members] == [3, 3, 4, 3, 5, 3]
    assert grows(Target("alg1", "paper"), members) and grows(Target("alg1", "paper-1-1-end"), members)
    assert not grows(Target("alg1", "paper-5d-end"), members)
    assert not grows(Target("alg1-1-x1.25", "paper"), members)
    found = Found(Target("alg1-1-x1.25", "paper"))
    found.by_n = {3: 2.0, 4: 3.0}
    assert growth(found.target, found, members).endswith(
        "| 3.000 | 4 | search | bounded on everything tried, largest ratio seen 3.000 at n = 4 |")
    found = Found(Target("alg1", "paper"))
    found.by_n = {2: 2.0}
    row = growth(found.target, found, members)
    assert "| 2.500 | 16 | halving line | **grows**: the halving line, 1.50 at n = 4 to 2.50 at n = 16" in row


def test_family_row_of_an_unproven_optimum_is_feasible_and_stops_the_family():
    # With a method that cannot prove its answer (the greedy itself: 4 robots at L = 7, bound 2),
    # the member is shown feasible with its bound, never optimal, and L = 15 is not tried.
    members = family((7, 15), (1.0,), reference="paper")
    assert [m.length for m in members] == [7] and not members[0].proven
    row = family_table(members, 1.0)[-1]
    assert row == "| 8 | 4 | 2 | 4 | 2 | 4 | feasible | 2 | >= 1.00 |" and "optimal" not in row


def test_worst_help_has_a_description(capsys):
    with pytest.raises(SystemExit):
        main(["worst", "--help"])
    out = capsys.readouterr().out
    assert "Search for the worst greedy/optimum ratio per claim and reading." in out


def test_found_keeps_the_smaller_instance_on_a_tie():
    # At 1.25 c_max the literal Alg. 1-1 uses 3 robots on the halving line L = 15 ([-15],
    # [1..10], [11..15]) and on L = 3 ([-3], [1, 2], [3]), the optimum 2: ratio 1.5 on both,
    # so the 4-KPOI member replaces the 16-KPOI one; a larger one with the same ratio does not.
    target = Target("alg1-1-x1.25", "paper")
    found = Found(target)
    for length in (15, 3, 7):
        found.offer(halving_line(length), score(halving_line(length), target), "plane")
    assert found.ratio == 1.5 and found.instance.n == 4 and found.by_n == {16: 1.5, 4: 1.5, 8: 1.5}


def _recorded_worst(monkeypatch, tmp_path, *flags):
    """Run `parcover worst` in tmp_path with report() replaced by a recorder; its keyword arguments."""
    from parcover import worst

    calls = []
    monkeypatch.setattr(worst, "report", lambda **kwargs: calls.append(kwargs) or "")
    monkeypatch.chdir(tmp_path)
    assert main(["worst", "--budget", "1", *flags]) == 0
    return calls[0]


def test_worst_writes_under_its_out_folder_by_default(monkeypatch, tmp_path):
    # run in a clone, the defaults must not overwrite the committed instances/worst and reports/worst.md
    call = _recorded_worst(monkeypatch, tmp_path)
    assert (call["out_dir"], call["report_path"]) == ("worst-out/instances", "worst-out/worst.md")
    call = _recorded_worst(monkeypatch, tmp_path, "--out", "mine")
    assert (call["out_dir"], call["report_path"]) == ("mine/instances", "mine/worst.md")


def test_worst_regenerates_the_committed_report_when_asked(monkeypatch, tmp_path):
    # the committed report names the explicit command that rewrites it
    from pathlib import Path

    committed = (Path(__file__).parent.parent / "reports" / "worst.md").read_text()
    command = "parcover worst --budget 8 --out-dir instances/worst --report reports/worst.md"
    assert f"    {command}\n" in committed
    call = _recorded_worst(monkeypatch, tmp_path, *command.split()[4:])
    assert (call["out_dir"], call["report_path"]) == ("instances/worst", "reports/worst.md")


def test_worst_refuses_a_file_as_its_out_folder(monkeypatch, tmp_path, capsys):
    (tmp_path / "taken").write_text("")
    monkeypatch.chdir(tmp_path)
    assert main(["worst", "--out", "taken"]) == 2
    assert "--out taken is a file" in capsys.readouterr().err


def test_worst_help_shows_every_default(capsys):
    with pytest.raises(SystemExit):
        main(["worst", "--help"])
    out = " ".join(capsys.readouterr().out.split())
    for option in ("--budget SECONDS seconds of search per claim and reading (default: 5)",
                   "--seed SEED seed of the search (default: 0)", "(default: worst-out)",
                   "(default: OUT/instances)", "(default: OUT/worst.md)"):
        assert option in out
