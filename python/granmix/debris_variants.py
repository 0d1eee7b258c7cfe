"""The saturated debris flow four ways (issue 44 item 5): dry, saturated as the scene has
it (ψ = 0), saturated with a dilatant soil and with a contractant one, each run with
``granmix run`` and reported side by side: run-out, peak barrier load (grains and
water), and the excess pore pressure in the soil around each boulder, upstream (behind
it) and downstream (ahead of it), while the boulders move (seed 001 Figs. 23–24).

    python -m granmix.debris_variants                 # models/scenes/debris_flow_saturated.toml
    python -m granmix.debris_variants --out out/variants --threads 2

The variants differ from the scene only by ``--set`` overrides (``VARIANTS``). The
dilatant soil starts denser than its critical packing (φ0 = 1 − n = 0.60 against
φ_c = 0.57, as Rondon's dense column), the contractant one looser (φ_c = 0.63); both
with K = 4 and b = 1 (docs/method.md §Dilatancy). Writes ``report.md`` (the tables)
and ``report.png`` (barrier loads and run-out against time, and the ring pressures).
Report only: no ordering is asserted.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from granmix.vtu import read_vtu

ROOT = Path(__file__).resolve().parents[2]

#: name → the scene overrides of each variant.
VARIANTS: dict[str, list[str]] = {
    "dry": ["materials.0.saturated=false"],
    "saturated": [],
    "dilatant": [
        "materials.0.dilatancy.k=4.0",
        "materials.0.dilatancy.phi_c=0.57",
        "materials.0.dilatancy.b=1.0",
    ],
    "contractant": [
        "materials.0.dilatancy.k=4.0",
        "materials.0.dilatancy.phi_c=0.63",
        "materials.0.dilatancy.b=1.0",
    ],
}

#: the times at which the rings around the boulders are read (s), as the validation
#: test `saturated_debris_flow_runs_to_rest` reads them.
RING_TIMES = (0.6, 1.0, 1.4, 1.8)


@dataclass
class Ring:
    """The soil in a ring around a boulder: the mean excess pore pressure upstream and
    downstream (Pa; NaN where the side holds no soil) and the boulder's speed less the
    ring's mean velocity along the boulder's direction (m/s)."""

    up: float
    down: float
    lead: float


def ring_pressures(
    soil: dict[str, np.ndarray],
    centre: np.ndarray,
    velocity: np.ndarray,
    radius: float,
    width: float,
) -> Ring:
    """The ring of soil particles at a distance in [radius, radius + width] from a
    boulder's centre, split by the sign of their offset along the boulder's velocity.
    ``soil`` holds ``points`` and ``velocity`` (n × 3) and ``excess_pore_pressure`` (n)."""
    if "excess_pore_pressure" not in soil:
        # a dry soil: no pore pressure to read
        return Ring(up=float("nan"), down=float("nan"), lead=float("nan"))
    x = soil["points"][:, :2].astype(float)
    d = x - np.asarray(centre, float)[:2]
    dist = np.linalg.norm(d, axis=1)
    on = (dist >= radius) & (dist <= radius + width)
    v = np.asarray(velocity, float)[:2]
    speed = max(float(np.linalg.norm(v)), 1e-12)
    along = d[on] @ v / speed
    p = soil["excess_pore_pressure"][on].astype(float)
    up, down = p[along < 0.0], p[along >= 0.0]
    ring_v = soil["velocity"][on, :2].astype(float) @ v / speed
    return Ring(
        up=float(up.mean()) if len(up) else float("nan"),
        down=float(down.mean()) if len(down) else float("nan"),
        lead=speed - (float(ring_v.mean()) if len(ring_v) else 0.0),
    )


def soil_frames(out: Path) -> dict[float, Path]:
    """The soil snapshots of a run by time, from its ``.pvd`` collection."""
    (pvd,) = out.glob("*.pvd")
    frames = {}
    for m in re.finditer(r'timestep="([^"]+)"[^>]*name="soil" file="([^"]+)"', pvd.read_text()):
        frames[float(m.group(1))] = out / m.group(2)
    return frames


def nearest(keys: list[float], t: float) -> float:
    """The key closest to ``t``."""
    return min(keys, key=lambda k: abs(k - t))


def run_variant(
    binary: Path, scene: Path, out: Path, sets: list[str], threads: int | None
) -> pd.DataFrame:
    """Run the scene with ``sets`` into ``out`` (unless a finished run is there) and
    return its series."""
    series = out / "series.csv"
    if not (out / "summary.json").exists():
        args = [str(binary), "run", str(scene), "--out", str(out), "--quiet", "--no-plots"]
        for s in sets:
            args += ["--set", s]
        env = dict(os.environ)
        if threads:
            env["RAYON_NUM_THREADS"] = str(threads)
        subprocess.run(args, check=True, env=env)
    return pd.read_csv(series)


def column(df: pd.DataFrame, name: str) -> pd.Series:
    """The series' column whose name (less its unit) is ``name``."""
    for c in df.columns:
        if c.split(" [")[0] == name:
            return df[c]
    raise KeyError(f"series.csv has no column {name!r}")


def has(df: pd.DataFrame, name: str) -> bool:
    """Whether the series has the column ``name``."""
    return any(c.split(" [")[0] == name for c in df.columns)


def water_load(df: pd.DataFrame) -> pd.Series:
    """The water's part of the barrier's load along x (zero for a run without water)."""
    if has(df, "barrier.force_water.x"):
        return column(df, "barrier.force_water.x").abs()
    return column(df, "barrier.force.x") * 0.0


def grain_load(df: pd.DataFrame) -> pd.Series:
    """The grains' part of the barrier's load along x: the load less the water's."""
    total = column(df, "barrier.force.x")
    if has(df, "barrier.force_water.x"):
        return (total - column(df, "barrier.force_water.x")).abs()
    return total.abs()


