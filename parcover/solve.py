"""One entry point, :func:`solve`, and the registry of methods behind it.

Every method returns a :class:`~parcover.problem.Solution` in KPOI indices;
:func:`solve` maps it to ids, has the independent verifier recompute it, attaches
the best proven bound, decides the status honestly and returns a
:class:`~parcover.result.Result`. A method whose routes fail the verifier is a bug:
:class:`SolverError` is raised and nothing is printed.
"""

from __future__ import annotations

import importlib
import importlib.util
import inspect
import logging
import time
from dataclasses import replace
from functools import partial
from typing import Any

from milp.core.timelimit import TimeLimit, TimeLimitLike, interrupted
from parcover.bounds import lower_bound, robots_lower_bound
from parcover.errors import InputError
from parcover.instance import Instance, check_whole, finite_float, short_repr
from parcover.memory import SOLVE_BYTES_PER_ENTRY, check_memory
from parcover.problem import MethodInfo, Problem, Solution, meets_bound, meets_deadline
from parcover.result import Result, RoutesKind, Status, gap
from parcover.verify import InvalidSolution, route_costs, verify

__all__ = ["solve", "METHODS", "MethodInfo", "SolverError", "register_method", "method_with_options"]

# Share of a time limit kept back from the method for verifying its routes, the
# spanning-tree bound, printing and the process's exit (a few milliseconds, but 0.2 s
# of exit after numba was loaded), and for the methods' uninterruptible steps (numba
# loading its compiled labelling: 0.3 s): measured at 200 KPOIs. At most _CHECK_SECONDS:
# a share without a cap made a proof depend on a longer limit than it took (40 KPOIs,
# 3 tours, proven at 110 s: with --time-limit 120 the method had 108 s).
_CHECK_SHARE, _CHECK_SECONDS = 0.1, 2.0
#: The note of an answer the user stopped (:func:`milp.core.timelimit.interrupt_stops`).
INTERRUPTED = "interrupted (Ctrl-C)"


log = logging.getLogger(__name__)


class SolverError(RuntimeError):
    """A method produced something the verifier rejects: a bug, never user error."""


METHODS: dict[str, MethodInfo] = {}
_LOADED = False

# Modules holding methods, each with a module-level ``METHODS`` tuple of MethodInfo.
_METHOD_MODULES = (
    "parcover.algorithms.trivial",
    "parcover.algorithms.paper",
    "parcover.algorithms.baselines",
    "parcover.algorithms.local_search",
    "parcover.exact",
)


def register_method(info: MethodInfo) -> None:
    """Make ``info.function`` available as ``solve(..., method=info.name)``."""
    METHODS[info.name] = info


