"""Run the benchmarks and write the report: ``python -m benchmarks [--quick] [--out FILE]``.

The full run writes ``reports/benchmarks.md`` with its figures and CSVs in
``reports/benchmarks/``; ``--quick`` (a smoke run of a few minutes, for CI) writes
``reports/benchmarks-quick.md`` unless ``--out`` says otherwise. ``--sections`` runs
some of them only: each section's text is also kept in ``<figures>/<section>.json``, and
the report shows the sections not run this time from there, each with the date and
command of its own run (``--sections ''`` runs none and only rewrites the report). The report
starts with the command that reruns every section, the command that wrote it, the machine
and the package versions; it ends with the targets and the figures reached.
"""

from __future__ import annotations

import argparse
import importlib
import json
import shlex
import subprocess
import sys
import time
from pathlib import Path

from benchmarks.common import ROOT, Config, Section, compile_pricing

SECTIONS = ("greedy_scaling", "exact_scaling", "exact_targets", "building_scale", "building_scale_unseen",
            "building_scale_makespan", "building_scale_makespan_unseen",
            "heuristic_quality", "mtsp_literature", "maps_speed", "report_speed")
PACKAGES = ("numpy", "scipy", "pandas", "highspy", "cvxpy", "networkx", "ortools", "pyvrp")


def main(argv: list[str] | None = None) -> int:
    """Parse the arguments, run the sections, write the report; exit status 0."""
    parser = argparse.ArgumentParser(prog="python -m benchmarks", description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a smoke run of a few minutes (CI)")
    parser.add_argument("--out", type=Path, help="report file (default: reports/benchmarks[-quick].md)")
    parser.add_argument("--sections", default=",".join(SECTIONS), help=f"comma-separated, of: {', '.join(SECTIONS)}")
    args = parser.parse_args(argv)
    names = [s for s in args.sections.split(",") if s]
    unknown = [s for s in names if s not in SECTIONS]
    if unknown:
        parser.error(f"unknown section {unknown[0]!r}; expected some of {', '.join(SECTIONS)}")
    out = args.out or Path("reports") / ("benchmarks-quick.md" if args.quick else "benchmarks.md")
    figures = out.with_suffix("")
    figures.mkdir(parents=True, exist_ok=True)
    config = Config(quick=args.quick, figures=figures, figures_link=figures.name)
    command = "python -m benchmarks " + " ".join(shlex.quote(a) for a in (sys.argv[1:] if argv is None else argv))
    commit = _commit()  # before the run: its own reports would count as local changes
    compile_pricing(config)
    for name in names:
        config.log(f"[benchmarks] {name} ...")
        began = time.perf_counter()
        section: Section = importlib.import_module(f"benchmarks.{name}").run(config)
        minutes = (time.perf_counter() - began) / 60
        config.log(f"[benchmarks] {name} done in {minutes * 60:.0f} s")
        for table, frame in section.tables.items():
            frame.to_csv(figures / f"{table}.csv", index=False)
        save_section(section, figures / f"{name}.json", command.strip(), minutes, commit)
    sections = [json.loads(path.read_text(encoding="utf-8"))
                for path in (figures / f"{name}.json" for name in SECTIONS) if path.exists()]
    out.write_text(render(sections, command.strip()), encoding="utf-8")
    config.log(f"[benchmarks] wrote {out}")
    return 0


def _every_section(command: str) -> str:
    """``command`` without its ``--sections``: the command that reruns every section."""
    words = shlex.split(command)
    kept = [w for i, w in enumerate(words)
            if not (w == "--sections" or w.startswith("--sections=") or (i and words[i - 1] == "--sections"))]
    return shlex.join(kept)


def save_section(section: Section, path: Path, command: str, minutes: float, commit: str) -> None:
    """Keep a section's text, targets and provenance (when, machine, command, commit) as JSON."""
    saved = {"title": section.title, "markdown": section.markdown, "targets": section.targets,
             "command": command, "written": _now(), "minutes": round(minutes, 1), "machine": _machine(),
             "commit": commit}
    path.write_text(json.dumps(saved, indent=1) + "\n", encoding="utf-8")


def _commit() -> str:
    """The git commit the code runs from (``+ local changes`` when a file outside
    ``reports/`` differs from it)."""
    try:
        head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                              text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no", "--", ".", ":!reports"], cwd=ROOT,
                               capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown (not a git checkout)"
    return head + (" + local changes" if dirty else "")


def _now() -> str:
    return time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())


def _machine() -> str:
    """One line: CPU, cores, memory, platform, Python and the package versions."""
    from parcover.report import machine_info, package_version

    machine = machine_info()
    versions = ", ".join(f"{name} {package_version(name) or 'not installed'}" for name in PACKAGES)
    return (f"{machine['cpu']}, {machine['cores']} cores, {machine['memory_gb']} GB, "
            f"{machine['platform']}, Python {machine['python']}; {versions}")


def render(sections: list[dict], command: str) -> str:
    """The report: header (command, machine, versions), the sections, the targets.

    ``sections`` are saved sections (:func:`save_section`); one run by another command
    than this one says when, how and on what it ran.
    """
    lines = [
        "# Benchmarks",
        "",
        "Regenerate with (every section; `--sections NAME` reruns one, `--sections ''` only rewrites this file):",
        "",
        f"    {_every_section(command)}",
        "",
        f"- machine and packages: {_machine()}",
        f"- written {_now()} by `{command}`. Machines here are shared and noisy:",
        "  compare the ratios between methods measured in the same run, not absolute seconds.",
        "- a section can be rerun alone (`--sections NAME`); each says when and how it ran.",
        "",
    ]
    for section in sections:
        provenance = (f"Run {section['written']} in {section['minutes']:g} min from commit "
                      f"{section.get('commit', 'unknown')}: `{section['command']}`")
        if section["command"] != command:
            provenance += f" (machine: {section['machine']})"
        lines += [f"## {section['title']}", "", f"*{provenance}.*", "", section["markdown"].strip(), ""]
    targets = [t for s in sections for t in s["targets"]]
    if targets:
        lines += ["## Targets", "", *[f"- {t}" for t in targets], ""]
    return "\n".join(lines)


if __name__ == "__main__":
    sys.exit(main())
