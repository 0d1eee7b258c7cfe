"""A 3D scene with coarse grains (boulders) and a terrain heightmap behind the FMU:
3D variable names, validation, resources copied into the FMU, and bitwise rollback with
the coarse-grain sub-stepper and contacts in the state."""

import numpy as np
from conftest import ROOT, Slave, pack
from fmpy.validation import validate_fmu


def test_debris_flow_scene_as_fmu(tmp_path):
    fmu = pack(ROOT / "models" / "scenes" / "debris_barrier.toml", tmp_path / "debris.fmu")
    assert validate_fmu(str(fmu)) == []
    s = Slave(fmu, "debris")
    names = set(s.vr)
    for n in ["post_left.force.z", "post_left.moment.x", "exposed_1.orientation.w",
              "exposed_1.angular_velocity.z", "buried_1.position.z", "kinetic_energy.coarse",
              "solids.rock.density", "materials.soil.friction_angle"]:
        assert n in names, n
    outputs = ["exposed_1.position.x", "exposed_1.position.z", "exposed_1.velocity.z",
               "exposed_1.orientation.w",
               "kinetic_energy.fine", "kinetic_energy.coarse"]
    for _ in range(2):
        s.step(2e-3)
    state = s.fmu.getFMUstate()
    t = s.t
    first = []
    for _ in range(3):
        s.step(2e-3)
        first.append(s.get(*outputs))
    s.fmu.setFMUstate(state)
    s.t = t
    second = []
    for _ in range(3):
        s.step(2e-3)
        second.append(s.get(*outputs))
    assert np.array_equal(np.array(first), np.array(second))
    # the boulders fall under gravity from rest
    assert s.get("exposed_1.velocity.z") < 0.0
    q = s.get("exposed_1.orientation.w", "exposed_1.orientation.x", "exposed_1.orientation.y",
              "exposed_1.orientation.z")
    assert abs(np.linalg.norm(q) - 1.0) < 1e-12
    assert s.fmu.getInteger([s.vr["steps.coarse"]])[0] > 0
    s.fmu.freeFMUstate(state)
    s.free()
