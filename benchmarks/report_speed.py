"""Report speed: ``parcover report`` with default options, as a user first runs it.

Each report is the command a user types (``python -m parcover report ... --out DIR``,
default methods ``paper,mst,nn,best``, reference ``exact``, time limit 60 s per solve,
two workers, plots drawn), timed from start to exit:

- the **standard suite**: the instances of ``reports/gaps-standard`` (random, 6-14 KPOIs,
  seeds 0-4, 25 instances), both route kinds, every default question (2 and 3 robots;
  the fewest robots at the least possible makespan): 150 questions;
- **three small instances** (random, 7, 8 and 9 KPOIs, seed 0);
- the same on **unseen seeds** (standard sizes with seeds 100-104; 7-9 KPOIs with seed 101),
  never used while ``best``'s stopping rule was designed.

The peer, in the same run: the three small instances with ``best:until=limit`` (``best``
spending its whole time limit, what every default report did before the limit became a
cap) at a 5 s limit (1 s in the quick run); the ratio says how much faster the default
is than that, at a twelfth of its limit. ``best at optimum`` counts the rows where ``best`` meets the
reference's proven optimum.
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pandas as pd

from benchmarks.common import ROOT, Config, Section, markdown_table
from parcover.report import read_gaps

STANDARD = "random:n=6,8,10,12,14:seeds=0..4"
SMALL = "random:n=7..9:seeds=0"
UNSEEN_STANDARD = "random:n=6,8,10,12,14:seeds=100..104"
UNSEEN_SMALL = "random:n=7..9:seeds=101"
PEER_METHODS = ("--methods", "paper,mst,nn,best:until=limit")
PEER_LIMIT, QUICK_PEER_LIMIT = 5.0, 1.0
TARGETS = {STANDARD: 120.0, SMALL: 60.0}  # seconds


def time_report(spec: str, *options: str) -> dict[str, object]:
    """Run ``parcover report SPEC`` with ``options`` into a fresh folder; its wall time,
    questions, and how often ``best`` met a proven optimum."""
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder) / "report"
        began = time.perf_counter()
        subprocess.run([sys.executable, "-m", "parcover", "report", spec, *options, "--no-progress",
                        "--out", str(out)], check=True, cwd=ROOT, capture_output=True)
        seconds = time.perf_counter() - began
        frame = read_gaps(out / "gaps.csv")
    rows = frame[frame["method"].str.startswith("best")]
    questions = frame.groupby(["instance", "routes", "question"]).ngroups
    return {"instances": spec, "options": " ".join(options) or "(defaults)", "questions": questions,
            "seconds": seconds, "best at optimum": f"{int(rows['at_optimum'].sum())}/{len(rows)}",
            "reference optimal": f"{int((frame['reference_status'] == 'optimal').sum())}/{len(frame)}"}


def run(config: Config) -> Section:
    """Time each report (module docstring) and write the section."""
    peer = (*PEER_METHODS, "--time-limit", f"{QUICK_PEER_LIMIT if config.quick else PEER_LIMIT:g}")
    cases: list[tuple[str, tuple[str, ...]]] = [(SMALL, ()), (SMALL, peer)]
    if not config.quick:
        cases += [(STANDARD, ()), (UNSEEN_STANDARD, ()), (UNSEEN_SMALL, ())]
    rows = []
    for spec, options in cases:
        rows.append(time_report(spec, *options))
        config.log(f"[report_speed] {spec} {' '.join(options)}: {rows[-1]['seconds']:.1f} s")
    frame = pd.DataFrame(rows)
    default = frame[(frame["instances"] == SMALL) & (frame["options"] == "(defaults)")]["seconds"].iloc[0]
    peer = frame[(frame["instances"] == SMALL) & (frame["options"] != "(defaults)")]["seconds"].iloc[0]
    markdown = "\n\n".join([
        "`parcover report INSTANCES --out DIR` with default options (methods paper, mst, nn, best; "
        "reference exact; 60 s limit per solve; 2 workers; plots drawn), wall time from start to exit. "
        "The peer row runs `best` with `until=limit` at a short limit (how every default report ran before "
        f"the limit became a cap). Default / peer on the three small instances: **{default / peer:.3f}**.",
        markdown_table(frame, floatfmt=".1f"),
    ])
    return Section(title="Report speed", markdown=markdown, tables={"report_speed": frame},
                   targets=target_lines(frame))


def target_lines(frame: pd.DataFrame) -> list[str]:
    """The targets: the standard suite within 2 minutes, three 7-9-KPOI instances within 60 s."""
    lines = []
    for spec, limit in TARGETS.items():
        row = frame[(frame["instances"] == spec) & (frame["options"] == "(defaults)")]
        head = f"default report of {spec} within {limit:g} s"
        if row.empty:
            lines.append(f"{head}: not measured (quick run)")
            continue
        seconds = float(row["seconds"].iloc[0])
        lines.append(f"{head}: {'met' if seconds <= limit else 'not met'} — {seconds:.1f} s, "
                     f"best at the optimum on {row['best at optimum'].iloc[0]}")
    return lines
