//! [`Recorder`]: an MCAP file that opens in Foxglove with no plug-in.
//!
//! | topic | schema | encoding | one message per |
//! |---|---|---|---|
//! | `/particles` | `foxglove.PointCloud` | protobuf | recorded frame (fine and coarse grains) |
//! | `/water` | `foxglove.PointCloud` | protobuf | recorded frame, scenes with water |
//! | `/bodies` | `foxglove.FrameTransforms` | protobuf | sample, scenes with bodies |
//! | `/walls` | `foxglove.PointCloud` | protobuf | recording (once, with the first frame): the wall particles (walls, slope, barriers), fields x, y, z, object |
//! | `/geometry` | `foxglove.SceneUpdate` | protobuf | first frame: every wall object as a solid entity; each later frame: the objects that can move, at their current offset |
//! | `/barriers` | `granmix.BarrierLoads` | JSON (JSON Schema) | sample: loads, their water/grain split, panels |
//! | `/energy` | `granmix.Energies` | JSON (JSON Schema) | sample: every family's energies |
//!
//! Message log times are simulation time in ns. The PointCloud's data are the
//! [`ParticleRecord`] bytes themselves (stride 56), so `/particles` and `/water` hold
//! exactly what the particle channel carries. `/geometry` has one entity a wall object,
//! `id` its name, frame `world`, metadata `object`, `kind` and `moving`: boxes as
//! cubes, spheres and cylinders as such, polygons, rings, polyhedra, meshes and terrain
//! as triangle lists, 2D solids extruded along z into a slab
//! [`SLAB_SPACINGS`](granmix_core::geometry::solids::SLAB_SPACINGS) dp thick
//! ([`geometry`](crate::geometry)). The scene goes in as the attachment `scene.toml` and
//! the metadata record `granmix`. The protobuf schemas are foxglove's own descriptors
//! (from the `foxglove` crate).

use crate::error::IpcError;
use crate::geometry;
use crate::payload::{append_record, ParticleRecord};
use foxglove::messages::packed_element_field::NumericType;
use foxglove::messages::{
    FrameTransform, FrameTransforms, PackedElementField, PointCloud, Pose, Quaternion, SceneUpdate,
    Timestamp, Vector3,
};
use foxglove::Encode;
use granmix_core::geometry::solids::WallSolid;
use granmix_core::run::observables;
use granmix_core::run::simulation::Sample;
use granmix_core::AnySimulation;
use serde_json::json;
use std::collections::BTreeMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// Topic names.
pub const TOPIC_PARTICLES: &str = "/particles";
/// The water particles' topic.
pub const TOPIC_WATER: &str = "/water";
pub const TOPIC_BODIES: &str = "/bodies";
/// The walls' particles, sent once: the geometry the particles move in.
pub const TOPIC_WALLS: &str = "/walls";
/// The wall objects as solids: all once, then the moving ones at every frame.
pub const TOPIC_GEOMETRY: &str = "/geometry";
pub const TOPIC_BARRIERS: &str = "/barriers";
pub const TOPIC_ENERGY: &str = "/energy";
/// Frame id of the simulation's coordinates.
pub use crate::geometry::WORLD_FRAME;

const BARRIER_SCHEMA: &str = r#"{
  "title": "granmix.BarrierLoads",
  "description": "Loads on every barrier, impulse-averaged over the sampling interval",
  "type": "object",
  "properties": {
    "time": {"type": "number", "description": "simulation time (s)"},
    "barriers": {
      "type": "array",
      "items": {
        "type": "object",
        "properties": {
          "name": {"type": "string"},
          "force": {"type": "array", "items": {"type": "number"}, "minItems": 3, "maxItems": 3, "description": "N (N/m in 2D)"},
          "moment": {"type": "array", "items": {"type": "number"}, "minItems": 3, "maxItems": 3, "description": "N·m about the reference point (N in 2D)"},
          "peak_force": {"type": "number", "description": "largest resultant of any solver step in the interval"},
          "force_water": {"type": "array", "items": {"type": "number"}, "minItems": 3, "maxItems": 3, "description": "the water's part of force (pressure and viscous traction); zero without water"},
          "force_grains": {"type": "array", "items": {"type": "number"}, "minItems": 3, "maxItems": 3, "description": "the grains' part of force: force - force_water"},
          "panels": {
            "type": "array",
            "description": "each panel's load (scene key panels; empty without), labelled as the FMU labels them",
            "items": {
              "type": "object",
              "properties": {
                "index": {"type": "integer", "description": "p of the FMU's panel_<p> (2D); i n2 + j of panel_<i>_<j> on an n1 x n2 grid (3D)"},
                "force": {"type": "array", "items": {"type": "number"}, "minItems": 3, "maxItems": 3},
                "force_water": {"type": "array", "items": {"type": "number"}, "minItems": 3, "maxItems": 3},
                "force_grains": {"type": "array", "items": {"type": "number"}, "minItems": 3, "maxItems": 3}
              },
              "required": ["index", "force", "force_water", "force_grains"]
            }
          }
        },
        "required": ["name", "force", "moment", "peak_force", "force_water", "force_grains", "panels"]
      }
    }
  },
  "required": ["time", "barriers"]
}"#;

