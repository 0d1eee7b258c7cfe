"""Read granmix .vtu snapshots (raw appended binary, UInt64 headers) into numpy-free lists."""
import re
import struct
import sys


def read_vtu(path):
    with open(path, "rb") as f:
        data = f.read()
    head, _, rest = data.partition(b'<AppendedData encoding="raw">')
    blob = rest[rest.index(b"_") + 1:]
    arrays = {}
    fmt = {"Float32": "f", "Int64": "q", "UInt8": "B", "UInt16": "H", "UInt32": "I"}
    for m in re.finditer(rb'<DataArray ([^>]*)/>', head):
        attrs = dict(re.findall(rb'(\w+)="([^"]*)"', m.group(1)))
        kind = attrs[b"type"].decode()
        name = attrs.get(b"Name", b"points").decode()
        comps = int(attrs.get(b"NumberOfComponents", b"1"))
        off = int(attrs[b"offset"])
        (nbytes,) = struct.unpack_from("<Q", blob, off)
        n = nbytes // struct.calcsize(fmt[kind])
        vals = struct.unpack_from(f"<{n}{fmt[kind]}", blob, off + 8)
        arrays[name] = [vals[i:i + comps] for i in range(0, n, comps)] if comps > 1 else list(vals)
    return arrays


if __name__ == "__main__":
    a = read_vtu(sys.argv[1])
    pts = a["points"]
    xs = [p[0] for p in pts]
    print(len(pts), "points; x range", min(xs), max(xs))
