"""Ensembles and resolution studies: the spread of each reduced output over a case's
members, and its convergence over the levels of a refine design.

A debris flow is chaotic and a boulder's impact a discrete event, so one run's peak load
is one draw of a random variable. An ensemble runs the same case N times, each member's
start perturbed by a stated, reproducible amount (every soil and water particle moved by
ε dp in directions drawn from the member's seed, the scene's
``simulation.perturbation``). Its statistics, per base case and output reduction:

- ``members`` (finished members), ``failed``;
- ``mean``, ``sd`` (the sample standard deviation, N − 1), ``min``, ``max``;
- ``p95``: the empirical 95th percentile (linear interpolation between order
  statistics, ``numpy.percentile``'s default), which needs about 20 members to mean
  more than the largest draw.

A refine design runs an ensemble at each particle spacing. :func:`convergence` fits the
ensemble means of the three finest levels with f(dp) = f₀ + C dp^p: the observed order
p and the extrapolated f₀ (Richardson), where the means converge monotonically and their
differences stand out of the spread; else it says which of these fails.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterator
from typing import Any

import numpy as np
import pandas as pd

from granmix.design import LEVEL
from granmix.store import column_unit, output_columns
from granmix.study import Study

#: The statistics of each reduced output over an ensemble's members.
STATISTICS = ("members", "failed", "mean", "sd", "min", "max", "p95")


def groups(study: Study) -> list[str]:
    """The columns that name a base case: the parameters, then a refine level."""
    return [p.name for p in study.parameters] + ([LEVEL] if study.design.levels else [])


def statistics(study: Study, rows: pd.DataFrame) -> pd.DataFrame:
    """One row per base case and reduced output: the base case's values, ``output``
    (``<variable>:<reduction>``) and :data:`STATISTICS` over its finished members."""
    by = groups(study)
    out = []
    keyed = rows.groupby(by, sort=False, dropna=False) if by else [((), rows)]
    for values, g in keyed:
        vals = values if isinstance(values, tuple) else (values,)
        ok = g[g["status"] == "ok"]
        for col in output_columns(study):
            x = ok[col].to_numpy(dtype=float) if col in ok else np.array([])
            row: dict[str, Any] = dict(zip(by, vals, strict=True))
            row.update(output=col, members=len(x), failed=len(g) - len(ok))
            row.update(_moments(x))
            out.append(row)
    return pd.DataFrame(out, columns=[*by, "output", *STATISTICS])


def _moments(x: np.ndarray) -> dict[str, float]:
    nan = float("nan")
    if len(x) == 0:
        return {"mean": nan, "sd": nan, "min": nan, "max": nan, "p95": nan}
    return {
        "mean": float(np.mean(x)),
        "sd": float(np.std(x, ddof=1)) if len(x) > 1 else nan,
        "min": float(np.min(x)),
        "max": float(np.max(x)),
        "p95": float(np.percentile(x, 95)),
    }


def convergence(study: Study, stats: pd.DataFrame) -> pd.DataFrame:
    """Per base case (without the level) and output of a refine design: each level's
    mean and sd, the observed order, the extrapolated value and a verdict."""
    by = [p.name for p in study.parameters]
    out = []
    keyed = stats.groupby([*by, "output"], sort=False, dropna=False)
    for values, g in keyed:
        g = g.sort_values(LEVEL, ascending=False)
        vals = values if isinstance(values, tuple) else (values,)
        row: dict[str, Any] = dict(zip([*by, "output"], vals, strict=True))
        for k, (_, r) in enumerate(g.iterrows()):
            row[f"dp{k}"] = r[LEVEL]
            row[f"mean{k}"] = r["mean"]
            row[f"sd{k}"] = r["sd"]
        row.update(
            observed_order(
                g[LEVEL].tolist(), g["mean"].tolist(), g["sd"].tolist(), g["members"].tolist()
            )
        )
        out.append(row)
    return pd.DataFrame(out)


def observed_order(
    dp: list[float], mean: list[float], sd: list[float], n: list[int]
) -> dict[str, float | str]:
    """The observed order p and the extrapolated f₀ of f(dp) = f₀ + C dp^p through the
    three finest levels (``dp`` coarsest first; each level's ensemble ``mean``, ``sd``
    and member count ``n``), and a verdict:

    - ``within spread``: the two finest means differ by less than twice the standard
      error of their difference, √(s₂²/n₂ + s₃²/n₃): against the ensembles' spread the
      levels resolve no trend (more members, or finer levels);
    - ``converging``: the differences shrink monotonically, 0 < (f₂ − f₃)/(f₁ − f₂) < 1:
      p and f₀ are given;
    - ``oscillating`` (the differences change sign) or ``diverging`` (they grow);
    - ``two levels``: one difference, no order.
    """
    nan = float("nan")
    res: dict[str, float | str] = {"order": nan, "extrapolated": nan}
    if len(dp) < 2 or any(not math.isfinite(m) for m in mean):
        return res | {"verdict": "no finished members at some level"}
    se = math.sqrt(
        sum(s * s / k for s, k in zip(sd[-2:], n[-2:], strict=True) if k > 1 and math.isfinite(s))
    )
    d23 = mean[-2] - mean[-1]
    if abs(d23) <= 2.0 * se:
        return res | {"verdict": "within spread"}
    if len(dp) < 3:
        return res | {"verdict": "two levels"}
    (h1, h2, h3), d12 = dp[-3:], mean[-3] - mean[-2]
    if d12 == 0 or d23 / d12 <= 0:
        return res | {"verdict": "oscillating"}
    if d23 / d12 >= 1:
        return res | {"verdict": "diverging"}
    p = _order(h1, h2, h3, d23 / d12)
    f0 = mean[-1] - d23 / ((h2 / h3) ** p - 1.0)
    return {"order": p, "extrapolated": f0, "verdict": "converging"}


def _order(h1: float, h2: float, h3: float, ratio: float) -> float:
    """p with (h₂^p − h₃^p)/(h₁^p − h₂^p) = ``ratio`` (in (0, 1)), by bisection: the
    left side falls from its value at p → 0, ln(h₂/h₃)/ln(h₁/h₂), towards 0."""

    def g(p: float) -> float:
        return (h2**p - h3**p) / (h1**p - h2**p) - ratio

    lo, hi = 1e-6, 20.0
    if g(lo) < 0:
        return lo
    if g(hi) > 0:
        return hi
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if g(mid) > 0:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def envelope_figures(
    study: Study, rows: pd.DataFrame, series: pd.DataFrame, units: dict[str, str] | None = None
) -> Iterator[tuple[str, Any]]:
    """One figure per collected output and base case without its level: every member's
    time series (thin), and each level's mean ± sd band over the members at each
    sample time, with its file name."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    units = units or {}
    ok = rows[rows["status"] == "ok"]
    if ok.empty or series.empty:
        return
    by = [p.name for p in study.parameters]
    keyed = list(ok.groupby(by, sort=False)) if by else [((), ok)]
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for values, g in keyed:
        vals = values if isinstance(values, tuple) else (values,)
        label = ", ".join(
            f"{n} = {v:g}" if isinstance(v, float) else f"{n} = {v}"
            for n, v in zip(by, vals, strict=True)
        )
        levels = sorted(g[LEVEL].unique(), reverse=True) if LEVEL in g else [None]
        for o in study.outputs:
            if o.variable not in series:
                continue
            fig, ax = plt.subplots(figsize=(7.2, 4.4))
            for k, level in enumerate(levels):
                members = g if level is None else g[g[LEVEL] == level]
                s = series[series["key"].isin(members["key"])]
                wide = s.pivot_table(
                    index="time", columns="key", values=o.variable, aggfunc="first"
                )
                c = colours[k % len(colours)]
                for key in wide.columns:
                    ax.plot(wide.index, wide[key], color=c, lw=0.5, alpha=0.35)
                m, sd = wide.mean(axis=1), wide.std(axis=1, ddof=1)
                name = "mean ± sd" if level is None else f"dp = {level:g} m: mean ± sd"
                ax.plot(wide.index, m, color=c, lw=1.6, label=f"{name} ({wide.shape[1]} members)")
                ax.fill_between(wide.index, m - sd, m + sd, color=c, alpha=0.25, lw=0)
            unit = units.get(o.variable, "")
            ax.set_xlabel("time [s]")
            ax.set_ylabel(f"{o.variable} [{unit}]" if unit else o.variable)
            ax.set_title(
                f"{study.name}: {o.variable}, every member" + (f"\n{label}" if label else ""),
                fontsize="medium",
            )
            ax.legend(fontsize="small")
            ax.grid(alpha=0.3)
            fig.tight_layout()
            tag = re.sub(
                r"[^A-Za-z0-9_.=-]",
                "_",
                "__".join(f"{n}={v}" for n, v in zip(by, vals, strict=True)),
            )
            yield (
                f"envelope__{re.sub(r'[^A-Za-z0-9_.-]', '_', o.variable)}"
                + (f"__{tag}" if tag else ""),
                fig,
            )