def summarise(name: str, df: pd.DataFrame, out: Path) -> dict[str, object]:
    """Run-out, peak loads and the boulders' rings of one variant."""
    t = column(df, "time")
    total = column(df, "barrier.force.x").abs()
    water, grains = water_load(df), grain_load(df)
    row: dict[str, object] = {
        "variant": name,
        "end [s]": float(t.iloc[-1]),
        "run-out [m]": float(column(df, "runout").iloc[-1]),
        "peak load [N/m]": float(total.max()),
        "at [s]": float(t[total.idxmax()]),
        "peak grains [N/m]": float(grains.max()),
        "peak water [N/m]": float(water.max()),
        "fine steps": int(column(df, "steps").iloc[-1]),
    }
    bodies = json.loads((out / "bodies.json").read_text())["series"]
    times = [b["time"] for b in bodies]
    frames = soil_frames(out)
    rings = []
    for tr in RING_TIMES:
        if tr > row["end [s]"] + 1e-9:
            continue
        sample = bodies[times.index(nearest(times, tr))]
        soil = read_vtu(frames[nearest(list(frames), tr)])
        for k, b in enumerate(sample["bodies"]):
            r = ring_pressures(soil, np.array(b["position"]), np.array(b["velocity"]), 0.08, 0.06)
            rings.append({"variant": name, "t [s]": tr, "boulder": k + 1, **r.__dict__})
    row["rings"] = rings
    row["series"] = df
    return row


def markdown(rows: list[dict[str, object]]) -> str:
    """The report's two tables."""
    keys = ["variant", "run-out [m]", "peak load [N/m]", "at [s]", "peak grains [N/m]",
            "peak water [N/m]", "end [s]", "fine steps"]
    lines = ["| " + " | ".join(keys) + " |", "|" + "---|" * len(keys)]
    for r in rows:
        cells = [f"{r[k]:.3f}" if isinstance(r[k], float) else str(r[k]) for k in keys]
        lines.append("| " + " | ".join(cells) + " |")
    lines += ["", ("Excess pore pressure around each boulder (Pa), upstream / downstream, "
                   "and the boulder's lead over its ring (m/s):"), ""]
    lines += ["| variant | t [s] | boulder 1 | boulder 2 | boulder 3 |", "|---|---|---|---|---|"]
    for r in rows:
        rings = r["rings"]
        assert isinstance(rings, list)
        for t in RING_TIMES:
            rs = [g for g in rings if g["t [s]"] == t]
            # a dry soil has no pore pressure to report
            if rs and not all(np.isnan(g["up"]) and np.isnan(g["down"]) for g in rs):
                cells = [f"{g['up']:.0f} / {g['down']:.0f}, {g['lead']:+.2f}" for g in rs]
                lines.append(f"| {r['variant']} | {t} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def plot(rows: list[dict[str, object]], path: Path) -> None:
    """Barrier load (grains solid, water dashed) and run-out against time, per variant;
    and the ring pressures upstream against downstream."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 3, figsize=(15, 4.5))
    for r in rows:
        df = r["series"]
        assert isinstance(df, pd.DataFrame)
        t = column(df, "time")
        water, grains = water_load(df), grain_load(df)
        (line,) = ax[0].plot(t, grains, label=f"{r['variant']}")
        ax[0].plot(t, water, "--", color=line.get_color())
        ax[1].plot(t, column(df, "runout"), color=line.get_color(), label=str(r["variant"]))
        rings = r["rings"]
        assert isinstance(rings, list)
        if any(np.isfinite(g["up"]) for g in rings):
            ax[2].scatter([g["up"] for g in rings], [g["down"] for g in rings],
                          color=line.get_color(), label=str(r["variant"]))
    ax[0].set(xlabel="t [s]", ylabel="barrier load [N/m]",
              title="barrier load: grains (solid), water (dashed)")
    ax[1].set(xlabel="t [s]", ylabel="run-out [m]", title="front")
    lim = ax[2].get_xlim()
    ax[2].plot(lim, lim, "k:", lw=0.8)
    ax[2].set(xlabel="upstream excess [Pa]", ylabel="downstream excess [Pa]",
              title="soil around the boulders, 0.6–1.8 s")
    for a in ax:
        a.legend()
        a.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", type=Path,
                    default=ROOT / "models" / "scenes" / "debris_flow_saturated.toml")
    ap.add_argument("--granmix", type=Path, default=ROOT / "target" / "release" / "granmix")
    ap.add_argument("--out", type=Path, default=Path("out/debris_variants"))
    ap.add_argument("--threads", type=int, default=None, help="RAYON_NUM_THREADS per run")
    ap.add_argument("--variants", nargs="*", default=list(VARIANTS), choices=list(VARIANTS))
    ap.add_argument("--set", action="append", default=[], dest="sets",
                    help="an override for every variant (repeatable)")
    a = ap.parse_args(argv)
    if not a.granmix.exists():
        print(f"{a.granmix}: no granmix binary (cargo build --release -p granmix)",
              file=sys.stderr)
        return 2
    rows = []
    for name in a.variants:
        out = a.out / name
        print(f"{name}: granmix run {a.scene.name} " + " ".join(VARIANTS[name] + a.sets),
              flush=True)
        df = run_variant(a.granmix, a.scene, out, VARIANTS[name] + a.sets, a.threads)
        rows.append(summarise(name, df, out))
    text = markdown(rows)
    (a.out / "report.md").write_text(text)
    plot(rows, a.out / "report.png")
    print(text)
    print(f"wrote {a.out / 'report.md'} and {a.out / 'report.png'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