def solve(
    instance: Instance,
    routes: RoutesKind | Problem = "paths",
    robots: int | None = None,
    deadline: float | None = None,
    method: str = "exact",
    *,
    time_limit: TimeLimitLike = None,
    seed: int = 0,
    **options: Any,
) -> Result:
    """Answer one coverage question on ``instance``.

    Parameters
    ----------
    instance
        The instance.
    routes
        ``"paths"`` or ``"tours"``; or the whole question as a :class:`Problem`
        (``solve(instance, Problem("tours", robots=3))``), then without ``robots`` and
        ``deadline``.
    robots
        At most this many robots: minimise the makespan.
    deadline
        Every route within this cost: minimise the robots. With neither, the fewest
        robots at the least possible makespan (``c_max``, or ``2 c_max`` for tours).
    method
        A name from :data:`METHODS` (``parcover solve --help`` lists them), or a label
        with options, ``NAME:OPTION=VALUE[:...]`` (:func:`method_with_options`).
    time_limit
        Seconds for the whole answer (``None``: no limit), or a
        :class:`~milp.core.timelimit.TimeLimit` started earlier (the CLI starts one before it
        reads the instance). Every phase shares it: the method gets what is left less
        a small share kept for verification, and the answer arrives within the limit
        (plus the rounding of uninterruptible steps; the time-limit tests hold it within
        10% at 200-3000 KPOIs). When nothing is left before the method starts, the
        status is ``unknown`` with ``info["message"]`` saying so.
    seed
        Seed of randomised methods.
    **options
        Method-specific options (e.g. ``trace=True`` for ``paper``). ``warm_start``
        (exact methods): routes to start from, as a result gives them (KPOI ids; the
        start at either end is dropped), so ``warm_start=earlier.routes`` works;
        refused unless they visit every KPOI once and fit the question.

    Returns
    -------
    Result
        Verified routes, their proven bound and an honest status. A deadline below
        the least possible makespan gives ``infeasible`` without running the method.

    Raises
    ------
    InputError
        On an unknown method or option, an invalid question or argument (a file
        path instead of an :class:`Instance`: read it with :func:`parcover.load`).
    SolverError
        If the method's routes fail the verifier (a bug).
    """
    if not isinstance(instance, Instance):
        raise InputError(
            f"Expected an Instance, got {type(instance).__name__} {instance!r}; read a file with pc.load(path)."
        )
    if isinstance(routes, Problem):
        if robots is not None or deadline is not None:
            raise InputError("Give the question either as a Problem or as routes, robots and deadline, "
                             "not both.")
        problem = routes
    else:
        problem = Problem(routes, robots, deadline)
    info = method_with_options(method)
    check_memory(SOLVE_BYTES_PER_ENTRY * (instance.n + 1) ** 2, f"Solving {instance.n} KPOIs with {method}")
    unknown = sorted(set(options) - set(info.options))
    if unknown:
        raise InputError(f"Method {method!r} takes no option {unknown[0]!r}.")
    seed = check_whole(seed, "seed", 0)
    if options.get("warm_start") is not None:
        options["warm_start"] = _warm_start_indices(instance, problem, options["warm_start"])
    time_limit = _checked_time_limit(time_limit)
    started = time.perf_counter()
    coverage_deadline = problem.effective_deadline(instance)
    if coverage_deadline is not None and not meets_deadline(problem.least_makespan(instance), coverage_deadline):
        solution = Solution(routes=[], status=Status.INFEASIBLE,
                            info={"message": unreachable_reason(instance, problem, coverage_deadline)})
    elif interrupted():
        solution = Solution(routes=[], status=Status.UNKNOWN,
                            info={"message": f"{INTERRUPTED} before {method!r} could start"})
    elif time_limit.expired():
        spent = f"{time_limit.seconds:g} s" if time_limit.seconds is not None else "time"
        solution = Solution(routes=[], status=Status.UNKNOWN, info={
            "message": f"the time limit of {spent} was spent before {method!r} could start "
                       "(reading and building the instance); give a longer time limit"})
    else:
        left = time_limit.remaining()
        seconds = None if left is None else left - min(_CHECK_SHARE * left, _CHECK_SECONDS)
        log.info("solve: %s, %s, method %s, %s", instance.name or "instance", _question_text(instance, problem),
                 method, "no time limit" if seconds is None else f"{seconds:.3g} s for the method")
        solution = info.function(instance, _at_most_n_robots(instance, problem), time_limit=seconds, seed=seed,
                                 **options)
        if interrupted():  # it stopped as at its time limit (milp.core.timelimit.interrupt_stops)
            solution.info["message"] = "; ".join(filter(None, [INTERRUPTED, solution.info.get("message")]))
    result = build_result(instance, problem, method, solution, time.perf_counter() - started,
                          time_left=time_limit.remaining())
    log.info("solve: %s", result.headline())
    return result


def unreachable_reason(instance: Instance, problem: Problem, deadline: float) -> str:
    """Why no route set meets ``deadline``: the KPOI farthest from the start, whose
    shortest path (there and back, for tours) already exceeds it (paper, Prop. 1)."""
    far = max(range(1, instance.n + 1), key=lambda i: instance.distances[0, i])
    there = float(instance.distances[0, far])
    cost = 2 * there if problem.tours else there
    way = f"{2:g} x {there:.6g} = {cost:.6g} there and back" if problem.tours else f"{cost:.6g} from the start"
    return (f"KPOI {instance.ids[far]} is {way}, above the deadline {deadline:.6g}; "
            f"no {problem.routes[:-1]} can cover it in time (the least possible makespan is {cost:.6g})")


