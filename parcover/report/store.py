"""The rows of a gap report and their CSV file, gaps.csv.

:data:`COLUMNS` are the columns and their dtypes; :func:`read_gaps` reads a gaps.csv
back. A run resumes from the complete (question, method) units of an earlier file
made with the same settings (:func:`_kept_rows`), appends each new row as it comes
(:class:`_CsvSink`) and ends by writing the file whole, sorted in request order,
atomically (:func:`_write_csv_atomically`, :func:`_sorted`).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import pandas as pd

from parcover.errors import InputError
from parcover.instance import Instance
from parcover.problem import MethodInfo
from parcover.report.spec import GridQuestion

# pandas >= 3 has a string dtype "str" (missing values stay NaN); before, strings are objects.
_STRING_DTYPE = "str" if int(pd.__version__.split(".")[0]) >= 3 else "object"

# gaps.csv columns and their pandas dtypes (read_gaps restores them exactly).
COLUMNS: dict[str, str] = {
    "instance": "str",
    "n": "Int64",
    "routes": "str",
    "question": "str",
    "method": "str",
    "compared": "str",
    "objective": "str",
    "robots_limit": "Int64",
    "deadline": "float64",
    "status": "str",
    "value": "float64",
    "robots": "Int64",
    "makespan": "float64",
    "bound": "float64",
    "reference": "str",
    "reference_status": "str",
    "reference_value": "float64",
    "optimum": "float64",
    "gap_to_optimum": "float64",
    "gap": "float64",
    "at_optimum": "bool",
    "seed": "int64",
    "time_limit": "float64",
    "reference_seconds": "float64",
    "seconds": "float64",
}
TIMING_COLUMNS = ("reference_seconds", "seconds")
_UNIT_KEY = ["instance", "routes", "question", "method"]
AS_ASKED = "as asked"
ROBOTS_AT_MAKESPAN = "robots at its makespan"
MAKESPAN_AT_ROBOTS = "makespan at its robots"


def _empty() -> pd.DataFrame:
    return _frame([])


def _frame(rows: list[dict[str, Any]]) -> pd.DataFrame:
    """Rows as a DataFrame with the dtypes of :data:`COLUMNS`."""
    frame = pd.DataFrame(rows, columns=list(COLUMNS))
    return _typed(frame)


def _typed(frame: pd.DataFrame) -> pd.DataFrame:
    """A copy of ``frame`` with the dtypes of :data:`COLUMNS`."""
    frame = frame.copy()
    for name, dtype in COLUMNS.items():
        if dtype == "float64":
            frame[name] = pd.to_numeric(frame[name], errors="coerce").astype("float64")
        elif dtype == "Int64":
            frame[name] = pd.to_numeric(frame[name], errors="coerce").astype("Int64")
        elif dtype == "bool":
            frame[name] = frame[name].map(lambda x: str(x) == "True").astype("bool")
        elif dtype == "str":
            frame[name] = frame[name].astype(_STRING_DTYPE)
        else:
            frame[name] = frame[name].astype(dtype)
    return frame


def read_gaps(path: str | os.PathLike[str]) -> pd.DataFrame:
    """Read a gaps.csv back, with the dtypes of :data:`COLUMNS`.

    Rows cut short by an interrupt (a missing ``seconds``) are dropped.
    """
    path = Path(path)
    try:
        frame = pd.read_csv(path, dtype={k: _STRING_DTYPE for k, v in COLUMNS.items() if v == "str"})
    except pd.errors.EmptyDataError:
        return _empty()
    except (OSError, pd.errors.ParserError) as exc:
        raise InputError(f"{path}: cannot be read as gaps.csv ({exc}).") from None
    if list(frame.columns) != list(COLUMNS):
        raise InputError(f"{path}: not a gaps.csv (columns differ).")
    frame = frame[frame["seconds"].notna()]
    return _typed(frame).reset_index(drop=True)


def _kept_rows(csv_path: str | os.PathLike[str], settings: dict[str, Any]) -> pd.DataFrame:
    """Rows of an earlier run to keep: those of complete (question, method) units.

    Raises InputError when the file was made with other settings.
    """
    path = Path(csv_path)
    if not path.exists():
        return _empty()
    frame = read_gaps(path)
    for key, value in settings.items():
        column = frame[key]
        wrong = column.notna() if value is None else (column.isna() | (column != value))
        if wrong.any():
            raise InputError(f"{path} holds rows made with another {key.replace('_', ' ')}; use a new file.")
    return frame[_complete_units(frame)].reset_index(drop=True)


def _complete_units(frame: pd.DataFrame) -> pd.Series:
    """Rows whose (question, method) unit has all its rows: the asked one, or both
    rows of a dropped deadline."""
    def complete(compared: pd.Series) -> bool:
        seen = set(compared)
        return AS_ASKED in seen or {ROBOTS_AT_MAKESPAN, MAKESPAN_AT_ROBOTS} <= seen

    if frame.empty:
        return pd.Series([], dtype="bool")
    return frame.groupby(_UNIT_KEY, sort=False)["compared"].transform(complete).astype("bool")


class _CsvSink:
    """Appends rows to the CSV as they come, flushed (an interrupt loses only rows in flight)."""

    def __init__(self, path: str | os.PathLike[str] | None, kept: pd.DataFrame) -> None:
        self.path = None if path is None else Path(path)
        self.rows: list[dict[str, Any]] = []
        if self.path is not None:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            _write_csv_atomically(kept, self.path)

    def write(self, rows: list[dict[str, Any]]) -> None:
        self.rows += rows
        if self.path is None or not rows:
            return
        text = _frame(rows).to_csv(index=False, header=False)
        with self.path.open("a", encoding="utf-8", newline="") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())


def _write_csv_atomically(frame: pd.DataFrame, path: Path) -> None:
    temporary = path.with_name(path.name + ".tmp")
    frame.to_csv(temporary, index=False)
    os.replace(temporary, path)


def _sort_order(
    insts: list[Instance], kinds: Sequence[str], grid: list[GridQuestion], infos: Sequence[MethodInfo]
) -> dict[str, dict[str, int]]:
    """Position of each key value in the request: the sort order of the rows."""
    return {
        "instance": {inst.name: i for i, inst in enumerate(insts)},
        "routes": {k: i for i, k in enumerate(kinds)},
        "question": {q.label: i for i, q in enumerate(grid)},
        "method": {m.name: i for i, m in enumerate(infos)},
        "compared": {c: i for i, c in enumerate((AS_ASKED, ROBOTS_AT_MAKESPAN, MAKESPAN_AT_ROBOTS))},
    }


def _sorted(frame: pd.DataFrame, order: dict[str, dict[str, int]]) -> pd.DataFrame:
    keys = pd.DataFrame({k: frame[k].map(pos).astype("float64") for k, pos in order.items()})
    index = keys.sort_values(list(order), kind="stable", na_position="last").index
    return frame.loc[index].reset_index(drop=True)


def _check_request(
    frame: pd.DataFrame, order: dict[str, dict[str, int]], path: str | os.PathLike[str] | None
) -> None:
    """Refuse a CSV holding rows of another request (they would be silently mixed in)."""
    for key, pos in order.items():
        stray = ~frame[key].isin(list(pos))
        if stray.any():
            first = frame[key][stray].iloc[0]
            raise InputError(f"{path} holds rows of another request ({key} {first!r}); use a new file.")
