"""The ``parcover`` command line (docs/format.md section 3): parse, call, print.

Exit status: 0 on success (an ``infeasible`` answer is a success), 1 when ``verify``
finds the solution invalid, 2 with one line on stderr for usage errors and bad input, 130
when interrupted (a ``solve`` stopped by Ctrl-C prints the best routes it had first, a
``frontier`` the points it had, ``verify --certify`` its re-proof's outcome so far, a
``report`` how many answered rows its gaps.csv keeps); an interrupted ``solve`` whose
answer is proven all the same (optimal or infeasible) exits with 0.
"""

from __future__ import annotations

import argparse
import os
import shlex
import sys
import threading
from collections.abc import Callable, Iterator, Sequence
from contextlib import AbstractContextManager, contextmanager
from typing import NoReturn

from parcover import __version__
from milp.core.timelimit import TimeLimit, interrupt_stops, interrupted
from milp.core.sizes import SETPART_MAX_KPOIS
from parcover import generate as gen
from parcover.certify import Certificate, verify
from parcover.errors import InputError
from parcover.frontier import frontier
from parcover.result import Result, plural
from parcover.instance import Instance
from parcover.io import FileFormatError, read_instance, read_json, write_instance, write_text_atomic
from parcover.question import load as load_question
from parcover.solve import available_methods, solve
from parcover.verify import InvalidSolution

__all__ = ["main", "run"]

#: Exit status of an interrupted command (128 + SIGINT, as shells report it).
INTERRUPTED_STATUS = 130
#: Seconds after which a solve on a terminal without ``--log`` says it is still running.
STILL_SOLVING_SECONDS = 10.0


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (exit 2), as docs/format.md section 3 says."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: error: {message}\n")


