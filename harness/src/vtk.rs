//! ParaView output: `.vtu` unstructured-grid snapshots (raw appended binary) and a
//! `.pvd` collection indexing them by time.

use granmix_core::simulation::{Frame, Sample};
use granmix_core::AnySimulation;
use granmix_ipc::{Sink, SinkError};
use std::fmt::Write as _;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Writes numbered snapshots and keeps the `.pvd` index current.
pub struct VtkSeries {
    dir: PathBuf,
    stem: String,
    entries: Vec<(f64, String, Option<String>, Option<String>)>,
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

impl VtkSeries {
    pub fn new(dir: &Path, stem: &str) -> Self {
        VtkSeries {
            dir: dir.to_path_buf(),
            stem: stem.to_string(),
            entries: Vec::new(),
        }
    }

    /// Write the fine particles (and, on the first call, the walls) of `frame`.
    pub fn write(&mut self, frame: &Frame) -> std::io::Result<()> {
        let k = self.entries.len();
        let name = format!("{}_{k:05}.vtu", self.stem);
        let fine = &frame.fine;
        let mut a = Arrays::new();
        let vel: Vec<[f32; 3]> = fine.iter().map(|p| p.velocity).collect();
        a.push("velocity", "Float32", 3, &bytes_f32_3(&vel));
        let pressure: Vec<f32> = fine.iter().map(|p| p.pressure).collect();
        a.push("pressure", "Float32", 1, &bytes_f32(&pressure));
        a.push("density", "Float32", 1, &bytes_f32(&frame.density));
        let eps: Vec<f32> = fine.iter().map(|p| p.plastic_strain).collect();
        a.push("plastic_strain", "Float32", 1, &bytes_f32(&eps));
        if !frame.water.is_empty() {
            // the stress above is effective; the water's part is the pore pressure
            let pore: Vec<f32> = fine.iter().map(|p| p.pore_pressure).collect();
            a.push("pore_pressure", "Float32", 1, &bytes_f32(&pore));
            let excess: Vec<f32> = fine.iter().map(|p| p.excess_pore_pressure).collect();
            a.push("excess_pore_pressure", "Float32", 1, &bytes_f32(&excess));
        }
        let stress: Vec<u8> = frame
            .stress
            .iter()
            .flat_map(|s| s.iter().flat_map(|c| c.to_le_bytes()))
            .collect();
        a.push("stress_xx_yy_zz_xy_xz_yz", "Float32", 6, &stress);
        let ids: Vec<u8> = fine.iter().flat_map(|p| p.id.to_le_bytes()).collect();
        a.push("id", "UInt32", 1, &ids);
        // materials are u16 in the solver
        let mats: Vec<u8> = fine
            .iter()
            .flat_map(|p| (p.group as u16).to_le_bytes())
            .collect();
        a.push("material", "UInt16", 1, &mats);
        let pos: Vec<[f32; 3]> = fine.iter().map(|p| p.position).collect();
        write_vtu(&self.dir.join(&name), &pos, a)?;
        if k == 0 && !frame.wall_pos.is_empty() {
            let mut w = Arrays::new();
            let obj: Vec<u8> = frame
                .wall_object
                .iter()
                .flat_map(|i| i.to_le_bytes())
                .collect();
            w.push("object", "UInt16", 1, &obj);
            write_vtu(
                &self.dir.join(format!("{}_walls.vtu", self.stem)),
                &frame.wall_pos,
                w,
            )?;
        }
        let bodies = if frame.coarse.is_empty() {
            None
        } else {
            let coarse = &frame.coarse;
            let bname = format!("{}_bodies_{k:05}.vtu", self.stem);
            let mut b = Arrays::new();
            let vel: Vec<[f32; 3]> = coarse.iter().map(|p| p.velocity).collect();
            b.push("velocity", "Float32", 3, &bytes_f32_3(&vel));
            b.push(
                "fine_force",
                "Float32",
                3,
                &bytes_f32_3(&frame.coarse_fine_force),
            );
            let ids: Vec<u8> = coarse.iter().flat_map(|p| p.group.to_le_bytes()).collect();
            b.push("body", "UInt32", 1, &ids);
            let pos: Vec<[f32; 3]> = coarse.iter().map(|p| p.position).collect();
            write_vtu(&self.dir.join(&bname), &pos, b)?;
            Some(bname)
        };
        let water = if frame.water.is_empty() {
            None
        } else {
            let water = &frame.water;
            let wname = format!("{}_water_{k:05}.vtu", self.stem);
            let mut a = Arrays::new();
            let vel: Vec<[f32; 3]> = water.iter().map(|p| p.velocity).collect();
            a.push("velocity", "Float32", 3, &bytes_f32_3(&vel));
            let pressure: Vec<f32> = water.iter().map(|p| p.pressure).collect();
            a.push("pressure", "Float32", 1, &bytes_f32(&pressure));
            a.push("density", "Float32", 1, &bytes_f32(&frame.water_density));
            let excess: Vec<f32> = water.iter().map(|p| p.excess_pore_pressure).collect();
            a.push("excess_pressure", "Float32", 1, &bytes_f32(&excess));
            let ids: Vec<u8> = water.iter().flat_map(|p| p.id.to_le_bytes()).collect();
            a.push("id", "UInt32", 1, &ids);
            let pos: Vec<[f32; 3]> = water.iter().map(|p| p.position).collect();
            write_vtu(&self.dir.join(&wname), &pos, a)?;
            Some(wname)
        };
        self.entries.push((frame.time, name, bodies, water));
        self.write_pvd()
    }

    fn write_pvd(&self) -> std::io::Result<()> {
        let mut s = String::from(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n",
        );
        for (t, f, b, w) in &self.entries {
            let _ = writeln!(
                s,
                "    <DataSet timestep=\"{t:.9e}\" group=\"\" part=\"0\" file=\"{f}\"/>"
            );
            if let Some(b) = b {
                let _ = writeln!(
                    s,
                    "    <DataSet timestep=\"{t:.9e}\" group=\"\" part=\"1\" file=\"{b}\"/>"
                );
            }
            if let Some(w) = w {
                let _ = writeln!(
                    s,
                    "    <DataSet timestep=\"{t:.9e}\" group=\"\" part=\"2\" file=\"{w}\"/>"
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
        self.write(&sim.frame())
            .map_err(|e| SinkError::new("writing VTK snapshot", e))
    }
    /// The state the guard stopped on, as the last snapshot, so that the blow-up can
    /// be looked at in ParaView.
    fn blowup(&mut self, sim: &AnySimulation) -> Result<(), SinkError> {
        self.write(&sim.frame())
            .map_err(|e| SinkError::new("writing the VTK snapshot of the blow-up", e))
    }
}
