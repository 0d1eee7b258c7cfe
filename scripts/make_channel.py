"""Write models/terrain/channel.asc: a U-shaped channel on a 38° slope that flattens
into a run-out pad (ESRI ASCII grid, 0.25 m cells). Used by debris_barrier.toml.

x runs downslope (0 … 30 m), y across (−4 … 4 m). Bed elevation: 38° slope for
x < 14 m, a circular transition, flat beyond x = 20 m. Channel: a parabolic U of
half-width 2 m and depth 1 m, with banks rising beyond it."""
import math
import sys

cell = 0.25
xs = [i * cell for i in range(int(30 / cell) + 1)]
ys = [-4 + j * cell for j in range(int(8 / cell) + 1)]


def bed(x):
    s = math.tan(math.radians(38))
    if x < 14:
        return (20 - x) * s
    if x < 20:
        # quadratic easing from slope s to 0 over 6 m
        t = x - 14
        return 6 * s - s * t + s * t * t / 12
    return 6 * s - s * 6 + s * 36 / 12


def ground(x, y):
    a = abs(y)
    lip = 1.0 * min(a / 2.0, 1.0) ** 2  # parabolic U, 1 m deep at |y| = 2 m
    bank = max(0.0, a - 2.0) * 0.5
    return bed(x) + lip + bank


out = sys.argv[1] if len(sys.argv) > 1 else "models/terrain/channel.asc"
with open(out, "w") as f:
    f.write(f"ncols {len(xs)}\nnrows {len(ys)}\nxllcenter 0\nyllcenter -4\n")
    f.write(f"cellsize {cell}\nNODATA_value -9999\n")
    f.writelines(" ".join(f"{ground(x, y):.4f}" for x in xs) + "\n" for y in reversed(ys))
print("wrote", out)
