"""The particle channel and MCAP recordings seen from Python: the example subscriber
(examples/python/subscriber.py, iceoryx2 from PyPI) in its own process, the FMU
publishing at communication points, and `granmix run --record` read with `mcap`."""

import json
import select
import subprocess
import sys
import tomllib
import uuid

import numpy as np
from conftest import ROOT, granmix_bin
from fmpy import simulate_fmu
from mcap.reader import make_reader

SUBSCRIBER = ROOT / "examples" / "python" / "subscriber.py"
sys.path.insert(0, str(SUBSCRIBER.parent))
from subscriber import pattern_words


def unique(tag):
    """A service name no earlier (possibly killed) run has left state under."""
    return f"test-{tag}-{uuid.uuid4().hex[:12]}"


def start(cmd, timeout=60.0):
    """Start `cmd` and wait for its `ready` line."""
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, text=True)
    ready, _, _ = select.select([p.stdout], [], [], timeout)
    line = p.stdout.readline() if ready else ""
    if not line.startswith("ready"):
        p.kill()
        raise AssertionError(f"{cmd} did not get ready: {line!r}")
    return p


def finish(p, timeout=120):
    out, _ = p.communicate(timeout=timeout)
    assert p.returncode == 0, f"{p.args} exited {p.returncode}: {out[-2000:]}"
    return out


def varint(b, i):
    """Protobuf varint at b[i:] → (value, next index)."""
    v = shift = 0
    while True:
        x = b[i]
        i += 1
        v |= (x & 0x7F) << shift
        shift += 7
        if x < 0x80:
            return v, i


def protobuf_fields(b):
    """Top-level fields of a protobuf message: {number: [raw values]}."""
    out, i = {}, 0
    while i < len(b):
        key, i = varint(b, i)
        num, wire = key >> 3, key & 7
        if wire == 0:
            v, i = varint(b, i)
        elif wire == 1:
            v, i = b[i : i + 8], i + 8
        elif wire == 5:
            v, i = b[i : i + 4], i + 4
        elif wire == 2:
            n, i = varint(b, i)
            v, i = b[i : i + n], i + n
        else:
            raise ValueError(f"wire type {wire}")
        out.setdefault(num, []).append(v)
    return out


def test_python_and_rust_subscribers_read_the_same_frames(tmp_path):
    svc = unique("pattern")
    n, frames = 100_000, 100
    pub = start(
        [granmix_bin(), "ipc-pattern", svc, "--particles", str(n), "--frames", str(frames),
         "--subscribers", "2", "--timeout", "60"]
    )
    py_json, rec = tmp_path / "py.json", tmp_path / "watch.mcap"
    py = start(
        [sys.executable, SUBSCRIBER, svc, "--frames", str(frames), "--timeout", "60",
         "--check-pattern", "--json", str(py_json)]
    )
    rs = start(
        [granmix_bin(), "watch", svc, "--frames", str(frames), "--timeout", "60",
         "--record", str(rec)]
    )
    finish(py)
    finish(rs)
    finish(pub)
    got = json.loads(py_json.read_text())
    assert got["mismatches"] == 0
    assert [h["sequence"] for h in got["headers"]] == list(range(frames))
    assert [h["time"] for h in got["headers"]] == [k * 0.5 for k in range(frames)]
    assert all(h["fine_count"] + h["coarse_count"] + h["water_count"] == n for h in got["headers"])
    # what the Rust subscriber received (and recorded) is the same, bit for bit
    with open(rec, "rb") as f:
        msgs = list(make_reader(f).iter_messages(topics=["/particles"]))
    assert len(msgs) == frames
    for k, (_, _, m) in enumerate(msgs):
        data = protobuf_fields(m.data)[6][0]  # PointCloud.data
        assert data == pattern_words(k, n).tobytes()


