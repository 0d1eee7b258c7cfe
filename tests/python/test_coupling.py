"""Master loops coupling granmix (barrier driven by input displacement) with the
structural post FMU (VALIDATION.md §10): static settlement at F/k and impulse = momentum."""

import numpy as np
from conftest import Slave

H = 1e-3


def couple(granular, post, steps, h=H):
    """Gauss–Seidel loop: the post takes the force of granmix's last step, then granmix
    moves its barrier to the post's new displacement. Returns per-step forces passed on
    and the post displacement."""
    forces, xs = [], []
    f = granular.get("barrier.force.x")
    for _ in range(steps):
        post.set("force", f)
        post.step(h)
        forces.append(f)
        x = post.get("displacement")
        xs.append(x)
        granular.set("barrier.displacement.x", x)
        granular.step(h)
        f = granular.get("barrier.force.x")
    return np.array(forces), np.array(xs)


def test_static_layer_settles_at_f_over_k(fmus):
    g = Slave(fmus["barrier"], "granular")
    p = Slave(fmus["post"], "post")
    k = p.get("k")
    forces, xs = couple(g, p, 400)
    f_end = forces[-50:].mean()
    assert f_end > 20.0, f"earth load {f_end} N/m"
    x_end = xs[-1]
    assert abs(x_end - f_end / k) <= 0.02 * f_end / k, f"x = {x_end}, F/k = {f_end / k}"
    # the barrier really moved with the post
    assert x_end > 0.5e-3
    g.free()
    p.free()


def test_impact_impulse_equals_structure_momentum(fmus):
    g = Slave(fmus["impact"], "granular")
    m = 200.0
    p = Slave(fmus["post"], "post", start={"m": m, "k": 0.0, "c": 0.0})
    forces, _ = couple(g, p, 60)
    passed = float(np.sum(forces * H))  # impulse granmix passed on
    received = p.get("impulse")
    momentum = m * p.get("velocity")
    assert passed > 10.0, f"impulse {passed} N·s/m: the layer must hit the barrier"
    assert abs(received - passed) <= 1e-9 * abs(passed)
    assert abs(momentum - passed) <= 1e-9 * abs(passed)
    g.free()
    p.free()