def run() -> NoReturn:
    """The ``parcover`` program: :func:`main`, then exit without the interpreter's
    teardown, which spends about 0.3 s unloading numba's compiled code (branch-and-price)
    after the answer is written; that would push a short ``--time-limit`` over."""
    status = main()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a closed pipe: nothing more can be written
            pass
    os._exit(status)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    parser = _build_parser()
    args = parser.parse_args(argv)
    args.command_line = shlex.join(["parcover", *(sys.argv[1:] if argv is None else argv)])
    if not hasattr(args, "run"):
        parser.print_help(sys.stderr)
        return 2
    try:
        return args.run(args)
    except InputError as exc:
        print(f"parcover {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # e.g. `parcover solve ... | head`
        sys.stderr.close()
        return 0
    except KeyboardInterrupt:
        print(f"parcover {args.command}: interrupted", file=sys.stderr)
        return INTERRUPTED_STATUS
    except MemoryError:
        print(f"parcover {args.command}: error: not enough memory for this instance.", file=sys.stderr)
        return 2


# -- commands ------------------------------------------------------------------------


def _solve(args: argparse.Namespace) -> int:
    # One deadline from here: reading the instance counts against --time-limit.
    time_limit = TimeLimit(args.time_limit)
    _start_log(args)
    frames = _frames_folder(args)
    _check_outputs(args, out=args.out, plot=None if frames else args.plot, model=args.export_model)
    instance, question = load_question(args.instance, metric=args.distance)
    if question is not None and args.routes is None and args.robots is None and args.deadline is None:
        args.routes, args.robots, args.deadline = question.routes, question.robots, question.deadline
        print(f"question from the file ({question.claim}): {question.text}; method {args.method}",
              file=sys.stderr if args.json else sys.stdout)
        if question.greedy_limit == "none" and args.method == question.method:
            print(f"note: the claim runs {question.method} without a robot limit (the paper's "
                  f"Algorithm 2 as published); `parcover props --check {args.instance}` compares "
                  "that with the optimum", file=sys.stderr if args.json else sys.stdout)
    options: dict[str, object] = {"trace": True} if args.trace else {}
    if args.export_model:
        options["export_model"] = args.export_model
    with _ctrl_c_stops("solve", "the best routes found so far"), _still_solving_notice(args, time_limit):
        result = solve(
            instance,
            routes=args.routes or "paths",
            robots=args.robots,
            deadline=args.deadline,
            method=args.method,
            time_limit=time_limit,
            seed=args.seed,
            **options,
        )
        stopped = interrupted()
    if args.trace and not args.json:
        for line in result.info.get("trace", []):
            print(line)
        print()
    if frames:
        from parcover.frames import save_frames

        _draw(lambda: save_frames(instance, result, args.plot), args.plot)
        print(f"wrote {len(result.info['steps'])} frames and steps.gif to {args.plot}",
              file=sys.stderr if args.json else sys.stdout)
    elif args.plot:
        if not result.routes:
            raise InputError(f"No routes to draw: the answer is {result.status.value}.")
        from parcover.plot import save_routes_plot

        _draw(lambda: save_routes_plot(instance, result, args.plot), args.plot)
    _emit(result.to_json() if args.json else result.summary(), result.to_json(), args.out)
    return INTERRUPTED_STATUS if stopped and not result.status.decided else 0


def _ctrl_c_stops(command: str, keeps: str) -> AbstractContextManager[None]:
    """Within the block, a first Ctrl-C stops the work as its time limit would (the
    command then prints ``keeps`` and exits with :data:`INTERRUPTED_STATUS`), a second
    quits (:func:`milp.core.timelimit.interrupt_stops`)."""
    return interrupt_stops(f"parcover {command}: stopping with {keeps} (Ctrl-C again to quit without them)")


@contextmanager
def _still_solving_notice(args: argparse.Namespace, time_limit: TimeLimit) -> Iterator[None]:
    """On a terminal, without ``--log``: one line on stderr once the solve has run
    :data:`STILL_SOLVING_SECONDS`, saying how to see its progress or stop it."""
    if getattr(args, "log", False) or not sys.stderr.isatty():
        yield
        return
    limit = "no time limit" if time_limit.seconds is None else f"time limit {time_limit.seconds:g} s"
    timer = threading.Timer(STILL_SOLVING_SECONDS, lambda: print(
        f"parcover solve: still solving ({args.method}, {limit}); --log shows its progress, "
        "Ctrl-C stops it with the best routes found so far", file=sys.stderr, flush=True))
    timer.daemon = True
    timer.start()
    try:
        yield
    finally:
        timer.cancel()


def _start_log(args: argparse.Namespace) -> None:
    """``--log``: progress lines (phases, incumbents, bounds, gaps, nodes) on stderr."""
    if getattr(args, "log", False):
        from milp.core.progress import log_to_stderr

        log_to_stderr()


def _verify(args: argparse.Namespace) -> int:
    _start_log(args)
    instance = read_instance(args.instance, metric=args.distance)
    solution = read_json(args.solution)
    if not (isinstance(solution, dict) and "routes" in solution) and not isinstance(solution, list):
        raise FileFormatError(f"{args.solution}: not a solution: expected a JSON object with 'routes'.")
    try:
        with _ctrl_c_stops("verify", "what the re-proof has found so far"):
            verdict = verify(instance, solution, certify=args.certify, time_limit=args.time_limit)
            stopped = interrupted()
    except InvalidSolution as exc:
        for problem in exc.problems:
            print(f"invalid: {problem}")
        return 1
    if verdict.makespan is None:  # an infeasible or unknown answer without routes
        status = solution["status"]
        if verdict.certificate is None:
            print(f"valid: no routes, status {status} (not re-proved without --certify)")
            return 0
        print(f"no routes, status {status}")
        return _certificate_status(verdict.certificate, stopped)
    summary = (
        f"{plural(verdict.robots, 'robot')}, makespan {verdict.makespan:.10g}"
        f" ({verdict.routes_kind})"
    )
    if not verdict.valid:
        for problem in verdict.violations():
            print(f"invalid: {problem}")
        print(f"routes are well formed: {summary}")
        return 1
    print(f"valid: {summary}")
    return 0 if verdict.certificate is None else _certificate_status(verdict.certificate, stopped)


def _certificate_status(certificate: Certificate, stopped: bool) -> int:
    """Print the certifier's outcome; the exit status of ``verify --certify``: that of
    the outcome, or :data:`INTERRUPTED_STATUS` when a Ctrl-C (``stopped``) left it undecided."""
    outcome = _print_certificate(certificate)
    return INTERRUPTED_STATUS if stopped and certificate.outcome == "undecided" else outcome


def _print_certificate(certificate: Certificate) -> int:
    """Print the certifier's outcome; its exit status."""
    if certificate.outcome == "refuted":
        for reason in certificate.reasons:
            print(f"invalid: {reason}")
        return 1
    if certificate.outcome == "undecided":
        for reason in certificate.reasons:
            print(f"undecided: {reason}")
        return 3
    print(f"{certificate.outcome}" + (f" by {certificate.method}" if certificate.method else ""))
    return 0


def _frontier(args: argparse.Namespace) -> int:
    _start_log(args)
    _check_outputs(args, out=args.out, plot=args.plot)
    instance = read_instance(args.instance, metric=args.distance)
    progress = _print_frontier_point if sys.stderr.isatty() else None
    with _ctrl_c_stops("frontier", "the points found so far"):
        result = frontier(
            instance, args.routes, args.method, time_limit=args.time_limit, seed=args.seed, progress=progress
        )
    if args.plot:
        from parcover.plot import distance_unit, plot_frontier

        _draw(lambda: plot_frontier(result, args.plot, unit=distance_unit(instance)), args.plot)
    _emit(result.to_json() if args.json else result.summary(), result.to_json(), args.out)
    return INTERRUPTED_STATUS if result.note else 0


def _report(args: argparse.Namespace) -> int:
    from parcover.report import write_report

    if os.path.exists(args.out) and not os.path.isdir(args.out):
        raise InputError(f"--out {args.out} is a file; the report needs a folder.")
    try:
        path = write_report(
            args.instances,
            args.out,
            args.methods.split(","),
            routes=args.routes.split(","),
            robots=[_whole(k, "--robots") for k in args.robots.split(",")],
            deadlines=args.deadlines.split(","),
            reference=args.reference,
            time_limit=args.time_limit,
            seed=args.seed,
            workers=args.workers,
            scheduler=args.scheduler,
            progress=False if args.no_progress else None,
            plots=not args.no_plots,
            command=args.command_line,
        )
    except KeyboardInterrupt:
        print(f"parcover report: interrupted; {_kept_rows_text(args.out)}, the same command resumes from them",
              file=sys.stderr)
        return INTERRUPTED_STATUS
    print(f"wrote {path}")
    return 0


def _kept_rows_text(out: str) -> str:
    """How many answered rows an interrupted report left in ``out``/gaps.csv (each row
    is appended as it comes; :func:`parcover.report.store.read_gaps` drops one cut short)."""
    from parcover.report.store import read_gaps

    path = os.path.join(out, "gaps.csv")
    try:
        rows = len(read_gaps(path))
    except InputError:  # not written yet, or not readable as gaps.csv
        rows = 0
    return f"{plural(rows, 'answered row')} kept in {path}"


def _props(args: argparse.Namespace) -> int:
    from parcover.props import props, render_table

    if args.check:
        return _props_check(args)
    command = "parcover props" + "".join(
        f" {flag}" for flag, on in (
            (f"--seed {args.seed}", args.seed != 0), ("--quick", args.quick),
            (f"--time-limit {args.time_limit:g}", args.time_limit != 10.0),
            (f"--reference {args.reference}", args.reference not in (None, "exact")),
            (f"--out-dir {args.out_dir}", bool(args.out_dir)), (f"--report {args.report}", bool(args.report)),
        ) if on
    )
    verdicts = props(
        seed=args.seed, quick=args.quick, time_limit=args.time_limit, reference=args.reference or "exact",
        greedy=args.greedy.split(",") if args.greedy else None,
        out_dir=args.out_dir, report_path=args.report, command=command,
    )
    print(render_table(verdicts))
    return 0


def _props_check(args: argparse.Namespace) -> int:
    """Ask each file's question again; 0 when every file still refutes its claim, else 1."""
    from parcover.question import check, render_check

    questions = []
    for path in args.check:
        instance, question = load_question(path)
        if question is None:
            raise FileFormatError(f"{path}: has no question block to check (see instances/README.md).")
        questions.append((path, instance, question))
    refuted = True
    for path, instance, question in questions:
        outcome = check(question, instance, reference=args.reference, time_limit=args.time_limit, seed=args.seed)
        print(render_check(path, outcome))
        refuted = refuted and outcome.refuted
    return 0 if refuted else 1


def _worst(args: argparse.Namespace) -> int:
    from parcover.worst import report

    out_dir = args.out_dir or os.path.join(args.out, "instances")
    report_path = args.report or os.path.join(args.out, "worst.md")
    for flag, path in (("--out", args.out), ("--out-dir", out_dir)):
        if os.path.exists(path) and not os.path.isdir(path):
            raise InputError(f"{flag} {path} is a file; the search writes a folder there.")
    report(budget=args.budget, seed=args.seed, out_dir=out_dir, report_path=report_path,
           command=args.command_line)
    print(f"wrote {report_path} and the worst instances in {out_dir}")
    return 0


def _whole(text: str, flag: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise InputError(f"{flag} takes whole numbers separated by commas, got {text!r}.") from None


def _print_frontier_point(k: int, result: Result) -> None:
    makespan = "-" if result.makespan is None else f"{result.makespan:.6g}"
    print(f"  k = {k}: makespan {makespan} ({result.status.value}, {result.seconds:.2f} s)", file=sys.stderr)


def _generate(args: argparse.Namespace) -> int:
    makers = {
        "grid": lambda: gen.grid(args.rows, args.cols),
        "star": lambda: gen.star(args.n, args.radius),
        "random": lambda: gen.random_points(
            args.n, args.seed, layout=args.layout, size=args.size, clusters=args.clusters, start=args.start
        ),
        "graph": lambda: gen.random_graph(args.n, args.seed, virtual=args.virtual, size=args.size, detour=args.detour),
        "map": lambda: _map_instance(args),
    }
    instance = makers[args.kind]()
    if args.name:
        instance = instance.replace(name=args.name)
    if args.out:
        write_instance(instance, args.out)
    else:
        sys.stdout.write(write_instance(instance))
    return 0


def _map_instance(args: argparse.Namespace) -> Instance:
    from parcover.maps import instance_from_map

    scale = args.metres_per_pixel[0] if len(args.metres_per_pixel) == 1 else tuple(args.metres_per_pixel)
    return instance_from_map(
        args.image, scale, kpois=args.kpois, seed=args.seed, start=tuple(args.start) if args.start else None,
        graph=args.graph, robot_radius=args.robot_radius, origin=tuple(args.origin),
    )


# -- helpers -------------------------------------------------------------------------


def _emit(text: str, json_text: str, out: str | None) -> None:
    print(text)
    if out:
        write_text_atomic(out, json_text + "\n")


def _frames_folder(args: argparse.Namespace) -> bool:
    """Whether ``--plot`` names a folder (ends in a slash or exists) for the frames of ``--trace``.

    Refuses a folder without ``--trace`` and a folder whose parent does not exist.
    """
    plot = args.plot
    if not plot or not (plot.endswith(("/", os.sep)) or os.path.isdir(plot)):
        return False
    if not args.trace:
        raise InputError(f"--plot {plot} is a folder: it takes one picture per step of --trace (method paper*); "
                         "add --trace, or give a file name such as routes.png.")
    parent = os.path.dirname(os.path.normpath(plot)) or "."
    if not os.path.isdir(parent):
        raise InputError(f"Cannot write --plot {plot}: no folder {parent}.")
    return True


def _draw(plot: Callable[[], object], path: str) -> None:
    """Run a drawing (before ``--out`` is written: a failed drawing leaves no result behind)."""
    try:
        plot()
    except OSError as exc:
        raise InputError(f"Cannot write {path}: {exc.strerror or exc}.") from None


#: What ``--plot`` draws to (matplotlib picks the format from the suffix).
_PLOT_SUFFIXES = (".png", ".pdf", ".svg")


def _check_outputs(
    args: argparse.Namespace, *, out: str | None, plot: str | None, model: str | None = None
) -> None:
    """Refuse output paths that cannot be written, before any work or any file is written.

    ``--out`` must not be the instance itself; ``--plot`` needs a drawing suffix and
    ``--export-model`` ``.mps`` or ``.lp``; every folder must exist.
    """
    if out and os.path.exists(out) and os.path.exists(args.instance) and os.path.samefile(out, args.instance):
        raise InputError(f"--out {out} is the instance file; choose another name.")
    if plot and not plot.lower().endswith(_PLOT_SUFFIXES):
        raise InputError(f"--plot {plot}: the file must end in one of {', '.join(_PLOT_SUFFIXES)}.")
    if model and not model.endswith((".mps", ".lp")):
        raise InputError(f"--export-model {model}: the file must end in .mps or .lp.")
    for flag, path in (("--out", out), ("--plot", plot), ("--export-model", model)):
        if not path:
            continue
        if os.path.isdir(path):
            raise InputError(f"{flag} {path} is a folder, not a file name.")
        folder = os.path.dirname(path) or "."
        if not os.path.isdir(folder):
            raise InputError(f"Cannot write {flag} {path}: no folder {folder}.")


def _positive_float(text: str) -> float:
    value = _float(text)
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be > 0, got {text!r}")
    return value


def _seed(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a whole number: {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be >= 0, got {text!r}")
    return value


def _float(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None


def _methods_epilog() -> str:
    lines = ["methods:"]
    for name, info in sorted(available_methods().items()):
        lines.append(f"  {name:<18} {info.description}")
    return "\n".join(lines)


def _add_common(p: argparse.ArgumentParser, *, routes: bool = True) -> None:
    p.add_argument("instance", help="instance file (.json, see docs/format.md, or TSPLIB .tsp)")
    if routes:
        p.add_argument("--routes", choices=("paths", "tours"), default="paths",
                       help="paths: robots stay where they finish; tours: they come home (default: paths)")
    p.add_argument("--distance", choices=("euclidean", "tsplib"), default=None,
                   help="how coordinates become distances: exact Euclidean (default) or TSPLIB nint rounding")


def _build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="parcover", description="Exact and greedy multi-robot parallel coverage.")
    parser.add_argument("--version", action="version", version=f"parcover {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")

    p = commands.add_parser(
        "solve", help="answer one coverage question",
        description="Fewest robots within a deadline (default: the least possible makespan), "
        "or least makespan with at most K robots. A file with a question block (a counterexample, "
        "instances/README.md) asks its own routes and limit unless --routes, --robots or --deadline is given. "
        "Instance and result formats: docs/format.md; the methods: docs/methods.md.",
        epilog=_methods_epilog(), formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    _add_common(p)
    question = p.add_mutually_exclusive_group()
    question.add_argument("--robots", type=int, metavar="K", help="at most K robots: minimise the makespan")
    question.add_argument("--deadline", type=_float, metavar="C", help="every route within C: minimise the robots")
    p.add_argument("--method", default="exact",
                   help="solution method, NAME or NAME:OPTION=VALUE such as best:until=limit (see below; default: exact)")
    limits = p.add_argument_group("limits")
    limits.add_argument("--time-limit", type=_positive_float, metavar="SECONDS", help="seconds for the whole solve, reading the instance included")
    limits.add_argument("--seed", type=_seed, default=0, help="seed of randomised methods (default: 0)")
    p.add_argument("--trace", action="store_true",
                   help="print every step of the paper's algorithms (with --plot DIR/, draw each step)")
    p.add_argument("--export-model", metavar="FILE.mps",
                   help="write the compact MILP (method exact) to an .mps or .lp file any MILP solver reads")
    p.add_argument("--json", action="store_true", help="print the result as one JSON object")
    p.add_argument("--out", metavar="FILE", help="also write the result JSON to FILE")
    p.add_argument("--plot", metavar="FILE.png|DIR/",
                   help="draw the routes to FILE.png (over the map image when there is one); with --trace and a "
                   "folder (DIR/ or an existing one), one PNG per step of the algorithm and an animated steps.gif")
    p.add_argument("--log", action="store_true",
                   help="print progress on stderr: phases, incumbents, bounds and gaps, nodes, elapsed time")
    p.set_defaults(run=_solve, routes=None)  # None: the file's question's routes, else paths

    p = commands.add_parser(
        "verify", help="check a solution file against an instance",
        description="Recompute every route cost and every claim of the file (route_costs, makespan, "
                    "robots, objective, status, bound, gap). Exit 0 if valid, 1 with a reason per "
                    "violation or false claim, 2 on unreadable input; with --certify, 3 when the "
                    "independent exact method could not decide within --time-limit.")
    _add_common(p, routes=False)
    p.add_argument("solution", help="solution JSON (a result of 'solve --json', or an object with 'routes')")
    p.add_argument("--certify", action="store_true",
                   help="also re-prove an 'optimal'/'infeasible' status and the bound with an exact "
                        "method other than the file's")
    p.add_argument("--time-limit", type=float, default=60.0, metavar="SECONDS",
                   help="for --certify (default 60)")
    p.add_argument("--log", action="store_true",
                   help="print progress on stderr: phases, incumbents, bounds and gaps, nodes, elapsed time")
    p.set_defaults(run=_verify)

    p = commands.add_parser("frontier", help="the robots-versus-makespan trade-off",
                            epilog=_methods_epilog(), formatter_class=argparse.RawDescriptionHelpFormatter)
    _add_common(p)
    p.add_argument("--method", default="exact", help="solution method (default: exact)")
    p.add_argument("--time-limit", type=_positive_float, metavar="SECONDS", help="time limit for each k")
    p.add_argument("--seed", type=_seed, default=0, help="seed of randomised methods (default: 0)")
    p.add_argument("--json", action="store_true", help="print the frontier as one JSON object")
    p.add_argument("--out", metavar="FILE", help="also write the frontier JSON to FILE")
    p.add_argument("--plot", metavar="FILE.png", help="draw robots against makespan")
    p.add_argument("--log", action="store_true",
                   help="print progress on stderr: phases, incumbents, bounds and gaps, nodes, elapsed time")
    p.set_defaults(run=_frontier)

    p = commands.add_parser(
        "report", help="optimality gaps of methods against an exact reference",
        description="Runs every method and an exact reference on the instances and writes "
        "gaps.csv, report.md, meta.json and plots to --out. An interrupted run resumes from gaps.csv.",
        epilog="instance specs: files, folders, or generators such as random:n=6..10:seeds=0..4, "
        "graph:n=8:seeds=0,1, grid:rows=3:cols=3, star:n=6",
    )
    p.add_argument("instances", nargs="+", help="instance files, folders or generator specs")
    p.add_argument("--methods", default="paper,mst,nn,best",
                   help="comma-separated methods, each NAME or NAME:OPTION=VALUE such as best:iterations=100 "
                   "(default: paper,mst,nn,best)")
    p.add_argument("--routes", default="paths,tours", help="comma-separated route kinds (default: paths,tours)")
    p.add_argument("--robots", default="2,3", help="robot limits for the makespan question (default: 2,3)")
    p.add_argument("--deadlines", default="least",
                   help="deadlines for the robots question: 'least' or factors of it, e.g. least,1.2 (default: least)")
    p.add_argument("--reference", default="exact", help="the exact method giving the optimum (default: exact)")
    p.add_argument("--time-limit", type=_positive_float, default=60.0, metavar="SECONDS",
                   help="per solve, methods and reference alike (default: 60)")
    p.add_argument("--seed", type=_seed, default=0)
    p.add_argument("--workers", type=int, default=None, help="local processes (default: min(2, cores))")
    p.add_argument("--scheduler", metavar="ADDRESS", help="run on a Dask cluster instead (dask.distributed)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--no-plots", action="store_true", help="skip the PNG plots")
    p.add_argument("--out", required=True, metavar="DIR", help="output folder")
    p.set_defaults(run=_report)

    p = commands.add_parser(
        "props", help="verdicts on the paper's claims, from exact optima",
        description="Checks Props. 1-2, Figs. 1 and 3 and the optimality claims of Algorithms 1, 1-1 "
        "and 2 against exact optima on grids, stars, random and graph instances; shrinks counterexamples.",
    )
    p.add_argument("--seed", type=_seed, default=0, help="seed of the random instance families (default: 0)")
    p.add_argument("--quick", action="store_true", help="small families only (seconds)")
    p.add_argument("--time-limit", type=_positive_float, default=10.0, metavar="SECONDS",
                   help="per exact solve (default: 10); unproven instances count as undecided")
    p.add_argument("--reference", "--exact", dest="reference", metavar="METHOD",
                   help="the exact method giving the optima (default: exact; with --check setpart up to "
                   f"{SETPART_MAX_KPOIS} KPOIs, exact above; --exact is its former name)")
    p.add_argument("--greedy", help="comma-separated methods to judge (default: every paper* method)")
    p.add_argument("--out-dir", metavar="DIR", help="save shrunk counterexamples here (e.g. instances/counterexamples)")
    p.add_argument("--report", metavar="FILE.md", help="write the verdicts with pictures (e.g. reports/verdicts.md)")
    p.add_argument("--check", nargs="+", metavar="FILE",
                   help="instead, ask each counterexample file's question again with its greedy and an exact method; "
                   "exit 0 when every file still refutes its claim, 1 when one does not")
    p.set_defaults(run=_props)

    p = commands.add_parser(
        "worst", help="adversarial search for the greedy's worst ratio to the optimum",
        description="Search for the worst greedy/optimum ratio per claim and reading. By default everything is "
        "written under --out, which is no committed folder; the committed report is regenerated with "
        "`parcover worst --budget 8 --out-dir instances/worst --report reports/worst.md`.",
    )
    p.add_argument("--budget", type=_positive_float, default=5.0, metavar="SECONDS",
                   help="seconds of search per claim and reading (default: 5)")
    p.add_argument("--seed", type=_seed, default=0, help="seed of the search (default: 0)")
    p.add_argument("--out", default="worst-out", metavar="DIR",
                   help="folder of everything written (default: worst-out)")
    p.add_argument("--out-dir", metavar="DIR", help="where the worst instances go (default: OUT/instances)")
    p.add_argument("--report", metavar="FILE.md",
                   help="the report; its pictures go to a folder of the same name (default: OUT/worst.md)")
    p.set_defaults(run=_worst)

    p = commands.add_parser("generate", help="write a generated instance file")
    kinds = p.add_subparsers(dest="kind", metavar="KIND", required=True)
    g = kinds.add_parser("grid", help="rows x cols cells, unit 4-neighbour moves, start in a corner (Fig. 1)")
    g.add_argument("--rows", type=int, default=3)
    g.add_argument("--cols", type=int, default=3)
    g = kinds.add_parser("star", help="n KPOIs equidistant from the start (Fig. 3)")
    g.add_argument("--n", type=int, default=6)
    g.add_argument("--radius", type=_positive_float, default=1.0)
    g = kinds.add_parser("random", help="uniform or clustered random Euclidean points")
    g.add_argument("--n", type=int, default=10, help="number of KPOIs (default: 10)")
    g.add_argument("--layout", choices=("uniform", "clustered"), default="uniform")
    g.add_argument("--clusters", type=int, default=3)
    g.add_argument("--size", type=_positive_float, default=100.0, help="side of the square (default: 100)")
    g.add_argument("--start", choices=("random", "center", "corner"), default="random")
    g = kinds.add_parser("graph", help="random connected sparse graph with virtual nodes")
    g.add_argument("--n", type=int, default=10, help="number of KPOIs (default: 10)")
    g.add_argument("--virtual", type=int, default=None, help="number of virtual nodes (default: 2n)")
    g.add_argument("--size", type=_positive_float, default=100.0)
    g.add_argument("--detour", type=_float, default=0.5, help="edge weight = length x U[1, 1 + detour]")
    g = kinds.add_parser("map", help="a floor-plan bitmap: random KPOIs in free space, a graph around the walls")
    g.add_argument("--image", required=True, help="bitmap: black = wall, white = free, grey = unknown (wall)")
    g.add_argument("--metres-per-pixel", type=_positive_float, nargs="+", required=True, metavar="X [Y]",
                   help="scale of a pixel (two values when the axes differ)")
    g.add_argument("--kpois", type=int, default=20, help="number of random KPOIs (default: 20)")
    g.add_argument("--start", type=_float, nargs=2, metavar=("X", "Y"), help="start position in metres (default: random)")
    g.add_argument("--graph", choices=("decomposition", "visibility"), default="decomposition",
                   help="the paper's vertical cell decomposition (default) or a visibility graph (true distances)")
    g.add_argument("--robot-radius", type=_float, default=0.0, help="inflate the walls by this many metres")
    g.add_argument("--origin", type=_float, nargs=2, default=(0.0, 0.0), metavar=("X", "Y"),
                   help="world position of the image's lower-left corner (default: 0 0)")
    for g in kinds.choices.values():
        g.add_argument("--seed", type=_seed, default=0, help="random seed (default: 0)")
        g.add_argument("--name", help="instance name (default: derived from the parameters)")
        g.add_argument("--out", metavar="FILE", help="write to FILE instead of stdout")
    p.set_defaults(run=_generate)
    return parser


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
