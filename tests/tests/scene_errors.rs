//! Bad scene input gets a clear error naming the file, key path and line.

use granmix_core::input::load_scene_str;
use granmix_core::scene::SceneError;

const GOOD: &str = r#"
[simulation]
dimension = 2
gravity = [0.0, -9.81]
end_time = 0.1
dp = 0.01
output_interval = 0.01

[[materials]]
name = "sand"
density = 2000.0
youngs_modulus = 5e6
poisson_ratio = 0.3
friction_angle = 30.0

[[regions]]
name = "block"
material = "sand"
shape = { type = "box", min = [0.0, 0.0], max = [0.1, 0.1] }
"#;

fn err(text: &str, set: &[&str]) -> SceneError {
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    load_scene_str(text, "bad.toml", &set).expect_err("must be rejected")
}

#[test]
fn good_scene_loads() {
    load_scene_str(GOOD, "good.toml", &[]).unwrap();
}

#[test]
fn unknown_key_names_path_and_line() {
    let text = GOOD.replace("dp = 0.01", "dp = 0.01\ntimestep = 3");
    let e = err(&text, &[]);
    let msg = e.to_string();
    assert!(msg.contains("timestep"), "{msg}");
    assert!(msg.starts_with("bad.toml:7:"), "{msg}");
    assert!(e.path.starts_with("simulation"), "{}", e.path);
}

#[test]
fn unknown_key_in_array_of_tables() {
    let text = GOOD.replace(
        "friction_angle = 30.0",
        "friction_angle = 30.0\nfriction = 0.5",
    );
    let e = err(&text, &[]);
    assert!(e.to_string().contains("friction"), "{e}");
    assert_eq!(e.line, Some(15), "{e}");
    assert_eq!(e.path, "materials[0].friction");
}

#[test]
fn invalid_values_name_key_and_line() {
    let e = err(
        &GOOD.replace("poisson_ratio = 0.3", "poisson_ratio = 0.7"),
        &[],
    );
    assert_eq!(e.path, "materials[0].poisson_ratio");
    assert_eq!(e.line, Some(13));
    let e = err(
        &GOOD.replace("material = \"sand\"", "material = \"clay\""),
        &[],
    );
    assert_eq!(e.path, "regions[0].material");
    assert!(e.message.contains("unknown material `clay`"), "{e}");
    let e = err(
        &GOOD.replace("gravity = [0.0, -9.81]", "gravity = [0.0, 0.0, -9.81]"),
        &[],
    );
    assert_eq!(e.path, "simulation.gravity");
    assert_eq!(e.line, Some(4));
    let e = err(&GOOD.replace("dp = 0.01", "dp = \"fine\""), &[]);
    assert_eq!(e.line, Some(6), "{e}");
    let e = err(&GOOD.replace("type = \"box\"", "type = \"cube\""), &[]);
    assert!(e.to_string().contains("cube"), "{e}");
    assert_eq!(e.line, Some(19), "{e}");
}

#[test]
fn overrides_apply_and_report_errors() {
    let ok = load_scene_str(
        GOOD,
        "good.toml",
        &[
            "simulation.dp=0.02".into(),
            "materials.0.friction_angle=25".into(),
        ],
    )
    .unwrap();
    assert_eq!(ok.scene.simulation.dp, 0.02);
    assert_eq!(ok.scene.materials[0].friction_angle, Some(25.0));
    let e = err(GOOD, &["materials.3.density=1"]);
    assert!(e.to_string().contains("out of range"), "{e}");
    let e = err(GOOD, &["simulation.dp"]);
    assert!(e.to_string().contains("key.path=value"), "{e}");
    let e = err(GOOD, &["simulation.bogus=1"]);
    assert!(e.to_string().contains("bogus"), "{e}");
}

#[test]
fn syntax_error_has_line() {
    let e = err(&GOOD.replace("end_time = 0.1", "end_time = = 0.1"), &[]);
    assert_eq!(e.line, Some(5), "{e}");
}

const BODY: &str = r#"
[[solids]]
name = "rock"
density = 2500.0
youngs_modulus = 1e9
poisson_ratio = 0.2

