"""Verdicts on the paper's claims, checked against exact optima, with shrunk counterexamples.

Each claim of Min & Papanikolopoulos is checked on instance families (the Fig. 1
grids, the Fig. 3 stars, seeded random Euclidean and graph instances, the bundled
``instances/*.json``) against the exact reference (method ``exact`` by default):

- ``prop1-paths`` / ``prop1-tours`` (Prop. 1): the least makespan over any number of
  robots is ``c_max`` (``2 c_max`` for tours). Makespan is non-increasing in the robot
  limit (idle robots are allowed) and ``n`` robots can do whatever more robots can, so
  the exact makespan with ``k = n`` is the least over every ``k``.
- ``prop2-x1``, ``prop2-x1.25`` (Prop. 2): the fewest robots for a deadline
  ``c_p >= c_max`` lies in ``[1, |V| - |P_max| + 1]`` (``c_p = c_max, 1.25 c_max``).
- ``fig1`` (Fig. 1): exact path makespans 8, 4, 4 for 1, 2, 3 robots on the 3x3 grid.
- ``fig3-paths`` / ``fig3-tours[-METHOD]`` (Fig. 3): on a star, ``|V|`` paths (exact
  fewest at ``c_max``) and ``ceil(|V| / 2)`` tours: the exact fewest tours at the
  makespan the method's Algorithm 2 reaches ("tours by connecting shortest paths").
- ``alg1-METHOD`` (Alg. 1): the method's robots at ``c_max`` are the fewest.
- ``alg1-1-x1.25-METHOD``, ``alg1-1-x1.5-METHOD`` (Alg. 1-1): the fewest at ``c_p``.
- ``alg2-robots-METHOD`` (Alg. 2): its tours are the fewest for the makespan it reaches.
- ``alg2-makespan-METHOD`` (Alg. 2): its makespan is the least for that many tours.

Honesty: every claim is a statement about an optimum ``opt`` that the reference
brackets between its proven bound and its verified value (:mod:`parcover.compare`).
An instance refutes a claim only when that bracket does: a proven optimum or bound
on the wrong side, or a verified exact solution better than the greedy's (a witness).
When the bracket straddles the claimed value the instance is *undecided* and counted
as such.

Counterexamples are shrunk by :func:`parcover.shrinking.shrink` (fewest KPOIs first,
then simplest coordinates; importable from here too), saved with
:func:`parcover.io.write_instance` and drawn beside the optimal routes when
:mod:`parcover.plot` is available.
"""

from __future__ import annotations

import dataclasses
import math
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from parcover import generate
from parcover.compare import CheckStatus, Outcome, brief, compare_optimum, number
from parcover.instance import Instance
from parcover.question import Question
from parcover.result import Result
from parcover.shrinking import instance_size, shrink

__all__ = [
    "Claim",
    "Outcome",
    "Verdict",
    "props",
    "claims",
    "CachedSolver",
    "compare_optimum",
    "check_instance",
    "draw_counterexample",
    "families",
    "evaluate",
    "shrink",
    "instance_size",
    "render_table",
    "render_verdicts",
]

Progress = Callable[[str], None]

_INSTANCES_DIR = Path(__file__).resolve().parent.parent / "instances"


@dataclass(frozen=True)
class Claim:
    """A claim of the paper, the instances it is checked on and how.

    Attributes
    ----------
    id
        File-name-safe id, e.g. ``alg1-paper``.
    statement
        The claim in one sentence, with the paper's reference.
    check
        ``check(instance) -> Outcome``.
    instances
        The instances the claim is checked on.
    method
        The greedy method it is about, or ``None`` for claims about optima.
    shrinkable
        Whether a counterexample stays meaningful on a smaller instance (not for
        Fig. 1 and Fig. 3, whose claimed numbers belong to one picture).
    greedy_vs_optimum
        Whether the claim is that the greedy ``method`` is optimal, so that a
        counterexample carries the question that shows it (:mod:`parcover.question`).
    deadline_factor
        The claim's deadline as a multiple of ``c_max``, when it has one.
    """

    id: str
    statement: str
    check: Callable[[Instance], Outcome]
    instances: tuple[Instance, ...]
    method: str | None = None
    shrinkable: bool = True
    greedy_vs_optimum: bool = False
    deadline_factor: float | None = None


