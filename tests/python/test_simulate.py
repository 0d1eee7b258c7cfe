"""`fmpy.simulate_fmu` runs the granular FMU of the bundled small barrier scene."""

import numpy as np
from fmpy import simulate_fmu


def test_simulate_returns_the_barrier_force_series(fmus):
    r = simulate_fmu(
        str(fmus["barrier"]),
        stop_time=0.1,
        output_interval=0.002,
        output=["barrier.force.x", "barrier.peak_force", "steps.fine"],
    )
    assert len(r) == 51
    assert np.allclose(np.diff(r["time"]), 0.002)
    f = r["barrier.force.x"][1:]
    # A 0.1 m layer (ρ = 2040 kg/m³, φ = 30°) at rest: ½ K ρ g H² with K between the
    # active 1/3 and the at-rest 0.5 is 34–51 N/m; the start is not yet at rest.
    assert np.all(np.isfinite(f))
    assert 20.0 < f[-10:].mean() < 80.0
    # the peak of a step is at least its average resultant
    assert np.all(r["barrier.peak_force"][1:] >= np.abs(f) - 1e-9)
    assert np.all(np.diff(r["steps.fine"]) > 0)


def test_parameters_reach_the_solver(fmus):
    coarse = simulate_fmu(
        str(fmus["barrier"]),
        stop_time=0.01,
        output=["steps.fine"],
        start_values={"particle_spacing": 0.02, "multi_rate": False},
    )
    fine = simulate_fmu(str(fmus["barrier"]), stop_time=0.01, output=["steps.fine"])
    # Δt ∝ dp: twice the spacing takes about half the steps
    assert coarse["steps.fine"][-1] < 0.7 * fine["steps.fine"][-1]
