"""Run the benchmarks and write the report: ``python -m benchmarks [--quick] [--out FILE]``.

The full run writes ``reports/benchmarks.md`` with its figures and CSVs in
``reports/benchmarks/``; ``--quick`` (a smoke run of a few minutes, for CI) writes
``reports/benchmarks-quick.md`` unless ``--out`` says otherwise. ``--sections`` runs
some of them only. The report starts with the command, the machine and the package
versions; it ends with the issue's targets and the figures reached.
"""

from __future__ import annotations

import argparse
import importlib
import shlex
import sys
import time
from pathlib import Path

from benchmarks.common import Config, Section

SECTIONS = ("greedy_scaling", "exact_scaling", "heuristic_quality", "mtsp_literature", "maps_speed")
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
    sections = []
    for name in names:
        config.log(f"[benchmarks] {name} ...")
        began = time.perf_counter()
        section: Section = importlib.import_module(f"benchmarks.{name}").run(config)
        config.log(f"[benchmarks] {name} done in {time.perf_counter() - began:.0f} s")
        for table, frame in section.tables.items():
            frame.to_csv(figures / f"{table}.csv", index=False)
        sections.append(section)
    out.write_text(render(sections, command.strip()), encoding="utf-8")
    config.log(f"[benchmarks] wrote {out}")
    return 0


def render(sections: list[Section], command: str) -> str:
    """The report: header (command, machine, versions), the sections, the targets."""
    from parcover.report import machine_info, package_version

    machine = machine_info()
    versions = ", ".join(f"{name} {package_version(name) or 'not installed'}" for name in PACKAGES)
    lines = [
        "# Benchmarks",
        "",
        "Regenerate with:",
        "",
        f"    {command}",
        "",
        f"- machine: {machine['cpu']}, {machine['cores']} cores, {machine['memory_gb']} GB, "
        f"{machine['platform']}, Python {machine['python']}",
        f"- packages: {versions}",
        f"- written {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}. Machines here are shared and noisy:",
        "  compare the ratios between methods measured in the same run, not absolute seconds.",
        "",
    ]
    for section in sections:
        lines += [f"## {section.title}", "", section.markdown.strip(), ""]
    targets = [t for s in sections for t in s.targets]
    if targets:
        lines += ["## Targets", "", *[f"- {t}" for t in targets], ""]
    return "\n".join(lines)


if __name__ == "__main__":
    sys.exit(main())