[[bodies]]
name = "boulder"
material = "rock"
model = "rigid"
shape = { type = "sphere", center = [0.05, 0.2], radius = 0.02 }
"#;

#[test]
fn body_errors_name_the_key() {
    let good = format!("{GOOD}{BODY}");
    load_scene_str(&good, "good.toml", &[]).unwrap();
    // a fine-grain material is not a solid
    let e = err(
        &good.replace("material = \"rock\"", "material = \"sand\""),
        &[],
    );
    assert_eq!(e.path, "bodies[0].material", "{e}");
    assert!(e.to_string().contains("[[solids]]"), "{e}");
    // unknown model
    let e = err(
        &good.replace("model = \"rigid\"", "model = \"plastic\""),
        &[],
    );
    assert!(e.to_string().contains("bodies"), "{e}");
    assert!(e.line.is_some(), "{e}");
    // an elastic body cannot be fixed
    let e = err(
        &good.replace("model = \"rigid\"", "model = \"elastic\"\nfixed = true"),
        &[],
    );
    assert_eq!(e.path, "bodies[0].fixed", "{e}");
    // restitution outside (0, 1]
    let e = err(&format!("{good}\n[contact]\nrestitution = 1.5\n"), &[]);
    assert_eq!(e.path, "contact.restitution", "{e}");
    // wrong rotation arity in 2D
    let e = err(&good, &["bodies.0.rotation=[1.0, 2.0, 3.0]"]);
    assert_eq!(e.path, "bodies[0].rotation", "{e}");
}

#[test]
fn missing_mesh_and_terrain_files_name_the_key() {
    let text = &mesh_boulder("no_such_rock.obj");
    let e = err(text, &[]);
    assert_eq!(e.path, "bodies[0].shape.file", "{e}");
    assert!(e.to_string().contains("no_such_rock.obj"), "{e}");
    assert!(e.line.is_some(), "{e}");
    let text = text.replace(
        "[[bodies]]",
        "[[walls]]\nname = \"ground\"\nshape = { type = \"heightmap\", file = \"none.asc\" }\n\n[[bodies]]",
    );
    let text = text.replace("no_such_rock.obj", "none.asc");
    let e = err(&text, &[]);
    assert!(e.path.ends_with(".shape.file"), "{e}");
}

const ROCKS: &str = r#"
[[solids]]
name = "rock"
density = 2400.0
youngs_modulus = 1e9
poisson_ratio = 0.2

[[rock_fills]]
name = "rock"
material = "rock"
model = "rigid"
region = { type = "box", min = [0.0, 0.0], max = [0.1, 0.1] }
content = 0.2
size = 0.015
seed = 4
clearance = 0.004
"#;

#[test]
fn rock_fills_place_the_content_reproducibly_or_say_why_not() {
    let text = format!("{GOOD}{ROCKS}");
    let a = load_scene_str(&text, "rocks.toml", &[]).unwrap();
    let b = load_scene_str(&text, "rocks.toml", &[]).unwrap();
    let r = &a.scene.rock_reports[0];
    assert!(r.rocks > 0 && (r.content - 0.2).abs() < 0.5 * 0.2 / r.rocks as f64 + 1e-12);
    // the same seed gives the same rocks
    assert_eq!(
        format!("{:?}", a.scene.bodies),
        format!("{:?}", b.scene.bodies)
    );
    let e = err(&text, &["rock_fills.0.content=0.48"]);
    assert_eq!(e.path, "rock_fills[0].content", "{e}");
    assert!(e.to_string().contains("could not place"), "{e}");
    // an error in a `--set` value names that argument, not a line of the file
    let e = err(&text, &["rock_fills.0.material=\"sand\""]);
    assert_eq!(e.path, "rock_fills[0].material", "{e}");
    assert_eq!(e.file, "--set rock_fills.0.material=\"sand\"", "{e}");
    assert_eq!(e.line, None, "{e}");
}

