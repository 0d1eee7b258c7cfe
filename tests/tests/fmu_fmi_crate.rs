//! The packed granular FMU loaded by the `fmi` crate (a second importer beside fmpy) and
//! stepped with an input-driven barrier; its outputs must equal, bit for bit, the same
//! scene run through `Simulation` directly with the same barrier motion.

use fmi::fmi2::import::Fmi2Import;
use fmi::fmi2::instance::{CoSimulation, Common};
use fmi::traits::FmiImport;
use granmix_core::input::load_scene_file;
use granmix_core::AnySimulation;
use granmix_fmu::granular::Granular;
use granmix_fmu::model::Model;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The cdylib built beside this test (cargo builds it with the rlib).
fn fmu_library() -> PathBuf {
    let exe = std::env::current_exe().expect("test executable path");
    let deps = exe.parent().expect("deps directory");
    [
        deps.join("libgranmix_fmu.so"),
        deps.join("../libgranmix_fmu.so"),
    ]
    .into_iter()
    .find(|p| p.is_file())
    .unwrap_or_else(|| panic!("libgranmix_fmu.so not found next to {}", exe.display()))
}

#[test]
fn fmi_crate_drives_the_packed_fmu_like_the_simulation() {
    let scene = root().join("models/scenes/fmu_barrier_2d.toml");
    let dir = std::env::temp_dir().join(format!("granmix-fmi-crate-{}", std::process::id()));
    let fmu = dir.join("fmu_barrier.fmu");
    granmix_fmu::package::write_fmu(&scene, &fmu, &fmu_library(), &[]).expect("pack the FMU");

    let import = fmi::import::from_path::<Fmi2Import>(&fmu).expect("import the FMU");
    let md = import.model_description();
    let vr = |name: &str| {
        md.model_variables
            .variables
            .iter()
            .find(|v| v.name == name)
            .unwrap_or_else(|| panic!("no variable `{name}`"))
            .value_reference
    };
    let outputs = [
        vr("barrier.force.x"),
        vr("barrier.force.y"),
        vr("barrier.moment"),
        vr("barrier.peak_force"),
        vr("kinetic_energy.fine"),
    ];
    let disp = vr("barrier.displacement.x");
    // round trip: the XML lists the model's table, value reference = index
    let loaded = load_scene_file(&scene, &[]).expect("scene");
    let model = Granular::new(loaded.clone(), scene.parent().expect("dir")).expect("model");
    let table = model.variables();
    assert_eq!(md.model_variables.variables.len(), table.len());
    for (i, (x, v)) in md.model_variables.variables.iter().zip(table).enumerate() {
        assert_eq!(
            (x.value_reference as usize, x.name.as_str()),
            (i, v.name.as_str())
        );
    }
    let mut inst = import
        .instantiate_cs("granmix", false, false)
        .expect("instantiate");
    inst.setup_experiment(None, 0.0, None).expect("setup");
    inst.enter_initialization_mode().expect("enter init");
    inst.exit_initialization_mode().expect("exit init");

    let mut sim = AnySimulation::new(&loaded).expect("simulation");
    sim.sample();

    let (h, steps) = (1e-3, 30);
    let mut t = 0.0;
    for n in 0..steps {
        let x = 2e-5 * n as f64;
        inst.set_real(&[disp], &[x]).expect("set displacement");
        inst.do_step(t, h, true).expect("do step");
        let mut got = [0.0; 5];
        inst.get_real(&outputs, &mut got).expect("get outputs");

        let d = sim.barrier_displacement(0);
        sim.drive_barrier(0, [(x - d[0]) / h, (0.0 - d[1]) / h, (0.0 - d[2]) / h])
            .expect("driven barrier");
        sim.advance_to(t + h).expect("advance");
        let s = sim.sample();
        let b = &s.barriers[0];
        let want = [
            b.force[0],
            b.force[1],
            b.moment[2],
            b.peak_force,
            s.kinetic_energy,
        ];
        for k in 0..5 {
            assert_eq!(
                got[k].to_bits(),
                want[k].to_bits(),
                "step {n}, output {k}: {got:?} vs {want:?}"
            );
        }
        t += h;
    }
    assert!(sim.barrier_displacement(0)[0] > 5e-4);
    let _ = std::fs::remove_dir_all(&dir);
}
