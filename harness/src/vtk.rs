//! ParaView output: `.vtu` unstructured-grid snapshots (raw appended binary) and a
//! `.pvd` collection indexing them by time, one named part per family (soil, bodies,
//! water) and the walls, whose particles carry their pressure at each snapshot.
//! docs/scenes.md lists every array with its unit.

use granmix_core::run::simulation::{Frame, Sample};
use granmix_core::AnySimulation;
use granmix_ipc::{Sink, SinkError};
use std::fmt::Write as _;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Writes numbered snapshots and keeps the `.pvd` index current.
pub struct VtkSeries {
    dir: PathBuf,
    stem: String,
    entries: Vec<Entry>,
}

struct Arrays {
    xml: String,
    data: Vec<u8>,
}

impl Arrays {
    fn new() -> Self {
        Arrays {
            xml: String::new(),
            data: Vec::new(),
        }
    }
    fn push(&mut self, name: &str, kind: &str, comps: usize, bytes: &[u8]) {
        let _ = writeln!(
            self.xml,
            r#"        <DataArray type="{kind}" Name="{name}" NumberOfComponents="{comps}" format="appended" offset="{}"/>"#,
            self.data.len()
        );
        self.data
            .extend_from_slice(&(bytes.len() as u64).to_le_bytes());
        self.data.extend_from_slice(bytes);
    }
}

fn bytes_f32(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}
fn bytes_f32_3(v: &[[f32; 3]]) -> Vec<u8> {
    v.iter()
        .flat_map(|x| x.iter().flat_map(|c| c.to_le_bytes()))
        .collect()
}

/// Write one point cloud as a `.vtu` file with vertex cells.
fn write_vtu(path: &Path, pos: &[[f32; 3]], point_arrays: Arrays) -> std::io::Result<()> {
    let n = pos.len();
    let mut arr = Arrays::new();
    arr.data = point_arrays.data;
    let points_offset = arr.data.len();
    arr.data.extend_from_slice(&((n * 12) as u64).to_le_bytes());
    arr.data.extend_from_slice(&bytes_f32_3(pos));
    let conn: Vec<u8> = (0..n as i64).flat_map(|i| i.to_le_bytes()).collect();
    let conn_offset = arr.data.len();
    arr.data
        .extend_from_slice(&(conn.len() as u64).to_le_bytes());
    arr.data.extend_from_slice(&conn);
    let offs: Vec<u8> = (1..=n as i64).flat_map(|i| i.to_le_bytes()).collect();
    let offs_offset = arr.data.len();
    arr.data
        .extend_from_slice(&(offs.len() as u64).to_le_bytes());
    arr.data.extend_from_slice(&offs);
    let types: Vec<u8> = vec![1u8; n];
    let types_offset = arr.data.len();
    arr.data
        .extend_from_slice(&(types.len() as u64).to_le_bytes());
    arr.data.extend_from_slice(&types);

    let mut f = std::io::BufWriter::new(std::fs::File::create(path)?);
    write!(
        f,
        r#"<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64">
  <UnstructuredGrid>
    <Piece NumberOfPoints="{n}" NumberOfCells="{n}">
      <PointData>
{}      </PointData>
      <Points>
        <DataArray type="Float32" NumberOfComponents="3" format="appended" offset="{points_offset}"/>
      </Points>
      <Cells>
        <DataArray type="Int64" Name="connectivity" format="appended" offset="{conn_offset}"/>
        <DataArray type="Int64" Name="offsets" format="appended" offset="{offs_offset}"/>
        <DataArray type="UInt8" Name="types" format="appended" offset="{types_offset}"/>
      </Cells>
    </Piece>
  </UnstructuredGrid>
  <AppendedData encoding="raw">
   _"#,
        point_arrays.xml
    )?;
    f.write_all(&arr.data)?;
    write!(f, "\n  </AppendedData>\n</VTKFile>\n")?;
    f.flush()
}

/// ParaView's order of a symmetric tensor's six components: XX, YY, ZZ, XY, YZ, XZ.
/// granmix keeps xx, yy, zz, xy, xz, yz (`Sym`), so the last two swap.
const PARAVIEW_ORDER: [usize; 6] = [0, 1, 2, 3, 5, 4];

/// Six stress components in ParaView's order, little-endian f32.
fn stress_bytes(stress: &[[f32; 6]]) -> Vec<u8> {
    stress
        .iter()
        .flat_map(|s| PARAVIEW_ORDER.iter().flat_map(move |&k| s[k].to_le_bytes()))
        .collect()
}

fn bytes_u8(v: impl Iterator<Item = u8>) -> Vec<u8> {
    v.collect()
}
fn bytes_u16(v: impl Iterator<Item = u16>) -> Vec<u8> {
    v.flat_map(|x| x.to_le_bytes()).collect()
}
fn bytes_u32(v: impl Iterator<Item = u32>) -> Vec<u8> {
    v.flat_map(|x| x.to_le_bytes()).collect()
}