def _question_text(instance: Instance, problem: Problem) -> str:
    """The question in words, for the log: ``"tours, at most 3 robots"``."""
    if problem.robots is not None:
        return f"{problem.routes}, at most {problem.robots} robots: least makespan"
    deadline = problem.effective_deadline(instance)
    return f"{problem.routes}, deadline {deadline:.6g}: fewest robots"


def _warm_start_indices(instance: Instance, problem: Problem, routes: Any) -> list[list[int]]:
    """A warm start given as KPOI ids (a result's routes) as KPOI indices; InputError
    unless it visits every KPOI exactly once in routes the question allows."""
    if not isinstance(routes, (list, tuple)) or not all(isinstance(r, (list, tuple)) for r in routes):
        raise InputError("warm_start must be a list of routes, each a list of KPOI ids.")
    try:
        rows = [[instance.index(str(node)) for node in route] for route in routes]
    except KeyError as exc:
        raise InputError(f"warm_start names {exc.args[0]!r}, which is not a node of the instance.") from None
    rows = [[i for i in row if i != 0] for row in rows]
    rows = [row for row in rows if row]
    if sorted(i for row in rows for i in row) != list(range(1, instance.n + 1)):
        raise InputError("warm_start must visit every KPOI exactly once.")
    if problem.robots is not None and len(rows) > problem.robots:
        raise InputError(f"warm_start has {len(rows)} routes; the question allows {problem.robots}.")
    coverage_deadline = problem.effective_deadline(instance)
    if coverage_deadline is not None:
        costs = route_costs(instance, rows, tours=problem.tours)
        if not all(meets_deadline(c, coverage_deadline) for c in costs):
            raise InputError(f"warm_start has a route of cost {max(costs):g}, above the deadline {coverage_deadline:g}.")
    return rows


def _at_most_n_robots(instance: Instance, problem: Problem) -> Problem:
    """The question with the robot limit cut to ``n``: a robot more than KPOIs covers
    nothing, and methods may lay out one route per robot (``robots=10**9``)."""
    if problem.robots is None or problem.robots <= instance.n:
        return problem
    return Problem(problem.routes, instance.n, None)


def _checked_time_limit(time_limit: TimeLimitLike) -> TimeLimit:
    """The deadline of a solve, after checking that the limit is a positive number of seconds."""
    given = time_limit.seconds if isinstance(time_limit, TimeLimit) else time_limit
    seconds = None if given is None else finite_float(given)
    if given is not None and not (seconds is not None and seconds > 0):
        raise InputError(f"The time limit must be a positive number of seconds, got {short_repr(given)}.")
    return time_limit if isinstance(time_limit, TimeLimit) else TimeLimit(seconds)


def build_result(
    instance: Instance, problem: Problem, method: str, solution: Solution, seconds: float,
    *, time_left: float | None = None,
) -> Result:
    """Verify a method's :class:`Solution` and wrap it as a :class:`Result`; ``time_left``
    (None: no limit) bounds the time spent on the trivial lower bound."""
    deadline = None if solution.drops_deadline else problem.effective_deadline(instance)
    common = dict(
        instance=instance.name,
        routes_kind=problem.routes,
        objective=problem.objective,
        robots_limit=problem.robots,
        deadline=deadline,
        method=method,
        seconds=seconds,
        info=solution.info,
    )
    if not solution.routes:
        status = solution.status or Status.UNKNOWN
        if status not in (Status.INFEASIBLE, Status.UNKNOWN):
            raise SolverError(f"Method {method!r} claims {status.value} without routes.")
        return Result(
            status=status, robots=None, makespan=None, bound=solution.bound, gap=None,
            routes=[], route_costs=[], **common,
        )

    id_routes = _id_routes(instance, solution.routes, tours=problem.tours)
    try:
        verdict = verify(
            instance, id_routes, routes_kind=problem.routes, deadline=deadline, robots_limit=problem.robots
        )
    except InvalidSolution as exc:
        raise SolverError(f"Method {method!r} returned invalid routes: {exc}") from None
    if not verdict.feasible:
        raise SolverError(f"Method {method!r} broke the question: {'; '.join(verdict.violations())}.")

    value = verdict.makespan if problem.objective == "makespan" else float(verdict.robots)
    bound = _best_bound(instance, problem, solution, verdict.makespan, time_left)
    if not meets_bound(bound, value):
        raise SolverError(f"Method {method!r} reports bound {bound} above its value {value}.")
    status = solution.status or (Status.OPTIMAL if meets_bound(value, bound) else Status.FEASIBLE)
    if status not in (Status.OPTIMAL, Status.FEASIBLE):
        raise SolverError(f"Method {method!r} claims {status.value} with routes.")
    return Result(
        status=status,
        robots=verdict.robots,
        makespan=verdict.makespan,
        bound=bound,
        gap=0.0 if status is Status.OPTIMAL else gap(value, bound),
        routes=id_routes,
        route_costs=verdict.route_costs,
        **common,
    )


