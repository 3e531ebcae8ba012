"""The table of a study: one row per record and intensity (CSV and Parquet).

Rows are flat dicts of numbers, strings and booleans; the columns are the union of the
rows' keys in first-seen order (a joint or probe a row lacks is missing, read as NaN).
The CSV holds every float with 17 significant digits (``repr``), so that it reads back to
the same bits; the Parquet file (pyarrow, the ``study`` extra) has one typed column each.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from ..errors import InputError, ResultsError
from ..io import utf8_text

#: the text columns that every row has, empty when there is nothing to say (a run that
#: completed has no stop reason, a reliable one no warnings): an empty cell of the CSV is
#: read back as "" there, and as a missing value (NaN) in the other columns
TEXT_COLUMNS = ("stop_reason", "warnings")


@dataclass
class StudyTable:
    """Rows of a study (see the module doc).

    >>> t = StudyTable([{"record": "a", "intensity": 0.1, "slip": 0.002},
    ...                 {"record": "b", "intensity": 0.1}])
    >>> t.columns, t.column("slip").tolist()
    (['record', 'intensity', 'slip'], [0.002, nan])
    """

    rows: list[dict[str, Any]]

    def __len__(self) -> int:
        return len(self.rows)

    @property
    def columns(self) -> list[str]:
        seen: dict[str, None] = {}
        for r in self.rows:
            seen.update(dict.fromkeys(r))
        return list(seen)

    def __getitem__(self, name: str) -> npt.NDArray[Any]:
        return self.column(name)

    def column(self, name: str) -> npt.NDArray[Any]:
        """A column as an array: booleans or integers where every row has one (the
        ``completed``, ``level`` and ``steps`` columns), else floats (NaN where a row
        lacks it) for numbers, objects for strings."""
        if name not in self.columns:
            raise InputError(f"study table: no column {name!r}; the columns are "
                             f"{', '.join(self.columns)}")  # fmt: skip
        vals = [r.get(name) for r in self.rows]
        if vals and all(isinstance(v, (bool, np.bool_)) for v in vals):
            return np.array(vals, dtype=bool)
        if vals and all(isinstance(v, (int, np.integer)) and not isinstance(v, (bool, np.bool_))
                        for v in vals):  # fmt: skip
            return np.array(vals, dtype=np.int64)
        if all(v is None or isinstance(v, (int, float, bool, np.number)) for v in vals):
            return np.array([math.nan if v is None else float(v) for v in vals])
        return np.array(["" if v is None else v for v in vals], dtype=object)

    def to_csv(self, path: str | Path) -> None:
        """Write the table as CSV (floats as ``repr``: they read back to the same bits)."""
        cols = self.columns
        # (UTF-8; a record named by a file name that is not UTF-8 keeps its bytes as
        # \xe9 escapes, pfeie.io.utf8_text, where the table could not be written)
        with open(path, "w", newline="", encoding="utf-8") as fh:
            w = csv.writer(fh)
            w.writerow(cols)
            for r in self.rows:
                w.writerow([_cell(r.get(c)) for c in cols])

    def to_parquet(self, path: str | Path) -> None:
        """Write the table as Parquet (needs pyarrow: ``pip install pfeie[study]``)."""
        try:
            import pyarrow as pa
            import pyarrow.parquet as pq
        except ImportError:
            raise ResultsError(f"{path}: writing Parquet needs pyarrow (pip install "
                               "'pfeie[study]'); the CSV table is written") from None  # fmt: skip
        data = {c: [r.get(c) for r in self.rows] for c in self.columns}
        pq.write_table(pa.table(data), str(path))

    @classmethod
    def read(cls, path: str | Path) -> StudyTable:
        """Read a table written by :meth:`to_csv` or :meth:`to_parquet`."""
        p = Path(path)
        if not p.is_file():
            raise InputError(f"{p}: study table not found")
        if p.suffix == ".parquet":
            import pyarrow.parquet as pq

            rows = pq.read_table(str(p)).to_pylist()
            return cls([{k: v for k, v in r.items() if v is not None} for r in rows])
        with open(p, newline="", encoding="utf-8") as fh:
            rows = [{k: v if k in TEXT_COLUMNS else _parse(v) for k, v in r.items()
                     if v != "" or k in TEXT_COLUMNS}
                    for r in csv.DictReader(fh)]  # fmt: skip
        return cls(rows)


def _cell(v: Any) -> str:
    if v is None:
        return ""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return repr(v)
    return utf8_text(str(v))  # (a record named by a file name that is not UTF-8)


def _parse(text: str) -> Any:
    if text in ("true", "false"):
        return text == "true"
    try:
        return int(text)
    except ValueError:
        pass
    try:
        return float(text)
    except ValueError:
        return text


__all__ = ["StudyTable"]