@dataclass(frozen=True)
class Verdict:
    """The verdict on one claim.

    Attributes
    ----------
    claim, statement, method
        As in :class:`Claim`.
    tried, holds, refuted, undecided, errors
        Instance counts (``tried`` = all of them).
    counterexample
        The smallest refuting instance found, shrunk when the claim allows.
    found_on
        Name of the instance the counterexample was found on.
    numbers
        The exact numbers on the counterexample (greedy vs optimal).
    results
        The results on the counterexample, for drawing.
    file, picture
        Where the counterexample and its drawing were written, if they were.
    notes
        Anything the reader must know (undecided instances, errors, skipped drawings).
    question
        The question the counterexample answers worse with the greedy than the
        optimum does (greedy-versus-optimum claims only); saved in its file.
    """

    claim: str
    statement: str
    method: str | None
    tried: int
    holds: int
    refuted: int
    undecided: int
    errors: int
    counterexample: Instance | None = None
    found_on: str = ""
    numbers: str = ""
    results: tuple[Result, ...] = field(default=(), repr=False)
    file: str | None = None
    picture: str | None = None
    notes: tuple[str, ...] = ()
    question: Question | None = None

    @property
    def is_refuted(self) -> bool:
        return self.refuted > 0

    @property
    def text(self) -> str:
        """``refuted (R of M)`` or ``holds on N of M (U undecided)``."""
        extra = [f"{self.undecided} undecided"] if self.undecided else []
        extra += [f"{self.errors} errors"] if self.errors else []
        tail = f" ({', '.join(extra)})" if extra else ""
        if self.is_refuted:
            return f"refuted on {self.refuted} of {self.tried}{tail}"
        return f"holds on {self.holds} of {self.tried}{tail}"


# -- claims -------------------------------------------------------------------------


class CachedSolver:
    """``parcover.solve`` with a cache, so claims sharing a question solve it once.

    Parameters
    ----------
    time_limit
        Seconds per solve (``None``: no limit).
    seed
        Seed passed to every method.
    """

    def __init__(self, time_limit: float | None, seed: int) -> None:
        self.time_limit = time_limit
        self.seed = seed
        self._cache: dict[tuple, tuple[Instance, Result]] = {}

    def __call__(self, instance: Instance, method: str, routes: str = "paths", *,
                 robots: int | None = None, deadline: float | None = None) -> Result:
        from parcover.solve import solve

        key = (id(instance), method, routes, robots, deadline)
        if key not in self._cache:
            result = solve(instance, routes, robots=robots, deadline=deadline, method=method,  # type: ignore[arg-type]
                           time_limit=self.time_limit, seed=self.seed)
            self._cache[key] = (instance, result)  # the instance is kept so its id stays unique
        return self._cache[key][1]


