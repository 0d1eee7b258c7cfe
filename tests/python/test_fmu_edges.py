"""No silent wrong loads (issue 38, points 1–6): a barrier driven out of reach, a
barrier faster than the solver step, communication steps shorter than the solver's Δt,
memory edge cases, the error state through a serialised state, and one rule for
getters in the error state. Each case was first measured wrong on the FMU of
`fmu_barrier_2d.toml`: an OK status with a wrong load, a lost state or an aborted host."""

import subprocess
import sys
import textwrap

import numpy as np
import pytest
from conftest import SCENE, Slave, granmix_bin, pack
from fmpy.fmi1 import FMICallException

H = 1e-3
OUT = ["barrier.force.x", "barrier.force.y", "barrier.moment", "kinetic_energy.fine"]


def outputs(s):
    return np.array(s.get(*OUT))


def refused_step(s, h=H):
    """A doStep that must be refused; the master's time stays."""
    with pytest.raises(FMICallException):
        s.fmu.doStep(currentCommunicationPoint=s.t, communicationStepSize=h)


# --- 1 and 2: a displacement out of reach is refused and changes nothing -------------

@pytest.mark.parametrize("target", [1e308, 10.0, -10.0])
def test_a_barrier_driven_out_of_reach_is_refused_and_changes_nothing(fmus, capsys, target):
    """Before: 1e308 overflowed the drive velocity to inf and every later step was OK
    with force.x = 0; −10 m within 1 ms passed the barrier through the soil (OK, zero
    load). Now the step is refused with the reason, and the instance continues bitwise
    as one that never received the call."""
    s = Slave(fmus["barrier"], "far")
    s.step(H)
    s.set("barrier.displacement.x", target)
    refused_step(s)
    out = capsys.readouterr().out
    assert "fmi2DoStep" in out and "barrier" in out, out
    # back to a reachable command: the refused call left no trace
    s.set("barrier.displacement.x", 0.0)
    s.step(H)
    after = outputs(s)
    fresh = Slave(fmus["barrier"], "never")
    fresh.step(H)
    fresh.set("barrier.displacement.x", 0.0)
    fresh.step(H)
    assert np.array_equal(after, outputs(fresh)), (after, outputs(fresh))
    assert after[0] > 20.0  # the soil still rests on the barrier
    for x in (s, fresh):
        x.free()


@pytest.mark.parametrize("value", [float("inf"), float("-inf"), float("nan")])
def test_non_finite_displacements_are_refused_at_the_set(fmus, value):
    s = Slave(fmus["barrier"], "nonfinite")
    s.step(H)
    with pytest.raises(FMICallException):
        s.set("barrier.displacement.x", value)
    s.step(H)
    fresh = Slave(fmus["barrier"], "never")
    fresh.step(H)
    fresh.step(H)
    assert np.array_equal(outputs(s), outputs(fresh))
    for x in (s, fresh):
        x.free()


def test_a_fast_barrier_sub_steps_instead_of_tunnelling(tmp_path):
    """The prescribed motion of a barrier enters the solver's Δt: no wall moves more
    than CFL·h (h = 1.3 dp = 13 mm, CFL 0.4) per solver step. With the guard's speed
    bound raised, the barrier retreats 0.3 m within one 1 ms step (300 m/s): at least
    0.3 / (0.4 · 0.013) = 58 solver steps. Before, the step took the soil's Δt
    (≈ 1.1e-4 s, 9 steps of 3.3 cm each), and a barrier moved back as fast passed
    through the soil that had followed it."""
    fmu = pack(SCENE, tmp_path / "fast.fmu", "simulation.max_speed=2000.0")
    s = Slave(fmu, "fast")

    def steps() -> int:
        return int(s.fmu.getInteger([s.vr["steps.fine"]])[0])

    s.step(H)
    rest = s.get("barrier.force.x")
    n0 = steps()
    s.set("barrier.displacement.x", 0.3)
    s.step(H)
    assert steps() - n0 >= 58, steps() - n0
    assert s.get("barrier.force.x") >= 0.0
    s.free()
    assert rest > 20.0


# --- 3: communication steps shorter than the solver's Δt ----------------------------