const ENERGY_SCHEMA: &str = r#"{
  "title": "granmix.Energies",
  "description": "Energies and step counts at a sample (J, or J/m in 2D)",
  "type": "object",
  "properties": {
    "time": {"type": "number"},
    "steps": {"type": "integer"},
    "steps_coarse": {"type": "integer"},
    "kinetic_fine": {"type": "number"},
    "potential_fine": {"type": "number"},
    "kinetic_coarse": {"type": "number"},
    "potential_coarse": {"type": "number"},
    "strain": {"type": "number"},
    "contact": {"type": "number"},
    "kinetic_water": {"type": "number", "description": "the water's; 0 without water"},
    "potential_water": {"type": "number", "description": "the water's; 0 without water"},
    "kinetic_total": {"type": "number", "description": "kinetic_fine + kinetic_coarse + kinetic_water"}
  },
  "required": ["time", "steps", "kinetic_fine", "potential_fine", "kinetic_coarse"]
}"#;

/// Messages written per topic.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct RecordCounts {
    pub particles: u64,
    /// `/water` messages (left out of the summary without water).
    #[serde(skip_serializing_if = "is_zero")]
    pub water: u64,
    pub bodies: u64,
    pub barriers: u64,
    pub energy: u64,
    /// `/walls` messages: 1 once a frame is recorded in a scene with walls.
    #[serde(skip_serializing_if = "is_zero")]
    pub walls: u64,
    /// `/geometry` messages: the first frame's, then one a frame while an object can
    /// move (0 without walls).
    #[serde(skip_serializing_if = "is_zero")]
    pub geometry: u64,
}

/// The scene stored in a recording.
#[derive(Clone, Debug)]
pub struct SceneInfo {
    /// Scene file text (TOML).
    pub text: String,
    /// Where it came from.
    pub file: String,
    /// Scene name, if any.
    pub name: Option<String>,
    pub dimension: usize,
    /// The scene has water: the recording gets the `/water` topic.
    pub water: bool,
}

fn is_zero(n: &u64) -> bool {
    *n == 0
}

struct Channels {
    particles: u16,
    walls: u16,
    geometry: u16,
    water: Option<u16>,
    bodies: u16,
    barriers: u16,
    energy: u16,
}

/// An open MCAP recording.
pub struct Recorder {
    path: PathBuf,
    writer: mcap::Writer<BufWriter<File>>,
    channels: Channels,
    counts: RecordCounts,
    /// The solids of the wall objects that can move (taken with the first frame).
    moving: Vec<WallSolid>,
    /// Scratch for particle records and the encoded message (reused).
    records: Vec<ParticleRecord>,
    bytes: Vec<u8>,
    out: Vec<u8>,
}

fn rec_err(path: &Path, reason: impl std::fmt::Display) -> IpcError {
    IpcError::Record {
        path: path.display().to_string(),
        reason: reason.to_string(),
    }
}

/// Simulation time (s) as MCAP log time (ns); negative or non-finite times clamp to 0.
fn nanos(t: f64) -> u64 {
    if t.is_finite() && t > 0.0 {
        (t * 1e9).round() as u64
    } else {
        0
    }
}

fn stamp(t: f64) -> Timestamp {
    let ns = nanos(t);
    Timestamp::new((ns / 1_000_000_000) as u32, (ns % 1_000_000_000) as u32)
}

/// The PointCloud fields over a [`ParticleRecord`].
fn point_fields() -> Vec<PackedElementField> {
    let f = |name: &str, offset: u32, t: NumericType| PackedElementField {
        name: name.to_string(),
        offset,
        r#type: t as i32,
    };
    vec![
        f("x", 0, NumericType::Float32),
        f("y", 4, NumericType::Float32),
        f("z", 8, NumericType::Float32),
        f("vx", 12, NumericType::Float32),
        f("vy", 16, NumericType::Float32),
        f("vz", 20, NumericType::Float32),
        f("pressure", 24, NumericType::Float32),
        f("plastic_strain", 28, NumericType::Float32),
        f("id", 32, NumericType::Uint32),
        f("group", 36, NumericType::Uint32),
        f("family", 40, NumericType::Uint32),
        f("pore_pressure", 44, NumericType::Float32),
        f("excess_pore_pressure", 48, NumericType::Float32),
        f("porosity", 52, NumericType::Float32),
    ]
}

