"""Issue 39: a `granmix run --record` file reads back with the `mcap` package, every
protobuf message decodes with the Foxglove schema stored in the file itself
(mcap-protobuf-support), and every topic of docs/ipc.md's table is there with the
fields the table gives. `/geometry` draws each wall object as a solid of the scene's
own numbers, and a barrier moving at a prescribed speed moves in it by v Δt from one
frame to the next.
"""

import itertools
import json
import re
import subprocess
import tomllib

import numpy as np
import pytest
from conftest import ROOT, granmix_bin
from mcap.reader import make_reader
from mcap_protobuf.decoder import DecoderFactory

SCENES = ROOT / "models" / "scenes"
# the slab of a 2D solid along z, in particle spacings (granmix_core::solids::SLAB_SPACINGS)
SLAB = 4.0

CLOUD = [("x", "FLOAT32"), ("y", "FLOAT32"), ("z", "FLOAT32"), ("vx", "FLOAT32"),
         ("vy", "FLOAT32"), ("vz", "FLOAT32"), ("pressure", "FLOAT32"),
         ("plastic_strain", "FLOAT32"), ("id", "UINT32"), ("group", "UINT32"),
         ("family", "UINT32"), ("pore_pressure", "FLOAT32"),
         ("excess_pore_pressure", "FLOAT32"), ("porosity", "FLOAT32")]
WALLS = [("x", "FLOAT32"), ("y", "FLOAT32"), ("z", "FLOAT32"), ("object", "UINT32")]
BARRIER = {"name", "force", "moment", "peak_force", "force_water", "force_grains", "panels"}
PANEL = {"index", "force", "force_water", "force_grains"}
ENERGY = {"time", "steps", "steps_coarse", "kinetic_fine", "potential_fine", "kinetic_coarse",
          "potential_coarse", "strain", "contact", "kinetic_water", "potential_water",
          "kinetic_total"}


def documented_topics():
    """(topic, schema) of each row of docs/ipc.md's MCAP table."""
    text = (ROOT / "docs" / "ipc.md").read_text()
    return dict(re.findall(r"^\| `(/\w+)` \| `([\w.]+)` \|", text, re.MULTILINE))


class JsonDecoder:
    """Decodes the JSON topics (`/barriers`, `/energy`)."""

    def decoder_for(self, encoding, schema):
        return json.loads if encoding == "json" else None


def record(scene, out, *sets):
    """Run `scene` with a recording; return the decoded messages by topic and the scene."""
    rec = out / "run.mcap"
    args = [str(granmix_bin()), "run", str(SCENES / scene), "--quiet", "--no-plots",
            "--no-vtk", "--out", str(out), "--record", str(rec)]
    for s in sets:
        args += ["--set", s]
    subprocess.run(args, check=True, capture_output=True)
    topics, schemas = {}, {}
    with open(rec, "rb") as f:
        r = make_reader(f, decoder_factories=[DecoderFactory(), JsonDecoder()])
        for ch in r.get_summary().channels.values():
            schemas[ch.topic] = r.get_summary().schemas[ch.schema_id].name
        for _, ch, msg, dec in r.iter_decoded_messages():
            topics.setdefault(ch.topic, []).append((msg.log_time * 1e-9, dec))
    return topics, schemas, tomllib.loads((out / "scene.toml").read_text())


def fields(cloud):
    """(name, numeric type name) of a PointCloud's fields."""
    enum = cloud.fields[0].DESCRIPTOR.fields_by_name["type"].enum_type
    return [(f.name, enum.values_by_number[f.type].name) for f in cloud.fields]


def wall_objects(scene):
    """Names of the wall objects in scene order: walls, barriers, closed container faces."""
    dim = scene["simulation"]["dimension"]
    names = [w["name"] for w in scene.get("walls", []) + scene.get("barriers", [])]
    vertical = "xyz"[dim - 1]
    face = {"-x": "left", "+x": "right", "-y": "front", "+y": "back",
            f"-{vertical}": "bottom", f"+{vertical}": "top"}
    for c in scene.get("containers", []):
        open_ = c.get("open", [f"+{vertical}"])
        names += [f"{c['name']}.{face[s + a]}" for a in "xyz"[:dim] for s in "-+"
                  if s + a not in open_]
    return names


def check_topics(topics, schemas, scene):
    """Every documented topic with its schema, and the fields the table gives."""
    doc = documented_topics()
    # the channels: the table's, `/water` only with water
    assert schemas == {t: s for t, s in doc.items() if t != "/water" or "water" in scene}
    has = {"/water": "water" in scene, "/bodies": bool(scene.get("bodies"))}
    for topic in doc:
        assert bool(topics.get(topic)) == has.get(topic, True), (topic, sorted(topics))
    for topic in ("/particles", "/water"):
        for _, m in topics.get(topic, []):
            assert fields(m) == CLOUD and m.point_stride == 56 and m.frame_id == "world"
    (_, walls), = topics["/walls"]
    assert fields(walls) == WALLS and walls.point_stride == 16
    for _, m in topics.get("/bodies", []):
        names = [b["name"] for b in scene["bodies"]]
        assert [t.child_frame_id for t in m.transforms] == names
        assert {t.parent_frame_id for t in m.transforms} == {"world"}
    for _, m in topics["/barriers"]:
        for b in m["barriers"]:
            assert set(b) == BARRIER, b
            assert all(set(p) == PANEL for p in b["panels"]), b
    for _, m in topics["/energy"]:
        assert set(m) == ENERGY, m


