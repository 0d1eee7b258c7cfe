"""Stability of the explicit (Gauss–Seidel) coupling loop of docs/fmu.md, measured and
predicted (docs/fmu.md, "Coupling stability").

1. Soil: the bundled 2D layer (models/scenes/fmu_barrier_2d.toml) is brought to rest
   against a barrier moved out by 0.8 mm (active state, as the coupled loop leaves it);
   its step response to a 1 µm move *into* the soil (elastic unloading) is measured
   through the FMU at a 0.1 ms step, against an unperturbed branch restored from the same
   FMU state. Its dynamic stiffness K(f) = -dF/dx(f) is fitted by k_s - m_a (2πf)² over
   20–80 Hz (stiffness and added mass), and c_s(f) = Im K / (2πf) is the soil's damping.
2. Loop: the post's exact step for a force held over the step, y' = Φ y + Γ F_n, and the
   soil's load averaged over a step in which the barrier moves linearly from x_n to
   x_{n+1}: F_{n+1} = -k_s (x_n + x_{n+1})/2 - c_s Δx_n/h - m_a (Δx_n - Δx_{n-1})/h²
   (Δx_n = x_{n+1} - x_n). The loop is the linear map on (x, v, F, Δx_{n-1}); it is stable
   when its spectral radius ρ < 1. c_s is taken at the coupled mode's frequency
   f_c = √(k_s / (m + m_a)) / 2π. The growth rate of an oscillation is ln ρ / h.
3. Optionally (--runs h,m,zeta[,kick] ...): the real loop of two FMUs for 0.3 s, or with
   a kick (an impulse in N·s/m added to the post's load at 0.1 s) to 0.225 s; the
   measured growth rate is the slope of the log of the load's half range over 25 ms
   windows after 0.1 s (after the kick). --svg writes the map of the runs in (h, ζ) with
   the predicted bound (docs/coupling_stability.svg).

Usage (after `cargo build --release -p granmix -p granmix-fmu`):
    .venv/bin/python scripts/coupling_stability.py [--svg map.svg] \
        [--runs 5e-4,20,0.05 1e-3,20,1,-0.3 ...]
"""

import argparse
import os
import pathlib
import subprocess
import sys
import tempfile

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "python"))
from conftest import Slave, granmix_bin

K_POST = 4.0e4  # models/structures/post.toml
H0 = 1e-4  # identification step (one solver step)
X_SETTLED = 0.8e-3  # the documented post settles near 0.8 mm (F/k at the active load)
DX = -1e-6  # perturbation: 1 µm into the soil


def pack(out_dir):
    paths = {}
    for name, src in [
        ("barrier", ROOT / "models" / "scenes" / "fmu_barrier_2d.toml"),
        ("post", ROOT / "models" / "structures" / "post.toml"),
    ]:
        paths[name] = pathlib.Path(out_dir) / f"{name}.fmu"
        subprocess.run(
            [str(granmix_bin()), "pack-fmu", str(src), "-o", str(paths[name])],
            check=True,
        )
    return paths


def step_response(barrier_fmu, duration=0.2):
    """dF/dx per step (N/m per m) after a move of DX during the first step, at the
    settled (active) state."""
    g = Slave(barrier_fmu, "soil")
    t_ramp, t_hold = 0.05, 0.08
    for i in range(round(t_hold / H0)):
        s = min((i + 1) * H0 / t_ramp, 1.0)
        g.set("barrier.displacement.x", X_SETTLED * (0.5 - 0.5 * np.cos(np.pi * s)))
        g.step(H0)
    state, t0 = g.fmu.getFMUstate(), g.t

    def branch(dx):
        g.fmu.setFMUstate(state)
        g.t = t0
        out = []
        for _ in range(round(duration / H0)):
            g.set("barrier.displacement.x", X_SETTLED + dx)
            g.step(H0)
            out.append(g.get("barrier.force.x"))
        return np.array(out)

    s = (branch(DX) - branch(0.0)) / DX
    g.free()
    return s


class Soil:
    """k_s, m_a and c_s(f) of the soil from its step response."""

    def __init__(self, s, window=0.06):
        self.ds = np.diff(np.concatenate([[0.0], s]))
        j = np.arange(len(s))
        self.phase_j = j * H0
        self.w = np.exp(-self.phase_j / window)  # the layer rings for ~0.1 s
        f = np.arange(20.0, 81.0, 5.0)
        om = 2 * np.pi * f
        re = np.array([self.K(x).real for x in f])
        (self.ks, self.ma), *_ = np.linalg.lstsq(
            np.c_[np.ones_like(om), -(om**2)], re, rcond=None
        )
        self.fit_error = np.abs(self.ks - self.ma * om**2 - re).max() / self.ks

    def K(self, f):
        om = 2 * np.pi * f
        return -(self.ds * self.w * np.exp(-1j * om * self.phase_j)).sum()

    def f_coupled(self, m, k=K_POST):
        return np.sqrt((self.ks + k) / (m + self.ma)) / (2 * np.pi)

    def cs(self, m):
        f = self.f_coupled(m)
        return self.K(f).imag / (2 * np.pi * f)


