"""Issue 44 item 5: the ring of soil around a boulder that `granmix.debris_variants`
reads, upstream and downstream of the boulder's motion, on a synthetic frame whose
answer is known."""

import numpy as np
import pytest
from granmix.debris_variants import VARIANTS, ring_pressures


def ring_frame(centre, radius, width, n=72):
    """Particles on two circles inside the ring and a few outside it; the excess is
    +100 Pa where x > centre, −50 Pa where x < centre, and 1e6 Pa outside the ring."""
    ang = np.linspace(0.0, 2 * np.pi, n, endpoint=False) + 0.01
    rings = [radius + 0.25 * width, radius + 0.75 * width]
    pts = [np.c_[centre[0] + r * np.cos(ang), centre[1] + r * np.sin(ang)] for r in rings]
    inside = np.c_[centre[0] + 0.5 * radius * np.cos(ang), centre[1] + 0.5 * radius * np.sin(ang)]
    far = np.c_[centre[0] + 3 * radius * np.cos(ang), centre[1] + 3 * radius * np.sin(ang)]
    xy = np.vstack(pts + [inside, far])
    p = np.where(xy[:, 0] > centre[0], 100.0, -50.0)
    p[2 * n:] = 1e6
    vel = np.zeros((len(xy), 3))
    vel[:, 0] = 0.3
    points = np.c_[xy, np.zeros(len(xy))]
    return {"points": points, "velocity": vel, "excess_pore_pressure": p}


@pytest.mark.parametrize("direction, up, down", [((1.0, 0.0), -50.0, 100.0),
                                                 ((-1.0, 0.0), 100.0, -50.0)])
def test_issue_44_ring_splits_by_the_boulders_motion(direction, up, down):
    centre = np.array([1.0, 2.0])
    soil = ring_frame(centre, 0.08, 0.06)
    v = 0.5 * np.array(direction)
    r = ring_pressures(soil, centre, v, 0.08, 0.06)
    assert r.up == pytest.approx(up) and r.down == pytest.approx(down)
    # the ring moves at 0.3 m/s along x: the boulder leads it by 0.5 − (±0.3)
    assert r.lead == pytest.approx(0.5 - 0.3 * direction[0])


def test_issue_44_variants_differ_from_the_scene_by_overrides_only():
    assert set(VARIANTS) == {"dry", "saturated", "dilatant", "contractant"}
    assert VARIANTS["saturated"] == []
    phi_c = {k: [s for s in v if "phi_c" in s] for k, v in VARIANTS.items()}
    # the scene's soil has n = 0.4: φ0 = 0.60 above φ_c dilates, below contracts
    assert phi_c["dilatant"] == ["materials.0.dilatancy.phi_c=0.57"]
    assert phi_c["contractant"] == ["materials.0.dilatancy.phi_c=0.63"]
    assert VARIANTS["dry"] == ["materials.0.saturated=false"]
