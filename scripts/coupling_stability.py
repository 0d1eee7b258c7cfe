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
3. Optionally (--runs h,m,zeta ...): the real loop of two FMUs for 0.3 s; the measured
   growth rate is the slope of the log of the load's half range over 25 ms windows after
   0.1 s.

Usage (after `cargo build --release -p granmix -p granmix-fmu`):
    .venv/bin/python scripts/coupling_stability.py [--runs 5e-4,20,0.05 1e-3,20,1 ...]
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
from conftest import Slave, granmix_bin  # noqa: E402

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
    for i in range(int(round(t_hold / H0))):
        s = min((i + 1) * H0 / t_ramp, 1.0)
        g.set("barrier.displacement.x", X_SETTLED * (0.5 - 0.5 * np.cos(np.pi * s)))
        g.step(H0)
    state, t0 = g.fmu.getFMUstate(), g.t

    def branch(dx):
        g.fmu.setFMUstate(state)
        g.t = t0
        out = []
        for _ in range(int(round(duration / H0))):
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


def run_loop(fmus, h, m, zeta, duration=0.3):
    g = Slave(fmus["barrier"], "soil")
    p = Slave(fmus["post"], "post", start={"m": m, "c": 2 * zeta * np.sqrt(K_POST * m)})
    f, forces = g.get("barrier.force.x"), []
    for _ in range(int(round(duration / h))):
        p.set("force", f)
        p.step(h)
        g.set("barrier.displacement.x", p.get("displacement"))
        g.step(h)
        f = g.get("barrier.force.x")
        forces.append(f)
    g.free()
    p.free()
    forces = np.array(forces)
    w = int(round(0.025 / h))
    env = np.array(
        [np.ptp(forces[i : i + w]) / 2 for i in range(0, len(forces) - w + 1, w)]
    )
    tt = (np.arange(len(env)) + 0.5) * 0.025
    sel = tt > 0.1
    growth = np.polyfit(tt[sel], np.log(np.maximum(env[sel], 1e-9)), 1)[0]
    return growth, env[-1], forces[-w:].mean()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--runs", nargs="*", default=[], help="h,m,zeta points to run")
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
        for spec in args.runs:
            h, m, z = map(float, spec.split(","))
            r = rho(soil, m, z, h)
            growth, amp, mean = run_loop(fmus, h, m, z)
            print(
                f"h = {h * 1e3:g} ms, m = {m:g}, zeta = {z:g}: predicted rho = {r:.4f} "
                f"(growth {np.log(r) / h:+.1f}/s); measured growth {growth:+.1f}/s, "
                f"load {mean:.2f} N/m ± {amp:.2f}"
            )


if __name__ == "__main__":
    os.environ.setdefault("PYTHONDONTWRITEBYTECODE", "1")
    main()