def claims(
    solver: Callable[..., Result],
    *,
    reference: str = "exact",
    greedy: Sequence[str] = ("paper",),
    general: Sequence[Instance] = (),
    grids: Sequence[Instance] = (),
    stars: Sequence[Instance] = (),
) -> list[Claim]:
    """The paper's claims as checks against ``exact``, one per greedy method where it applies.

    Parameters
    ----------
    solver
        ``solver(instance, method, routes, robots=, deadline=) -> Result``.
    reference
        The exact reference method.
    greedy
        The methods implementing the paper's algorithms.
    general
        Instances for Props. 1-2 and the algorithms' optimality.
    grids
        Instances for Fig. 1 (the 3x3 grid).
    stars
        Instances for Fig. 3.
    """
    general, grids, stars = tuple(general), tuple(grids), tuple(stars)

    def prop1(routes: str) -> Callable[[Instance], Outcome]:
        def check(inst: Instance) -> Outcome:
            least = 2 * inst.c_max if routes == "tours" else inst.c_max
            ref = solver(inst, reference, routes, robots=inst.n)
            return compare_optimum(ref, "eq", least, f"least makespan claimed {number(least)} with k = n = {inst.n}")
        return check

    def prop2(factor: float) -> Callable[[Instance], Outcome]:
        def check(inst: Instance) -> Outcome:
            upper = inst.n - len(inst.P_max) + 1
            ref = solver(inst, reference, "paths", deadline=factor * inst.c_max)
            return compare_optimum(ref, "le", upper, f"|V| - |P_max| + 1 = {upper} at c_p = {factor:g} c_max")
        return check

    def fig1(inst: Instance) -> Outcome:
        parts = [
            compare_optimum(solver(inst, reference, "paths", robots=k), "eq", claimed, f"{k} robots: claimed {claimed:g}")
            for k, claimed in ((1, 8.0), (2, 4.0), (3, 4.0))
        ]
        return _all_of(parts)

    def fig3_paths(inst: Instance) -> Outcome:
        ref = solver(inst, reference, "paths")
        return compare_optimum(ref, "eq", inst.n, f"|V| = {inst.n} paths claimed at c_max")

    def greedy_optimal(method: str, routes: str, factor: float | None) -> Callable[[Instance], Outcome]:
        """Algorithms 1 and 1-1: the method's robots are the exact fewest."""
        def check(inst: Instance) -> Outcome:
            deadline = None if factor is None else factor * inst.c_max
            mine = solver(inst, method, routes, deadline=deadline)
            ref = solver(inst, reference, routes, deadline=deadline)
            out = compare_optimum(ref, "ge", mine.robots, brief(mine))
            return dataclasses.replace(out, results=(mine, ref))
        return check

    def alg2(method: str, objective: str) -> Callable[[Instance], Outcome]:
        """Algorithm 2 (tours, no deadline): fewest tours at its makespan, least makespan for its tours."""
        def check(inst: Instance) -> Outcome:
            mine = solver(inst, method, "tours")
            assert mine.makespan is not None and mine.robots is not None
            label = brief(mine)
            if objective == "robots":
                ref = solver(inst, reference, "tours", deadline=mine.makespan)
                out = compare_optimum(ref, "ge", mine.robots, label)
            else:
                ref = solver(inst, reference, "tours", robots=mine.robots)
                out = compare_optimum(ref, "ge", mine.makespan, label)
            return dataclasses.replace(out, results=(mine, ref))
        return check

    def fig3_tours(method: str) -> Callable[[Instance], Outcome]:
        def check(inst: Instance) -> Outcome:
            mine = solver(inst, method, "tours")
            ref = solver(inst, reference, "tours", deadline=mine.makespan)
            claimed = math.ceil(inst.n / 2)
            out = compare_optimum(ref, "eq", claimed,
                                  f"ceil(|V|/2) = {claimed} tours claimed at {method}'s makespan {number(mine.makespan)}")
            return dataclasses.replace(out, results=(mine, ref))
        return check

    out = [
        Claim("prop1-paths", "Prop. 1: the least path makespan over any number of robots is c_max.",
              prop1("paths"), general),
        Claim("prop1-tours", "Prop. 1: the least tour makespan over any number of robots is 2 c_max.",
              prop1("tours"), general),
        Claim("prop2-x1", "Prop. 2: the fewest robots at c_p = c_max is in [1, |V| - |P_max| + 1].",
              prop2(1.0), general),
        Claim("prop2-x1.25", "Prop. 2: the fewest robots at c_p = 1.25 c_max is in [1, |V| - |P_max| + 1].",
              prop2(1.25), general),
        Claim("fig1", "Fig. 1: exact path makespans 8, 4, 4 for 1, 2, 3 robots on the 3x3 grid.",
              fig1, grids, shrinkable=False),
        Claim("fig3-paths", "Fig. 3: |V| paths on a star (exact fewest at c_max).",
              fig3_paths, stars, shrinkable=False),
    ]
    for m in greedy:
        out += [
            Claim(f"fig3-tours-{m}", f"Fig. 3: ceil(|V|/2) tours on a star (exact fewest at the makespan {m}'s "
                  "Algorithm 2 reaches by connecting shortest paths).", fig3_tours(m), stars, m, shrinkable=False),
            Claim(f"alg1-{m}", f"Alg. 1 ({m}): the fewest robots for paths at c_max.",
                  greedy_optimal(m, "paths", None), general, m, greedy_vs_optimum=True, deadline_factor=1.0),
            Claim(f"alg1-1-x1.25-{m}", f"Alg. 1-1 ({m}): the fewest robots for paths at c_p = 1.25 c_max.",
                  greedy_optimal(m, "paths", 1.25), general, m, greedy_vs_optimum=True, deadline_factor=1.25),
            Claim(f"alg1-1-x1.5-{m}", f"Alg. 1-1 ({m}): the fewest robots for paths at c_p = 1.5 c_max.",
                  greedy_optimal(m, "paths", 1.5), general, m, greedy_vs_optimum=True, deadline_factor=1.5),
            Claim(f"alg2-robots-{m}", f"Alg. 2 ({m}): the fewest tours for the makespan it reaches.",
                  alg2(m, "robots"), general, m, greedy_vs_optimum=True),
            Claim(f"alg2-makespan-{m}", f"Alg. 2 ({m}): the least tour makespan for the number of tours it uses.",
                  alg2(m, "makespan"), general, m, greedy_vs_optimum=True),
        ]
    return out


