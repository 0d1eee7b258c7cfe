#!/usr/bin/env python3
"""Subscribe to a granmix particle service and read every frame into numpy.

    python examples/python/subscriber.py run1            # granmix/run1/particles
    python examples/python/subscriber.py granmix/run1/particles --frames 10

Needs `pip install iceoryx2==0.10.0 numpy`. Run it in its own process: a subscriber
in the same process as a granmix FMU receives nothing.

The layouts below mirror `granmix_ipc::payload` (docs/ipc.md): a 56-byte header and
56-byte records, fine particles first, then coarse-grain particles, then water.
"""

import argparse
import ctypes
import json
import sys
import time

import iceoryx2 as iox2
import numpy as np

SCHEMA_VERSION = 4


class ParticleRecord(ctypes.Structure):
    """One particle, as `granmix_ipc::ParticleRecord`."""

    _fields_ = [
        ("position", ctypes.c_float * 3),
        ("velocity", ctypes.c_float * 3),
        ("pressure", ctypes.c_float),
        ("plastic_strain", ctypes.c_float),
        ("id", ctypes.c_uint32),
        ("group", ctypes.c_uint32),
        ("family", ctypes.c_uint32),
        ("pore_pressure", ctypes.c_float),
        ("excess_pore_pressure", ctypes.c_float),
        ("porosity", ctypes.c_float),
    ]

    @staticmethod
    def type_name() -> str:
        return "granmix::ParticleRecord"


class FrameHeader(ctypes.Structure):
    """Per-frame header, as `granmix_ipc::FrameHeader`."""

    _fields_ = [
        ("time", ctypes.c_double),
        ("step", ctypes.c_uint64),
        ("sequence", ctypes.c_uint64),
        ("sent_unix_ns", ctypes.c_uint64),
        ("fine_count", ctypes.c_uint32),
        ("coarse_count", ctypes.c_uint32),
        ("dimension", ctypes.c_uint32),
        ("schema_version", ctypes.c_uint32),
        ("water_count", ctypes.c_uint32),
        ("reserved", ctypes.c_uint32),
    ]

    @staticmethod
    def type_name() -> str:
        return "granmix::FrameHeader"


#: numpy view of a record; `group` is the material (fine) or body (coarse) index,
#: `family` 0 (fine), 1 (coarse) or 2 (water).
RECORD_DTYPE = np.dtype(
    [
        ("position", "<f4", (3,)),
        ("velocity", "<f4", (3,)),
        ("pressure", "<f4"),
        ("plastic_strain", "<f4"),
        ("id", "<u4"),
        ("group", "<u4"),
        ("family", "<u4"),
        ("pore_pressure", "<f4"),
        ("excess_pore_pressure", "<f4"),
        ("porosity", "<f4"),
    ]
)
assert RECORD_DTYPE.itemsize == ctypes.sizeof(ParticleRecord) == 56
assert ctypes.sizeof(FrameHeader) == 56
#: 32-bit words in a record
WORDS = RECORD_DTYPE.itemsize // 4


def service_name(spec: str) -> str:
    """`run1` → `granmix/run1/particles`; names with a `/` are used as given."""
    return spec if "/" in spec else f"granmix/{spec}/particles"


class Subscriber:
    """A subscriber on one particle service; keep it alive while receiving."""

    def __init__(self, spec: str, buffer: int = 0):
        """Open (or create) the service. With `buffer` > 0 the subscriber queues that
        many frames before the oldest is dropped; this needs the subscriber to create
        the service (start it before the publisher)."""
        iox2.set_log_level_from_env_or(iox2.LogLevel.Error)
        self.name = service_name(spec)
        self.node = iox2.NodeBuilder.new().create(iox2.ServiceType.Ipc)
        builder = (
            self.node.service_builder(iox2.ServiceName.new(self.name))
            .publish_subscribe(iox2.Slice[ParticleRecord])
            .user_header(FrameHeader)
        )
        if buffer > 0:
            builder = builder.subscriber_max_buffer_size(buffer)
        self.service = builder.open_or_create()
        sub = self.service.subscriber_builder()
        if buffer > 0:
            sub = sub.buffer_size(buffer)
        self.subscriber = sub.create()

    def receive(self):
        """The next frame as (header dict, structured numpy array), or None.

        The array is a copy, so the shared-memory sample is released at once. The
        element count comes from the header: the Python `Slice.len()` of iceoryx2 0.10
        counts bytes, not records.
        """
        sample = self.subscriber.receive()
        if sample is None:
            return None
        h = sample.user_header().contents
        header = {name: getattr(h, name) for name, _ in FrameHeader._fields_}
        if h.schema_version != SCHEMA_VERSION:
            raise ValueError(
                f"{self.name}: schema version {h.schema_version}, expected {SCHEMA_VERSION}"
            )
        n = h.fine_count + h.coarse_count + h.water_count
        raw = (ctypes.c_uint8 * (n * RECORD_DTYPE.itemsize)).from_address(
            sample.payload().as_ptr()
        )
        records = np.frombuffer(raw, dtype=RECORD_DTYPE, count=n).copy()
        sample.delete()
        return header, records

    def wait(self, timeout: float):
        """Block (polling) until a frame arrives; None after `timeout` seconds."""
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            frame = self.receive()
            if frame is not None:
                return frame
            time.sleep(0.0005)
        return None


def pattern_words(k: int, n: int) -> np.ndarray:
    """The test pattern of `granmix ipc-pattern` (granmix_ipc::pattern), as (n, WORDS) u32."""
    i = np.arange(n, dtype=np.uint32)
    out = np.empty((n, WORDS), dtype=np.uint32)
    for w in range(WORDS):
        h = i * np.uint32(2654435761) + np.uint32((k * 40503 + w * 97) % 2**32)
        float_word = not 8 <= w < 11
        out[:, w] = (h & np.uint32(0x807FFFFF)) | np.uint32(0x3F000000) if float_word else h
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("service", help="instance name or full service name")
    ap.add_argument("--frames", type=int, default=0, help="stop after N frames (0: never)")
    ap.add_argument("--timeout", type=float, default=30.0, help="give up after S s without a frame")
    ap.add_argument("--json", help="write the received headers (and checks) to this file")
    ap.add_argument(
        "--buffer", type=int, default=0, help="queue N frames (start before the publisher)"
    )
    ap.add_argument(
        "--check-pattern", action="store_true", help="compare frames with the test pattern"
    )
    a = ap.parse_args()
    sub = Subscriber(a.service, a.buffer)
    print(f"ready: subscribed to {sub.name}", flush=True)
    headers, mismatches, received = [], 0, 0
    while a.frames == 0 or received < a.frames:
        frame = sub.wait(a.timeout)
        if frame is None:
            print(f"no frame for {a.timeout} s", flush=True)
            break
        header, records = frame
        received += 1
        headers.append(header)
        if a.check_pattern:
            got = records.view(np.uint32).reshape(len(records), WORDS)
            if not np.array_equal(got, pattern_words(header["sequence"], len(records))):
                mismatches += 1
        pos = records["position"]
        print(
            f"t = {header['time']:.6f} s  step {header['step']}  {len(records)} particles"
            f"  mean z {pos[:, 2].mean() if len(pos) else 0.0:.4f} m",
            flush=True,
        )
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"headers": headers, "mismatches": mismatches}, f)
    return 0 if received and not mismatches else 1


if __name__ == "__main__":
    sys.exit(main())
