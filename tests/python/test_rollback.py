"""FMU state: get → step → set → step gives bitwise-identical outputs, through the
in-memory state and through serialisation; instances in one process are independent."""

import time

import numpy as np
import pytest
from conftest import SCENE, Slave, pack
from fmpy.fmi1 import FMICallException

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


# --- serialised states: the state itself, in a checked envelope (fmu/src/envelope.rs) ---

MAGIC = b"GRANMIX\x1a"


def saved(s):
    """Serialise the current state of `s`; returns (blob, steps.fine)."""
    st = s.fmu.getFMUstate()
    blob = s.fmu.serializeFMUstate(st)
    s.fmu.freeFMUstate(st)
    return blob, int(s.fmu.getInteger([s.vr["steps.fine"]])[0])


def decoded_length(blob):
    """Payload length once decoded, from the envelope header."""
    glen = blob[12]
    at = 13 + glen + 8
    return int.from_bytes(blob[at:at + 8], "little")


def restore(s, blob):
    """Deserialise `blob` into `s` and set it; returns the restore time (s)."""
    t0 = time.perf_counter()
    st = s.fmu.deSerializeFMUstate(blob)
    dt = time.perf_counter() - t0
    s.fmu.setFMUstate(st)
    s.fmu.freeFMUstate(st)
    return dt


def test_state_size_and_restore_do_not_grow_with_steps(tmp_path):
    """A state after ~1e2 solver steps and one after ~1e4 have the same size, and
    restoring either takes the solver nowhere: `steps.fine` is the saved count. The
    scene is coarsened (dp = 0.02 m, 50 grains) so that 1e4 steps take about a second."""
    fmu = pack(SCENE, tmp_path / "coarse.fmu", "simulation.dp=0.02")
    s = Slave(fmu, "long")
    s.step(0.021)
    early, n_early = saved(s)
    t0 = time.perf_counter()
    s.step(2.1)
    run_time = time.perf_counter() - t0
    late, n_late = saved(s)
    assert 80 <= n_early <= 150 and n_late >= 80 * n_early, (n_early, n_late)
    assert early[:8] == MAGIC and late[:8] == MAGIC
    # same particles, same lists: only varints (counters) and the neighbour-list
    # length may differ; an O(steps) format would be 100 times larger
    raw_e, raw_l = decoded_length(early), decoded_length(late)
    assert abs(raw_l - raw_e) < 0.05 * raw_e, (raw_e, raw_l)
    assert len(late) < 1.5 * len(early), (len(early), len(late))
    other = Slave(fmu, "restored")
    times = {}
    for name, blob, n in (("early", early, n_early), ("late", late, n_late)):
        times[name] = min(restore(other, blob) for _ in range(3))
        assert int(other.fmu.getInteger([other.vr["steps.fine"]])[0]) == n
    print(f"\nstate bytes: {len(early)} at {n_early} steps, {len(late)} at {n_late} steps "
          f"(raw {raw_e} / {raw_l}); restore {times['early'] * 1e3:.3f} ms / "
          f"{times['late'] * 1e3:.3f} ms; the run between them {run_time:.2f} s")
    s.free()
    other.free()


def test_restored_state_continues_bitwise(fmus):
    """Deserialised into another instance, a state continues exactly as the original,
    grains flowing and the barrier moving (neighbour lists, the driven wall's position
    and the step counters included)."""
    s = Slave(fmus["impact"], "orig")
    run(s, 30, 0.0)
    blob, n = saved(s)
    t, at_save = s.t, s.get(*OUTPUTS)
    first = run(s, 20, 3e-4)
    other = Slave(fmus["impact"], "copy")
    restore(other, blob)
    other.t = t
    assert int(other.fmu.getInteger([other.vr["steps.fine"]])[0]) == n
    # the outputs of the saved communication point come back with it
    assert np.array_equal(other.get(*OUTPUTS), at_save)
    second = run(other, 20, 3e-4)
    assert np.array_equal(first, second)
    steps = [x.fmu.getInteger([x.vr["steps.fine"], x.vr["steps.coarse"]]) for x in (s, other)]
    assert steps[0] == steps[1] and steps[0][0] > n, steps
    s.free()
    other.free()


def refused(s, blob, capsys, message):
    with pytest.raises(FMICallException):
        s.fmu.deSerializeFMUstate(blob)
    out = capsys.readouterr().out
    assert message in out, out


def test_corrupt_garbage_and_foreign_states_are_refused(fmus, capsys):
    s = Slave(fmus["barrier"], "check")
    run(s, 3)
    blob, n = saved(s)
    t = s.t
    expected = run(s, 3, 1e-4)
    glen = blob[12]
    header = [9, 10, 11, 13 + glen // 2, 13 + glen + 3, 13 + glen + 12]
    for i in header + [len(blob) // 3, len(blob) // 2, len(blob) - 5, len(blob) - 1]:
        bad = bytearray(blob)
        bad[i] ^= 0x10
        refused(s, bytes(bad), capsys, "serialised state corrupted: CRC-32")
    refused(s, blob[:-1], capsys, "serialised state corrupted")
    bad = bytearray(blob)
    bad[0] ^= 0x01
    refused(s, bytes(bad), capsys, "not a granmix FMU state")
    refused(s, bytes(range(256)) * 8, capsys, "not a granmix FMU state")
    refused(s, b"", capsys, "not a granmix FMU state")
    impact = Slave(fmus["impact"], "impact")
    refused(s, saved(impact)[0], capsys, "serialised state of another FMU (GUID")
    post = Slave(fmus["post"], "post")
    st = post.fmu.getFMUstate()
    refused(s, post.fmu.serializeFMUstate(st), capsys,
            "serialised state of a structural partner, not of a granular scene")
    # the structure's own state still goes through bytes
    post.fmu.setFMUstate(post.fmu.deSerializeFMUstate(post.fmu.serializeFMUstate(st)))
    # the instance is still usable: the good blob restores and continues bitwise
    restore(s, blob)
    s.t = t
    assert int(s.fmu.getInteger([s.vr["steps.fine"]])[0]) == n
    assert np.array_equal(run(s, 3, 1e-4), expected)
    for x in (s, impact, post):
        x.free()
