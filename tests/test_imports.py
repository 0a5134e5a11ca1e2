"""The project's modules import one another one way: no import cycle, counting every
``import`` statement (inside functions and under ``TYPE_CHECKING`` too), and ``milp``
imports nothing from ``parcover``.

The graph is read from the source with :mod:`ast`, not from an interpreter's
``sys.modules``: an import inside a function is an edge although it runs late. An edge
goes to the module an import names (``from parcover import generate`` is an edge to
``parcover.generate``, ``from parcover import __version__`` one to the package
``parcover``); the package ``__init__`` that Python runs first on the way to a
submodule is not counted, else every submodule would sit below its package's imports.
"""

from __future__ import annotations

import ast
from pathlib import Path

import networkx as nx

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("parcover", "milp")


def project_modules(root: Path = ROOT) -> dict[str, Path]:
    """Every module of :data:`PACKAGES` under ``root`` by dotted name (a package by its own name)."""
    out = {}
    for package in PACKAGES:
        for path in sorted((root / package).rglob("*.py")):
            parts = path.relative_to(root).with_suffix("").parts
            if parts[-1] == "__init__":
                parts = parts[:-1]
            out[".".join(parts)] = path
    return out


def imports_of(name: str, path: Path, modules: dict[str, Path]) -> set[str]:
    """The modules that the source of module ``name`` imports, every statement counted.

    Relative imports are resolved; ``from X import y`` names ``X.y`` when that is one of
    ``modules``, else ``X``; ``import X.y`` names ``X.y``. A module outside the project
    is named as written.
    """
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package[: len(package) - (node.level - 1)]
                base = ".".join(anchor + ([base] if base else []))
            for alias in node.names:
                out.add(f"{base}.{alias.name}" if f"{base}.{alias.name}" in modules else base)
    return out


def import_graph(root: Path = ROOT) -> nx.DiGraph:
    """The directed graph module -> module it imports, among the project's modules."""
    modules = project_modules(root)
    graph = nx.DiGraph()
    graph.add_nodes_from(modules)
    for name, path in modules.items():
        graph.add_edges_from((name, target) for target in imports_of(name, path, modules) if target in modules)
    return graph


def test_the_project_has_no_import_cycle():
    cycles = sorted(nx.simple_cycles(import_graph()), key=len)
    assert not cycles, "import cycles:\n" + "\n".join(" -> ".join([*c, c[0]]) for c in cycles[:20])


def test_milp_imports_nothing_from_parcover():
    modules = project_modules()
    offending = sorted(
        f"{name} imports {target}"
        for name, path in modules.items() if name.split(".")[0] == "milp"
        for target in imports_of(name, path, modules) if target.split(".")[0] == "parcover"
    )
    assert not offending, "\n".join(offending)


def test_the_reader_counts_every_import_statement(tmp_path):
    """Imports inside functions, under ``TYPE_CHECKING`` and relative ones are edges; the
    package a submodule is taken from is not."""
    (tmp_path / "milp").mkdir()
    (tmp_path / "milp" / "__init__.py").write_text("from .a import f\n")
    (tmp_path / "milp" / "a.py").write_text(
        "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from milp.b import B\n"
        "def f():\n    from . import c\n")
    (tmp_path / "milp" / "b.py").write_text("import milp.c\n")
    (tmp_path / "milp" / "c.py").write_text("from milp import a, __doc__\n")
    (tmp_path / "parcover").mkdir()
    (tmp_path / "parcover" / "__init__.py").write_text("")
    graph = import_graph(tmp_path)
    assert set(graph.edges) == {("milp", "milp.a"), ("milp.a", "milp.b"), ("milp.a", "milp.c"),
                                ("milp.b", "milp.c"), ("milp.c", "milp.a"), ("milp.c", "milp")}
    assert ["milp.a", "milp.c"] in map(sorted, nx.simple_cycles(graph))
