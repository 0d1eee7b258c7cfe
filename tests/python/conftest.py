"""Shared fixtures: FMUs packed by `granmix pack-fmu` and a small master-loop helper."""

import os
import pathlib
import subprocess

import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCENE = ROOT / "models" / "scenes" / "fmu_barrier_2d.toml"
WATER_SCENE = ROOT / "models" / "scenes" / "fmu_water_barrier_2d.toml"
DEBRIS_SCENE = ROOT / "models" / "scenes" / "debris_flow_saturated.toml"
STRUCTURES = ROOT / "models" / "structures"


def granmix_bin() -> pathlib.Path:
    """The granmix executable of the current build (GRANMIX_BIN overrides)."""
    if "GRANMIX_BIN" in os.environ:
        return pathlib.Path(os.environ["GRANMIX_BIN"])
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    return target / "release" / "granmix"


def pack(src: pathlib.Path, out: pathlib.Path, *sets: str) -> pathlib.Path:
    """Run `granmix pack-fmu` and return the FMU path."""
    cmd = [str(granmix_bin()), "pack-fmu", str(src), "-o", str(out)]
    for s in sets:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True)
    return out


@pytest.fixture(scope="session")
def fmus(tmp_path_factory):
    """Every FMU the tests use: the granular scene (fixed and impact), the water scene,
    the saturated debris flow and each structure."""
    d = tmp_path_factory.mktemp("fmus")
    out = {
        "barrier": pack(SCENE, d / "barrier.fmu"),
        "impact": pack(SCENE, d / "impact.fmu", "regions[0].velocity=[2.0, 0.0]"),
        "panels": pack(SCENE, d / "panels.fmu", "barriers[0].panels=[4]"),
        "water": pack(WATER_SCENE, d / "water.fmu"),
        "debris": pack(DEBRIS_SCENE, d / "debris.fmu", 'barriers[0].input="displacement"'),
    }
    for s in sorted(STRUCTURES.glob("*.toml")):
        out[s.stem] = pack(s, d / f"{s.stem}.fmu")
    return out


class Slave:
    """An FMU2Slave with variables by name, instantiated and initialised."""

    def __init__(self, path, name="instance", start=None, guid=None, t0=0.0):
        self.md = read_model_description(str(path))
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.dir = extract(str(path))
        self.fmu = FMU2Slave(
            guid=guid or self.md.guid,
            unzipDirectory=self.dir,
            modelIdentifier=self.md.coSimulation.modelIdentifier,
            instanceName=name,
        )
        self.fmu.instantiate()
        self.fmu.setupExperiment(startTime=t0)
        self.fmu.enterInitializationMode()
        for k, v in (start or {}).items():
            self.set(k, v)
        self.fmu.exitInitializationMode()
        self.t = t0

    def get(self, *names):
        vals = self.fmu.getReal([self.vr[n] for n in names])
        return vals[0] if len(names) == 1 else vals

    def set(self, name, value):
        self.fmu.setReal([self.vr[name]], [value])

    def step(self, h):
        self.fmu.doStep(currentCommunicationPoint=self.t, communicationStepSize=h)
        self.t += h

    def free(self):
        self.fmu.terminate()
        self.fmu.freeInstance()


def post_coupling(root: str = "") -> str:
    """The study tables that couple the granmix FMU to the bundled post (files under
    `root`, a path prefix ending in `/`, or relative to the repository)."""
    return f"""
[[partners]]
name = "post"
fmu = "{root}models/structures/post.toml"

[[connections]]
from = "granmix.barrier.force.x"
to = "post.force"

[[connections]]
from = "post.displacement"
to = "granmix.barrier.displacement.x"
"""
