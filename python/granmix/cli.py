"""``granmix-sweep STUDY``: run a study's cases on Dask (a LocalCluster by default, or
``--scheduler tcp://HOST:PORT``) or serially, store each case the moment it finishes,
and write the result table, the time series and one plot per collected output against
each varied parameter. ``--resume`` runs only the cases not stored yet;
``--variables`` prints the variables of the study's FMUs."""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import os
import re
import signal
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pandas as pd

from granmix import ensemble, extracted, preflight
from granmix.design import Case, cases
from granmix.pack import PackCache, PackError
from granmix.store import CaseStore, column_unit, output_columns
from granmix.study import Study, StudyError, load_study
from granmix.sweep import Progress, StudyInterrupted, pending, run_dask, run_serial, write


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
    p.add_argument(
        "--dashboard",
        default=":8787",
        help="address of the local cluster's dashboard (default :8787; another free port "
        "if it is taken)",
    )
    p.add_argument("--serial", action="store_true", help="run the cases in this process")
    p.add_argument(
        "--resume",
        action="store_true",
        help="run only the cases of the current design not stored in <out>/cases yet",
    )
    p.add_argument(
        "--retry-failed",
        action="store_true",
        help="with --resume, run the failed cases again too",
    )
    p.add_argument(
        "--wall-time-limit",
        type=float,
        metavar="SECONDS",
        help="stop a case after this many seconds as a failed row (overrides the study's "
        "study.wall_time_limit)",
    )
    p.add_argument(
        "--variables",
        action="store_true",
        help="print the variables of the study's FMUs (names, causality, unit, start) and exit",
    )
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    a = p.parse_args(argv)
    if a.retry_failed and not a.resume:
        p.error("--retry-failed goes with --resume")
    if a.wall_time_limit is not None and not a.wall_time_limit > 0:
        p.error("--wall-time-limit must be > 0")
    return a


@contextlib.contextmanager
def _sigterm_interrupts() -> Iterator[None]:
    """SIGTERM (a batch system's stop, ``kill``) stops the study as Ctrl-C does."""

    def stop(_sig: int, _frame: Any) -> None:
        raise KeyboardInterrupt

    try:
        old = signal.signal(signal.SIGTERM, stop)
    except ValueError:  # not the main thread
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, old)