def post_step(m, k, c, h):
    """Φ, Γ of the exact step for a held force: exp of the augmented system."""
    a = np.array([[0.0, 1.0, 0.0], [-k / m, -c / m, 1.0 / m], [0.0, 0.0, 0.0]]) * h
    sq = max(0, int(np.ceil(np.log2(max(np.abs(a).sum(axis=1).max(), 1e-300)))) + 1)
    a = a / 2**sq
    e, term = np.eye(3), np.eye(3)
    for i in range(1, 20):
        term = term @ a / i
        e = e + term
    for _ in range(sq):
        e = e @ e
    return e[:2, :2], e[:2, 2]


def loop_map(ks, cs, ma, m, k, c, h):
    phi, gam = post_step(m, k, c, h)
    t = np.zeros((4, 4))  # state (x_n, v_n, F_n, Δx_{n-1})
    t[0, :3] = [phi[0, 0], phi[0, 1], gam[0]]
    t[1, :3] = [phi[1, 0], phi[1, 1], gam[1]]
    dxn = np.array([phi[0, 0] - 1.0, phi[0, 1], gam[0], 0.0])
    xn = np.array([1.0, 0.0, 0.0, 0.0])
    t[2] = -ks * (xn + t[0]) / 2 - (cs / h + ma / h**2) * dxn
    t[2, 3] += ma / h**2
    t[3] = dxn
    return t


def rho(soil, m, zeta, h, k=K_POST):
    c = 2 * zeta * np.sqrt(k * m)
    return np.abs(np.linalg.eigvals(loop_map(soil.ks, soil.cs(m), soil.ma, m, k, c, h))).max()


def h_bound(soil, m, zeta):
    lo, hi = 1e-5, 1e-2
    for _ in range(50):
        mid = np.sqrt(lo * hi)
        lo, hi = (mid, hi) if rho(soil, m, zeta, mid) < 1 else (lo, mid)
    return lo


def run_loop(fmus, h, m, zeta, duration=0.3, kick=0.0, t_kick=0.1):
    """The loop of docs/fmu.md; `kick` (N·s/m) is added to the post's load over the step
    starting at t_kick. Returns the growth rate of the load's oscillation after 0.1 s,
    its half range over the last 25 ms and its mean there."""
    g = Slave(fmus["barrier"], "soil")
    p = Slave(fmus["post"], "post", start={"m": m, "c": 2 * zeta * np.sqrt(K_POST * m)})
    f, forces = g.get("barrier.force.x"), []
    n_kick = round(t_kick / h)
    for n in range(round(duration / h)):
        p.set("force", f + (kick / h if kick and n == n_kick else 0.0))
        p.step(h)
        g.set("barrier.displacement.x", p.get("displacement"))
        g.step(h)
        f = g.get("barrier.force.x")
        forces.append(f)
    g.free()
    p.free()
    forces = np.array(forces)
    w = round(0.025 / h)
    env = np.array(
        [np.ptp(forces[i : i + w]) / 2 for i in range(0, len(forces) - w + 1, w)]
    )
    tt = (np.arange(len(env)) + 0.5) * 0.025
    sel = tt > (t_kick + 0.025 if kick else 0.1)
    growth = np.polyfit(tt[sel], np.log(np.maximum(env[sel], 1e-9)), 1)[0]
    return growth, env[-1], forces[-w:].mean()


def status(growth, amp):
    """settles / decays (slowly, still above 1 N/m) / oscillates (limit cycle)."""
    if amp < 1.0:
        return "settles"
    return "decays" if growth < -1.0 else "oscillates"