def refine_figures(
    study: Study, stats: pd.DataFrame, conv: pd.DataFrame, units: dict[str, str] | None = None
) -> Iterator[tuple[str, Any]]:
    """One figure per reduced output of a refine design: each level's ensemble mean
    with its sd (bar) and min–max (whiskers) against dp, one line per base case, and
    the extrapolated value where the means converge, with its file name."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    units = units or {}
    by = [p.name for p in study.parameters]
    for col in output_columns(study):
        variable, how = col.rsplit(":", 1)
        unit = column_unit(col, units)
        fig, ax = plt.subplots(figsize=(6.4, 4.4))
        s = stats[stats["output"] == col]
        keyed = list(s.groupby(by, sort=False)) if by else [((), s)]
        for values, g in keyed:
            vals = values if isinstance(values, tuple) else (values,)
            label = ", ".join(f"{n} = {v}" for n, v in zip(by, vals, strict=True))
            g = g.sort_values(LEVEL)
            line = ax.errorbar(
                g[LEVEL], g["mean"], g["sd"], fmt="o-", capsize=4, label=label or "mean ± sd"
            )
            ax.vlines(g[LEVEL], g["min"], g["max"], color=line[0].get_color(), lw=0.8, alpha=0.5)
            c = conv[conv["output"] == col]
            for n, v in zip(by, vals, strict=True):
                c = c[c[n] == v]
            if len(c) and c.iloc[0]["verdict"] == "converging":
                f0, p = c.iloc[0]["extrapolated"], c.iloc[0]["order"]
                ax.axhline(
                    f0,
                    ls="--",
                    color=line[0].get_color(),
                    lw=1,
                    label=f"extrapolated {f0:.4g} (order {p:.2f})",
                )
        ax.set_xscale("log")
        ax.set_xlabel("dp [m]")
        ax.set_ylabel(f"{how} of {variable}" + (f" [{unit}]" if unit else ""))
        ax.set_title(
            f"{study.name}: {how} of {variable} against dp\n"
            f"(ensembles of {study.design.members}: mean ± sd, min–max)",
            fontsize="medium",
        )
        ax.legend(fontsize="small")
        ax.grid(alpha=0.3, which="both")
        fig.tight_layout()
        yield f"refine__{re.sub(r'[^A-Za-z0-9_.-]', '_', col)}", fig
