"""Running a study's cases: serially in this process, or as one Dask task per case on a
``LocalCluster`` or an existing cluster, and writing the results.

Results go to ``<out>/``:

- ``results.parquet`` and ``results.csv``: one row per case (parameters, reduced
  outputs, status, diagnostic, wall time, host), in case order;
- ``series.parquet``: every case's time series (case key, time, collected outputs);
- ``fmus/``: the pack cache.

A case's result depends only on its specification, so the table is the same serially
and on any number of workers. With ``resume``, cases whose key already has a row in
``results.parquet`` are not run again.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable, Iterable
from pathlib import Path

import pandas as pd

from granmix.design import Case, cases
from granmix.master import CaseResult, run_case
from granmix.pack import PackCache
from granmix.study import Study

#: Columns that differ between runs of the same case (left out of comparisons).
RUN_COLUMNS = ("wall_time", "setup_time", "loop_time", "close_time", "host")


def _task(study: Study, case: Case, cache_dir: str, threads: int) -> CaseResult:
    """One case on a worker: its FMUs from the shared pack cache, then the loop."""
    return run_case(study, case, PackCache(cache_dir), threads)


class Progress:
    """A live progress bar on stderr: cases done, failed, elapsed time and ETA."""

    def __init__(self, total: int, enabled: bool = True) -> None:
        self.total, self.enabled = total, enabled
        self.done = self.failed = 0
        self.start = time.perf_counter()

    def update(self, r: CaseResult) -> None:
        self.done += 1
        self.failed += r.status != "ok"
        if not self.enabled:
            return
        el = time.perf_counter() - self.start
        eta = el / self.done * (self.total - self.done)
        filled = round(30 * self.done / self.total)
        sys.stderr.write(
            f"\r[{'#' * filled}{'.' * (30 - filled)}] {self.done}/{self.total} cases, "
            f"{self.failed} failed, {el:.0f} s elapsed, ETA {eta:.0f} s "
        )
        if self.done == self.total:
            sys.stderr.write("\n")
        sys.stderr.flush()


def pending(study: Study, out: Path, resume: bool) -> tuple[list[Case], pd.DataFrame | None]:
    """The cases still to run, and the rows kept from an earlier run (``resume``)."""
    all_cases = cases(study)
    table = out / "results.parquet"
    if not (resume and table.is_file()):
        return all_cases, None
    old = pd.read_parquet(table)
    done = set(old["key"])
    return [c for c in all_cases if c.key not in done], old


def run_serial(
    study: Study,
    todo: Iterable[Case],
    cache_dir: Path,
    threads: int = 1,
    on_result: Callable[[CaseResult], None] | None = None,
) -> list[CaseResult]:
    """Every case of ``todo`` in this process, in order."""
    cache = PackCache(cache_dir)
    out = []
    for c in todo:
        r = run_case(study, c, cache, threads)
        if on_result:
            on_result(r)
        out.append(r)
    return out


def run_dask(
    study: Study,
    todo: list[Case],
    cache_dir: Path,
    client: object,
    threads: int = 1,
    on_result: Callable[[CaseResult], None] | None = None,
) -> list[CaseResult]:
    """One task per case on the cluster of ``client`` (a ``distributed.Client``). A
    worker that dies mid-case has its task run again elsewhere (Dask's own
    rescheduling); each case's row comes back exactly once."""
    from distributed import as_completed

    futures = [
        client.submit(_task, study, c, str(cache_dir), threads, key=f"case-{c.key}", pure=False)
        for c in todo
    ]
    results: dict[str, CaseResult] = {}
    for fut in as_completed(futures):
        r = fut.result()
        results[r.key] = r
        if on_result:
            on_result(r)
    return [results[c.key] for c in todo]


def table(results: Iterable[CaseResult], kept: pd.DataFrame | None = None) -> pd.DataFrame:
    """The result table in case order (rows kept from an earlier run included)."""
    df = pd.DataFrame([r.row() for r in results])
    if kept is not None and len(kept):
        df = pd.concat([kept, df], ignore_index=True) if len(df) else kept.copy()
    return df.sort_values("case", kind="stable").reset_index(drop=True)


def series_table(results: Iterable[CaseResult]) -> pd.DataFrame:
    """Every case's time series, one row per case and sample time."""
    parts = []
    for r in results:
        if r.series:
            s = pd.DataFrame(r.series)
            s.insert(0, "key", r.key)
            parts.append(s)
    return pd.concat(parts, ignore_index=True) if parts else pd.DataFrame({"key": []})


def write(out: Path, rows: pd.DataFrame, series: pd.DataFrame) -> None:
    """``results.parquet``, ``results.csv`` and ``series.parquet`` (appended to an
    earlier run's series when resuming)."""
    out.mkdir(parents=True, exist_ok=True)
    rows.to_parquet(out / "results.parquet", index=False)
    rows.to_csv(out / "results.csv", index=False)
    old = out / "series.parquet"
    if old.is_file() and len(series):
        kept = pd.read_parquet(old)
        kept = kept[~kept["key"].isin(set(series["key"]))]
        series = pd.concat([kept, series], ignore_index=True)
    elif old.is_file():
        return
    series.to_parquet(old, index=False)
