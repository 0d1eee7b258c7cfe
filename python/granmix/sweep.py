"""Running a study's cases: serially in this process, or as one Dask task per case on a
``LocalCluster`` or an existing cluster, and writing the results.

Results go to ``<out>/``:

- ``cases/``: every finished case at once, its row and its time series (see
  :mod:`granmix.store`), so a stopped study loses only the cases in flight;
- ``results.parquet`` and ``results.csv``: one row per case (parameters, reduced
  outputs, status, diagnostic, timings, host), in case order, assembled from ``cases/``;
- ``series.parquet``: every case's time series (case key, time, collected outputs);
- ``fmus/``: the pack cache.

A case's result depends only on its specification, so the table is the same serially
and on any number of workers. With ``resume``, cases of the current design whose row is
in ``cases/`` are not run again; rows of cases no longer in the design stay out of the
table.
"""

from __future__ import annotations

import socket
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

import pandas as pd

from granmix import extracted
from granmix.design import Case, cases
from granmix.master import CaseResult, run_case
from granmix.pack import PackCache
from granmix.store import RUN_COLUMNS, CaseStore
from granmix.study import Study

__all__ = [
    "RUN_COLUMNS",
    "CaseStore",
    "Progress",
    "StudyInterrupted",
    "pending",
    "run_dask",
    "run_serial",
    "series_table",
    "table",
    "write",
]


class StudyInterrupted(RuntimeError):
    """The client lost its cluster (the scheduler went away, the futures were
    cancelled). The cases finished before are stored; ``--resume`` runs the rest."""


def _worker_host() -> str:
    """``<hostname>/<worker name>`` of the Dask worker running this task."""
    from distributed import get_worker

    try:
        w = get_worker()
    except ValueError:
        return f"{socket.gethostname()}/serial"
    return f"{socket.gethostname()}/{w.name}"


_cleared: set[str] = set()


def _task(
    study: Study, case: Case, cache_dir: str, threads: int, store_dir: str | None
) -> CaseResult:
    """One case on a worker: its FMUs from the shared pack cache, then the loop. The
    worker stores the finished case itself when it sees the study's ``cases/`` directory
    (a shared file system), so that a case finishing after its client has gone is kept.
    Before its first case, a worker process clears the FMUs that dead processes of its
    host left extracted (:func:`granmix.extracted.clear_stale`)."""
    if cache_dir not in _cleared:
        extracted.clear_stale(Path(cache_dir))
        _cleared.add(cache_dir)
    r = run_case(study, case, PackCache(cache_dir), threads, _worker_host())
    if store_dir is not None and Path(store_dir).is_dir():
        CaseStore(store_dir).put(r)
    return r


class Progress:
    """A progress bar on stderr (tqdm): cases done, failed, rate and time left. It shows
    from :meth:`start` (or the first case done) on, so that what the cluster prints
    when it starts comes before it."""

    def __init__(self, total: int, enabled: bool = True) -> None:
        self.total, self.enabled = total, enabled
        self.done = self.failed = 0
        self.bar: Any = None

    def start(self) -> None:
        if self.bar is None:
            from tqdm import tqdm

            # a line per finished case (cases take seconds): no rate limit on the display
            self.bar = tqdm(
                total=self.total,
                unit="case",
                mininterval=0,
                miniters=1,
                disable=not self.enabled or self.total == 0,
            )

    def update(self, r: CaseResult) -> None:
        self.start()
        self.done += 1
        self.failed += r.status != "ok"
        self.bar.set_postfix(failed=self.failed, refresh=False)
        self.bar.update(1)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def pending(
    study: Study, store: CaseStore | Path, resume: bool, retry_failed: bool = False
) -> tuple[list[Case], list[Case]]:
    """The cases still to run and those done (``resume``: stored rows that the current
    study can keep; see :meth:`CaseStore.done`). ``store`` is a :class:`CaseStore` or a
    study output directory."""
    if not isinstance(store, CaseStore):
        store = CaseStore(Path(store) / "cases")
    design = cases(study)
    if not resume:
        return design, []
    done = store.done(study, design, retry_failed)
    return [c for c in design if c.key not in done], [c for c in design if c.key in done]