#[test]
fn a_mesh_error_names_the_file_once() {
    let dir = std::env::temp_dir().join(format!("granmix_mesh_err_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("rock.ply"), "ply\n").unwrap();
    let text = &mesh_boulder("rock.ply");
    let e = granmix_core::input::load_scene_in(text, "bad.toml", &[], &dir)
        .expect_err("an unknown mesh format is refused");
    let msg = e.to_string();
    assert_eq!(e.path, "bodies[0].shape.file", "{msg}");
    assert!(msg.contains("unknown mesh format `.ply`"), "{msg}");
    assert_eq!(msg.matches("rock.ply").count(), 1, "{msg}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_region_outside_every_container_is_refused() {
    let text =
        format!("{GOOD}\n[[containers]]\nname = \"tank\"\nmin = [0.0, 0.0]\nmax = [0.5, 0.5]\n");
    load_scene_str(&text, "good.toml", &[]).unwrap();
    // beside the closed +x face: no grain can reach the tank
    let outside = text.replace(
        "min = [0.0, 0.0], max = [0.1, 0.1]",
        "min = [0.6, 0.0], max = [0.7, 0.1]",
    );
    let e = err(&outside, &[]);
    assert_eq!(e.path, "regions[0].shape", "{e}");
    assert_eq!(e.line, Some(19), "{e}");
    let msg = e.to_string();
    assert!(
        msg.contains("region `block` lies entirely outside container `tank`"),
        "{msg}"
    );
    assert!(msg.contains("+x face at x = 0.5"), "{msg}");
    // above the open top it is poured in; straddling the wall it is partly inside
    let above = text.replace(
        "min = [0.0, 0.0], max = [0.1, 0.1]",
        "min = [0.1, 0.6], max = [0.2, 0.7]",
    );
    load_scene_str(&above, "above.toml", &[]).unwrap();
    let straddling = text.replace(
        "min = [0.0, 0.0], max = [0.1, 0.1]",
        "min = [0.45, 0.0], max = [0.6, 0.1]",
    );
    load_scene_str(&straddling, "straddling.toml", &[]).unwrap();
    // with the +x face open the region may flow in
    let open = outside.replace(
        "max = [0.5, 0.5]\n",
        "max = [0.5, 0.5]\nopen = [\"+y\", \"+x\"]\n",
    );
    load_scene_str(&open, "open.toml", &[]).unwrap();
}

/// A 3D scene of one rigid boulder whose shape is the mesh `file`.
fn mesh_boulder(file: &str) -> String {
    format!(
        r#"
[simulation]
dimension = 3
gravity = [0.0, 0.0, -9.81]
end_time = 0.1
dp = 0.01
output_interval = 0.01

[[solids]]
name = "rock"
density = 2500.0
youngs_modulus = 1e9
poisson_ratio = 0.2

[[bodies]]
name = "boulder"
material = "rock"
model = "rigid"
shape = {{ type = "mesh", file = "{file}" }}
"#
    )
}

#[test]
fn sleep_thresholds_are_checked_and_the_key_named() {
    let e = err(GOOD, &["numerics.sleep=true", "numerics.sleep_steps=1"]);
    assert_eq!(e.path, "numerics.sleep_steps", "{e}");
    assert!(e.message.contains("[2, 65535]"), "{e}");
    let e = err(GOOD, &["numerics.sleep=true", "numerics.sleep_speed=-1e-3"]);
    assert_eq!(e.path, "numerics.sleep_speed", "{e}");
    let no_g = GOOD.replace("gravity = [0.0, -9.81]", "gravity = [0.0, 0.0]");
    let e = err(&no_g, &["numerics.sleep=true"]);
    assert_eq!(e.path, "numerics.sleep_speed", "{e}");
    assert!(e.message.contains("needs gravity"), "{e}");
    let e = err(&no_g, &["numerics.sleep=true", "numerics.sleep_speed=1e-3"]);
    assert_eq!(e.path, "numerics.sleep_acceleration", "{e}");
    load_scene_str(
        &no_g,
        "good.toml",
        &[
            "numerics.sleep=true".into(),
            "numerics.sleep_speed=1e-3".into(),
            "numerics.sleep_acceleration=0.5".into(),
        ],
    )
    .unwrap();
    let wet = format!("{GOOD}\n[water]\ndensity = 1000.0\n");
    let e = err(&wet, &["numerics.sleep=true"]);
    assert_eq!(e.path, "numerics.sleep", "{e}");
}
