//! Every way a scene can be wrong is an error naming the file and, where it can, the line;
//! none of them panics.

use passgraph::scene::{SceneError, load_mesh, load_scene};
use proptest::prelude::*;
use std::path::{Path, PathBuf};

/// Writes `files` (name, content) into a fresh temp dir.
fn files(list: &[(&str, &str)]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for (name, content) in list {
        std::fs::write(dir.path().join(name), content).unwrap();
    }
    dir
}

/// A valid scene file naming `mesh`.
const SCENE: &str = "Scene(\n    mesh: \"mesh.obj\",\n    camera: Camera(eye: (0, 0, -5), target: (0, 0, 0), up: (0, 1, 0), fov_y: 40),\n)\n";

const QUAD: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";

fn load_error(path: &Path) -> (SceneError, String) {
    let error = match load_mesh(path) {
        Ok(_) => panic!("{} should not load", path.display()),
        Err(e) => e,
    };
    let message = error.to_string();
    (error, message)
}

/// Asserts the message points at `path:line`.
fn assert_names_line(message: &str, path: &Path, line: usize) {
    let at = format!("{}:{line}", path.display());
    assert!(message.contains(&at), "expected '{at}' in: {message}");
}

#[test]
fn missing_scene_file_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("nope.ron");
    let error = load_scene(&path).unwrap_err();
    assert!(matches!(error, SceneError::Io { .. }), "{error:?}");
    assert!(error.to_string().contains(&path.display().to_string()));
}

#[test]
fn ron_syntax_error_names_file_line_and_column() {
    let dir = files(&[(
        "scene.ron",
        "Scene(\n    mesh: \"mesh.obj\"\n    camera: oops,\n)\n",
    )]);
    let path = dir.path().join("scene.ron");
    let error = load_scene(&path).unwrap_err();
    match &error {
        SceneError::Ron { line, col, .. } => assert_eq!((*line, *col > 0), (3, true), "{error}"),
        other => panic!("expected a RON error, got {other:?}"),
    }
    assert_names_line(&error.to_string(), &path, 3);
}

#[test]
fn unknown_scene_field_is_rejected_with_its_line() {
    let text = SCENE.replace("fov_y: 40", "fov_y: 40, aperture: 2");
    let dir = files(&[("scene.ron", &text), ("mesh.obj", QUAD)]);
    let path = dir.path().join("scene.ron");
    let error = load_scene(&path).unwrap_err();
    assert!(
        matches!(error, SceneError::Ron { line: 3, .. }),
        "{error:?}"
    );
    assert!(error.to_string().contains("aperture"), "{error}");
}

#[test]
fn invalid_cameras_name_the_file_and_field_line() {
    for (from, to) in [
        ("target: (0, 0, 0)", "target: (0, 0, -5)"),
        ("up: (0, 1, 0)", "up: (0, 0, 3)"),
        ("up: (0, 1, 0)", "up: (0, 0, 0)"),
        ("fov_y: 40", "fov_y: 0"),
        ("fov_y: 40", "fov_y: 180"),
        ("fov_y: 40", "fov_y: -10"),
        ("fov_y: 40", "fov_y: NaN"),
    ] {
        let text = SCENE.replace(from, to);
        let dir = files(&[("scene.ron", &text), ("mesh.obj", QUAD)]);
        let path = dir.path().join("scene.ron");
        let error = load_scene(&path).unwrap_err();
        assert!(
            matches!(error, SceneError::Camera { .. }),
            "{to}: {error:?}"
        );
        assert_names_line(&error.to_string(), &path, 3);
    }
}

#[test]
fn missing_mesh_file_is_named() {
    let dir = files(&[("scene.ron", SCENE)]);
    let error = load_scene(&dir.path().join("scene.ron")).unwrap_err();
    assert!(matches!(error, SceneError::Io { .. }), "{error:?}");
    assert!(
        error
            .to_string()
            .contains(&dir.path().join("mesh.obj").display().to_string())
    );
}

