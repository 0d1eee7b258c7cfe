"""Finished cases on disk, each written the moment it finishes.

``<out>/cases/`` holds two Parquet files per finished case: ``<key>.series.parquet`` (its
time series) and ``<key>.parquet`` (its row), each written to a temporary file and
renamed into place, the row last. A case whose row file exists is finished; a client or
worker stopped at any moment leaves whole files or none. The study's tables
(``results.parquet``, ``series.parquet``) are assembled from these parts, for the keys of
the current design only.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Iterable
from pathlib import Path

import pandas as pd

from granmix.design import LEVEL, MEMBER, Case
from granmix.master import CaseResult, reduce
from granmix.study import Study

#: Columns that differ between runs of the same case (left out of comparisons).
RUN_COLUMNS = ("wall_time", "setup_time", "loop_time", "close_time", "host")
_ROW = ".parquet"
_SERIES = ".series.parquet"


def output_columns(study: Study) -> list[str]:
    """The reduced outputs' columns, ``<instance>.<variable>:<reduction>``, in file order."""
    return [f"{o.variable}:{r}" for o in study.outputs for r in o.reduce]


def column_unit(column: str, units: dict[str, str]) -> str:
    """The unit of a reduced output's column ``<variable>:<reduction>``, from the
    variables' ``units``: the variable's, times s for an integral (a load's impulse,
    N·s/m for a load in N/m)."""
    variable, how = column.rsplit(":", 1)
    unit = units.get(variable, "")
    if how != "integral":
        return unit
    if not unit:
        return "s"
    # N/m → N·s/m, not N/m·s (which reads as N/(m·s))
    num, slash, den = unit.partition("/")
    return f"{num}·s{slash}{den}"


def columns(study: Study) -> list[str]:
    """The result table's columns, in order."""
    return [
        "key",
        "case",
        *(p.name for p in study.parameters),
        *([LEVEL] if study.design.levels else []),
        *([MEMBER] if study.design.ensemble else []),
        *output_columns(study),
        "status",
        "diagnostic",
        *RUN_COLUMNS,
    ]


class CaseStore:
    """The finished cases under ``directory`` (one row file and one series file each)."""

    def __init__(self, directory: str | Path) -> None:
        self.dir = Path(directory)

    def create(self) -> None:
        self.dir.mkdir(parents=True, exist_ok=True)

    def put(self, r: CaseResult) -> None:
        """Write case ``r``: its series, then its row, each atomically."""
        s = pd.DataFrame(r.series) if r.series else pd.DataFrame({"time": []})
        s.insert(0, "key", r.key)
        self._write(s, self.dir / f"{r.key}{_SERIES}")
        self._write(pd.DataFrame([r.row()]), self.dir / f"{r.key}{_ROW}")

    def _write(self, df: pd.DataFrame, path: Path) -> None:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=self.dir)
        os.close(fd)
        try:
            df.to_parquet(tmp, index=False)
            os.replace(tmp, path)
        except BaseException:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
            raise

    def adopt(self, results: Path, series: Path) -> int:
        """Store the rows of a study table written before the store existed
        (``results.parquet``, with its ``series.parquet``), so that ``--resume`` keeps
        them; returns how many. Rows are kept as they are: their keys decide, as for any
        stored case, whether the current design has them."""
        rows = pd.read_parquet(results)
        s = pd.read_parquet(series) if series.is_file() else pd.DataFrame({"key": []})
        by_key = dict(tuple(s.groupby("key", sort=False))) if len(s) else {}
        self.create()
        for _, row in rows.drop_duplicates("key", keep="last").iterrows():
            key = str(row["key"])
            part = by_key.get(key, pd.DataFrame({"key": [], "time": []}))
            self._write(part.reset_index(drop=True), self.dir / f"{key}{_SERIES}")
            self._write(row.to_frame().T.infer_objects(), self.dir / f"{key}{_ROW}")
        return len(rows)

    def keys(self) -> set[str]:
        """The keys of every finished case."""
        if not self.dir.is_dir():
            return set()
        return {
            p.name[: -len(_ROW)]
            for p in self.dir.iterdir()
            if p.name.endswith(_ROW) and not p.name.endswith(_SERIES) and not p.name.startswith(".")
        }

    def row(self, key: str) -> pd.DataFrame:
        return pd.read_parquet(self.dir / f"{key}{_ROW}")

    def series(self, key: str) -> pd.DataFrame:
        p = self.dir / f"{key}{_SERIES}"
        return pd.read_parquet(p) if p.is_file() else pd.DataFrame({"key": [], "time": []})

    def done(self, study: Study, design: Iterable[Case], retry_failed: bool = False) -> set[str]:
        """The keys of ``design`` with a stored row this ``study`` can keep: a failed row
        (unless ``retry_failed``), or a finished row with every output the study now
        collects."""
        stored = self.keys()
        wanted = output_columns(study)
        out = set()
        for c in design:
            if c.key not in stored:
                continue
            row = self.row(c.key)
            if row["status"].iloc[0] != "ok":
                if not retry_failed:
                    out.add(c.key)
            elif all(col in row.columns for col in wanted) or self._reduce_again(study, c.key, row):
                out.add(c.key)
        return out

    def _reduce_again(self, study: Study, key: str, row: pd.DataFrame) -> bool:
        """Add to the finished row of case ``key`` the reductions ``study`` now asks
        for, computed from its stored series as the case's run computes them
        (:func:`granmix.master.reduce`, the same numbers), and store the row again;
        False (nothing written) when an output was not collected by that run."""
        series = self.series(key)
        missing = [
            (o.variable, how)
            for o in study.outputs
            for how in o.reduce
            if f"{o.variable}:{how}" not in row.columns
        ]
        if not len(series) or any(v not in series.columns for v, _ in missing):
            return False
        times = series["time"].tolist()
        row = row.copy()
        for variable, how in missing:
            row[f"{variable}:{how}"] = reduce(times, series[variable].tolist(), how)
        self._write(row, self.dir / f"{key}{_ROW}")
        return True

    def assemble(self, study: Study, design: list[Case]) -> tuple[pd.DataFrame, pd.DataFrame]:
        """The result table and the series table of the stored cases of ``design``, in
        case order, with the case indices of ``design`` and the study's columns."""
        stored = self.keys()
        present = [c for c in design if c.key in stored]
        cols = columns(study)
        if not present:
            return pd.DataFrame(columns=cols), pd.DataFrame(columns=["key", "time"])
        rows = []
        for c in present:
            r = self.row(c.key)
            r["case"] = c.index
            rows.append(r)
        table = pd.concat(rows, ignore_index=True).reindex(columns=cols)
        variables = [o.variable for o in study.outputs]
        series = pd.concat([self.series(c.key) for c in present], ignore_index=True).reindex(
            columns=["key", "time", *variables]
        )
        return table, series