def write_svg(path, soil, m, runs):
    """Stability map in (h, ζ) for a post of mass m: the map's bound, the first-order
    rule, and the measured runs."""
    w, ht, x0, y0, x1, y1 = 640, 510, 70, 20, 610, 390
    hx = (np.log10(0.1e-3), np.log10(3e-3))
    zy = (np.log10(0.03), np.log10(3.0))

    def px(h):
        return x0 + (np.log10(h) - hx[0]) / (hx[1] - hx[0]) * (x1 - x0)

    def py(z):
        return y1 - (np.log10(z) - zy[0]) / (zy[1] - zy[0]) * (y1 - y0)

    out = [
        (f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{ht}" '
        'font-family="sans-serif" font-size="12">'),
        f'<rect x="{x0}" y="{y0}" width="{x1 - x0}" height="{y1 - y0}" fill="none" stroke="black"/>',
    ]
    for h in [0.1e-3, 0.2e-3, 0.5e-3, 1e-3, 2e-3]:
        out.append(f'<line x1="{px(h):.1f}" y1="{y0}" x2="{px(h):.1f}" y2="{y1}" stroke="#ddd"/>')
        out.append(f'<text x="{px(h):.1f}" y="{y1 + 16}" text-anchor="middle">{h * 1e3:g}</text>')
    for z in [0.05, 0.1, 0.3, 1.0, 2.0]:
        out.append(f'<line x1="{x0}" y1="{py(z):.1f}" x2="{x1}" y2="{py(z):.1f}" stroke="#ddd"/>')
        out.append(f'<text x="{x0 - 6}" y="{py(z) + 4:.1f}" text-anchor="end">{z:g}</text>')
    out.append(f'<text x="{(x0 + x1) / 2}" y="{y1 + 34}" text-anchor="middle">communication step h (ms)</text>')
    out.append(f'<text x="16" y="{(y0 + y1) / 2}" text-anchor="middle" transform="rotate(-90 16 {(y0 + y1) / 2})">post damping ratio ζ</text>')
    zs = np.logspace(zy[0], zy[1], 60)
    bound = " ".join(f"{px(min(h_bound(soil, m, z), 3e-3)):.1f},{py(z):.1f}" for z in zs)
    out.append(f'<polyline points="{bound}" fill="none" stroke="#1f77b4" stroke-width="2"/>')
    cs = soil.cs(m)
    rule = " ".join(
        f"{px(min((2 * z * np.sqrt(K_POST * m) + cs) * (m + soil.ma) / (soil.ks * m), 3e-3)):.1f},{py(z):.1f}"
        for z in zs
    )
    out.append(f'<polyline points="{rule}" fill="none" stroke="#1f77b4" stroke-dasharray="5,4"/>')
    for h, z, st in runs:
        x, y = px(h), py(z)
        if st == "settles":
            out.append(f'<circle cx="{x:.1f}" cy="{y:.1f}" r="6" fill="#2ca02c"/>')
        elif st == "decays":
            out.append(f'<circle cx="{x:.1f}" cy="{y:.1f}" r="6" fill="none" stroke="#2ca02c" stroke-width="2"/>')
        else:
            out.append(
                f'<path d="M{x - 6:.1f},{y - 6:.1f}L{x + 6:.1f},{y + 6:.1f}M{x - 6:.1f},{y + 6:.1f}L{x + 6:.1f},{y - 6:.1f}" '
                'stroke="#d62728" stroke-width="2.5"/>'
            )
    legend = [
        ("#1f77b4", f"bound of the linear map (m = {m:g} kg/m): stable left of it"),
        ("#1f77b4", "first-order rule h = (c + c_s)(m + m_a)/(k_s m)"),
        ("#2ca02c", "measured: settles (filled) / decays slowly (open)"),
        ("#d62728", "measured: oscillates (limit cycle)"),
    ]
    for i, (col, txt) in enumerate(legend):
        out.append(f'<text x="{x0}" y="{y1 + 60 + 16 * i}" fill="{col}">{txt}</text>')
    out.append("</svg>")
    pathlib.Path(path).write_text("\n".join(out) + "\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument(
        "--runs",
        nargs="*",
        default=[],
        help="h,m,zeta[,kick] points to run (kick: N·s/m on the post at 0.1 s, run to 0.225 s)",
    )
    ap.add_argument("--svg", help="write the stability map in (h, zeta) of the runs' mass")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as d:
        fmus = pack(d)
        soil = Soil(step_response(fmus["barrier"]))
        print(
            f"soil: k_s = {soil.ks:.3e} N/m per m, m_a = {soil.ma:.2f} kg/m "
            f"(fit within {soil.fit_error:.1%} over 20-80 Hz)"
        )
        masses = [10.0, 20.0, 40.0, 80.0]
        for m in masses:
            print(f"  m = {m:5.1f} kg/m: f_c = {soil.f_coupled(m):6.1f} Hz, c_s = {soil.cs(m):7.1f} N s/m")
        print("predicted bound h* (ms): rho < 1 for h < h*")
        print("  zeta  " + "".join(f"m={m:<8g}" for m in masses))
        for z in [0.05, 0.3, 1.0, 2.0]:
            print(f"  {z:4.2f}  " + "".join(f"{h_bound(soil, m, z) * 1e3:<10.3f}" for m in masses))
        runs, mass = [], 20.0
        for spec in args.runs:
            h, m, z, *kick = map(float, spec.split(","))
            kick = kick[0] if kick else 0.0
            r = rho(soil, m, z, h)
            growth, amp, mean = run_loop(fmus, h, m, z, 0.225 if kick else 0.3, kick)
            st = status(growth, amp)
            runs.append((h, z, st))
            mass = m
            print(
                f"h = {h * 1e3:g} ms, m = {m:g}, zeta = {z:g}, kick = {kick:g}: predicted "
                f"rho = {r:.4f} (growth {np.log(r) / h:+.1f}/s); measured growth "
                f"{growth:+.1f}/s, load {mean:.2f} N/m ± {amp:.2f}: {st}",
                flush=True,
            )
        if args.svg:
            write_svg(args.svg, soil, mass, runs)


if __name__ == "__main__":
    os.environ.setdefault("PYTHONDONTWRITEBYTECODE", "1")
    main()
