"""The package layout of :mod:`milp` (milp/README.md, "Map"): its layers import one way,
the documented imports work, and the former flat module paths still import, as the
modules that moved into the subpackages."""

from __future__ import annotations

import importlib
import subprocess
import sys

import pytest

from test_imports import ROOT, imports_of, project_modules

FORMER = {
    "milp.arcflow": "milp.compact.arcflow", "milp.cvx": "milp.compact.cvx",
    "milp.result": "milp.core.result", "milp.routes": "milp.core.routes", "milp.highs": "milp.core.highs",
    "milp.merge": "milp.core.merge", "milp.sizes": "milp.core.sizes", "milp.jit": "milp.core.jit",
    "milp.progress": "milp.core.progress", "milp.orphans": "milp.core.orphans",
    "milp.deadline": "milp.core.timelimit",
    "milp.ngroute": "milp.branchprice.ngroute", "milp.columns": "milp.branchprice.columns",
    "milp.cuts": "milp.branchprice.cuts", "milp.tree": "milp.branchprice.tree",
    "milp.enumeration": "milp.branchprice.enumeration", "milp.colgen": "milp.branchprice.colgen",
    "milp.compiling": "milp.branchprice.compiling",
}


def _milp_imports(module: str) -> set[str]:
    modules = project_modules()
    return {m for m in imports_of(module, modules[module], modules) if m.startswith("milp")}


def test_core_imports_nothing_else_of_milp() -> None:
    modules = project_modules()
    for name in (m for m in modules if m.startswith("milp.core.")):
        assert all(m == "milp.core" or m.startswith("milp.core.") for m in _milp_imports(name)), name


@pytest.mark.parametrize("name", ["milp.bounds", "milp.warmstart"])
def test_what_every_method_starts_from_needs_only_core(name: str) -> None:
    assert all(m.startswith("milp.core") for m in _milp_imports(name))


@pytest.mark.parametrize("former", sorted(FORMER))
def test_former_paths_import_the_moved_module(former: str) -> None:
    assert importlib.import_module(former) is importlib.import_module(FORMER[former])


def test_former_names_in_a_fresh_interpreter() -> None:
    script = ("import milp.arcflow, milp.compact.arcflow as a; from milp.deadline import Deadline; "
              "from milp.core.timelimit import TimeLimit; from milp.colgen import robots_lower_bound; "
              "from milp import arcflow, setpart, cvx, frontier, MilpResult, build_model, write_model; "
              "assert milp.arcflow is a is arcflow and Deadline is TimeLimit and callable(frontier); print('ok')")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120, cwd=ROOT)
    assert done.stdout.strip() == "ok", done.stderr


@pytest.mark.parametrize("package", ["milp", "milp.branchprice", "parcover"])
def test_an_unknown_name_is_refused_as_by_any_module(package: str) -> None:
    with pytest.raises(AttributeError, match=rf"^module '{package}' has no attribute 'nothing'$"):
        getattr(importlib.import_module(package), "nothing")


def test_a_lazy_name_is_imported_once_then_kept_in_the_package() -> None:
    import milp
    from milp.core.timelimit import TimeLimit

    milp.__dict__.pop("deadline", None)
    assert milp.deadline.TimeLimit is TimeLimit and "deadline" in vars(milp)


def test_the_column_generation_bounds_load_without_numba() -> None:
    # the package's search names (numba's labelling) load only when one is read
    script = ("import sys, milp.branchprice.colgen; "
              "print('numba' in sys.modules, 'milp.branchprice.search' in sys.modules)")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120, cwd=ROOT)
    assert done.stdout.split() == ["False", "False"], done.stderr


def test_the_project_itself_uses_the_new_paths() -> None:
    """The former paths are for users' code: no module of the project imports one."""
    modules = project_modules()
    for name, path in modules.items():
        text = path.read_text()
        for former in FORMER:
            assert f"from {former} import" not in text and f"import {former}\n" not in text, (name, former)
