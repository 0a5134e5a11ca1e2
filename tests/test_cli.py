"""The command line contract of docs/format.md section 3."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from parcover.cli import main

ROOT = Path(__file__).resolve().parents[1]
GRID = str(ROOT / "instances" / "fig1_grid.json")
CONTRACT_KEYS = [
    "instance", "routes_kind", "objective", "robots_limit", "deadline", "method", "status",
    "robots", "makespan", "bound", "gap", "routes", "route_costs", "seconds",
]


def run(capsys, *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_solve_json_is_one_object_with_the_contract_keys(capsys):
    code, out, _ = run(capsys, "solve", GRID, "--method", "trivial", "--robots", "2", "--json")
    result = json.loads(out)
    assert code == 0 and list(result) == CONTRACT_KEYS
    assert result["objective"] == "makespan" and result["robots_limit"] == 2 and result["robots"] <= 2


def test_an_unproven_json_answer_says_why_in_an_optional_note(capsys):
    # a limit spent before the method starts: no routes, and the reason as the one extra key
    code, out, _ = run(capsys, "solve", GRID, "--robots", "2", "--time-limit", "1e-9", "--json")
    result = json.loads(out)
    assert code == 0 and result["status"] == "unknown" and list(result) == [*CONTRACT_KEYS, "note"]
    assert "time limit" in result["note"]
    code, out, _ = run(capsys, "solve", GRID, "--robots", "2", "--json")  # proven: nothing to note
    # exact names the model that proved it, an optional key after "method"
    at = CONTRACT_KEYS.index("method") + 1
    assert code == 0 and json.loads(out)["status"] == "optimal"
    assert list(json.loads(out)) == [*CONTRACT_KEYS[:at], "model", *CONTRACT_KEYS[at:]]


def test_solve_output_passes_verify(capsys, tmp_path):
    out_file = tmp_path / "result.json"
    code, _, _ = run(capsys, "solve", GRID, "--method", "trivial", "--routes", "tours", "--out", str(out_file))
    assert code == 0
    code, out, _ = run(capsys, "verify", GRID, str(out_file))
    assert code == 0 and out.startswith("valid: 8 robots, makespan 8 (tours)")


def test_verify_lists_each_violation_and_exits_1(capsys, tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"routes": [["r0c0", "r0c1", "nowhere"], ["r1c1"]], "routes_kind": "paths"}))
    code, out, _ = run(capsys, "verify", GRID, str(bad))
    lines = out.splitlines()
    assert code == 1 and len(lines) == 3
    assert "unknown id 'nowhere'" in lines[0] and "does not begin at the start" in lines[1]
    assert "not covered" in lines[2]


def test_verify_reports_a_missed_deadline_and_exits_1(capsys, tmp_path):
    late = tmp_path / "late.json"
    routes = [["r0c0", "r0c1", "r0c2", "r1c2", "r2c2", "r2c1", "r2c0", "r1c0", "r1c1"]]
    late.write_text(json.dumps({"routes": routes, "deadline": 4}))
    code, out, _ = run(capsys, "verify", GRID, str(late))
    assert code == 1 and "missed by 4" in out


def test_infeasible_deadline_is_an_answer_not_an_error(capsys):
    code, out, _ = run(capsys, "solve", GRID, "--method", "trivial", "--deadline", "3.5", "--json")
    assert code == 0 and json.loads(out)["status"] == "infeasible"


def test_frontier_json_contract(capsys):
    code, out, _ = run(capsys, "frontier", GRID, "--method", "trivial", "--json")
    data = json.loads(out)
    assert code == 0 and {"instance", "routes_kind", "points"} <= set(data)
    assert [p["robots"] for p in data["points"]] == list(range(1, len(data["points"]) + 1))
    assert set(data["points"][0]) == {"robots", "makespan", "status", "bound"}
    assert data["points"][-1]["makespan"] == 4  # it stops once c_max is reached


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["solve", GRID, "--robots", "0"], "robot limit must be a whole number >= 1"),  # no robots
        (["solve", GRID, "--robots", "two"], "invalid int value"),  # not a number
        (["solve", GRID, "--deadline", "-1"], "deadline must be finite and >= 0"),  # negative time
        (["solve", GRID, "--deadline", "nan"], "deadline must be finite"),  # not a time
        (["solve", GRID, "--robots", "2", "--deadline", "5"], "not allowed with argument"),  # one question
        (["solve", GRID, "--method", "magic"], "Unknown method 'magic'"),  # no such method
        (["solve", GRID, "--time-limit", "0"], "must be > 0"),  # no time at all
        (["solve", GRID, "--routes", "loops"], "invalid choice"),  # paths or tours
        (["solve", "no/such/file.json"], "no such file"),  # missing file
        (["solve", GRID, "--method", "trivial", "--trace"], "takes no option 'trace'"),  # trace is the paper's
        (["solve", GRID, "--method", "trivial", "--out", "no/such/dir/r.json"], "Cannot write"),  # bad output
        (["verify", GRID, str(ROOT / "instances" / "README.md")], "malformed JSON"),  # not JSON
        (["verify", GRID, GRID], "not a solution"),  # an instance, not a solution
        (["generate", "grid", "--rows", "0"], "rows must be a whole number >= 1"),  # empty grid
        (["generate", "random", "--n", "-3"], "n must be a whole number >= 1"),  # no KPOIs
        (["generate", "hexagon"], "invalid choice"),  # no such generator
        (["explode"], "invalid choice"),  # no such command
    ],
)
def test_bad_input_exits_2_with_one_line(capsys, argv, message):
    assert _exit_status(argv) == 2
    _, err = capsys.readouterr()
    assert message in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err


def _exit_status(argv: list[str]) -> int:
    """main()'s status, whether it returns it or argparse exits with it."""
    try:
        return main(argv)
    except SystemExit as exc:
        return int(exc.code or 0)