def test_fmu_publishes_at_every_communication_point(fmus, tmp_path):
    svc = unique("fmu")
    h, stop = 0.002, 0.02
    points = [round(k * h, 12) for k in range(round(stop / h) + 1)]
    out = tmp_path / "frames.json"
    # the subscriber creates the service with a queue deep enough for every frame
    sub = start(
        [sys.executable, SUBSCRIBER, svc, "--frames", str(len(points)), "--timeout", "60",
         "--buffer", "32", "--json", str(out)]
    )
    rec = tmp_path / "fmu.mcap"
    r = simulate_fmu(
        str(fmus["barrier"]),
        stop_time=stop,
        output_interval=h,
        output=["steps.fine"],
        start_values={"ipc.enabled": True, "ipc.service": svc, "record.path": str(rec)},
    )
    finish(sub)
    headers = json.loads(out.read_text())["headers"]
    assert np.allclose([x["time"] for x in headers], points, rtol=0, atol=1e-12)
    assert [x["time"] for x in headers] == list(r["time"])
    assert [x["step"] for x in headers] == list(r["steps.fine"])
    assert all(x["dimension"] == 2 and x["coarse_count"] == 0 for x in headers)
    with open(rec, "rb") as f:
        counts = make_reader(f).get_summary().statistics.channel_message_counts
    # particles, barriers, energy at every point; the wall particles once; the walls'
    # solids at every point (the barrier is driven through its input, so it may move)
    assert sorted(counts.values()) == [1] + [len(points)] * 4


def test_run_record_reads_back_with_python_mcap(tmp_path):
    out, rec = tmp_path / "run", tmp_path / "run.mcap"
    scene = ROOT / "models" / "scenes" / "blocks_impact.toml"
    subprocess.run(
        [granmix_bin(), "run", str(scene), "--out", str(out), "--no-vtk", "--quiet",
         "--set", "simulation.end_time=0.002", "--set", "simulation.output_interval=0.0005",
         "--record", str(rec)],
        check=True,
    )
    summary = json.loads((out / "summary.json").read_text())
    samples = len((out / "series.csv").read_text().splitlines()) - 1
    with open(rec, "rb") as f:
        reader = make_reader(f)
        s = reader.get_summary()
        schemas = {c.topic: s.schemas[c.schema_id] for c in s.channels.values()}
        counts = {c.topic: s.statistics.channel_message_counts[i] for i, c in s.channels.items()}
        assert schemas["/particles"].name == "foxglove.PointCloud"
        assert schemas["/bodies"].name == "foxglove.FrameTransforms"
        for t in ["/particles", "/bodies"]:
            assert schemas[t].encoding == "protobuf"
            # a FileDescriptorSet holding foxglove's own .proto
            assert f"foxglove/{schemas[t].name.split('.')[1]}.proto".encode() in schemas[t].data
        for t in ["/barriers", "/energy"]:
            assert schemas[t].encoding == "jsonschema"
            json.loads(schemas[t].data)
        topics = ["/particles", "/bodies", "/barriers", "/energy"]
        # the walls' particles and solids go once (nothing moves)
        assert counts == {t: samples for t in topics} | {"/walls": 1, "/geometry": 1}
        assert summary["record"]["messages"] == {
            "particles": samples, "bodies": samples, "barriers": samples, "energy": samples,
            "walls": 1, "geometry": 1,
        }
        n = summary["particles"] + summary["particles_coarse"]
        times = []
        for _, ch, m in reader.iter_messages():
            if ch.topic == "/particles":
                pc = protobuf_fields(m.data)
                assert len(pc[6][0]) == 56 * n
                times.append(m.log_time)
            elif ch.topic == "/barriers":
                assert isinstance(json.loads(m.data)["barriers"], list)
        assert times == sorted(times) and len(times) == samples
        scene_text = (out / "scene.toml").read_text()
        atts = list(reader.iter_attachments())
        assert [a.name for a in atts] == ["scene.toml"]
        assert atts[0].data.decode() == scene_text
        tomllib.loads(atts[0].data.decode())
        meta = {m.name: m.metadata for m in reader.iter_metadata()}
        assert meta["granmix"]["scene"] == scene_text