#[test]
fn unsupported_mesh_extension_is_an_error() {
    let dir = files(&[("mesh.stl", QUAD), ("mesh", QUAD)]);
    for name in ["mesh.stl", "mesh"] {
        let (error, message) = load_error(&dir.path().join(name));
        assert!(
            matches!(error, SceneError::UnsupportedMeshFormat { .. }),
            "{error:?}"
        );
        assert!(message.contains(name));
    }
}

#[test]
fn non_finite_vertex_names_its_line() {
    for bad in [
        "nan 0 0",
        "0 inf 0",
        "0 0 -infinity",
        "1e39 0 0",
        "1 1 1 1e-40",
    ] {
        let text = format!("# header\nv 0 0 0\nv 1 0 0\nv {bad}\nf 1 2 3\n");
        let dir = files(&[("mesh.obj", &text)]);
        let path = dir.path().join("mesh.obj");
        let (error, message) = load_error(&path);
        assert!(
            matches!(error, SceneError::NonFiniteVertex { .. }),
            "{bad}: {error:?}"
        );
        assert_names_line(&message, &path, 4);
    }
}

#[test]
fn face_index_out_of_range_names_its_line() {
    for face in ["f 1 2 5", "f 0 1 2", "f -5 1 2", "f 1/1/1 2 9/1"] {
        let text = format!("v 0 0 0\nv 1 0 0\nv 1 1 0\n\nv 0 1 0\n{face}\n");
        let dir = files(&[("mesh.obj", &text)]);
        let path = dir.path().join("mesh.obj");
        let (error, message) = load_error(&path);
        assert!(
            matches!(error, SceneError::FaceIndexOutOfRange { .. }),
            "{face}: {error:?}"
        );
        assert_names_line(&message, &path, 6);
    }
}

#[test]
fn face_before_its_vertices_is_out_of_range() {
    let dir = files(&[("mesh.obj", "v 0 0 0\nf 1 2 3\nv 1 0 0\nv 1 1 0\n")]);
    let path = dir.path().join("mesh.obj");
    let (_, message) = load_error(&path);
    assert_names_line(&message, &path, 2);
}

#[test]
fn malformed_obj_lines_name_their_line() {
    for bad in [
        "v 1 2",
        "v 1 2 x",
        "v 1 2 3 4 5",
        "v 1 2 3 0",
        "f a b c",
        "f 1/2/3/4 2 3",
        "f",
    ] {
        let text = format!("v 0 0 0\nv 1 0 0\nv 1 1 0\n{bad}\nf 1 2 3\n");
        let dir = files(&[("mesh.obj", &text)]);
        let path = dir.path().join("mesh.obj");
        let (error, message) = load_error(&path);
        assert!(
            matches!(error, SceneError::Syntax { .. }),
            "{bad}: {error:?}"
        );
        assert_names_line(&message, &path, 4);
    }
}

#[test]
fn mesh_without_triangles_is_an_error() {
    for text in [
        "",
        "v 0 0 0\nv 1 0 0\n",
        "v 0 0 0\nv 1 0 0\nf 1 2\nl 1 2\nf 1\n",
    ] {
        let dir = files(&[("mesh.obj", text)]);
        let path = dir.path().join("mesh.obj");
        let (error, message) = load_error(&path);
        assert!(matches!(error, SceneError::NoTriangles { .. }), "{error:?}");
        assert!(message.contains(&path.display().to_string()));
    }
}

#[test]
fn usemtl_naming_an_undefined_material_names_its_line() {
    let obj = format!("mtllib m.mtl\n{QUAD}usemtl red\nusemtl bleu\nf 1 2 3\n");
    let dir = files(&[("mesh.obj", &obj), ("m.mtl", "newmtl red\nKd 1 0 0\n")]);
    let path = dir.path().join("mesh.obj");
    let (error, message) = load_error(&path);
    assert!(
        matches!(error, SceneError::UnknownMaterial { .. }),
        "{error:?}"
    );
    assert_names_line(&message, &path, 8);
    assert!(
        message.contains("bleu") && message.contains("red"),
        "{message}"
    );
}

