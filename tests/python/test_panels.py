"""Barrier panels: per-panel forces sum to the barrier total, and each post of the
flexible-barrier FMU receives exactly the impulse of its panel."""

import numpy as np
from conftest import Slave

H = 1e-3


def test_panel_forces_drive_the_flexible_barrier(fmus):
    g = Slave(fmus["panels"], "granular")
    s = Slave(fmus["flexible_barrier"], "structure")
    names = [f"barrier.panel_{i}.force.x" for i in range(4)]
    passed = np.zeros(4)
    for _ in range(100):
        g.step(H)
        panels = np.array(g.get(*names))
        total = g.get("barrier.force.x")
        assert abs(panels.sum() - total) <= 1e-9 * np.abs(panels).sum()
        for i, f in enumerate(panels):
            s.set(f"post_{i}.force", f)
        s.step(H)
        passed += panels * H
    received = np.array([s.get(f"post_{i}.impulse") for i in range(4)])
    assert np.all(np.abs(received - passed) <= 1e-9 * np.abs(passed).max())
    # the layer is 0.1 m deep on a 0.2 m barrier: the lower panels carry the load
    assert passed[0] > passed[2] > 0.0 and passed[3] == 0.0
    # the loaded posts deflect, and drag their neighbours along through the coupling
    x = [s.get(f"post_{i}.displacement") for i in range(4)]
    assert x[0] > 0.0 and x[3] > 0.0
    g.free()
    s.free()
