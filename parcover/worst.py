"""How bad can the paper's greedy get? An adversarial search for the worst greedy/optimum ratio.

For each claim of :mod:`parcover.props` about the paper's Algorithms 1, 1-1 and 2 and
each reading of their steps (the methods ``paper``, ``paper-5d-end``,
``paper-1-1-end``, ``paper-nearest-end``; :mod:`parcover.algorithms.paper`), the
search looks for the instance maximising

- ``alg1``: greedy robots / fewest robots, paths at ``c_max`` (Alg. 1);
- ``alg1-1-x1.25``, ``alg1-1-x1.5``: the same at ``c_p = 1.25, 1.5 c_max`` (Alg. 1-1);
- ``alg2-robots``: Alg. 2's tours / the fewest tours within the makespan it reaches;
- ``alg2-makespan``: Alg. 2's makespan / the least makespan with as many tours.

The optimum is proven inside the loop by ``setpart`` (:mod:`milp.setpart`), so
instances have at most :data:`MAX_KPOIS` KPOIs.

The search (simulated annealing with random restarts, Kirkpatrick, Gelatt and Vecchi,
Science 220, 1983) runs over three spaces of instances, one per restart in turn:

``grid``
    The start at the origin and KPOIs at distinct integer points of
    ``[-GRID, GRID]^2``; a move shifts a KPOI by one unit, jumps it anywhere, adds
    or removes a KPOI.
``plane``
    As ``grid`` with real coordinates in ``[-GRID, GRID]^2``; a shift is a Gaussian
    step of standard deviation 1.
``graph``
    A connected graph on the start, KPOIs and virtual nodes, integer edge weights
    1..:data:`MAX_WEIGHT`; a move changes a weight, adds or removes an edge (keeping
    the graph connected), turns a KPOI virtual or back, adds a node (a KPOI or
    virtual, joined to a random node) or removes a leaf.

A restart starts from a random instance of 3 to ``max_kpois`` KPOIs and runs
:data:`RESTART_STEPS` moves. A move is kept when it does not lower the score
``ratio - TIE * n`` (ties go to fewer KPOIs), or with the Metropolis probability
``exp(delta / T)``, ``T`` falling geometrically from :data:`T_START` to :data:`T_END`
over the restart. Every restart draws from one generator seeded by ``seed``, so a run
is reproducible up to where the time budget cuts it (a faster machine gets further).

The worst instance of each target is saved with a ``"question"`` block (the claim,
the question asked, the greedy's and the optimum's values), so that
``parcover props --check FILE`` reproduces it (``parcover solve FILE`` asks its question).
A target whose search found no ratio above 1 gets no file (it would refute nothing).

The halving line (:func:`halving_line`) is a family whose ratio grows for Alg. 1: its
members of :data:`FAMILY_LENGTHS` are solved at each deadline of :data:`FAMILY_FACTORS`
with every reading, their optima proven by ``exact`` within :data:`FAMILY_TIME_LIMIT`
seconds each (:func:`family`); :func:`growth` tells, per claim and reading, whether the
ratio grows on the family or stays bounded on everything tried.
"""

from __future__ import annotations

import math
import random
import sys
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from parcover.errors import InputError
from parcover.instance import Instance
from parcover.result import Result, Status

__all__ = [
    "CLAIMS",
    "READINGS",
    "SPACES",
    "Target",
    "Score",
    "Found",
    "Member",
    "score",
    "targets",
    "search",
    "save_worst",
    "save_found",
    "halving_line",
    "family",
    "growth",
    "report",
]

#: The claims searched, named as in :mod:`parcover.props` (without the method).
CLAIMS = ("alg1", "alg1-1-x1.25", "alg1-1-x1.5", "alg2-robots", "alg2-makespan")
#: The readings of the paper's steps: method name -> reading name in the question block.
READINGS = {"paper": "literal", "paper-5d-end": "5d-end", "paper-1-1-end": "1-1-end",
            "paper-nearest-end": "nearest-end"}