def main(argv: list[str] | None = None) -> int:
    a = _args(argv)
    try:
        study = load_study(a.study)
    except StudyError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    if a.wall_time_limit is not None:
        study = dataclasses.replace(study, wall_time_limit=a.wall_time_limit)
    out = a.out or Path("out") / study.name
    cache = out / "fmus"
    if a.variables:
        return _print_variables(study, cache)
    store = CaseStore(out / "cases")
    design = cases(study)
    if a.resume and not store.dir.is_dir() and (out / "results.parquet").is_file():
        n = store.adopt(out / "results.parquet", out / "series.parquet")
        print(
            f"resume: {n} rows of {out / 'results.parquet'} stored in {store.dir}", file=sys.stderr
        )
    todo, done = pending(study, store, a.resume, a.retry_failed)
    try:
        # the design's first case, as a clean run checks: a resume is a clean run of the
        # pending cases, where one whose scene value granmix refuses is a failed row
        found = preflight.check(study, design[0] if design else None, PackCache(cache), design)
    except (StudyError, PackError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    if a.resume:
        other = len(store.keys() - {c.key for c in design})
        print(
            f"resume: {len(done)} of {len(design)} cases stored, {len(todo)} to run"
            + (f"; {other} stored cases of another design left out" if other else ""),
            file=sys.stderr,
        )
    store.create()
    cleared = extracted.clear_stale(cache)
    if cleared:
        print(
            f"cleared {cleared} extracted FMU folder(s) that stopped processes left in "
            f"{extracted.root(cache)}",
            file=sys.stderr,
        )
    progress = Progress(len(todo), enabled=not a.quiet)
    results = []
    with _sigterm_interrupts():
        try:
            if a.serial or not todo:
                progress.start()
                results = run_serial(study, todo, cache, a.threads, progress.update, store)
            else:
                results = _on_dask(study, todo, cache, a, progress, store)
        except (KeyboardInterrupt, StudyInterrupted) as e:
            progress.close()
            rows, series = store.assemble(study, design)
            write(out, rows, series)
            why = "interrupted" if isinstance(e, KeyboardInterrupt) else f"stopped: {e}"
            print(
                f"{why}: {len(rows)} of {len(design)} cases stored in {store.dir} "
                f"(table so far: {out / 'results.parquet'}); `--resume` runs the other "
                f"{len(design) - len(rows)}",
                file=sys.stderr,
            )
            return 130 if isinstance(e, KeyboardInterrupt) else 1
        except PackError as e:
            print(f"error: {e}", file=sys.stderr)
            return 2
    progress.close()
    rows, series = store.assemble(study, design)
    write(out, rows, series)
    units = preflight.units(study, found)
    plots = plot(study, rows, out / "plots", units)
    if study.design.ensemble:
        plots += _ensemble(study, rows, series, out, units)
    failed = int((rows["status"] != "ok").sum())
    print(
        f"{len(rows)} cases ({len(results)} run now), {failed} failed: "
        f"{out / 'results.parquet'}, {out / 'results.csv'}, {len(plots)} plots in {out / 'plots'}"
    )
    return 0


def _ensemble(
    study: Study, rows: pd.DataFrame, series: pd.DataFrame, out: Path, units: dict[str, str]
) -> list[Path]:
    """``ensemble.parquet``/``.csv`` (the members' statistics), for a refine design
    ``refine.csv`` (the convergence over the levels), their summary on stdout, and the
    envelope and convergence plots; returns the plots written."""
    import matplotlib.pyplot as plt

    stats = ensemble.statistics(study, rows)
    stats.to_parquet(out / "ensemble.parquet", index=False)
    stats.to_csv(out / "ensemble.csv", index=False)
    by = ensemble.groups(study)
    print(f"ensembles of {study.design.members} members (ε = {study.design.epsilon:g} dp):")
    for _, r in stats.iterrows():
        case = ", ".join(f"{n} = {_fmt(r[n])}" for n in by)
        unit = column_unit(r["output"], units)
        print(
            f"  {r['output']}{' (' + case + ')' if case else ''}: {r['mean']:.4g} ± "
            f"{r['sd']:.2g} {unit} (min {r['min']:.4g}, max {r['max']:.4g}, p95 {r['p95']:.4g}; "
            f"{r['members']} members" + (f", {r['failed']} failed)" if r["failed"] else ")")
        )
    figs = list(ensemble.envelope_figures(study, rows, series, units))
    if study.design.levels:
        conv = ensemble.convergence(study, stats)
        conv.to_csv(out / "refine.csv", index=False)
        for _, r in conv.iterrows():
            extra = (
                f": order {r['order']:.2f}, extrapolated {r['extrapolated']:.4g}"
                if r["verdict"] == "converging"
                else ""
            )
            print(f"  refine {r['output']}: {r['verdict']}{extra}")
        figs += list(ensemble.refine_figures(study, stats, conv, units))
    directory = out / "plots"
    directory.mkdir(parents=True, exist_ok=True)
    written = []
    for name, fig in figs:
        path = directory / f"{name}.png"
        fig.savefig(path, dpi=100)
        plt.close(fig)
        written.append(path)
    return written


def _print_variables(study: Study, cache: Path) -> int:
    design = cases(study)
    try:
        found = preflight.variables(study, design[0] if design else None, PackCache(cache))
    except (StudyError, PackError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    sources = {"granmix": study.scene} | {p.name: p.fmu for p in study.partners}
    order = ("parameter", "input", "output")
    for inst, variables in found.items():
        print(f"{inst}  ({sources[inst]})")
        rows = sorted(
            variables.values(),
            key=lambda v: (order.index(v.causality) if v.causality in order else 3, v.name),
        )
        width = max((len(inst) + 1 + len(v.name) for v in rows), default=0)
        for v in rows:
            start = f"start {v.start}" if v.start else ""
            print(
                f"  {v.causality:<11} {inst + '.' + v.name:<{width}}  {v.unit or '-':<8} "
                f"{start:<18} {v.description}".rstrip()
            )
    print(
        "scene parameters: `scene:<key.path>` takes any key of the scene file, as "
        "`granmix check SCENE --set key.path=value` does"
    )
    return 0


def _on_dask(
    study: Study,
    todo: list[Case],
    cache: Path,
    a: argparse.Namespace,
    progress: Progress,
    store: CaseStore,
) -> list:
    from distributed import Client, LocalCluster

    if a.scheduler:
        with Client(a.scheduler) as client:
            services = client.scheduler_info().get("services", {})
            link = client.dashboard_link if "dashboard" in services else "none"
            print(f"dashboard: {link}", file=sys.stderr)
            progress.start()
            return run_dask(study, todo, cache.resolve(), client, a.threads, progress.update, store)
    with (
        LocalCluster(
            n_workers=min(a.workers, len(todo)),
            threads_per_worker=1,
            processes=True,
            dashboard_address=a.dashboard,
        ) as cluster,
        Client(cluster) as client,
    ):
        link = cluster.dashboard_link
        print(
            f"dashboard: {link}" if link else "dashboard: none (it needs bokeh >= 3.1)",
            file=sys.stderr,
        )
        progress.start()
        return run_dask(study, todo, cache.resolve(), client, a.threads, progress.update, store)


def _label(name: str, unit: str) -> str:
    return f"{name} [{unit}]" if unit else name


def _fmt(v: Any) -> str:
    return f"{v:g}" if isinstance(v, float) else str(v)


#: At most this many groups are drawn as lines; more as points coloured by value.
MAX_LINES = 8


def plot(
    study: Study, rows: pd.DataFrame, directory: Path, units: dict[str, str] | None = None
) -> list[Path]:
    """The PNGs of :func:`figures` in ``directory``."""
    import matplotlib.pyplot as plt

    directory.mkdir(parents=True, exist_ok=True)
    written = []
    for name, fig in figures(study, rows, units):
        path = directory / f"{name}.png"
        fig.savefig(path, dpi=100)
        plt.close(fig)
        written.append(path)
    return written


def figures(
    study: Study, rows: pd.DataFrame, units: dict[str, str] | None = None
) -> Iterator[tuple[str, Any]]:
    """One figure per collected output and reduction against each parameter that takes
    more than one value (finished cases), with its file name.

    The axes carry units (``units``, by parameter name and output variable: the study's
    or the FMU's; an integral's unit times s) and the title names the study, the output
    and the parameter. The points are grouped by the other varied parameters: one line
    per combination of their values, so a grid reads as a family of curves; with more
    than :data:`MAX_LINES` combinations (random and Latin hypercube designs), points
    coloured by the first other parameter."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    units = units or {}
    ok = rows[rows["status"] == "ok"]
    failed = int((rows["status"] != "ok").sum())
    varied = [p for p in study.parameters if rows[p.name].nunique() > 1]
    for col in output_columns(study):
        variable, how = col.rsplit(":", 1)
        unit = column_unit(col, units)
        for p in varied:
            others = [q.name for q in varied if q is not p]
            fig, ax = plt.subplots(figsize=(6.4, 4.4))
            groups = list(ok.groupby(others, sort=True)) if others else [((), ok)]
            if len(groups) <= MAX_LINES:
                for values, g in groups:
                    g = g.sort_values(p.name, kind="stable")
                    vals = values if isinstance(values, tuple) else (values,)
                    label = ", ".join(
                        f"{n} = {_fmt(v)}{' ' + units[n] if units.get(n) else ''}"
                        for n, v in zip(others, vals, strict=True)
                    )
                    if study.design.ensemble:
                        # each value's members: their mean, and their sd as a bar
                        m = g.groupby(p.name, sort=True)[col].agg(["mean", "std"])
                        ax.errorbar(
                            m.index,
                            m["mean"],
                            m["std"],
                            fmt="o-",
                            capsize=3,
                            label=(label + ", " if label else "") + "mean ± sd",
                        )
                        continue
                    ax.plot(g[p.name], g[col], "o-", label=label or None)
                if others or study.design.ensemble:
                    ax.legend(fontsize="small")
            else:
                sc = ax.scatter(ok[p.name], ok[col], c=ok[others[0]], cmap="viridis")
                fig.colorbar(sc, ax=ax, label=_label(others[0], units.get(others[0], "")))
            ax.set_xlabel(_label(p.name, units.get(p.name, "")))
            ax.set_ylabel(_label(f"{how} of {variable}", unit))
            ax.set_title(
                f"{study.name}: {how} of {variable} against {p.name}"
                + (f"\n({failed} failed cases not shown)" if failed else ""),
                fontsize="medium",
            )
            ax.grid(alpha=0.3)
            fig.tight_layout()
            yield f"{re.sub(r'[^A-Za-z0-9_.-]', '_', col)}__{p.name}", fig


if __name__ == "__main__":
    sys.exit(main())
