"""``granmix-sweep STUDY``: run a study's cases on Dask (a LocalCluster by default, or
``--scheduler tcp://HOST:PORT``) or serially, and write the result table, the time
series and one plot per collected output against each varied parameter."""

from __future__ import annotations

import argparse
import os
import re
import sys
from pathlib import Path

import pandas as pd

from granmix import preflight
from granmix.pack import PackCache, PackError
from granmix.study import Study, StudyError, load_study
from granmix.sweep import Progress, pending, run_dask, run_serial, series_table, table, write


def _args(argv: list[str] | None) -> argparse.Namespace:
    p = argparse.ArgumentParser(prog="granmix-sweep", description=__doc__)
    p.add_argument("study", type=Path, help="study file (TOML, docs/sweeps.md)")
    p.add_argument("--out", type=Path, help="output directory (default: out/<study name>)")
    p.add_argument(
        "--workers",
        type=int,
        default=os.cpu_count() or 1,
        help="worker processes of the local cluster (default: one per core)",
    )
    p.add_argument(
        "--threads", type=int, default=1, help="solver threads per FMU instance (default 1)"
    )
    p.add_argument("--scheduler", help="address of an existing Dask scheduler (tcp://HOST:PORT)")
    p.add_argument("--serial", action="store_true", help="run the cases in this process")
    p.add_argument("--resume", action="store_true", help="skip cases already in the results")
    p.add_argument("--quiet", action="store_true", help="no progress line")
    return p.parse_args(argv)


def main(argv: list[str] | None = None) -> int:
    a = _args(argv)
    try:
        study = load_study(a.study)
    except StudyError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    out = a.out or Path("out") / study.name
    todo, kept = pending(study, out, a.resume)
    progress = Progress(len(todo), enabled=not a.quiet)
    cache = out / "fmus"
    try:
        preflight.check(study, todo[0] if todo else None, PackCache(cache))
    except (StudyError, PackError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    try:
        if a.serial or not todo:
            results = run_serial(study, todo, cache, a.threads, progress.update)
        else:
            results = _on_dask(study, todo, cache, a, progress)
    except PackError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    rows = table(results, kept)
    write(out, rows, series_table(results))
    plots = plot(study, rows, out / "plots")
    failed = int((rows["status"] != "ok").sum())
    print(
        f"{len(rows)} cases ({len(results)} run now), {failed} failed: "
        f"{out / 'results.parquet'}, {out / 'results.csv'}, {len(plots)} plots in {out / 'plots'}"
    )
    return 0


def _on_dask(study: Study, todo: list, cache: Path, a: argparse.Namespace, progress: Progress):
    from distributed import Client, LocalCluster

    if a.scheduler:
        with Client(a.scheduler) as client:
            return run_dask(study, todo, cache.resolve(), client, a.threads, progress.update)
    with (
        LocalCluster(
            n_workers=a.workers, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster,
        Client(cluster) as client,
    ):
        return run_dask(study, todo, cache.resolve(), client, a.threads, progress.update)


def plot(study: Study, rows: pd.DataFrame, directory: Path) -> list[Path]:
    """One PNG per collected output against each parameter that takes more than one
    value (finished cases)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ok = rows[rows["status"] == "ok"]
    outputs = [f"{o.variable}:{r}" for o in study.outputs for r in o.reduce]
    directory.mkdir(parents=True, exist_ok=True)
    written = []
    for col in outputs:
        for p in study.parameters:
            if rows[p.name].nunique() < 2:
                continue
            fig, ax = plt.subplots(figsize=(5, 3.5))
            ax.plot(ok[p.name], ok[col], "o")
            ax.set_xlabel(f"{p.name} ({p.target})")
            ax.set_ylabel(col)
            ax.grid(alpha=0.3)
            fig.tight_layout()
            path = directory / f"{re.sub(r'[^A-Za-z0-9_.-]', '_', col)}__{p.name}.png"
            fig.savefig(path, dpi=100)
            plt.close(fig)
            written.append(path)
    return written


if __name__ == "__main__":
    sys.exit(main())
