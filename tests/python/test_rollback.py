"""FMU state: get → step → set → step gives bitwise-identical outputs, through the
in-memory state and through serialisation; instances in one process are independent."""

import numpy as np
from conftest import Slave

H = 1e-3
OUTPUTS = ["barrier.force.x", "barrier.force.y", "barrier.moment", "barrier.peak_force",
           "kinetic_energy.fine"]


def run(s, n, x0=0.0):
    out = []
    for i in range(n):
        s.set("barrier.displacement.x", x0 + 1e-5 * i)
        s.step(H)
        out.append(s.get(*OUTPUTS))
    return np.array(out)


def test_get_set_state_is_bitwise(fmus):
    s = Slave(fmus["impact"])
    run(s, 5)
    state = s.fmu.getFMUstate()
    t = s.t
    first = run(s, 5, 1e-4)
    s.fmu.setFMUstate(state)
    s.t = t
    second = run(s, 5, 1e-4)
    assert np.array_equal(first, second)
    # through bytes, into a second instance
    blob = s.fmu.serializeFMUstate(state)
    other = Slave(fmus["impact"], "other")
    restored = other.fmu.deSerializeFMUstate(blob)
    other.fmu.setFMUstate(restored)
    other.t = t
    third = run(other, 5, 1e-4)
    assert np.array_equal(first, third)
    s.fmu.freeFMUstate(state)
    other.fmu.freeFMUstate(restored)
    s.free()
    other.free()


def test_instances_are_independent(fmus):
    a = Slave(fmus["impact"], "a")
    b = Slave(fmus["impact"], "b")
    run(a, 5, 2e-3)  # a moves its barrier far; b must not notice
    rb = run(b, 5)
    c = Slave(fmus["impact"], "c")
    rc = run(c, 5)
    assert np.array_equal(rb, rc)
    for s in (a, b, c):
        s.free()