@pytest.mark.parametrize("speed", [0.1, 1.0, 5.0])
@pytest.mark.parametrize("h", [1e-6, 5e-6, 2e-5, 1e-3])
def test_no_pull_on_a_retreating_barrier_at_any_step(fmus, h, speed):
    """The barrier pulled away from the resting layer at `speed` through its
    displacement input, in communication steps of `h` (the solver's Δt is about
    1.1e-4 s). Before, h ≤ 2e-5 s at 0.1 m/s read a pull of down to −2.21 N/m within
    20 µs (the layer at rest carries 49.7 N/m). The load is the impulse over the step
    divided by h; a cohesionless soil cannot pull."""
    s = Slave(fmus["barrier"], f"pull_{h}_{speed}")
    f0 = s.get("barrier.force.x")
    n = max(10, round(3e-4 / h))
    loads = []
    for k in range(1, n + 1):
        s.set("barrier.displacement.x", speed * k * h)
        s.step(h)
        loads.append(s.get("barrier.force.x"))
    s.free()
    assert min(loads) >= -1e-9 * f0, f"pulling loads {min(loads)} N/m (at rest {f0:.3f})"


@pytest.fixture(scope="module")
def settled_pulls(fmus):
    """The grid of issue 74: the layer settled 50, 100 and 200 ms (1 ms steps), then
    pulled away at 0.1, 1 and 5 m/s in steps of 1, 10 and 100 us, each for at least 10
    steps or 0.3 ms, every branch from the settled state (fmi2GetFMUstate). The
    lowest load of each branch, keyed (settle, speed, h), and the load at rest."""
    s = Slave(fmus["barrier"], "settled_pulls")
    out, rest = {}, {}
    for settle in (0.05, 0.1, 0.2):
        while s.t < settle - 1e-9:
            s.step(1e-3)
        rest[settle] = s.get("barrier.force.x")
        state = s.fmu.getFMUstate()
        t0 = s.t
        for speed in (0.1, 1.0, 5.0):
            for h in (1e-6, 1e-5, 1e-4):
                s.fmu.setFMUstate(state)
                s.t = t0
                low = np.inf
                for k in range(1, max(10, round(3e-4 / h)) + 1):
                    s.set("barrier.displacement.x", speed * k * h)
                    s.step(h)
                    low = min(low, s.get("barrier.force.x"))
                out[(settle, speed, h)] = low
        s.fmu.setFMUstate(state)
        s.t = t0
        s.set("barrier.displacement.x", 0.0)
        s.fmu.freeFMUstate(state)
    s.free()
    return out, rest


def test_no_pull_on_a_receding_barrier_after_settling(settled_pulls):
    """No step of the grid reads force.x < 0. Before, 1 m/s in 1 us steps read
    -2.0e-3 to -3.3e-3 N/m at step 9 (a closed pair's shear across the face, and the
    barrier's Eq. (33) normal leaning up at its toe; docs/method.md, Walls)."""
    lows, rest = settled_pulls
    assert all(f > 10.0 for f in rest.values()), rest
    pulls = {k: f for k, f in lows.items() if f < 0.0}
    assert not pulls, f"pulling loads (settle s, speed m/s, step s): N/m {pulls}"


# --- 4: memory edge cases -----------------------------------------------------------

def test_check_refuses_a_subnormal_spacing():
    r = subprocess.run([str(granmix_bin()), "check", str(SCENE), "--set",
                        "simulation.dp=1e-160"], check=False, capture_output=True, text=True,
                       timeout=60)
    text = r.stdout + r.stderr
    assert r.returncode != 0, text
    assert "simulation.dp" in text and "NaN" not in text, text


def test_an_allocation_beyond_the_machine_is_an_error_not_an_abort(fmus):
    """A budget of 1e300 B lets dp = 1e-7 m past the estimate; before, the host
    process aborted ("memory allocation of 4294967296 bytes failed"). Run in a child
    process so that an abort fails this test instead of killing the suite."""
    code = textwrap.dedent(f"""
        import sys
        sys.path.insert(0, {str(SCENE.parents[2] / 'tests' / 'python')!r})
        from test_memory_budget import start
        from fmpy.fmi1 import FMICallException
        fmu, vr, _ = start({str(fmus['barrier'])!r}, 'huge', particle_spacing=1e-7,
                           memory_budget=1e300)
        try:
            fmu.exitInitializationMode()
        except FMICallException:
            print('REFUSED')
        fmu.freeInstance()
        print('HOST ALIVE')
    """)
    r = subprocess.run([sys.executable, "-c", code], check=False, capture_output=True,
                       text=True, timeout=120)
    text = r.stdout + r.stderr
    assert r.returncode == 0, text
    assert "REFUSED" in text and "HOST ALIVE" in text, text
    assert "memory" in text, text