def _all_of(parts: Sequence[Outcome]) -> Outcome:
    """Refuted if any part is, holds if all do, else undecided."""
    statuses = {p.status for p in parts}
    status: CheckStatus = next(s for s in ("error", "refuted", "undecided", "holds") if s in statuses)
    return Outcome(status, " | ".join(p.numbers for p in parts), tuple(r for p in parts for r in p.results))


# -- instance families -------------------------------------------------------------


def families(seed: int = 0, *, quick: bool = False) -> dict[str, tuple[Instance, ...]]:
    """The instances checked: ``general``, ``grids`` (Fig. 1) and ``stars`` (Fig. 3).

    Full: grids r x c for 2 <= r <= c <= 4, stars n = 3..8, three seeded random
    Euclidean instances for each n in 4, 6, ..., 14, two random graphs for each n in
    4, 6, ..., 12, and ``instances/*.json``. Quick: the 2x2, 2x3 and 3x3 grids, stars
    3..6, one random Euclidean instance each for n = 4, 6, one random graph with 5
    KPOIs. Seeds are ``seed``, ``seed + 1``, ...
    """
    if quick:
        grid_sizes = [(2, 2), (2, 3), (3, 3)]
        star_sizes = range(3, 7)
        points = [(n, seed) for n in (4, 6)]
        graphs = [(5, seed)]
        bundled: list[Instance] = []
    else:
        grid_sizes = [(r, c) for r in range(2, 5) for c in range(r, 5)]
        star_sizes = range(3, 9)
        points = [(n, seed + i) for n in range(4, 15, 2) for i in range(3)]
        graphs = [(n, seed + i) for n in range(4, 13, 2) for i in range(2)]
        bundled = _bundled()
    grids = tuple(generate.grid(r, c) for r, c in grid_sizes)
    stars = tuple(generate.star(n) for n in star_sizes)
    general = (
        grids
        + stars
        + tuple(generate.random_points(n, s) for n, s in points)
        + tuple(generate.random_graph(n, s) for n, s in graphs)
        + tuple(bundled)
    )
    fig1 = tuple(g for g in grids if g.name == "grid-3x3")
    return {"general": general, "grids": fig1, "stars": stars}


def _bundled() -> list[Instance]:
    from parcover.io import read_instance

    return [read_instance(p) for p in sorted(_INSTANCES_DIR.glob("*.json"))]


# -- evaluation ---------------------------------------------------------------------


def evaluate(claim: Claim, progress: Progress | None = None) -> tuple[Verdict, list[tuple[Instance, Outcome]]]:
    """Check ``claim`` on each of its instances; the verdict names the smallest refuting one.

    Returns the verdict (not yet shrunk) and the outcome per instance.
    """
    outcomes = []
    for inst in claim.instances:
        outcomes.append((inst, check_instance(claim, inst)))
        if progress is not None:
            progress(f"{claim.id} on {inst.name} (n={inst.n}): {outcomes[-1][1].status}")
    counts = {s: sum(o.status == s for _, o in outcomes) for s in ("holds", "refuted", "undecided", "error")}
    refuting = [(inst, o) for inst, o in outcomes if o.status == "refuted"]
    notes = tuple(f"{inst.name}: {o.status}: {o.numbers}" for inst, o in outcomes if o.status in ("undecided", "error"))
    verdict = Verdict(claim.id, claim.statement, claim.method, len(outcomes), counts["holds"], counts["refuted"],
                      counts["undecided"], counts["error"], notes=notes)
    if refuting:
        inst, o = min(refuting, key=lambda pair: instance_size(pair[0]))  # fewest KPOIs, edges, magnitude
        verdict = dataclasses.replace(verdict, counterexample=inst, found_on=inst.name, numbers=o.numbers,
                                      results=o.results)
    return verdict, outcomes


def check_instance(claim: Claim, inst: Instance) -> Outcome:
    """The claim's check, with a raising method reported as an ``error`` outcome."""
    try:
        return claim.check(inst)
    except Exception as exc:  # noqa: BLE001 - a failing method is reported, not fatal
        return Outcome("error", f"{type(exc).__name__}: {exc}")


