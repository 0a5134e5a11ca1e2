"""Build the API reference of ``parcover`` and ``milp`` from their docstrings with pdoc.

    python docs/build_api.py [OUTPUT_FOLDER]

writes HTML pages (default: ``docs/api``; open ``index.html``), one per module, every
module of both packages included (``parcover``'s ``__all__`` alone would hide most of
them). Docstrings are numpydoc. Exit status 0 when pdoc built every page without a
warning; 1 when it warned (a docstring it could not read, an annotation it could not
resolve: each warning printed on one line); 2 on a bad argument.
"""

from __future__ import annotations

import pkgutil
import sys
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("parcover", "milp")


def modules() -> list[str]:
    """Every module of :data:`PACKAGES`, packages first."""
    import importlib

    names = []
    for package in PACKAGES:
        names.append(package)
        found = importlib.import_module(package)
        names += sorted(m.name for m in pkgutil.walk_packages(found.__path__, prefix=f"{package}.")
                        if not m.name.endswith(".__main__"))  # running it would run the program
    return names


def build(output: Path) -> list[str]:
    """Write the reference to ``output``; returns pdoc's warnings, one line each."""
    import pdoc
    import pdoc.render

    pdoc.render.configure(docformat="numpy", math=True, search=True,
                          footer_text="parcover: multi-robot parallel coverage")
    _load_lazy_names()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        pdoc.pdoc(*modules(), output_directory=output)
    # pdoc adds the submodules a package's __all__ names by itself, then says so when the
    # list names them again: not a problem of the reference.
    return [" ".join(str(w.message).split()) for w in caught if "has already been added" not in str(w.message)]


def _load_lazy_names() -> None:
    """Bind the names ``parcover`` loads on first use (``parcover._LAZY``: the drawing
    functions) in its namespace, where pdoc looks for the names of ``__all__``."""
    import parcover

    for name in parcover._LAZY:
        setattr(parcover, name, getattr(parcover, name))


def main(argv: list[str]) -> int:
    if len(argv) > 1 or (argv and argv[0].startswith("-")):
        print("usage: python docs/build_api.py [OUTPUT_FOLDER]", file=sys.stderr)
        return 2
    output = Path(argv[0]) if argv else ROOT / "docs" / "api"
    sys.path.insert(0, str(ROOT))
    try:
        problems = build(output)
    except Exception as exc:  # pdoc could not import or render a module
        cause = f" ({exc.__cause__!r})" if exc.__cause__ else ""
        print(f"pdoc failed: {exc}{cause}", file=sys.stderr)
        return 1
    for problem in problems:
        print(f"pdoc warning: {problem}", file=sys.stderr)
    print(f"wrote {output / 'index.html'}" + (f" with {len(problems)} warning(s)" if problems else ""))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