SPACES = ("grid", "plane", "graph")
MAX_KPOIS = 12
GRID = 6
MAX_WEIGHT = 4
RESTART_STEPS = 150
T_START, T_END = 0.3, 0.005
TIE = 1e-3
EXACT = "setpart"
#: Halving-line lengths L (n = L + 1 KPOIs, 4 to 2048). ``exact`` proves each member in
#: seconds; the cap keeps the family's part of the report near half a minute.
FAMILY_LENGTHS = tuple(2**k - 1 for k in range(2, 12))
#: Deadlines of the family, as multiples of ``c_max``: Alg. 1 and Alg. 1-1's two claims.
FAMILY_FACTORS = (1.0, 1.25, 1.5)
#: Seconds for each exact solve of a family member; the family stops at the first member
#: not proven within it (that member is shown ``feasible``, with its bound).
FAMILY_TIME_LIMIT = 30.0
#: A family's ratio grows for a target when it rose at each of the last this many
#: doublings of n (over proven members).
GROWTH_STEPS = 2


@dataclass(frozen=True)
class Target:
    """One claim about one reading, e.g. ``alg1-1-x1.5`` about ``paper-1-1-end``."""

    claim: str
    method: str

    @property
    def id(self) -> str:
        """The claim id of :mod:`parcover.props`, e.g. ``alg1-1-x1.5-paper-1-1-end``."""
        return f"{self.claim}-{self.method}"

    @property
    def factor(self) -> float | None:
        """The deadline as a multiple of ``c_max`` (paths claims), else ``None``."""
        if self.claim == "alg1":
            return 1.0
        if self.claim.startswith("alg1-1-x"):
            return float(self.claim.removeprefix("alg1-1-x"))
        return None

    @property
    def routes(self) -> str:
        return "tours" if self.claim.startswith("alg2") else "paths"

    @property
    def objective(self) -> str:
        return "makespan" if self.claim == "alg2-makespan" else "robots"


@dataclass(frozen=True)
class Score:
    """The greedy's and the optimum's answers to a target's question on one instance."""

    greedy: Result
    optimum: Result
    objective: str

    @property
    def values(self) -> tuple[float, float]:
        """(greedy, optimum) of the objective."""
        pick = (lambda r: float(r.robots)) if self.objective == "robots" else (lambda r: float(r.makespan))
        return pick(self.greedy), pick(self.optimum)

    @property
    def ratio(self) -> float:
        """greedy / optimum (>= 1: the optimum is proven)."""
        mine, best = self.values
        return mine / best

    @property
    def refutes(self) -> bool:
        """The optimum beats the greedy, as ``props --check`` decides it (same tolerance)."""
        from parcover.props import compare_optimum

        mine, _ = self.values
        return compare_optimum(self.optimum, "ge", mine, self.greedy.method).status == "refuted"


def targets(claims: Iterable[str] = CLAIMS, methods: Iterable[str] = READINGS) -> list[Target]:
    """Every (claim, reading) pair, checking the names."""
    claims, methods = list(claims), list(methods)
    for c in claims:
        if c not in CLAIMS:
            raise InputError(f"Unknown claim {c!r}; expected one of {', '.join(CLAIMS)}.")
    for m in methods:
        if m not in READINGS:
            raise InputError(f"Unknown reading {m!r}; expected one of {', '.join(READINGS)}.")
    return [Target(c, m) for c in claims for m in methods]


def score(instance: Instance, target: Target, reference: str = EXACT) -> Score:
    """Run the greedy and the exact method on the target's question (as :mod:`parcover.props`).

    Raises
    ------
    RuntimeError
        When the exact method does not prove its answer optimal.
    """
    from parcover.solve import solve

    routes = target.routes
    deadline = None if target.factor is None else target.factor * instance.c_max
    greedy = solve(instance, routes, deadline=deadline, method=target.method)  # type: ignore[arg-type]
    if target.claim == "alg2-robots":
        optimum = solve(instance, "tours", deadline=greedy.makespan, method=reference)
    elif target.claim == "alg2-makespan":
        optimum = solve(instance, "tours", robots=greedy.robots, method=reference)
    else:
        optimum = solve(instance, routes, deadline=deadline, method=reference)  # type: ignore[arg-type]
    if optimum.status is not Status.OPTIMAL:
        raise RuntimeError(f"{reference} did not prove {target.id} on {instance.name}: {optimum.status.value}")
    return Score(greedy, optimum, target.objective)


def save_worst(instance: Instance, target: Target, found: Score, path: str | Path) -> Path:
    """Write the instance JSON (docs/format.md section 2) with its ``"question"`` block
    (:class:`parcover.question.Question`, as ``props`` writes its counterexamples)."""
    from parcover.io import write_instance
    from parcover.question import Question

    question = Question.from_results(target.id, found.greedy, found.optimum, deadline_factor=target.factor)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    write_instance(instance, path, question=question)
    return path