#[test]
fn usemtl_without_any_material_library_is_an_error() {
    let dir = files(&[("mesh.obj", &format!("{QUAD}usemtl red\nf 1 2 3\n"))]);
    let path = dir.path().join("mesh.obj");
    let (error, message) = load_error(&path);
    assert!(
        matches!(error, SceneError::UnknownMaterial { .. }),
        "{error:?}"
    );
    assert_names_line(&message, &path, 6);
}

#[test]
fn missing_material_library_names_the_mtllib_line() {
    let dir = files(&[("mesh.obj", &format!("# box\nmtllib gone.mtl\n{QUAD}"))]);
    let path = dir.path().join("mesh.obj");
    let (error, message) = load_error(&path);
    assert!(
        matches!(error, SceneError::MissingMaterialLibrary { .. }),
        "{error:?}"
    );
    assert_names_line(&message, &path, 2);
    assert!(message.contains("gone.mtl"));
}

#[test]
fn malformed_mtl_lines_name_the_mtl_file_and_line_without_panicking() {
    // "Kd 0.5" makes tobj panic (it unwraps three numbers): it must never reach it.
    for bad in [
        "Kd 0.5",
        "Ks 1 1",
        "Ke 1 1 x",
        "Ka",
        "Ns",
        "Kd -1 0 0",
        "Ke nan 1 1",
        "Ns inf",
        "illum x",
        "newmtl",
    ] {
        let mtl = format!("newmtl a\n{bad}\n");
        let obj = format!("mtllib m.mtl\n{QUAD}");
        let dir = files(&[("mesh.obj", &obj), ("m.mtl", &mtl)]);
        let (error, message) = load_error(&dir.path().join("mesh.obj"));
        assert!(
            matches!(error, SceneError::Syntax { .. }),
            "{bad}: {error:?}"
        );
        assert_names_line(&message, &dir.path().join("m.mtl"), 2);
    }
}

#[test]
fn ply_face_index_out_of_range_names_the_line_or_face() {
    let ascii = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                 property float z\nelement face 2\nproperty list uchar int vertex_indices\n\
                 end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 3\n";
    let dir = files(&[("mesh.ply", ascii)]);
    let path = dir.path().join("mesh.ply");
    let (error, message) = load_error(&path);
    assert!(
        matches!(error, SceneError::FaceIndexOutOfRange { index: 3, .. }),
        "{error:?}"
    );
    assert_names_line(&message, &path, 14);

    let mut binary = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n\
property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
        .to_vec();
    for c in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0] {
        binary.extend(c.to_le_bytes());
    }
    binary.push(3);
    for i in [0i32, 1, 7] {
        binary.extend(i.to_le_bytes());
    }
    let path = dir.path().join("binary.ply");
    std::fs::write(&path, binary).unwrap();
    let (error, message) = load_error(&path);
    assert!(
        matches!(error, SceneError::FaceIndexOutOfRange { index: 7, .. }),
        "{error:?}"
    );
    assert!(
        message.contains("binary.ply") && message.contains("face 0"),
        "{message}"
    );
}

#[test]
fn ply_errors_name_file_and_line() {
    let header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                  property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    for (body, line, nan) in [
        ("0 0 0\n1e39 0 0\n0 1 0\n3 0 1 2\n", 11, true),
        ("0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n", 11, false),
        ("0 0 0\n1 0 0\n0 1 x\n3 0 1 2\n", 12, false),
        ("0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", 13, false),
    ] {
        let dir = files(&[("mesh.ply", &format!("{header}{body}"))]);
        let path = dir.path().join("mesh.ply");
        let (error, message) = load_error(&path);
        assert_eq!(
            matches!(error, SceneError::NonFiniteVertex { .. }),
            nan,
            "{error:?}"
        );
        assert_names_line(&message, &path, line);
    }
    let dir = files(&[(
        "mesh.ply",
        "ply\nformat ascii 1.0\nelement vertex 1\nbogus line\nend_header\n",
    )]);
    let path = dir.path().join("mesh.ply");
    let (_, message) = load_error(&path);
    assert_names_line(&message, &path, 4);
}