def props(
    *,
    seed: int = 0,
    quick: bool = False,
    time_limit: float | None = 10.0,
    reference: str = "exact",
    greedy: Sequence[str] | None = None,
    out_dir: str | Path | None = None,
    report_path: str | Path | None = None,
    progress: Progress | None = None,
    command: str | None = None,
) -> list[Verdict]:
    """Check every claim of the paper against exact optima; shrink, save and draw counterexamples.

    Parameters
    ----------
    seed
        Seed of the random instance families (:func:`families`).
    quick
        Small families only (a few seconds; what the tests run).
    time_limit
        Seconds per exact solve (10 by default); unproven instances count as undecided.
    reference
        The exact reference method.
    greedy
        Methods implementing the paper's algorithms; default every registered method
        whose name starts with ``paper``.
    out_dir
        Where to write ``<claim-id>.json`` counterexamples (``<claim-id>`` includes the
        method); nothing is written without it.
    report_path
        Where to write the Markdown report (pictures go to ``<report stem>/`` beside it).
    progress
        Called with one line per instance checked.
    command
        The command that regenerates the report, printed at its top.

    Returns
    -------
    list[Verdict]
        One per claim, in :func:`claims` order.
    """
    from parcover.solve import available_methods

    if greedy is None:
        greedy = sorted(m for m in available_methods() if m.startswith("paper"))
    solver = CachedSolver(time_limit, seed)
    fam = families(seed, quick=quick)
    started = time.perf_counter()
    verdicts = []
    for claim in claims(solver, reference=reference, greedy=greedy, general=fam["general"], grids=fam["grids"],
                        stars=fam["stars"]):
        verdict, _ = evaluate(claim, progress)
        if verdict.counterexample is not None and claim.shrinkable:
            verdict = _shrunk(claim, verdict, progress)
        verdicts.append(_with_question(claim, verdict))
    if out_dir is not None:
        verdicts = [_save(v, Path(out_dir)) for v in verdicts]
    if report_path is not None:
        report_path = Path(report_path)
        pictures = report_path.parent / report_path.stem
        verdicts = [draw_counterexample(v, pictures) for v in verdicts]
        header = _header(command or _default_command(seed, quick, time_limit, reference, greedy, out_dir, report_path),
                         seed, quick, time_limit, reference, time.perf_counter() - started)
        report_path.parent.mkdir(parents=True, exist_ok=True)
        report_path.write_text(render_verdicts(verdicts, header, base=report_path.parent), encoding="utf-8")
    return verdicts


def _shrunk(claim: Claim, verdict: Verdict, progress: Progress | None) -> Verdict:
    """The verdict with its counterexample shrunk and its numbers recomputed on it."""
    assert verdict.counterexample is not None
    small = shrink(verdict.counterexample, lambda inst: check_instance(claim, inst).status == "refuted")
    small = small.replace(name=f"{claim.id}-counterexample")
    outcome = check_instance(claim, small)
    if progress is not None:
        progress(f"{claim.id}: shrunk {verdict.found_on} (n={verdict.counterexample.n}) to n={small.n}")
    return dataclasses.replace(verdict, counterexample=small, numbers=outcome.numbers, results=outcome.results)


def _with_question(claim: Claim, verdict: Verdict) -> Verdict:
    """The verdict with the question its counterexample answers (greedy-versus-optimum claims)."""
    if not (claim.greedy_vs_optimum and verdict.counterexample is not None and len(verdict.results) == 2):
        return verdict
    greedy, optimum = verdict.results
    question = Question.from_results(claim.id, greedy, optimum, deadline_factor=claim.deadline_factor)
    return dataclasses.replace(verdict, question=question)


# -- output ---------------------------------------------------------------------------


def _file_stem(verdict: Verdict) -> str:
    return verdict.claim


def _save(verdict: Verdict, out_dir: Path) -> Verdict:
    """Write the counterexample to ``out_dir/<claim-id>.json``."""
    if verdict.counterexample is None:
        return verdict
    from parcover.io import write_instance

    out_dir.mkdir(parents=True, exist_ok=True)
    path = out_dir / f"{_file_stem(verdict)}.json"
    write_instance(verdict.counterexample, path, question=verdict.question)
    return dataclasses.replace(verdict, file=str(path))