def _best_bound(instance: Instance, problem: Problem, solution: Solution, makespan: float,
                time_left: float | None) -> float:
    """The larger of the method's proven bound and the trivial one (its Held-Karp part
    only when ``time_left`` allows: :func:`parcover.bounds.lower_bound`)."""
    if solution.drops_deadline:
        trivial = float(robots_lower_bound(instance, makespan, tours=problem.tours, seconds=time_left))
    else:
        trivial = lower_bound(instance, problem, seconds=time_left)
    return trivial if solution.bound is None else max(trivial, solution.bound)


def _id_routes(instance: Instance, routes: list[list[int]], *, tours: bool) -> list[list[str]]:
    ids = instance.ids
    start = [instance.start]
    return [start + [ids[i] for i in route] + (start if tours else []) for route in routes]


def method_with_options(label: str) -> MethodInfo:
    """The method a label names: ``NAME`` or ``NAME:OPTION=VALUE[:...]``.

    ``best:iterations=200`` is ``best`` with a fixed number of rounds, so that its
    answers depend on the seed alone and not on the machine's speed;
    ``best:until=limit`` spends the whole time limit. A value is a number unless the
    option's default is text. The label is the method's name in results and reports.
    """
    if not isinstance(label, str):
        return _method(label)
    name, *settings = label.split(":")
    info = _method(name)
    if not settings:
        return info
    defaults = inspect.signature(info.function).parameters
    options: dict[str, int | float | str] = {}
    for setting in settings:
        key, _, text = setting.partition("=")
        if key not in info.options or not text:
            offered = ", ".join(info.options) or "none"
            raise InputError(f"{label!r}: method {name!r} has no option {key!r} (options: {offered}).")
        options[key] = _option_value(label, key, text, defaults[key].default if key in defaults else None)
    return replace(info, name=label, function=partial(info.function, **options))


def _option_value(label: str, key: str, text: str, default: Any) -> int | float | str:
    """An option's value from its text: kept as text when the option's default is
    text, else a number."""
    if isinstance(default, str):
        return text
    try:
        return int(text)
    except ValueError:
        try:
            return float(text)
        except ValueError:
            raise InputError(f"{label!r}: option {key!r} needs a number, not {text!r}.") from None


def _method(name: str) -> MethodInfo:
    _load_methods()
    if not isinstance(name, str) or name not in METHODS:
        raise InputError(f"Unknown method {name!r}; expected one of {', '.join(sorted(METHODS))}.")
    return METHODS[name]


def _load_methods() -> None:
    """Collect the built-in methods (on first use, so importing parcover stays fast)."""
    global _LOADED
    if _LOADED:
        return
    _LOADED = True
    for name in _METHOD_MODULES:
        if importlib.util.find_spec(name) is None:
            continue
        for info in importlib.import_module(name).METHODS:
            register_method(info)


def available_methods() -> dict[str, MethodInfo]:
    """Every registered method by name."""
    _load_methods()
    return dict(METHODS)