def run_serial(
    study: Study,
    todo: Iterable[Case],
    cache_dir: Path,
    threads: int = 1,
    on_result: Callable[[CaseResult], None] | None = None,
    store: CaseStore | None = None,
) -> list[CaseResult]:
    """Every case of ``todo`` in this process, in order; each stored in ``store`` the
    moment it finishes."""
    cache = PackCache(cache_dir)
    out = []
    for c in todo:
        r = run_case(study, c, cache, threads)
        if store is not None:
            store.put(r)
        if on_result:
            on_result(r)
        out.append(r)
    return out


def _lost(case: Case, error: BaseException) -> CaseResult:
    """The failed row of a case whose task did not return: its workers died (Dask's
    KilledWorker, after ``distributed.scheduler.allowed-failures`` retries) or the task
    raised."""
    from distributed import KilledWorker

    if isinstance(error, KilledWorker):
        why = (
            f"the worker running this case died {error.allowed_failures + 1} time(s) "
            f"(KilledWorker; last on {error.last_worker.address}): out of memory, "
            "killed or crashed in an FMU"
        )
        host = error.last_worker.address
    else:
        why = f"the case's task failed: {type(error).__name__}: {error}"
        host = ""
    return CaseResult(case.key, case.index, dict(case.values), "failed", why, host=host)


class ClearExtracted:
    """A Dask worker plugin: at the worker's shutdown, remove the FMUs its process
    left extracted under the study's pack cache (the cases it was stopped in)."""

    name = "granmix-clear-extracted"

    def __init__(self, cache_dir: str) -> None:
        self.cache_dir = cache_dir

    def setup(self, worker: Any) -> None:
        extracted.clear_stale(Path(self.cache_dir))

    def teardown(self, worker: Any) -> None:
        extracted.clear_own(Path(self.cache_dir))


def run_dask(
    study: Study,
    todo: list[Case],
    cache_dir: Path,
    client: object,
    threads: int = 1,
    on_result: Callable[[CaseResult], None] | None = None,
    store: CaseStore | None = None,
) -> list[CaseResult]:
    """One task per case on the cluster of ``client`` (a ``distributed.Client``), each
    stored in ``store`` the moment it finishes.

    A worker that dies mid-case has its task run again elsewhere (Dask's own
    rescheduling); a case whose workers keep dying (KilledWorker) or whose task raises
    becomes a failed row. Each case's row comes back exactly once. A client that loses
    its cluster raises :class:`StudyInterrupted`."""
    from distributed import as_completed

    store_dir = str(store.dir.resolve()) if store is not None else None
    from distributed import WorkerPlugin

    plugin = type("ClearExtractedPlugin", (ClearExtracted, WorkerPlugin), {})(str(cache_dir))
    client.register_plugin(plugin)  # type: ignore[attr-defined]
    by_key = {c.key: c for c in todo}
    futures = [
        client.submit(  # type: ignore[attr-defined]
            _task, study, c, str(cache_dir), threads, store_dir, key=f"case-{c.key}", pure=False
        )
        for c in todo
    ]
    results: dict[str, CaseResult] = {}
    for fut in as_completed(futures):
        case = by_key[fut.key[len("case-") :]]
        if fut.cancelled():
            raise StudyInterrupted("lost the cluster (its tasks were cancelled)")
        try:
            r = fut.result()
        except Exception as e:
            if fut.cancelled():
                raise StudyInterrupted(f"lost the cluster (its tasks were cancelled: {e})") from e
            r = _lost(case, e)
        fut.release()
        if store is not None:
            store.put(r)
        results[r.key] = r
        if on_result:
            on_result(r)
    return [results[c.key] for c in todo]


def table(results: Iterable[CaseResult], kept: pd.DataFrame | None = None) -> pd.DataFrame:
    """The result table of ``results`` in case order (rows ``kept`` from an earlier run
    included)."""
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
    """``results.parquet``, ``results.csv`` and ``series.parquet`` under ``out``."""
    out.mkdir(parents=True, exist_ok=True)
    rows.to_parquet(out / "results.parquet", index=False)
    rows.to_csv(out / "results.csv", index=False)
    series.to_parquet(out / "series.parquet", index=False)