def save_found(found: Found, out_dir: str | Path) -> Path | None:
    """Save ``found``'s worst instance as ``out_dir/<claim id>.json`` if it refutes the claim.

    An instance where the greedy is optimal would fail ``props --check``: then nothing is
    written, a file an earlier run left under that name is removed, and ``None`` returned.
    """
    path = Path(out_dir) / f"{found.target.id}.json"
    if found.instance is None or found.score is None or not found.score.refutes:
        path.unlink(missing_ok=True)
        return None
    return save_worst(found.instance, found.target, found.score, path)


def found_row(found: Found, path: Path | None) -> str:
    """The report's row for one target: the worst ratio, its instance and file (if saved)."""
    t = found.target
    file = f"`{path}`" if path is not None else "none saved: no ratio above 1 found"
    if found.instance is None or found.score is None:
        return f"| {t.claim} | {t.method} | - | - | - | - | - | {file} |"
    mine, best = found.score.values
    return (f"| {t.claim} | {t.method} | {found.ratio:.3f} | {mine:g} | {best:g} | "
            f"{found.instance.n} | {found.space} | {file} |")


# -- the instance spaces ------------------------------------------------------------


@dataclass(frozen=True)
class Points:
    """KPOIs in the plane around a start at the origin (``integer``: on the grid)."""

    xy: tuple[tuple[float, float], ...]
    integer: bool

    def instance(self, name: str) -> Instance:
        return Instance.from_points([(0.0, 0.0), *self.xy], name=name)

    @property
    def n(self) -> int:
        return len(self.xy)


@dataclass(frozen=True)
class Graph:
    """A weighted graph on nodes ``0`` (start), ``1..m``; ``kpois`` a subset, the rest virtual."""

    nodes: int
    edges: tuple[tuple[int, int, int], ...]
    kpois: frozenset[int]

    def instance(self, name: str) -> Instance:
        return Instance(
            "0", tuple(str(v) for v in sorted(self.kpois)),
            edges=tuple((str(u), str(v), float(w)) for u, v, w in self.edges), name=name,
        )

    @property
    def n(self) -> int:
        return len(self.kpois)


Shape = Points | Graph