def entities(topics):
    """The first `/geometry` message's entities by id, and the walls' object count."""
    (_, first), *_ = topics["/geometry"]
    (_, walls), = topics["/walls"]
    n = walls.point_stride
    objects = np.frombuffer(walls.data, dtype="<u4").reshape(-1, n // 4)[:, 3]
    return {e.id: e for e in first.entities}, len(set(objects.tolist()))


def check_box(entity, box, dp):
    """A 2D box wall as one cube: centre and size from the scene's min and max."""
    (cube,) = entity.cubes
    lo, hi = np.array(box["min"]), np.array(box["max"])
    p, s = cube.pose.position, cube.size
    assert np.allclose([p.x, p.y, p.z], [*(lo + hi) / 2, 0.0], rtol=0, atol=1e-12)
    assert np.allclose([s.x, s.y, s.z], [*(hi - lo), SLAB * dp], rtol=0, atol=1e-12)


def check_porosity(topics, scene):
    """Issue 44: each fine record carries its porosity, n = 1 - (1 - n0) rho/rho0, which
    in the first frames (the soil at rest, compressed by its own weight by well under
    1 %) stays within 0.01 of its material's n0; coarse and water records carry 0."""
    n0 = [m.get("porosity", 0.0) for m in scene["materials"]]
    for topic in ("/particles", "/water"):
        for _, m in topics.get(topic, []):
            rec = np.frombuffer(m.data, dtype="<f4").reshape(-1, m.point_stride // 4)
            fam, group, n = rec[:, 10].view("<u4"), rec[:, 9].view("<u4"), rec[:, 13]
            fine = fam == 0
            assert np.all(n[~fine] == 0.0)
            want = np.array(n0)[group[fine]]
            assert fine.any() == (topic == "/particles")
            if fine.any():
                assert np.any(want > 0)
                assert np.all(np.abs(n[fine] - want) < 0.01), np.abs(n[fine] - want).max()


@pytest.mark.parametrize(
    "scene, sets",
    [
        ("dam_break_2d.toml", ["simulation.end_time=0.004"]),
        ("debris_flow_saturated.toml", ["simulation.end_time=0.02"]),
    ],
)
def test_issue_39_recording_decodes_every_documented_topic(tmp_path, scene, sets):
    topics, schemas, sc = record(scene, tmp_path, *sets, "simulation.output_interval=0.002")
    check_topics(topics, schemas, sc)
    ents, objects = entities(topics)
    names = wall_objects(sc)
    # one entity a wall object, named after it, in the particles' frame
    assert sorted(ents) == sorted(names) and len(names) == objects
    for k, name in enumerate(names):
        meta = {m.key: m.value for m in ents[name].metadata}
        assert meta["object"] == str(k) and meta["moving"] == "false", meta
        assert ents[name].frame_id == "world"
    # nothing moves: the geometry goes once
    assert len(topics["/geometry"]) == 1
    dp = sc["simulation"]["dp"]
    if scene.startswith("dam_break"):
        # the container's bottom face: the tank's width plus both side walls, 4 dp deep
        tank = sc["containers"][0]
        t = sc.get("numerics", {}).get("wall_layers", 4) * dp
        lo, hi = tank["min"], tank["max"]
        box = {"min": [lo[0] - t, lo[1] - t], "max": [hi[0] + t, lo[1]]}
        check_box(ents["tank.bottom"], box, dp)
        return
    check_porosity(topics, sc)
    walls = {w["name"]: w["shape"] for w in sc["walls"] + sc["barriers"]}
    check_box(ents["runout"], walls["runout"], dp)
    check_box(ents["barrier"], walls["barrier"], dp)
    # the slope polygon extruded: its vertices at both faces, 2 caps of 2 + 4 sides x 2
    (tri,) = ents["slope"].triangles
    pts = {(round(p.x, 9), round(p.y, 9), round(p.z, 9)) for p in tri.points}
    want = {(x, y, round(z, 9)) for x, y in walls["slope"]["vertices"]
            for z in (-SLAB * dp / 2, SLAB * dp / 2)}
    assert pts == want
    assert len(tri.indices) == 3 * 12


def test_issue_39_moving_barrier_geometry_moves_by_v_dt(tmp_path):
    topics, _, sc = record("active_earth_pressure_2d.toml", tmp_path,
                           "simulation.end_time=0.01", "simulation.output_interval=0.0025",
                           "barriers[0].move_between=[0.0, 1.0]")
    (barrier,) = sc["barriers"]
    v = barrier["velocity"][0]
    geo = topics["/geometry"]
    # every object with the first frame, then the barrier alone at every frame
    assert len(geo) == len(topics["/particles"]) >= 4
    assert len(geo[0][1].entities) == len(wall_objects(sc))
    centre = (barrier["shape"]["min"][0] + barrier["shape"]["max"][0]) / 2
    xs = []
    for t, m in geo:
        (e,) = [e for e in m.entities if e.id == "barrier"]
        assert {k.key: k.value for k in e.metadata}["moving"] == "true"
        xs.append((t, e.cubes[0].pose.position.x))
        assert all(e.id == "barrier" for e in m.entities) or t == 0.0
    assert xs[0] == (0.0, centre)
    for (t0, x0), (t1, x1) in itertools.pairwise(xs):
        assert abs((x1 - x0) - v * (t1 - t0)) < 1e-9, (t0, t1, x0, x1)