#[test]
fn binary_ply_nan_vertex_names_the_vertex() {
    let mut binary = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n\
property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
        .to_vec();
    for c in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, f32::NAN, 0.0] {
        binary.extend(c.to_le_bytes());
    }
    binary.push(3);
    for i in [0i32, 1, 2] {
        binary.extend(i.to_le_bytes());
    }
    let dir = files(&[]);
    let path = dir.path().join("nan.ply");
    std::fs::write(&path, binary).unwrap();
    let (error, message) = load_error(&path);
    assert!(
        matches!(error, SceneError::NonFiniteVertex { .. }),
        "{error:?}"
    );
    assert!(
        message.contains("nan.ply") && message.contains("vertex 2"),
        "{message}"
    );
}

#[test]
fn truncated_binary_ply_is_an_error() {
    let mut binary =
        b"ply\nformat binary_little_endian 1.0\nelement vertex 1000\nproperty float x\n\
property float y\nproperty float z\nend_header\n"
            .to_vec();
    binary.extend([0u8; 17]);
    let dir = files(&[]);
    let path = dir.path().join("mesh.ply");
    std::fs::write(&path, binary).unwrap();
    let (error, message) = load_error(&path);
    assert!(matches!(error, SceneError::Syntax { .. }), "{error:?}");
    assert!(message.contains("mesh.ply"), "{message}");
}

/// The Cornell box's OBJ lines, for mutation.
fn cornell_lines() -> Vec<String> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell/cornell.obj");
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(str::to_string)
        .collect()
}

/// A line that often starts with a keyword the OBJ or MTL parser acts on.
fn mangled_line() -> impl Strategy<Value = String> {
    let keyword = prop::sample::select(vec![
        "v", "f", "vt", "vn", "l", "o", "g", "usemtl", "mtllib", "newmtl", "Kd", "Ks", "Ke", "Ka",
        "Ns", "Ni", "d", "illum", "map_Kd", "bump", "#",
    ]);
    let args =
        "([-+]?[0-9]{0,3}(\\.[0-9]{0,2})?(e[-+]?[0-9]{1,2})?|nan|inf|/|//|[ -~]{0,3}| ){0,6}";
    prop_oneof![
        "[ -~]{0,24}",
        (keyword, args).prop_map(|(k, a)| format!("{k} {a}")),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn mangled_obj_and_mtl_files_never_panic(
        edits in prop::collection::vec((0usize..200, mangled_line()), 1..6),
        mtl_line in mangled_line(),
    ) {
        let mut lines = cornell_lines();
        for (at, text) in edits {
            let at = at % (lines.len() + 1);
            lines.insert(at, text);
        }
        let mtl = format!("newmtl white\n{mtl_line}\nnewmtl red\nnewmtl green\nnewmtl light\n");
        let dir = files(&[("cornell.obj", &lines.join("\n")), ("cornell.mtl", &mtl)]);
        // Ok or Err, never a panic.
        let _ = load_mesh(&dir.path().join("cornell.obj"));
    }

    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        let dir = files(&[]);
        for name in ["m.obj", "m.ply", "scene.ron"] {
            let path = dir.path().join(name);
            std::fs::write(&path, &bytes).unwrap();
            let _ = if name == "scene.ron" { load_scene(&path).map(|_| ()) } else { load_mesh(&path).map(|_| ()) };
        }
    }

    #[test]
    fn ply_headers_with_random_payloads_never_panic(
        ascii in any::<bool>(),
        payload in prop::collection::vec(any::<u8>(), 0..300),
    ) {
        let format = if ascii { "ascii" } else { "binary_big_endian" };
        let mut bytes = format!(
            "ply\nformat {format} 1.0\nelement vertex 4\nproperty double x\nproperty double y\n\
             property double z\nelement face 2\nproperty list uchar uint vertex_indices\nend_header\n"
        ).into_bytes();
        bytes.extend(payload);
        let dir = files(&[]);
        let path = dir.path().join("m.ply");
        std::fs::write(&path, bytes).unwrap();
        let _ = load_mesh(&path);
    }
}
