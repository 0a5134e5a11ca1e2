"""Teaching frames: one picture per recorded step of the paper's algorithms (parcover.frames)."""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import pytest  # noqa: E402

import parcover as pc  # noqa: E402
from parcover.cli import main  # noqa: E402
from parcover.errors import InputError  # noqa: E402
from parcover.frames import draw_step, save_frames, trace_steps  # noqa: E402

ROOT = Path(__file__).parent.parent
GRID = str(ROOT / "instances" / "fig1_grid.json")
SMALL = str(ROOT / "instances" / "counterexamples" / "alg2-makespan-paper.json")  # 3 KPOIs
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def test_solve_plot_folder_writes_one_frame_per_trace_step(capsys, tmp_path):
    folder = tmp_path / "frames"
    assert main(["solve", GRID, "--method", "paper", "--trace", "--plot", f"{folder}/"]) == 0
    out = capsys.readouterr().out
    lines = out.split("\n\n")[0].splitlines()  # the trace, printed before the summary
    frames = sorted(folder.glob("step-*.png"))
    assert len(frames) == len(lines) == 11  # Fig. 1 grid: steps 1-4, 5a-5c and 5d x 3, 5a-5c, 6, result
    assert all(f.read_bytes()[:8] == PNG_MAGIC for f in frames)
    assert (folder / "steps.gif").read_bytes()[:6] == b"GIF89a"
    assert f"wrote 11 frames and steps.gif to {folder}/" in out


def test_an_existing_folder_means_frames_too(capsys, tmp_path):
    # tours: Alg. 1's steps, then Alg. 2's pairings
    argv = ["solve", SMALL, "--method", "paper", "--routes", "tours", "--trace", "--json",
            "--plot", str(tmp_path)]
    assert main(argv) == 0
    result = pc.solve(pc.read_instance(SMALL), "tours", method="paper", trace=True)
    assert len(list(tmp_path.glob("step-*.png"))) == len(result.info["trace"])
    assert any(line.startswith("Alg 2 steps 1-5") for line in result.info["trace"])


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--method", "paper", "--plot", "{tmp}/"], "is a folder: it takes one picture per step of --trace"),  # no trace
        (["--method", "paper", "--trace", "--plot", "{tmp}/no/such/"], "no folder"),  # parent missing
        (["--method", "nn", "--trace", "--plot", "{tmp}/"], "takes no option 'trace'"),  # only paper* trace
        (["--method", "paper", "--trace", "--deadline", "1", "--plot", "{tmp}/"],
         "No steps to draw: the answer is infeasible"),  # a deadline below c_max = 4: nothing ran
    ],
)
def test_bad_frame_requests_are_one_line(capsys, tmp_path, argv, message):
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    assert main(["solve", GRID, *argv]) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1


def test_save_frames_returns_the_frames_in_step_order(tmp_path):
    small = pc.read_instance(SMALL)
    result = pc.solve(small, method="paper-nearest-end", trace=True)
    frames = save_frames(small, result, tmp_path / "f", gif=False)
    assert [f.name for f in frames] == [f"step-{i:03d}.png" for i in range(1, len(result.info["trace"]) + 1)]
    assert not (tmp_path / "f" / "steps.gif").exists()


def test_a_step_5d_frame_shows_path_candidate_and_budget(fig1_grid):
    # literal Alg. 1 on Fig. 1: the 8th step refuses r1c2, measured from v_m = r0c1 (4 + 2 > 4)
    result = pc.solve(fig1_grid, method="paper", trace=True)
    steps = trace_steps(result)
    step = steps[7]
    fig, ax = plt.subplots()
    draw_step(ax, fig1_grid, result, step, 8, len(steps))
    title = ax.get_title(loc="left")
    assert "frame 8/11" in title and "Alg 1 step 5d: nearest KPOI to r0c1: r1c2; 4 + 2 = 6 > 4, break" in title
    assert "path 2: cost 4, c_max = 4, budget left 0" in title
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "candidate r1c2: refused" in labels and "distance measured from r0c1" in labels
    assert "path 2 (growing)" in labels and "KPOI not yet covered" in labels
    plt.close(fig)


def test_a_result_without_steps_is_refused(fig1_grid):
    with pytest.raises(InputError, match="no recorded steps"):
        trace_steps(pc.solve(fig1_grid, method="paper"))