def test_console_entry_point_runs_without_traceback():
    # the installed script and python -m parcover are the same main()
    done = subprocess.run(
        [sys.executable, "-m", "parcover", "solve", "no/such.json"], capture_output=True, text=True
    )
    assert done.returncode == 2 and done.stderr.count("\n") == 1 and "Traceback" not in done.stderr


@pytest.mark.parametrize(
    "argv",
    [
        ["grid", "--rows", "2", "--cols", "4"],
        ["star", "--n", "5"],
        ["random", "--n", "7", "--seed", "3", "--layout", "clustered"],
        ["graph", "--n", "6", "--seed", "2"],
    ],
)
def test_generate_is_deterministic_and_loadable(capsys, tmp_path, argv):
    code, first, _ = run(capsys, "generate", *argv)
    _, second, _ = run(capsys, "generate", *argv)
    assert code == 0 and first == second
    path = tmp_path / "g.json"
    path.write_text(first)
    code, _, _ = run(capsys, "solve", str(path), "--method", "trivial")
    assert code == 0


def test_bundled_instances_are_reproduced_by_their_commands(capsys):
    # instances/README.md lists the command that made each generated file
    commands = {
        "fig1_grid.json": ["grid", "--rows", "3", "--cols", "3", "--name", "fig1-grid-3x3"],
        "fig3_star.json": ["star", "--n", "6", "--name", "fig3-star-6"],
        "random8_s1.json": ["random", "--n", "8", "--seed", "1"],
        "random12_s2.json": ["random", "--n", "12", "--seed", "2"],
        "clustered20_s3.json": ["random", "--n", "20", "--seed", "3", "--layout", "clustered"],
        "graph10_s4.json": ["graph", "--n", "10", "--seed", "4"],
    }
    for name, argv in commands.items():
        _, out, _ = run(capsys, "generate", *argv)
        assert out == (ROOT / "instances" / name).read_text(), name


def test_generate_map_writes_a_solvable_instance_with_a_relative_image(capsys, tmp_path):
    out = tmp_path / "cave.json"
    image = ROOT / "instances" / "maps" / "cave.png"
    code, _, _ = run(capsys, "generate", "map", "--image", str(image), "--metres-per-pixel", "0.032",
                     "--kpois", "6", "--seed", "3", "--out", str(out))
    assert code == 0
    data = json.loads(out.read_text())
    assert not Path(data["map"]["image"]).is_absolute() and len(data["kpois"]) == 6
    code, _, _ = run(capsys, "solve", str(out), "--method", "nn", "--plot", str(tmp_path / "r.png"))
    assert code == 0 and (tmp_path / "r.png").stat().st_size > 1000


def test_frontier_plot(capsys, tmp_path):
    code, _, _ = run(capsys, "frontier", GRID, "--method", "trivial", "--plot", str(tmp_path / "f.png"))
    assert code == 0 and (tmp_path / "f.png").stat().st_size > 1000


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["generate", "map", "--image", "no/such.png", "--metres-per-pixel", "1"], "no such image file"),
        (["generate", "map", "--image", GRID, "--metres-per-pixel", "1"], "not a readable image"),
        (["solve", GRID, "--deadline", "1", "--plot", "x.png"], "No routes to draw"),
    ],
)
def test_bad_map_and_plot_input_exits_2(capsys, argv, message):
    assert _exit_status(argv) == 2
    _, err = capsys.readouterr()
    assert message in err and len(err.strip().splitlines()) == 1


def test_props_quick_prints_the_verdict_table(capsys):
    code, out, _ = run(capsys, "props", "--quick", "--greedy", "paper")
    assert code == 0 and "prop1-paths" in out and "alg1-paper" in out


def test_report_writes_the_command_that_regenerates_it(capsys, tmp_path):
    argv = ["report", "random:n=4:seeds=0", "--methods", "trivial", "--routes", "paths", "--robots", "2",
            "--time-limit", "5", "--workers", "1", "--no-progress", "--no-plots", "--out", str(tmp_path)]
    code, out, _ = run(capsys, *argv)
    text = (tmp_path / "report.md").read_text()
    assert code == 0 and f"    parcover {' '.join(argv)}" in text and (tmp_path / "gaps.csv").exists()
