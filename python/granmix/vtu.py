"""Read the ``.vtu`` point clouds that ``granmix run`` writes (raw appended binary,
UInt64 block headers; harness/src/vtk.rs) into numpy arrays, without VTK installed.

``python -m granmix.vtu FILE.vtu`` prints the point count, the x range and the arrays.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import numpy as np

_TYPES: dict[str, type[np.generic]] = {
    "Float32": np.float32,
    "Float64": np.float64,
    "UInt8": np.uint8,
    "UInt16": np.uint16,
    "UInt32": np.uint32,
    "UInt64": np.uint64,
    "Int32": np.int32,
    "Int64": np.int64,
}
_ARRAY = re.compile(rb"<DataArray ([^>]*)/>")
_ATTRIBUTE = re.compile(rb'(\w+)="([^"]*)"')


def read_vtu(path: str | Path) -> dict[str, np.ndarray]:
    """The arrays of a granmix ``.vtu`` file by name: ``points`` (n × 3), the point data
    (n, or n × components) and the cells' ``connectivity``, ``offsets`` and ``types``."""
    raw = Path(path).read_bytes()
    start = raw.index(b'<AppendedData encoding="raw">')
    # the data begin after the underscore that opens the appended section
    data = raw[raw.index(b"_", start) + 1 :]
    out: dict[str, np.ndarray] = {}
    for m in _ARRAY.finditer(raw[:start]):
        attrs = {k.decode(): v.decode() for k, v in _ATTRIBUTE.findall(m.group(1))}
        off = int(attrs["offset"])
        size = int(np.frombuffer(data[off : off + 8], dtype="<u8")[0])
        dtype = np.dtype(_TYPES[attrs["type"]]).newbyteorder("<")
        arr = np.frombuffer(data[off + 8 : off + 8 + size], dtype=dtype)
        comps = int(attrs.get("NumberOfComponents", "1"))
        out[attrs.get("Name", "points")] = arr.reshape(-1, comps) if comps > 1 else arr
    return out


def main(argv: list[str] | None = None) -> int:
    """Print what a ``.vtu`` file holds: its point count, x range and arrays."""
    args = sys.argv[1:] if argv is None else argv
    if len(args) != 1:
        print("usage: python -m granmix.vtu FILE.vtu", file=sys.stderr)
        return 2
    arrays = read_vtu(args[0])
    pts = arrays["points"]
    span = f"; x range {pts[:, 0].min()} {pts[:, 0].max()}" if len(pts) else ""
    print(f"{len(pts)} points{span}")
    for name, a in arrays.items():
        print(f"  {name}: {a.dtype} {a.shape}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