# --- 5: the error state survives serialisation --------------------------------------

def blown_up(tmp_path, capsys):
    # the barrier 9 cm into the soil within one step: the guard stops the step (an
    # initial speed above max_speed is refused at packing since issue 74)
    fmu = pack(SCENE, tmp_path / "blowup.fmu")
    s = Slave(fmu, "blowup")
    s.set("barrier.displacement.x", -0.09)
    refused_step(s)
    assert "numerical blow-up" in capsys.readouterr().out
    return fmu, s


def test_a_serialised_blown_up_state_stays_in_the_error_state(tmp_path, capsys):
    """Before, a state taken after a blow-up came back in step mode from its bytes, and
    fmi2DoStep ran on from the blown-up particles."""
    fmu, s = blown_up(tmp_path, capsys)
    state = s.fmu.getFMUstate()
    blob = s.fmu.serializeFMUstate(state)
    other = Slave(fmu, "other")
    restored = other.fmu.deSerializeFMUstate(blob)
    other.fmu.setFMUstate(restored)
    with pytest.raises(FMICallException):
        other.fmu.doStep(currentCommunicationPoint=0.0, communicationStepSize=H)
    out = capsys.readouterr().out
    assert "error state" in out, out
    # the in-memory state too
    s.fmu.setFMUstate(state)
    refused_step(s)
    for x, st in ((s, state), (other, restored)):
        x.fmu.freeFMUstate(st)
        x.fmu.reset()
        x.fmu.freeInstance()


def test_a_serialised_terminated_state_stays_terminated(fmus):
    s = Slave(fmus["barrier"], "done")
    s.step(H)
    s.fmu.terminate()
    state = s.fmu.getFMUstate()
    blob = s.fmu.serializeFMUstate(state)
    other = Slave(fmus["barrier"], "other")
    restored = other.fmu.deSerializeFMUstate(blob)
    other.fmu.setFMUstate(restored)
    with pytest.raises(FMICallException):
        other.fmu.doStep(currentCommunicationPoint=H, communicationStepSize=H)
    # a terminated instance still gives its final outputs
    assert other.get("barrier.force.x") == s.get("barrier.force.x")
    for x, st in ((s, state), (other, restored)):
        x.fmu.freeFMUstate(st)
        x.fmu.freeInstance()


# --- 6: one rule for getters in the error state -------------------------------------

def test_getters_in_the_error_state_are_refused_with_the_cause(tmp_path, capsys):
    """docs/fmu.md: in the error state every value getter returns fmi2Error and names
    why the instance is there. Before, after a blow-up fmi2GetReal returned OK with
    force 0.0, while after a memory refusal it returned fmi2Error."""
    _, s = blown_up(tmp_path, capsys)
    for get in (lambda: s.get("barrier.force.x"),
                lambda: s.fmu.getInteger([s.vr["steps.fine"]]),
                lambda: s.get("particle_spacing")):
        with pytest.raises(FMICallException):
            get()
        out = capsys.readouterr().out
        assert "error state" in out and "numerical blow-up" in out, out
    s.fmu.reset()
    s.fmu.freeInstance()


def test_a_refused_spacing_can_be_replaced_without_reset(fmus, capsys):
    """docs/fmu.md: an instance whose parameters are refused at initialisation (the
    memory budget) stays in initialisation mode; a coarser spacing is then accepted."""
    from test_memory_budget import start
    fmu, vr, start0 = start(fmus["barrier"], "coarser", particle_spacing=1e-7)
    with pytest.raises(FMICallException):
        fmu.exitInitializationMode()
    assert "over the memory budget" in capsys.readouterr().out
    fmu.setReal([vr["particle_spacing"]], [start0["particle_spacing"]])
    fmu.exitInitializationMode()
    fmu.doStep(currentCommunicationPoint=0.0, communicationStepSize=H)
    assert fmu.getReal([vr["barrier.force.x"]])[0] > 20.0
    fmu.terminate()
    fmu.freeInstance()
