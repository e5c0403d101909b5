//! `max_depth`: the scene file's (Mitsuba's meaning, default 3) reaches the
//! `scene_max_depth` override; `--max-depth` replaces it; 0 or negative is an error naming
//! the scene file's line, or a usage error on the command line; -1 is unbounded, with
//! Russian roulette (`rr_depth`) only.

use passgraph::render::session::RenderSettings;
use passgraph::scene::load_scene;
use std::process::Command;

const QUAD: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";

fn scene(extra: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("mesh.obj"), QUAD).unwrap();
    let ron = format!(
        "Scene(\n    mesh: \"mesh.obj\",\n    camera: Camera(eye: (0, 0, -5), target: (0, 0, 0), up: (0, 1, 0), fov_y: 40),\n{extra})\n"
    );
    std::fs::write(dir.path().join("scene.ron"), ron).unwrap();
    dir
}

#[test]
fn default_is_three_and_the_file_sets_it() {
    let dir = scene("");
    let s = load_scene(&dir.path().join("scene.ron")).unwrap();
    assert_eq!((s.max_depth, s.to_gpu().max_depth), (3, 3));
    let dir = scene("    max_depth: 8,\n");
    let s = load_scene(&dir.path().join("scene.ron")).unwrap();
    assert_eq!((s.max_depth, s.to_gpu().max_depth), (8, 8));
}

#[test]
fn zero_or_negative_names_the_scene_file_line() {
    for value in ["0", "-2"] {
        let dir = scene(&format!("    max_depth: {value},\n"));
        let path = dir.path().join("scene.ron");
        let message = load_scene(&path).unwrap_err().to_string();
        let at = format!("{}:4", path.display());
        assert!(message.contains(&at), "expected '{at}' in {message}");
        assert!(message.contains("max_depth"), "{message}");
    }
}

#[test]
fn unbounded_is_minus_one_with_russian_roulette_and_an_error_without() {
    let dir = scene("    max_depth: -1,\n    rr_depth: 5,\n");
    let s = load_scene(&dir.path().join("scene.ron")).unwrap();
    assert_eq!(
        (s.max_depth, s.rr_depth),
        (passgraph::scene::MAX_MAX_DEPTH, Some(5))
    );
    assert_eq!(s.to_gpu().rr_depth, 5);
    for (fields, line, what) in [
        ("    max_depth: -1,\n", 4, "needs Russian roulette"),
        (
            "    max_depth: 8,\n    rr_depth: 0,\n",
            5,
            "rr_depth must be 1",
        ),
        (
            "    max_depth: 8,\n    rr_depth: -3,\n",
            5,
            "rr_depth must be 1",
        ),
    ] {
        let dir = scene(fields);
        let path = dir.path().join("scene.ron");
        let message = load_scene(&path).unwrap_err().to_string();
        let at = format!("{}:{line}", path.display());
        assert!(message.contains(&at), "expected '{at}' in {message}");
        assert!(message.contains(what), "{message}");
    }
    // Without rr_depth the scene has none, and its GPU form says so.
    let dir = scene("    max_depth: 8,\n");
    let s = load_scene(&dir.path().join("scene.ron")).unwrap();
    assert_eq!(s.rr_depth, None);
    assert_eq!(s.to_gpu().rr_depth, u32::MAX);
}

#[test]
fn settings_replace_the_scene_files_depth() {
    let settings = RenderSettings {
        max_depth: Some(5),
        ..RenderSettings::new("g.ron", "s.ron")
    };
    assert_eq!(settings.max_depth, Some(5));
}

#[test]
fn the_command_line_rejects_a_depth_of_zero() {
    for command in ["render", "view", "bench"] {
        let out = Command::new(env!("CARGO_BIN_EXE_passgraph"))
            .args([command, "--max-depth", "0"])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{command}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            stderr.contains("max_depth must be 1"),
            "{command}: {stderr}"
        );
    }
}

#[test]
fn render_specialises_on_the_command_lines_depth() {
    let dir = tempfile::tempdir().unwrap();
    let out_png = dir.path().join("out.png");
    let out = Command::new(env!("CARGO_BIN_EXE_passgraph"))
        .args([
            "render",
            "--frames",
            "1",
            "--size",
            "16x16",
            "--max-depth",
            "5",
            "--out",
        ])
        .arg(&out_png)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("scene_max_depth=5"), "{stderr}");
}