def draw_counterexample(verdict: Verdict, folder: Path) -> Verdict:
    """Draw greedy routes beside the optimal ones, when :mod:`parcover.plot` exists."""
    if verdict.counterexample is None or not verdict.results:
        return verdict
    try:
        from parcover.plot import plot_side_by_side
    except ImportError:
        return dataclasses.replace(verdict, notes=verdict.notes + ("drawing skipped: parcover.plot is not available",))
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{_file_stem(verdict)}.png"
    roles = ("the greedy", "the exact method")[-len(verdict.results):]  # (greedy, reference) or (reference,)
    captions = [f"claim {verdict.claim}: {role}" for role in roles]
    try:
        plot_side_by_side(verdict.counterexample, list(verdict.results), path, captions)
    except Exception as exc:  # noqa: BLE001 - a drawing failure must not lose the verdicts
        return dataclasses.replace(verdict, notes=verdict.notes + (f"drawing failed: {type(exc).__name__}: {exc}",))
    return dataclasses.replace(verdict, picture=str(path))


def render_table(verdicts: Sequence[Verdict]) -> str:
    """A fixed-width text table: claim, instances tried, verdict, counterexample file."""
    rows = [("claim", "tried", "verdict", "counterexample")]
    for v in verdicts:
        where = v.file or (f"{v.found_on} (n={v.counterexample.n}, not saved)" if v.counterexample is not None else "-")
        rows.append((v.claim, str(v.tried), v.text, where))
    widths = [max(len(r[i]) for r in rows) for i in range(4)]
    lines = ["  ".join(cell.ljust(w) for cell, w in zip(row, widths)).rstrip() for row in rows]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(lines)


def render_verdicts(verdicts: Sequence[Verdict], header: str = "", base: Path | None = None) -> str:
    """Markdown: the header, the table, then each refuted claim with numbers and picture."""
    parts = [header, "## Verdicts", "", "```", render_table(verdicts), "```", ""]
    for v in verdicts:
        parts += [f"### {v.claim}: {v.text}", "", v.statement, ""]
        if v.counterexample is not None:
            parts += [f"- Smallest counterexample: found on `{v.found_on}`, "
                      f"{v.counterexample.n} KPOIs after shrinking.",
                      f"- Numbers: {v.numbers}"]
            if v.file:
                parts.append(f"- File: `{_relative(v.file, base)}`")
            if v.file and v.question is not None:
                parts.append(f"- Check it again: `parcover props --check {v.file}`")
            parts += [f"- Routes of {r.method}: {_routes_text(r)}" for r in v.results]
            if v.picture:
                parts += ["", f"![{v.claim}]({_relative(v.picture, base)})", ""]
        parts += [f"- Note: {n}" for n in v.notes]
        parts.append("")
    parts += ["", "## How bad can the greedy get?", "", _WORST_POINTER]
    return "\n".join(parts)


render_report = render_verdicts  # the old name, kept importable (parcover.report.render_report writes gap reports)


_WORST_POINTER = ("See [`worst.md`](worst.md) (`parcover worst`): the worst greedy/optimum ratios found per claim "
                  "and reading, and the halving line, on which the literal Algorithm 1 needs 1 + ~log2 n robots "
                  "where 2 suffice.")


def _routes_text(result: Result) -> str:
    """``s-a-b (2); s-c (1)``: each route with its cost."""
    return "; ".join(f"{'-'.join(r)} ({number(c)})" for r, c in zip(result.routes, result.route_costs))


def _relative(path: str, base: Path | None) -> str:
    if base is None:
        return path
    try:
        return str(Path(path).resolve().relative_to(base.resolve()))
    except ValueError:
        return path


def _header(command: str, seed: int, quick: bool, time_limit: float | None, reference: str, seconds: float) -> str:
    from parcover import __version__

    return "\n".join([
        "# Verdicts on the paper's claims",
        "",
        "Regenerate with:",
        "",
        f"    {command}",
        "",
        f"parcover {__version__}, Python {sys.version.split()[0]}; seed {seed}; "
        f"{'quick' if quick else 'full'} families; exact reference `{reference}`, "
        f"time limit {time_limit} s per solve; {seconds:.0f} s in all.",
        "",
        "A claim is refuted only by a proven optimum or bound on the wrong side, or by a "
        "verified exact solution better than the greedy's; instances where the exact "
        "reference is not proven either way are counted as undecided.",
        "",
    ])


def _default_command(seed: int, quick: bool, time_limit: float | None, reference: str, greedy: Sequence[str],
                     out_dir: str | Path | None, report_path: Path) -> str:
    args = [f"seed={seed}", f"quick={quick}", f"time_limit={time_limit}", f"reference={reference!r}",
            f"greedy={list(greedy)!r}", f"out_dir={str(out_dir) if out_dir else None!r}",
            f"report_path={str(report_path)!r}"]
    return f'python -c "import parcover.props as p; p.props({", ".join(args)})"'
