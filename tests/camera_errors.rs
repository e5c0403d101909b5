//! Bad lens, field-of-view, orthographic and filter input in a scene file: an error naming the
//! file, the line of the field and what is wrong; never a panic.

use passgraph::scene::{SceneError, load_scene};
use std::path::Path;

const QUAD: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";

/// A scene file with each camera field on its own line: `fields` (one per line, from line 5)
/// inside `Camera(` and `after` after the camera.
fn scene_text(kind: &str, fields: &[&str], after: &str) -> String {
    let mut text = format!(
        "Scene(\n    mesh: \"mesh.obj\",\n    camera: {kind}(\n        eye: (0, 0, -5), target: (0, 0, 0), up: (0, 1, 0),\n"
    );
    for f in fields {
        text += &format!("        {f},\n");
    }
    text += "    ),\n";
    text += after;
    text + ")\n"
}

/// Loads `text` as a scene; returns the error and the file's path.
fn error_of(text: &str) -> (SceneError, String, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("mesh.obj"), QUAD).unwrap();
    let path = dir.path().join("scene.ron");
    std::fs::write(&path, text).unwrap();
    let error = match load_scene(&path) {
        Ok(_) => panic!("should not load:\n{text}"),
        Err(e) => e,
    };
    let message = error.to_string();
    (error, message, dir)
}

fn assert_at(message: &str, path: &Path, line: usize, what: &str) {
    let at = format!("{}:{line}", path.display());
    assert!(message.contains(&at), "expected '{at}' in: {message}");
    assert!(message.contains(what), "expected '{what}' in: {message}");
}

#[test]
fn bad_lenses_name_the_field_line() {
    for (fields, line, what) in [
        (
            &["fov_y: 40", "aperture_radius: -1", "focus_distance: 5"][..],
            6,
            "aperture_radius is -1",
        ),
        (
            &["fov_y: 40", "aperture_radius: 0", "focus_distance: 5"],
            6,
            "aperture_radius is 0",
        ),
        (
            &["fov_y: 40", "aperture_radius: NaN", "focus_distance: 5"],
            6,
            "aperture_radius is NaN",
        ),
        (
            &["fov_y: 40", "aperture_radius: inf", "focus_distance: 5"],
            6,
            "aperture_radius is inf",
        ),
        (
            &["fov_y: 40", "aperture_radius: 1", "focus_distance: 0"],
            7,
            "focus_distance is 0",
        ),
        (
            &["fov_y: 40", "aperture_radius: 1", "focus_distance: -2"],
            7,
            "focus_distance is -2",
        ),
        (
            &["fov_y: 40", "aperture_radius: 1", "focus_distance: NaN"],
            7,
            "focus_distance is NaN",
        ),
        (
            &["fov_y: 40", "aperture_radius: 1", "focus_distance: -inf"],
            7,
            "focus_distance is -inf",
        ),
        (
            &["fov_y: 40", "aperture_radius: 1"],
            6,
            "needs a focus_distance",
        ),
        (
            &["fov_y: 40", "focus_distance: 3"],
            6,
            "without aperture_radius",
        ),
    ] {
        let (error, message, dir) = error_of(&scene_text("Camera", fields, ""));
        assert!(matches!(error, SceneError::Camera { .. }), "{error:?}");
        assert_at(&message, &dir.path().join("scene.ron"), line, what);
    }
}

#[test]
fn bad_fields_of_view_name_the_field_line() {
    for (fields, line, what) in [
        (&["fov: 0"][..], 5, "fov is 0"),
        (&["fov: 180"], 5, "fov is 180"),
        (&["fov: NaN", "fov_axis: Y"], 5, "fov is NaN"),
        (&["fov_y: 40", "fov: 30"], 6, "not both"),
        (
            &["fov_y: 40", "fov_axis: X"],
            6,
            "fov_axis applies to fov only",
        ),
    ] {
        let (error, message, dir) = error_of(&scene_text("Camera", fields, ""));
        assert!(matches!(error, SceneError::Camera { .. }), "{error:?}");
        assert_at(&message, &dir.path().join("scene.ron"), line, what);
    }
    // No field of view at all: the camera's line.
    let (_, message, dir) = error_of(&scene_text("Camera", &[], ""));
    assert_at(
        &message,
        &dir.path().join("scene.ron"),
        3,
        "needs a field of view",
    );
    // An axis Mitsuba does not have is a schema error at its line.
    let (error, message, _dir) = error_of(&scene_text("Camera", &["fov: 40", "fov_axis: Z"], ""));
    assert!(
        matches!(error, SceneError::Ron { line: 6, .. }),
        "{error:?}"
    );
    assert!(message.contains('Z'), "{message}");
}

#[test]
fn bad_orthographic_widths_name_the_field_line() {
    for (width, what) in [
        ("0", "width is 0"),
        ("-4", "width is -4"),
        ("NaN", "width is NaN"),
        ("inf", "width is inf"),
        ("1e30", "beyond"),
    ] {
        let field = format!("width: {width}");
        let (error, message, dir) = error_of(&scene_text("Orthographic", &[&field], ""));
        assert!(matches!(error, SceneError::Camera { .. }), "{error:?}");
        assert_at(&message, &dir.path().join("scene.ron"), 5, what);
    }
    // A lens on an orthographic camera is not a field it has.
    let (error, _, _dir) = error_of(&scene_text(
        "Orthographic",
        &["width: 2", "aperture_radius: 1"],
        "",
    ));
    assert!(
        matches!(error, SceneError::Ron { line: 6, .. }),
        "{error:?}"
    );
}

#[test]
fn bad_filters_name_the_filter_line() {
    for (filter, what) in [
        ("Gaussian(stddev: 0)", "Gaussian stddev is 0"),
        ("Gaussian(stddev: -0.5)", "Gaussian stddev is -0.5"),
        ("Gaussian(stddev: NaN)", "Gaussian stddev is NaN"),
        ("Gaussian(stddev: inf)", "Gaussian stddev is inf"),
        ("Tent(radius: 0)", "Tent radius is 0"),
        ("Tent(radius: -1)", "Tent radius is -1"),
        ("Tent(radius: NaN)", "Tent radius is NaN"),
        ("Tent(radius: inf)", "Tent radius is inf"),
    ] {
        let after = format!("    max_depth: 2,\n    filter: {filter},\n");
        let (error, message, dir) = error_of(&scene_text("Camera", &["fov_y: 40"], &after));
        assert!(matches!(error, SceneError::Syntax { .. }), "{error:?}");
        assert_at(&message, &dir.path().join("scene.ron"), 8, what);
    }
    let after = "    filter: Lanczos,\n";
    let (error, _, _dir) = error_of(&scene_text("Camera", &["fov_y: 40"], after));
    assert!(
        matches!(error, SceneError::Ron { line: 7, .. }),
        "{error:?}"
    );
}

#[test]
fn good_cameras_and_filters_load() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("mesh.obj"), QUAD).unwrap();
    let path = dir.path().join("scene.ron");
    for (kind, fields, after) in [
        (
            "Camera",
            &[
                "fov: 40",
                "fov_axis: Diagonal",
                "aperture_radius: 0.1",
                "focus_distance: 5",
            ][..],
            "    filter: Gaussian(stddev: 0.5),\n",
        ),
        ("Camera", &["fov: 40"], "    filter: Tent(radius: 1),\n"),
        ("Orthographic", &["width: 3"], "    filter: Box,\n"),
    ] {
        std::fs::write(&path, scene_text(kind, fields, after)).unwrap();
        load_scene(&path).unwrap_or_else(|e| panic!("{kind} {fields:?}: {e}"));
    }
}
