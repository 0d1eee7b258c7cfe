"""A granmix FMU of the saturated debris flow (`debris_flow_saturated.toml`: saturated
sand with boulders down a slope into a driven barrier) coupled with the structural post
FMU: the barrier reports its water and grain loads, both present once the flow
arrives, and the impulse of their sum passed on equals the momentum the post
receives."""

from conftest import Slave

H = 0.01


def test_debris_load_impulse_equals_post_momentum(fmus):
    g = Slave(fmus["debris"], "debris")
    m = 2000.0
    p = Slave(fmus["post"], "post", start={"m": m, "k": 0.0, "c": 0.0})
    passed, peak_water, peak_grains = 0.0, 0.0, 0.0
    f = g.get("barrier.force.x")
    for _ in range(200):
        p.set("force", f)
        p.step(H)
        passed += f * H
        g.set("barrier.displacement.x", p.get("displacement"))
        g.step(H)
        f = g.get("barrier.force.x")
        water, grains = g.get("barrier.force_water.x"), g.get("barrier.force_grains.x")
        # the load is the water's and the grains' parts
        assert abs(water + grains - f) <= 1e-9 * max(abs(f), 1.0)
        peak_water = max(peak_water, abs(water))
        peak_grains = max(peak_grains, abs(grains))
    received = p.get("impulse")
    momentum = m * p.get("velocity")
    assert passed > 10.0, f"impulse {passed} N·s/m: the flow must reach the barrier"
    assert peak_grains > 10.0 and peak_water > 1.0, (peak_grains, peak_water)
    assert abs(received - passed) <= 1e-9 * abs(passed)
    assert abs(momentum - passed) <= 1e-9 * abs(passed)
    g.free()
    p.free()