def random_shape(space: str, n: int, rng: random.Random) -> Shape:
    """A random instance of ``space`` with ``n`` KPOIs."""
    if space == "graph":
        virtual = rng.randint(0, n // 2 + 1)
        nodes = n + virtual
        edges = {(rng.randrange(v), v): rng.randint(1, MAX_WEIGHT) for v in range(1, nodes + 1)}  # a tree
        for _ in range(rng.randint(0, nodes)):
            u, v = sorted(rng.sample(range(nodes + 1), 2))
            edges.setdefault((u, v), rng.randint(1, MAX_WEIGHT))
        kpois = frozenset(rng.sample(range(1, nodes + 1), n))
        return Graph(nodes, tuple((u, v, w) for (u, v), w in sorted(edges.items())), kpois)
    integer = space == "grid"
    xy: list[tuple[float, float]] = []
    while len(xy) < n:
        p = _random_point(integer, rng)
        if p not in xy and p != (0.0, 0.0):
            xy.append(p)
    return Points(tuple(xy), integer)


def _random_point(integer: bool, rng: random.Random) -> tuple[float, float]:
    if integer:
        return (float(rng.randint(-GRID, GRID)), float(rng.randint(-GRID, GRID)))
    return (round(rng.uniform(-GRID, GRID), 3), round(rng.uniform(-GRID, GRID), 3))


def neighbour(shape: Shape, max_kpois: int, rng: random.Random) -> Shape | None:
    """One random local move (module docstring); ``None`` when the move is invalid."""
    if isinstance(shape, Points):
        return _move_points(shape, max_kpois, rng)
    return _move_graph(shape, max_kpois, rng)


def _move_points(shape: Points, max_kpois: int, rng: random.Random) -> Points | None:
    xy = list(shape.xy)
    move = rng.choice(("shift", "shift", "shift", "jump", "add", "remove"))
    if move == "add" and len(xy) < max_kpois:
        xy.insert(rng.randint(0, len(xy)), _random_point(shape.integer, rng))
    elif move == "remove" and len(xy) > 2:
        del xy[rng.randrange(len(xy))]
    else:
        i = rng.randrange(len(xy))
        if move == "jump":
            xy[i] = _random_point(shape.integer, rng)
        elif shape.integer:
            dx, dy = rng.choice(((1, 0), (-1, 0), (0, 1), (0, -1)))
            xy[i] = (xy[i][0] + dx, xy[i][1] + dy)
        else:
            xy[i] = (round(xy[i][0] + rng.gauss(0, 1), 3), round(xy[i][1] + rng.gauss(0, 1), 3))
    if len(set(xy)) < len(xy) or (0.0, 0.0) in xy:
        return None
    return Points(tuple(xy), shape.integer)


def _move_graph(shape: Graph, max_kpois: int, rng: random.Random) -> Graph | None:
    edges = {(u, v): w for u, v, w in shape.edges}
    kpois = set(shape.kpois)
    nodes = shape.nodes
    move = rng.choice(("weight", "weight", "add-edge", "remove-edge", "toggle", "add-node", "remove-leaf"))
    if move == "weight":
        e = rng.choice(list(edges))
        edges[e] = rng.randint(1, MAX_WEIGHT)
    elif move == "add-edge":
        u, v = sorted(rng.sample(range(nodes + 1), 2))
        edges[(u, v)] = rng.randint(1, MAX_WEIGHT)
    elif move == "remove-edge":
        del edges[rng.choice(list(edges))]
    elif move == "toggle":
        kpois ^= {rng.randint(1, nodes)}
    elif move == "add-node":
        nodes += 1
        edges[(rng.randrange(nodes), nodes)] = rng.randint(1, MAX_WEIGHT)
        if rng.random() < 0.7:
            kpois.add(nodes)
    elif move == "remove-leaf" and nodes > 1:
        degree = {v: 0 for v in range(nodes + 1)}
        for u, v in edges:
            degree[u] += 1
            degree[v] += 1
        if degree[nodes] != 1:
            return None
        edges = {e: w for e, w in edges.items() if nodes not in e}
        kpois.discard(nodes)
        nodes -= 1
    if not 2 <= len(kpois) <= max_kpois or not _connected(nodes, edges):
        return None
    return Graph(nodes, tuple((u, v, w) for (u, v), w in sorted(edges.items())), frozenset(kpois))


def _connected(nodes: int, edges: dict[tuple[int, int], int]) -> bool:
    """Every node reachable from the start."""
    adjacent: dict[int, list[int]] = {v: [] for v in range(nodes + 1)}
    for u, v in edges:
        adjacent[u].append(v)
        adjacent[v].append(u)
    seen, stack = {0}, [0]
    while stack:
        for v in adjacent[stack.pop()]:
            if v not in seen:
                seen.add(v)
                stack.append(v)
    return len(seen) == nodes + 1


# -- the search ---------------------------------------------------------------------


@dataclass
class Found:
    """The worst instance of a target, and the worst ratio seen at each KPOI count."""

    target: Target
    instance: Instance | None = None
    score: Score | None = None
    space: str = ""
    by_n: dict[int, float] = field(default_factory=dict)
    evaluations: int = 0
    seconds: float = 0.0

    @property
    def ratio(self) -> float:
        return self.score.ratio if self.score is not None else 1.0

    def offer(self, instance: Instance, found: Score, space: str) -> None:
        """Keep ``instance`` if it has a larger ratio, or the same with fewer KPOIs."""
        n = instance.n
        self.by_n[n] = max(self.by_n.get(n, 1.0), found.ratio)
        if (self.instance is None or found.ratio > self.ratio + 1e-9
                or (found.ratio > self.ratio - 1e-9 and n < self.instance.n)):
            self.instance, self.score, self.space = instance, found, space


def search(
    target: Target,
    *,
    budget: float,
    seed: int = 0,
    max_kpois: int = MAX_KPOIS,
    spaces: Sequence[str] = SPACES,
    reference: str = EXACT,
    tick: Callable[[Found], None] | None = None,
) -> Found:
    """Simulated annealing with restarts on ``target``'s ratio for ``budget`` seconds.

    Parameters
    ----------
    target
        The claim and reading.
    budget
        Seconds of search (the restart under way stops when it runs out).
    seed
        Seed of the one random generator every restart draws from.
    max_kpois
        Largest instance tried (at most 16 for ``setpart``).
    spaces
        The instance spaces, one per restart in turn.
    tick
        Called after every evaluation (progress).
    """
    if not 3 <= max_kpois <= 16:
        raise InputError(f"max_kpois must be between 3 and 16 (setpart stays under a second there), got {max_kpois}.")
    for s in spaces:
        if s not in SPACES:
            raise InputError(f"Unknown space {s!r}; expected one of {', '.join(SPACES)}.")
    rng = random.Random(f"{seed}:{target.id}")
    found = Found(target)
    started = time.perf_counter()

    def evaluate(shape: Shape, space: str) -> float | None:
        """The annealing score of ``shape``, offered to ``found``; None when invalid."""
        try:
            inst = shape.instance(f"worst-{target.id}")
        except InputError:
            return None
        result = score(inst, target, reference)
        found.evaluations += 1
        found.offer(inst, result, space)
        if tick is not None:
            tick(found)
        return result.ratio - TIE * inst.n

    restart = 0
    while time.perf_counter() - started < budget:
        space = spaces[restart % len(spaces)]
        restart += 1
        current = random_shape(space, rng.randint(3, max_kpois), rng)
        value = evaluate(current, space)
        if value is None:
            continue
        for step in range(RESTART_STEPS):
            if time.perf_counter() - started >= budget:
                break
            temperature = T_START * (T_END / T_START) ** (step / RESTART_STEPS)
            candidate = neighbour(current, max_kpois, rng)
            if candidate is None:
                continue
            new = evaluate(candidate, space)
            if new is None:
                continue
            if new >= value or rng.random() < math.exp((new - value) / temperature):
                current, value = candidate, new
    found.seconds = time.perf_counter() - started
    return found


# -- a family whose ratio grows with n ----------------------------------------------


def halving_line(length: int) -> Instance:
    """KPOIs at ``x = 1..length`` on a line and one at ``x = -length``: the literal
    step 5d covers about half of what is left per path, so Alg. 1 (``paper``) needs
    ``1 + ~log2(length)`` robots while 2 suffice.

    The start is at the origin and ``v_max`` is ``(-length, 0)`` (listed first, so it
    wins the tie with ``(length, 0)``): ``c_max = length``. Two paths are optimal: one
    to ``-length`` and one sweeping ``1..length`` (cost ``length``); one path cannot
    reach both ``-length`` and ``1`` within ``c_max``. The literal test
    ``cost + w(v_m, v_j) <= c_max`` of a path started at ``a`` accepts ``j`` only while
    ``(j - 1) + (j - a) <= length``, so each path halves the distance left to ``length``.
    """
    if length < 1:
        raise InputError(f"length must be at least 1, got {length}.")
    points = [(0.0, 0.0), (-float(length), 0.0)] + [(float(x), 0.0) for x in range(1, length + 1)]
    return Instance.from_points(points, name=f"halving-line-{length}")


@dataclass(frozen=True)
class Member:
    """One halving-line member at one deadline: each reading's robots and the exact answer."""

    length: int
    factor: float
    greedy: dict[str, int]
    optimum: Result

    @property
    def n(self) -> int:
        return self.length + 1

    @property
    def proven(self) -> bool:
        return self.optimum.status is Status.OPTIMAL

    def ratio(self, method: str) -> float | None:
        """The reading's robots / the exact method's (a lower bound on the ratio when not proven)."""
        return None if self.optimum.robots is None else self.greedy[method] / self.optimum.robots


def family(
    lengths: Sequence[int] = FAMILY_LENGTHS,
    factors: Sequence[float] = FAMILY_FACTORS,
    time_limit: float = FAMILY_TIME_LIMIT,
    reference: str = "exact",
) -> list[Member]:
    """Every reading and ``exact`` on :func:`halving_line` members, paths within ``factor x c_max``.

    Stops after the first length where ``exact`` does not prove some factor's optimum
    within ``time_limit`` seconds (its members are kept, with their status and bound).
    """
    from parcover.solve import solve

    members: list[Member] = []
    for length in lengths:
        inst = halving_line(length)
        for factor in factors:
            deadline = factor * inst.c_max
            greedy = {m: int(solve(inst, "paths", deadline=deadline, method=m).robots) for m in READINGS}
            optimum = solve(inst, "paths", deadline=deadline, method=reference, time_limit=time_limit)
            members.append(Member(length, factor, greedy, optimum))
        if not all(m.proven for m in members[-len(factors):]):
            break
    return members


def family_table(members: Sequence[Member], factor: float) -> list[str]:
    """The markdown table of the members at ``factor x c_max``: each reading's robots, the optimum
    with its status and bound, the literal reading's ratio (``>=`` when the optimum is not proven)."""
    lines = ["| n | " + " | ".join(READINGS) + " | optimum | status | bound | ratio (paper) |",
             "|---" * (len(READINGS) + 5) + "|"]
    for m in members:
        if m.factor != factor:
            continue
        ratio = m.ratio("paper")
        cell = "-" if ratio is None else f"{ratio:.2f}" if m.proven else f">= {ratio:.2f}"
        best = "-" if m.optimum.robots is None else str(m.optimum.robots)
        bound = "-" if m.optimum.bound is None else f"{m.optimum.bound:g}"
        lines.append(f"| {m.n} | " + " | ".join(str(m.greedy[r]) for r in READINGS)
                     + f" | {best} | {m.optimum.status.value} | {bound} | {cell} |")
    return lines


def proven_line(target: Target, members: Sequence[Member]) -> list[tuple[int, float]]:
    """(n, ratio) of ``target`` on the proven members at its deadline, by increasing n."""
    return [(m.n, m.ratio(target.method)) for m in members
            if m.proven and m.factor == target.factor]


def grows(target: Target, members: Sequence[Member]) -> bool:
    """The proven members' ratio for ``target`` rose at each of the last :data:`GROWTH_STEPS` members
    (each member doubles n)."""
    last = [r for _, r in proven_line(target, members)][-(GROWTH_STEPS + 1):]
    return len(last) == GROWTH_STEPS + 1 and all(a < b - 1e-9 for a, b in zip(last, last[1:]))


def growth(target: Target, found: Found, members: Sequence[Member]) -> str:
    """The row of "Does the ratio grow with n?" for ``target``: the largest ratio seen (by the
    search, or on a proven halving-line member), at the smallest n reaching it, and the verdict."""
    line = proven_line(target, members)
    seen = [(r, -n, "search") for n, r in found.by_n.items()] + [(r, -n, "halving line") for n, r in line]
    if not seen:
        return f"| {target.claim} | {target.method} | - | - | - | nothing tried |"
    ratio, minus_n, where = max(seen)
    if grows(target, members):
        verdict = (f"**grows**: the halving line, {line[0][1]:.2f} at n = {line[0][0]} to "
                   f"{line[-1][1]:.2f} at n = {line[-1][0]}, every member proven")
    else:
        verdict = f"bounded on everything tried, largest ratio seen {ratio:.3f} at n = {-minus_n}"
    return f"| {target.claim} | {target.method} | {ratio:.3f} | {-minus_n} | {where} | {verdict} |"


def draw_family(length: int, path: Path, reference: str = EXACT) -> Path:
    """Draw :func:`halving_line` ``length``: the literal Alg. 1's paths beside the optimum's,
    one lane per robot (the line's points all lie on y = 0, so routes are drawn apart)."""
    from parcover.plot import plt
    from parcover.solve import solve

    inst = halving_line(length)
    x = {"0": 0.0, **{str(i + 1): float(-length if i == 0 else i) for i in range(length + 1)}}
    results = [solve(inst, "paths", method="paper"), solve(inst, "paths", method=reference)]
    lanes = max(len(r.routes) for r in results)
    fig, axes = plt.subplots(1, 2, figsize=(11, 1.2 + 0.5 * lanes), sharey=True)
    for ax, result in zip(axes, results):
        for i, route in enumerate(result.routes):
            xs = [x[v] for v in route]
            cost = result.route_costs[i]
            ax.plot(xs, [-i] * len(xs), marker="o", markersize=4, label=f"robot {i + 1}: {cost:g}")
        ax.plot([0], [0], marker="*", markersize=12, color="gold", markeredgecolor="black", linestyle="")
        ax.set(xlabel="x (distance units; start at 0)", yticks=[])
        ax.set_title(f"{result.method} ({result.status.value}): {result.robots} paths within c_max = {length}",
                     fontsize=9)
        ax.legend(fontsize=7, loc="lower left")
    fig.suptitle(f"Halving line L = {length} ({inst.n} KPOIs): fewest paths within c_max = {length}, "
                 "the literal Alg. 1 (left) against the optimum (right); one lane per robot", fontsize=9)
    return _saved(fig, path)


def prop2_rows(count: int, seed: int = 0) -> list[tuple[int, int, int]]:
    """(n, fewest robots at c_max, |V| - |P_max| + 1) on ``count`` random instances, n = 6..12."""
    from parcover import generate
    from parcover.solve import solve

    rows = []
    for i in range(count):
        n = 6 + i % 7
        inst = generate.random_points(n, seed + i) if i % 2 else generate.random_graph(n, seed + i)
        best = solve(inst, "paths", method=EXACT)
        rows.append((n, int(best.robots), n - len(inst.P_max) + 1))
    return rows


def plot_ratios(founds: Sequence[Found], members: Sequence[Member], path: Path) -> Path:
    """Worst ratio against n: per claim from the search, and the halving line's proven members."""
    from parcover.plot import plt

    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
    by_claim: dict[str, dict[int, float]] = {}
    for found in founds:
        worst = by_claim.setdefault(found.target.claim, {})
        for n, ratio in found.by_n.items():
            worst[n] = max(worst.get(n, 1.0), ratio)
    for claim, worst in by_claim.items():
        ns = sorted(worst)
        left.plot(ns, [worst[n] for n in ns], marker="o", label=claim)
    left.set(xlabel="KPOIs n", ylabel="worst greedy / optimum seen")
    left.set_title("adversarial search: worst ratio per claim\n(largest over the readings)", fontsize=9)
    left.legend(fontsize=8)
    for factor in FAMILY_FACTORS:
        line = [(m.n, m.ratio("paper")) for m in members if m.proven and m.factor == factor]
        right.plot([n for n, _ in line], [r for _, r in line], marker="o", label=f"paper at {factor:g} c_max")
    ns = sorted({m.n for m in members if m.proven})
    right.plot(ns, [(1 + math.log2(n)) / 2 for n in ns], linestyle="--", label="(1 + log2 n) / 2")
    right.set(xscale="log", xlabel="KPOIs n", ylabel="greedy / optimum robots (proven)")
    right.set_title("halving line, paths: the literal reading's robots\nover the optimum's", fontsize=9)
    right.legend(fontsize=8)
    return _saved(fig, path)


def _saved(fig: Any, path: Path) -> Path:
    """Write ``fig`` to ``path`` with :func:`parcover.plot.save_figure`, folders made."""
    from parcover.plot import save_figure

    path.parent.mkdir(parents=True, exist_ok=True)
    save_figure(fig, path, dpi=100)
    return path


def report(*, budget: float, seed: int, out_dir: str | Path, report_path: str | Path, command: str) -> str:
    """Run the search on every target, the family and Prop. 2's bound; write the report."""
    import platform

    from tqdm import tqdm

    pictures = Path(report_path).with_suffix("")
    lines = ["# How bad can the paper's greedy get?", "", "Regenerate with:", "", f"    {command}", "",
             f"Machine: {platform.machine()}, {platform.system()}, Python {platform.python_version()}; "
             f"{budget:g} s of search per claim and reading, seed {seed}. Optima: the search's proven by "
             f"`{EXACT}` (n <= {MAX_KPOIS}); the halving line's by `exact` within {FAMILY_TIME_LIMIT:g} s "
             f"per solve (status in each row); Prop. 2's by `{EXACT}`.", "",
             "## Worst ratios found (greedy / optimum)", "",
             "A search that finds no ratio above 1 saves no file (it would refute nothing).", "",
             "| claim | reading | ratio | greedy | optimum | KPOIs | space | file |", "|---|---|---|---|---|---|---|---|"]
    founds = []
    for target in tqdm(targets(), desc="worst", unit="target"):
        found = search(target, budget=budget, seed=seed)
        founds.append(found)
        lines.append(found_row(found, save_found(found, out_dir)))
    _phase("the halving line: every reading against exact, n = 4, 8, ... (tens of seconds)")
    members = family()
    largest = max(m.n for m in members)
    lines += ["", "## A family whose ratio grows: the halving line", "",
              "KPOIs at x = 1..L on a line and one at x = -L (the start at 0, c_max = L, n = L + 1). "
              "Two paths are optimal at every deadline here (one to -L, one sweeping 1..L); one path "
              "visiting -L and L costs at least 3L. The literal step 5d tests cost + w(v_m, v_j) against "
              "the deadline c_p, measured from the path's first KPOI v_m, so a path started at a stops "
              "before the first j with (j - 1) + (j - a) > c_p. At c_p = c_max = L each path halves what "
              "is left, and Alg. 1 (`paper`) needs 1 + log2 n robots: the ratio grows without bound, as "
              "(1 + log2 n) / 2. At c_p = f c_max with f > 1, a path leaves about g / 2 - (f - 1) L / 2 "
              "of the g = L - a left to cover, which reaches 0 after 3 paths at f = 1.25 and 2 at f = 1.5: "
              "on long lines Alg. 1-1 needs 4 and 3 robots, and the ratio stops growing. "
              "`paper-1-1-end` needs as many robots as `paper` here; `paper-5d-end` and "
              "`paper-nearest-end` grow the path from its end and sweep the line in one path.", "",
              f"Members n = 4, 8, ... up to {largest}, each optimum by `exact` within {FAMILY_TIME_LIMIT:g} s; "
              "the family stops at the first member not proven (shown `feasible`, with its bound).", ""]
    for factor in FAMILY_FACTORS:
        title = "c_max (Alg. 1)" if factor == 1.0 else f"{factor:g} c_max (Alg. 1-1)"
        lines += [f"Paths within {title}, robots per reading:", "", *family_table(members, factor), ""]
    _phase("drawing the halving line and the ratios")
    drawing = draw_family(15, pictures / "halving_line.png")
    lines += [f"![the halving line, n = 16]({pictures.name}/{drawing.name})", "",
              "The halving line with L = 15 (n = 16): left, the literal Alg. 1's 5 paths "
              "([-15], [1..8], [9..12], [13, 14], [15]); right, the 2 optimal paths."]
    figure = plot_ratios(founds, members, pictures / "ratio_vs_n.png")
    lines += ["", f"![worst ratio against n]({pictures.name}/{figure.name})", "",
              "Left: the worst ratio the search saw at each KPOI count, per claim (the largest over "
              "the readings). Right: the halving line's literal reading at c_max, 1.25 and 1.5 c_max (proven "
              "optima), against (1 + log2 n) / 2."]
    lines += growth_section(founds, members, budget)
    _phase("Prop. 2's bound on 100 random instances against setpart")
    rows = prop2_rows(100, seed)
    tight = sum(best == upper for _, best, upper in rows)
    gaps = [upper - best for _, best, upper in rows]
    lines += ["", "## Prop. 2's bound |V| - |P_max| + 1 at c_max", "",
              "Tight: on the Fig. 3 star (KPOIs on a circle of radius r, at least 3 of them equally spaced) every "
              "KPOI is at distance c_max = r, so a path holding two KPOIs costs r + chord > r: every path holds "
              "one KPOI, the fewest robots is n, and P_max = {v_max} makes the bound n - 1 + 1 = n.", "",
              f"On 100 random instances (n = 6..12, alternately random graphs and random points, seeds {seed}..): "
              f"the optimum reaches the bound on {tight}; the bound exceeds it by {sum(gaps) / len(gaps):.2f} "
              f"robots on average (at most {max(gaps)}).", ""]
    text = "\n".join(lines)
    Path(report_path).parent.mkdir(parents=True, exist_ok=True)
    Path(report_path).write_text(text, encoding="utf-8")
    return text


def _phase(text: str) -> None:
    """One line on stderr as a phase of :func:`report` starts (the searches have a bar)."""
    print(f"worst: {text} ...", file=sys.stderr, flush=True)


def growth_section(founds: Sequence[Found], members: Sequence[Member], budget: float) -> list[str]:
    """The report's "Does the ratio grow with n?": one :func:`growth` row per claim and reading,
    and which of them have a growing family."""
    proven = [m.n for m in members if m.proven]
    lines = ["", "## Does the ratio grow with n?", "",
             f"Tried: the search (n <= {MAX_KPOIS}, {budget:g} s per claim and reading) for every row; for the "
             f"paths claims (alg1, alg1-1) also the halving line at their deadline, members proven by `exact` "
             f"up to n = {max(proven, default=0)}. A ratio grows on the family when it rose at each of "
             f"the last {GROWTH_STEPS} doublings of n (proven members).", "",
             "| claim | reading | largest ratio seen | at n | by | does it grow? |", "|---|---|---|---|---|---|"]
    lines += [growth(found.target, found, members) for found in founds]
    growing = ", ".join(f"`{found.target.id}`" for found in founds if grows(found.target, members))
    lines += ["", f"A growing family (the halving line) is known for {growing}; every other claim and reading "
              "is bounded on everything tried (its row)." if growing else
              "No growing family is known: every claim and reading is bounded on everything tried."]
    return lines
