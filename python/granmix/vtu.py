"""Read the ``.vtu`` point clouds that granmix writes (raw appended binary, UInt64
headers) into numpy arrays, without VTK installed."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

_TYPES = {
    "Float32": np.float32,
    "Float64": np.float64,
    "UInt8": np.uint8,
    "UInt16": np.uint16,
    "UInt32": np.uint32,
    "Int64": np.int64,
}
_ARRAY = re.compile(rb'<DataArray type="(\w+)"(?: Name="([^"]+)")?(?: NumberOfComponents="(\d+)")? format="appended" offset="(\d+)"/>')


def read_vtu(path: str | Path) -> dict[str, np.ndarray]:
    """The point arrays of a granmix ``.vtu`` file by name, with ``points`` (n × 3)."""
    raw = Path(path).read_bytes()
    start = raw.index(b'<AppendedData encoding="raw">')
    data = raw[raw.index(b"_", start) + 1 :]
    out: dict[str, np.ndarray] = {}
    for kind, name, comps, offset in _ARRAY.findall(raw[:start]):
        off = int(offset)
        size = int(np.frombuffer(data[off : off + 8], dtype="<u8")[0])
        arr = np.frombuffer(data[off + 8 : off + 8 + size], dtype=_TYPES[kind.decode()])
        n = int(comps) if comps else 1
        key = name.decode() if name else "points"
        out[key] = arr.reshape(-1, n) if n > 1 else arr
    return out
