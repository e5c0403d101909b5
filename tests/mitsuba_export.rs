//! `passgraph mitsuba-scene`: the loaded scene written for Mitsuba 3 (scripts/mitsuba-reference
//! renders through it); a material Mitsuba cannot render is an error naming it.

use std::path::Path;
use std::process::{Command, Output};

fn export(scene: &Path, out: &Path, extra: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_passgraph"))
        .arg("mitsuba-scene")
        .arg(scene)
        .arg("--out")
        .arg(out)
        .args(extra)
        .output()
        .unwrap()
}

fn write(dir: &Path, files: &[(&str, &[u8])]) {
    for (name, content) in files {
        std::fs::write(dir.join(name), content).unwrap();
    }
}

const SCENE: &str = "Scene(mesh: \"m.obj\", camera: Camera(eye: (0, 0, -5), target: (0, 0, 0), up: (0, 1, 0), fov_y: 40), max_depth: 6)\n";

#[test]
fn the_cornell_box_becomes_xml_and_one_mesh_per_material() {
    let out = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell/scene.ron");
    let result = export(&scene, out.path(), &["--size", "64x32", "--max-depth", "5"]);
    assert!(
        result.status.success(),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    let xml = std::fs::read_to_string(out.path().join("scene.xml")).unwrap();
    for part in [
        "<default name=\"max_depth\" value=\"5\"/>",
        "name=\"width\" value=\"64\"",
        "name=\"height\" value=\"32\"",
        "<emitter type=\"area\">",
        "face_normals",
    ] {
        assert!(xml.contains(part), "{part} in {xml}");
    }
    let loaded = passgraph::scene::load_scene(&scene).unwrap();
    let shapes = xml.matches("<shape type=\"obj\">").count();
    let mut triangles = 0;
    for n in 0..shapes {
        let obj = std::fs::read_to_string(out.path().join(format!("meshes/mesh{n}.obj"))).unwrap();
        triangles += obj.lines().filter(|l| l.starts_with("f ")).count();
    }
    assert_eq!(triangles, loaded.mesh.triangles.len());
}

#[test]
fn normals_uvs_and_maps_are_exported() {
    let dir = tempfile::tempdir().unwrap();
    let image = image::RgbImage::from_raw(1, 1, vec![200, 100, 50]).unwrap();
    image.save(dir.path().join("t.png")).unwrap();
    write(
        dir.path(),
        &[
            ("scene.ron", SCENE.as_bytes()),
            (
                "m.obj",
                b"mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 -1\nusemtl a\nf 1/1/1 2/2/1 3/3/1\n",
            ),
            ("m.mtl", b"newmtl a\nPm 0\nPr 0.5\nKd 1 1 1\nmap_Kd t.png\n"),
        ],
    );
    let out = dir.path().join("out");
    let result = export(&dir.path().join("scene.ron"), &out, &[]);
    assert!(
        result.status.success(),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    let xml = std::fs::read_to_string(out.join("scene.xml")).unwrap();
    let png = std::fs::canonicalize(dir.path().join("t.png")).unwrap();
    for part in [
        "<default name=\"max_depth\" value=\"6\"/>",
        "roughplastic",
        "name=\"alpha\" value=\"0.25\"",
        &format!("value=\"{}\"", png.display()),
    ] {
        assert!(xml.contains(part), "{part} in {xml}");
    }
    assert!(!xml.contains("face_normals"), "{xml}");
    let obj = std::fs::read_to_string(out.join("meshes/mesh0.obj")).unwrap();
    assert!(
        obj.contains("vt 1 0") && obj.contains("vn 0 0 -1") && obj.contains("f 1/1/1"),
        "{obj}"
    );
}

#[test]
fn a_phong_material_is_an_error_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        &[
            ("scene.ron", SCENE.as_bytes()),
            (
                "m.obj",
                b"mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl shiny\nf 1 2 3\n",
            ),
            (
                "m.mtl",
                b"newmtl shiny\nKd 0.5 0.5 0.5\nKs 0.5 0.5 0.5\nNs 20\n",
            ),
        ],
    );
    let out = dir.path().join("out");
    let result = export(&dir.path().join("scene.ron"), &out, &[]);
    assert_eq!(result.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(
        stderr.contains("material 'shiny' is Blinn-Phong, which Mitsuba 3 has no plugin for"),
        "{stderr}"
    );
    // Nothing is written for a scene that cannot be exported.
    assert!(!out.join("scene.xml").exists());
}

/// The race gives Mitsuba its default Russian roulette as well as none (scripts/benchmarks):
/// the exported scene takes `rr_depth` as a parameter whose default is the passgraph scene's,
/// and passgraph reads both back as written.
#[test]
fn russian_roulette_is_a_parameter_defaulting_to_the_scenes() {
    let out = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell/scene.ron");
    let result = export(&scene, out.path(), &["--size", "16x16", "--max-depth", "8"]);
    assert!(
        result.status.success(),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    let xml = out.path().join("scene.xml");
    let text = std::fs::read_to_string(&xml).unwrap();
    assert!(
        text.contains("<integer name=\"rr_depth\" value=\"$rr_depth\"/>"),
        "{text}"
    );
    let load = |defines: Vec<(String, String)>| {
        let options = passgraph::scene::SceneOptions {
            defines,
            ..Default::default()
        };
        passgraph::scene::load_scene_with(&xml, &options)
            .unwrap()
            .scene
    };
    // The Cornell box has no roulette, so neither has its export...
    assert_eq!(passgraph::scene::load_scene(&scene).unwrap().rr_depth, None);
    let exported = load(Vec::new());
    assert_eq!((exported.max_depth, exported.rr_depth), (8, None));
    // ... until Mitsuba's default is asked for.
    let with_roulette = load(vec![("rr_depth".into(), "5".into())]);
    assert_eq!(with_roulette.rr_depth, Some(5));
}