fn add_channel<T: Encode>(
    w: &mut mcap::Writer<BufWriter<File>>,
    topic: &str,
) -> mcap::McapResult<u16> {
    let schema = T::get_schema().expect("foxglove messages carry their schema");
    let id = w.add_schema(&schema.name, &schema.encoding, &schema.data)?;
    w.add_channel(id, topic, &T::get_message_encoding(), &BTreeMap::new())
}

impl Recorder {
    /// Create `path` and store `scene` in it.
    pub fn create(path: &Path, scene: &SceneInfo) -> Result<Self, IpcError> {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| rec_err(path, e))?;
        }
        let file = File::create(path).map_err(|e| rec_err(path, format!("cannot create: {e}")))?;
        let opts = mcap::WriteOptions::new()
            .profile("")
            .library(format!("granmix {}", env!("CARGO_PKG_VERSION")))
            .compression(Some(mcap::Compression::Zstd));
        let mut w = opts
            .create(BufWriter::with_capacity(1 << 20, file))
            .map_err(|e| rec_err(path, e))?;
        let e = |x| rec_err(path, x);
        let particles = add_channel::<PointCloud>(&mut w, TOPIC_PARTICLES).map_err(e)?;
        let water = if scene.water {
            Some(add_channel::<PointCloud>(&mut w, TOPIC_WATER).map_err(e)?)
        } else {
            None
        };
        let bodies = add_channel::<FrameTransforms>(&mut w, TOPIC_BODIES).map_err(e)?;
        let walls = add_channel::<PointCloud>(&mut w, TOPIC_WALLS).map_err(e)?;
        let geometry = add_channel::<SceneUpdate>(&mut w, TOPIC_GEOMETRY).map_err(e)?;
        let json_channel = |w: &mut mcap::Writer<_>, name: &str, schema: &str, topic: &str| {
            let id = w.add_schema(name, "jsonschema", schema.as_bytes())?;
            w.add_channel(id, topic, "json", &BTreeMap::new())
        };
        let barriers = json_channel(
            &mut w,
            "granmix.BarrierLoads",
            BARRIER_SCHEMA,
            TOPIC_BARRIERS,
        )
        .map_err(e)?;
        let energy =
            json_channel(&mut w, "granmix.Energies", ENERGY_SCHEMA, TOPIC_ENERGY).map_err(e)?;
        w.attach(&mcap::Attachment {
            log_time: 0,
            create_time: 0,
            name: "scene.toml".into(),
            media_type: "application/toml".into(),
            data: scene.text.as_bytes().into(),
        })
        .map_err(e)?;
        let mut meta = BTreeMap::new();
        meta.insert("version".to_string(), env!("CARGO_PKG_VERSION").to_string());
        meta.insert("scene_file".to_string(), scene.file.clone());
        meta.insert(
            "scene_name".to_string(),
            scene.name.clone().unwrap_or_default(),
        );
        meta.insert("dimension".to_string(), scene.dimension.to_string());
        meta.insert("scene".to_string(), scene.text.clone());
        w.write_metadata(&mcap::records::Metadata {
            name: "granmix".into(),
            metadata: meta,
        })
        .map_err(e)?;
        Ok(Recorder {
            path: path.to_path_buf(),
            writer: w,
            channels: Channels {
                particles,
                walls,
                geometry,
                water,
                bodies,
                barriers,
                energy,
            },
            counts: RecordCounts::default(),
            moving: Vec::new(),
            records: Vec::new(),
            bytes: Vec::new(),
            out: Vec::new(),
        })
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    pub fn counts(&self) -> RecordCounts {
        self.counts
    }

    fn write(
        &mut self,
        channel: u16,
        sequence: u64,
        time: f64,
        data: &[u8],
    ) -> Result<(), IpcError> {
        let t = nanos(time);
        self.writer
            .write_to_known_channel(
                &mcap::records::MessageHeader {
                    channel_id: channel,
                    sequence: sequence as u32,
                    log_time: t,
                    publish_time: t,
                },
                data,
            )
            .map_err(|e| rec_err(&self.path, e))
    }

    /// Write one `/particles` message from the records of a frame.
    pub fn write_particles(
        &mut self,
        time: f64,
        records: &[ParticleRecord],
    ) -> Result<(), IpcError> {
        let (channel, sequence) = (self.channels.particles, self.counts.particles);
        self.write_cloud(channel, sequence, time, records)?;
        self.counts.particles += 1;
        Ok(())
    }

    /// One PointCloud message of `records` on `channel`.
    fn write_cloud(
        &mut self,
        channel: u16,
        sequence: u64,
        time: f64,
        records: &[ParticleRecord],
    ) -> Result<(), IpcError> {
        let mut bytes = std::mem::take(&mut self.bytes);
        bytes.clear();
        bytes.reserve(std::mem::size_of_val(records));
        for r in records {
            append_record(&mut bytes, r);
        }
        let msg = PointCloud {
            timestamp: Some(stamp(time)),
            frame_id: WORLD_FRAME.into(),
            pose: Some(Pose {
                position: Some(Vector3::default()),
                orientation: Some(Quaternion {
                    x: 0.0,
                    y: 0.0,
                    z: 0.0,
                    w: 1.0,
                }),
            }),
            point_stride: std::mem::size_of::<ParticleRecord>() as u32,
            fields: point_fields(),
            data: foxglove::bytes::Bytes::from(bytes),
        };
        let mut out = std::mem::take(&mut self.out);
        out.clear();
        msg.encode(&mut out).map_err(|e| rec_err(&self.path, e))?;
        // take the particle buffer back for the next frame
        self.bytes = Vec::from(msg.data);
        let r = self.write(channel, sequence, time, &out);
        self.out = out;
        r
    }

    /// Write the particles of `sim` now.
    pub fn record_particles(&mut self, sim: &AnySimulation) -> Result<(), IpcError> {
        if self.counts.walls == 0 && sim.wall_count() > 0 {
            self.write_walls(sim)?;
        }
        self.write_geometry(sim)?;
        let (f, c) = sim.particle_counts();
        let nw = sim.water_count();
        let mut records = std::mem::take(&mut self.records);
        records.resize(f + c + nw, ParticleRecord::default());
        sim.fill_particles(&mut records);
        let mut r = self.write_particles(sim.time(), &records[..f + c]);
        if let (Some(ch), true) = (self.channels.water, r.is_ok()) {
            r = self.write_cloud(ch, self.counts.water, sim.time(), &records[f + c..]);
            self.counts.water += 1;
        }
        self.records = records;
        r
    }

    /// The `/walls` message: every wall particle as x, y, z (f32) and its object index
    /// (u32, walls, barriers and container faces in scene order), 16 bytes a point.
    /// Moving barriers are drawn where they start.
    fn write_walls(&mut self, sim: &AnySimulation) -> Result<(), IpcError> {
        let (pos, object) = sim.wall_points();
        let mut data = Vec::with_capacity(16 * pos.len());
        for (p, o) in pos.iter().zip(&object) {
            for c in p {
                data.extend_from_slice(&c.to_le_bytes());
            }
            data.extend_from_slice(&u32::from(*o).to_le_bytes());
        }
        let f = |name: &str, offset: u32, t: NumericType| PackedElementField {
            name: name.to_string(),
            offset,
            r#type: t as i32,
        };
        let msg = PointCloud {
            timestamp: Some(stamp(sim.time())),
            frame_id: WORLD_FRAME.into(),
            pose: Some(Pose {
                position: Some(Vector3::default()),
                orientation: Some(Quaternion {
                    x: 0.0,
                    y: 0.0,
                    z: 0.0,
                    w: 1.0,
                }),
            }),
            point_stride: 16,
            fields: vec![
                f("x", 0, NumericType::Float32),
                f("y", 4, NumericType::Float32),
                f("z", 8, NumericType::Float32),
                f("object", 12, NumericType::Uint32),
            ],
            data: foxglove::bytes::Bytes::from(data),
        };
        let mut out = Vec::new();
        msg.encode(&mut out).map_err(|e| rec_err(&self.path, e))?;
        self.write(self.channels.walls, 0, sim.time(), &out)?;
        self.counts.walls = 1;
        Ok(())
    }

    /// The `/geometry` message of this frame: every wall object with the first frame
    /// (keeping the solids of those that can move), the moving ones at their current
    /// offset with each later frame; nothing in a scene without walls, and nothing
    /// after the first when no object can move.
    fn write_geometry(&mut self, sim: &AnySimulation) -> Result<(), IpcError> {
        if self.counts.geometry == 0 {
            let all = sim.wall_solids();
            if all.is_empty() {
                return Ok(());
            }
            self.moving = all.iter().filter(|s| s.moving).cloned().collect();
            self.write_solids(&all, sim)
        } else if !self.moving.is_empty() {
            let moving = std::mem::take(&mut self.moving);
            let r = self.write_solids(&moving, sim);
            self.moving = moving;
            r
        } else {
            Ok(())
        }
    }

    /// One `/geometry` message of `solids` at their offsets now.
    fn write_solids(&mut self, solids: &[WallSolid], sim: &AnySimulation) -> Result<(), IpcError> {
        let msg = geometry::update(solids, &sim.wall_offsets(), stamp(sim.time()));
        let mut out = Vec::new();
        msg.encode(&mut out).map_err(|e| rec_err(&self.path, e))?;
        self.write(
            self.channels.geometry,
            self.counts.geometry,
            sim.time(),
            &out,
        )?;
        self.counts.geometry += 1;
        Ok(())
    }

    /// Write bodies (when there are any), barrier loads and energies of `s`.
    pub fn record_sample(&mut self, s: &Sample) -> Result<(), IpcError> {
        let water_ke = s.water.as_ref().map_or(0.0, |w| w.kinetic_energy);
        if !s.bodies.is_empty() {
            let msg = FrameTransforms {
                transforms: s
                    .bodies
                    .iter()
                    .map(|b| FrameTransform {
                        timestamp: Some(stamp(s.time)),
                        parent_frame_id: WORLD_FRAME.into(),
                        child_frame_id: b.name.clone(),
                        translation: Some(Vector3 {
                            x: b.position[0],
                            y: b.position[1],
                            z: b.position[2],
                        }),
                        rotation: Some(Quaternion {
                            w: b.orientation[0],
                            x: b.orientation[1],
                            y: b.orientation[2],
                            z: b.orientation[3],
                        }),
                    })
                    .collect(),
            };
            let mut out = Vec::new();
            msg.encode(&mut out).map_err(|e| rec_err(&self.path, e))?;
            self.write(self.channels.bodies, self.counts.bodies, s.time, &out)?;
            self.counts.bodies += 1;
        }
        let barriers = json!({
            "time": s.time,
            "barriers": s.barriers.iter().map(|b| json!({
                "name": b.name,
                "force": b.force,
                "moment": b.moment,
                "peak_force": b.peak_force,
                "force_water": b.force_water,
                "force_grains": b.force_grains,
                "panels": b.panels.iter().enumerate().map(|(p, f)| {
                    let fw = b.panels_water.get(p).copied().unwrap_or_default();
                    json!({
                        "index": p,
                        "force": f,
                        "force_water": fw,
                        "force_grains": b.panels_grains.get(p).copied().unwrap_or_default(),
                    })
                }).collect::<Vec<_>>(),
            })).collect::<Vec<_>>(),
        });
        let data = serde_json::to_vec(&barriers).map_err(|e| rec_err(&self.path, e))?;
        self.write(self.channels.barriers, self.counts.barriers, s.time, &data)?;
        self.counts.barriers += 1;
        let energy = json!({
            "time": s.time,
            "steps": s.steps,
            "steps_coarse": s.steps_coarse,
            "kinetic_fine": s.kinetic_energy,
            "potential_fine": s.potential_energy,
            "kinetic_coarse": s.coarse_kinetic_energy,
            "potential_coarse": s.coarse_potential_energy,
            "strain": s.strain_energy,
            "contact": s.contact_energy,
            "kinetic_water": water_ke,
            "potential_water": s.water.as_ref().map_or(0.0, |w| w.potential_energy),
            "kinetic_total": observables::total_kinetic_energy(s),
        });
        let data = serde_json::to_vec(&energy).map_err(|e| rec_err(&self.path, e))?;
        self.write(self.channels.energy, self.counts.energy, s.time, &data)?;
        self.counts.energy += 1;
        Ok(())
    }

    /// Particles of `sim` plus everything in `s`: one full sample.
    pub fn record(&mut self, sim: &AnySimulation, s: &Sample) -> Result<(), IpcError> {
        self.record_particles(sim)?;
        self.record_sample(s)
    }

    /// Write the summary and close the file.
    pub fn finish(mut self) -> Result<RecordCounts, IpcError> {
        self.close()
    }

    /// Write the summary and close the file, leaving the recorder in place (a second
    /// call writes nothing more).
    pub fn close(&mut self) -> Result<RecordCounts, IpcError> {
        self.writer.finish().map_err(|e| rec_err(&self.path, e))?;
        Ok(self.counts)
    }
}
