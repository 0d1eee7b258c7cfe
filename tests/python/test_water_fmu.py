"""A granmix FMU of a water scene (`fmu_water_barrier_2d.toml`: a dam-break surge on a
driven barrier) coupled with the structural post FMU: the barrier load is all water, and
the water load's impulse passed on equals the momentum the post receives."""

from conftest import Slave

H = 1e-3


def test_water_load_impulse_equals_post_momentum(fmus):
    g = Slave(fmus["water"], "water")
    m = 200.0
    p = Slave(fmus["post"], "post", start={"m": m, "k": 0.0, "c": 0.0})
    passed, grains = 0.0, 0.0
    f = g.get("barrier.force_water.x")
    for _ in range(250):
        p.set("force", f)
        p.step(H)
        passed += f * H
        g.set("barrier.displacement.x", p.get("displacement"))
        g.step(H)
        f = g.get("barrier.force_water.x")
        # no grains in the scene: the whole load is the water's
        assert g.get("barrier.force.x") == f
        grains = max(grains, abs(g.get("barrier.force_grains.x")))
        # the panels split the same way and sum to the barrier's water load
        panels = [g.get(f"barrier.panel_{i}.force_water.x") for i in range(3)]
        assert abs(sum(panels) - f) <= 1e-9 * max(abs(f), 1.0)
        for i in range(3):
            assert g.get(f"barrier.panel_{i}.force_grains.x") == 0.0
            assert g.get(f"barrier.panel_{i}.force.x") == panels[i]
    received = p.get("impulse")
    momentum = m * p.get("velocity")
    assert passed > 1.0, f"impulse {passed} N·s/m: the surge must reach the barrier"
    assert abs(received - passed) <= 1e-9 * abs(passed)
    assert abs(momentum - passed) <= 1e-9 * abs(passed)
    assert grains == 0.0
    assert g.get("kinetic_energy.water") > 0.0
    g.free()
    p.free()


def test_water_state_restored_continues_bitwise(fmus):
    """A water scene's FMU state, deserialised into another instance mid-surge, continues
    exactly as the original (the water's lists and scratch are rebuilt as needed)."""
    names = ["barrier.force.x", "barrier.force_water.x", "kinetic_energy.water"]

    def run(s, n):
        out = []
        for _ in range(n):
            s.step(H)
            out.append([s.get(v) for v in names])
        return out

    s = Slave(fmus["water"], "orig")
    run(s, 60)
    state = s.fmu.getFMUstate()
    blob = s.fmu.serializeFMUstate(state)
    s.fmu.freeFMUstate(state)
    t = s.t
    first = run(s, 40)
    other = Slave(fmus["water"], "copy")
    st = other.fmu.deSerializeFMUstate(blob)
    other.fmu.setFMUstate(st)
    other.fmu.freeFMUstate(st)
    other.t = t
    second = run(other, 40)
    assert first == second
    assert first[-1][2] > 0.0
    s.free()
    other.free()