/// The parts of the `.pvd` collection: index and block name.
const SOIL: (usize, &str) = (0, "soil");
const BODIES: (usize, &str) = (1, "bodies");
const WATER: (usize, &str) = (2, "water");
const WALLS: (usize, &str) = (3, "walls");

/// One snapshot: its time and the files of the parts it has (a family with no
/// particles at that time writes no file).
type Entry = (f64, Vec<((usize, &'static str), String)>);

impl VtkSeries {
    pub fn new(dir: &Path, stem: &str) -> Self {
        VtkSeries {
            dir: dir.to_path_buf(),
            stem: stem.to_string(),
            entries: Vec::new(),
        }
    }

    /// The fine particles (soil): velocity, pressures, density, porosity, stresses,
    /// plastic strain, id, family and material.
    fn soil(&self, frame: &Frame, name: &str) -> std::io::Result<()> {
        let fine = &frame.fine;
        let water = !frame.water.is_empty();
        let mut a = Arrays::new();
        let vel: Vec<[f32; 3]> = fine.iter().map(|p| p.velocity).collect();
        a.push("velocity", "Float32", 3, &bytes_f32_3(&vel));
        let pressure: Vec<f32> = fine.iter().map(|p| p.pressure).collect();
        a.push("pressure", "Float32", 1, &bytes_f32(&pressure));
        a.push("density", "Float32", 1, &bytes_f32(&frame.density));
        let porosity: Vec<f32> = fine.iter().map(|p| p.porosity).collect();
        a.push("porosity", "Float32", 1, &bytes_f32(&porosity));
        let eps: Vec<f32> = fine.iter().map(|p| p.plastic_strain).collect();
        a.push("plastic_strain", "Float32", 1, &bytes_f32(&eps));
        // the solver's stress is effective (Terzaghi): σ = σ' − p_w I, tension positive
        a.push(
            "effective_stress",
            "Float32",
            6,
            &stress_bytes(&frame.stress),
        );
        if water {
            let pore: Vec<f32> = fine.iter().map(|p| p.pore_pressure).collect();
            a.push("pore_pressure", "Float32", 1, &bytes_f32(&pore));
            let excess: Vec<f32> = fine.iter().map(|p| p.excess_pore_pressure).collect();
            a.push("excess_pore_pressure", "Float32", 1, &bytes_f32(&excess));
            let total: Vec<[f32; 6]> = frame
                .stress
                .iter()
                .zip(fine)
                .map(|(s, p)| {
                    let mut t = *s;
                    for c in t.iter_mut().take(3) {
                        *c -= p.pore_pressure;
                    }
                    t
                })
                .collect();
            a.push("total_stress", "Float32", 6, &stress_bytes(&total));
        }
        a.push("id", "UInt32", 1, &bytes_u32(fine.iter().map(|p| p.id)));
        if !frame.awake.is_empty() {
            // where resting grains sleep (numerics.sleep): 1 awake, 0 asleep
            a.push("awake", "UInt8", 1, &bytes_u8(frame.awake.iter().copied()));
        }
        a.push(
            "family",
            "UInt8",
            1,
            &bytes_u8(fine.iter().map(|p| p.family as u8)),
        );
        // materials are u16 in the solver
        a.push(
            "material",
            "UInt16",
            1,
            &bytes_u16(fine.iter().map(|p| p.group as u16)),
        );
        let pos: Vec<[f32; 3]> = fine.iter().map(|p| p.position).collect();
        write_vtu(&self.dir.join(name), &pos, a)
    }

    /// The coarse particles: velocity, the fine grains' and the water's force on each,
    /// body index, id and family.
    fn bodies(&self, frame: &Frame, name: &str) -> std::io::Result<()> {
        let coarse = &frame.coarse;
        let mut b = Arrays::new();
        let vel: Vec<[f32; 3]> = coarse.iter().map(|p| p.velocity).collect();
        b.push("velocity", "Float32", 3, &bytes_f32_3(&vel));
        b.push(
            "fine_force",
            "Float32",
            3,
            &bytes_f32_3(&frame.coarse_fine_force),
        );
        if !frame.water.is_empty() {
            b.push(
                "water_force",
                "Float32",
                3,
                &bytes_f32_3(&frame.coarse_water_force),
            );
        }
        b.push(
            "body",
            "UInt32",
            1,
            &bytes_u32(coarse.iter().map(|p| p.group)),
        );
        b.push("id", "UInt32", 1, &bytes_u32(coarse.iter().map(|p| p.id)));
        b.push(
            "family",
            "UInt8",
            1,
            &bytes_u8(coarse.iter().map(|p| p.family as u8)),
        );
        let pos: Vec<[f32; 3]> = coarse.iter().map(|p| p.position).collect();
        write_vtu(&self.dir.join(name), &pos, b)
    }

    /// The water particles: velocity, pressure, excess pore pressure, density, id,
    /// family and material (0: the scene's one water).
    fn water(&self, frame: &Frame, name: &str) -> std::io::Result<()> {
        let water = &frame.water;
        let mut a = Arrays::new();
        let vel: Vec<[f32; 3]> = water.iter().map(|p| p.velocity).collect();
        a.push("velocity", "Float32", 3, &bytes_f32_3(&vel));
        let pressure: Vec<f32> = water.iter().map(|p| p.pressure).collect();
        a.push("pressure", "Float32", 1, &bytes_f32(&pressure));
        a.push("density", "Float32", 1, &bytes_f32(&frame.water_density));
        let excess: Vec<f32> = water.iter().map(|p| p.excess_pore_pressure).collect();
        a.push("excess_pore_pressure", "Float32", 1, &bytes_f32(&excess));
        a.push("id", "UInt32", 1, &bytes_u32(water.iter().map(|p| p.id)));
        a.push(
            "family",
            "UInt8",
            1,
            &bytes_u8(water.iter().map(|p| p.family as u8)),
        );
        a.push(
            "material",
            "UInt16",
            1,
            &bytes_u16(water.iter().map(|p| p.group as u16)),
        );
        let pos: Vec<[f32; 3]> = water.iter().map(|p| p.position).collect();
        write_vtu(&self.dir.join(name), &pos, a)
    }

    /// The wall particles where they are now: object index, pressure and, with
    /// water, the water's part of it ([`AnySimulation::wall_pressure`]).
    fn walls(&self, frame: &Frame, sim: &AnySimulation, name: &str) -> std::io::Result<()> {
        let (pressure, water) = sim.wall_pressure();
        let mut w = Arrays::new();
        w.push(
            "object",
            "UInt16",
            1,
            &bytes_u16(frame.wall_object.iter().copied()),
        );
        w.push("pressure", "Float32", 1, &bytes_f32(&pressure));
        if let Some(water) = water {
            w.push("pressure_water", "Float32", 1, &bytes_f32(&water));
        }
        write_vtu(&self.dir.join(name), &frame.wall_pos, w)
    }

    /// Write the parts of `sim`'s state that have particles, the walls included.
    pub fn write(&mut self, sim: &AnySimulation) -> std::io::Result<()> {
        let frame = &sim.frame();
        let k = self.entries.len();
        let mut parts = Vec::new();
        if !frame.fine.is_empty() {
            let name = format!("{}_{k:05}.vtu", self.stem);
            self.soil(frame, &name)?;
            parts.push((SOIL, name));
        }
        if !frame.coarse.is_empty() {
            let name = format!("{}_bodies_{k:05}.vtu", self.stem);
            self.bodies(frame, &name)?;
            parts.push((BODIES, name));
        }
        if !frame.water.is_empty() {
            let name = format!("{}_water_{k:05}.vtu", self.stem);
            self.water(frame, &name)?;
            parts.push((WATER, name));
        }
        if !frame.wall_pos.is_empty() {
            let name = format!("{}_walls_{k:05}.vtu", self.stem);
            self.walls(frame, sim, &name)?;
            parts.push((WALLS, name));
        }
        self.entries.push((frame.time, parts));
        self.write_pvd()
    }

    /// The collection: every part of every snapshot, with its index and block name.
    fn write_pvd(&self) -> std::io::Result<()> {
        let mut s = String::from(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n",
        );
        for (t, parts) in &self.entries {
            for ((part, name), file) in parts {
                let _ = writeln!(
                    s,
                    "    <DataSet timestep=\"{t:.9e}\" group=\"\" part=\"{part}\" name=\"{name}\" file=\"{file}\"/>"
                );
            }
        }
        s.push_str("  </Collection>\n</VTKFile>\n");
        std::fs::write(self.dir.join(format!("{}.pvd", self.stem)), s)
    }
}

impl Sink for VtkSeries {
    fn name(&self) -> &str {
        "vtk"
    }
    fn sample(&mut self, sim: &AnySimulation, _s: &Sample) -> Result<(), SinkError> {
        self.write(sim)
            .map_err(|e| SinkError::new("writing VTK snapshot", e))
    }
    /// The state the guard stopped on, as the last snapshot, so that the blow-up can
    /// be looked at in ParaView.
    fn blowup(&mut self, sim: &AnySimulation) -> Result<(), SinkError> {
        self.write(sim)
            .map_err(|e| SinkError::new("writing the VTK snapshot of the blow-up", e))
    }
}

#[cfg(test)]
mod tests {
    /// Issue 39: granmix's xx, yy, zz, xy, xz, yz go out as ParaView's XX, YY, ZZ,
    /// XY, YZ, XZ (the last two were swapped, so 3D labels were wrong).
    #[test]
    fn issue_39_stress_is_in_paraview_order() {
        let b = super::stress_bytes(&[[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]]);
        let v: Vec<f32> = b
            .chunks(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        assert_eq!(v, [1.0, 2.0, 3.0, 4.0, 6.0, 5.0]);
    }
}
