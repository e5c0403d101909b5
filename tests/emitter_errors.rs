//! Bad lights and environments in a scene file: each is an error naming the scene file, the
//! line of the light (or of `environment:`) and what is wrong; none panics. No GPU. Bad
//! environment images themselves (NaN, negative, infinite texels, compressions, sizes) are
//! tests/environment_image.rs's.

use passgraph::scene::load_scene;

const QUAD: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";

/// A scene whose fields after the camera are `extra`, and its load error.
fn error_of(extra: &str) -> (String, std::path::PathBuf, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("mesh.obj"), QUAD).unwrap();
    let text = format!(
        "Scene(\n    mesh: \"mesh.obj\",\n    camera: Camera(eye: (0, 0, -5), target: (0, 0, 0), up: (0, 1, 0), fov_y: 40),\n{extra}\n)\n"
    );
    let path = dir.path().join("scene.ron");
    std::fs::write(&path, text).unwrap();
    let message = match load_scene(&path) {
        Ok(_) => panic!("should not load:\n{extra}"),
        Err(e) => e.to_string(),
    };
    (message, path, dir)
}

fn assert_error(extra: &str, line: usize, parts: &[&str]) {
    let (message, path, _dir) = error_of(extra);
    let at = format!("{}:{line}", path.display());
    assert!(message.contains(&at), "expected '{at}' in: {message}");
    for part in parts {
        assert!(message.contains(part), "expected '{part}' in: {message}");
    }
}

#[test]
fn a_spot_cutoff_outside_0_to_90_degrees_is_refused() {
    for cutoff in ["0", "-5", "90.5", "180", "NaN"] {
        assert_error(
            &format!(
                "    lights: [\n        Point(position: (0, 1, 0), intensity: (1, 1, 1)),\n        Spot(position: (0, 2, 0), target: (0, 0, 0), intensity: (1, 1, 1), cutoff_angle: {cutoff}),\n    ],"
            ),
            6,
            &["lights[1]", "cutoff_angle", "(0, 90]"],
        );
    }
}

#[test]
fn a_beam_wider_than_the_cutoff_is_refused() {
    assert_error(
        "    lights: [Spot(position: (0, 2, 0), target: (0, 0, 0), intensity: (1, 1, 1), cutoff_angle: 20, beam_width: 30)],",
        4,
        &["beam_width", "cutoff_angle = 20"],
    );
}

#[test]
fn a_spot_up_along_its_axis_or_zero_is_refused() {
    for up in ["(0, 1, 0)", "(0, -3, 0)", "(0, 0, 0)"] {
        assert_error(
            &format!(
                "    lights: [Spot(position: (0, 2, 0), target: (0, 0, 0), up: {up}, intensity: (1, 1, 1))],"
            ),
            4,
            &["lights[0]", "up", "axis"],
        );
    }
}

#[test]
fn a_spot_texture_that_is_missing_or_not_an_image_names_the_file() {
    assert_error(
        "    lights: [Spot(position: (0, 2, 0), target: (0, 0, 0), intensity: (1, 1, 1), texture: \"slide.png\")],",
        4,
        &["lights[0]", "texture", "slide.png"],
    );
    let (message, _path, _dir) = {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("mesh.obj"), QUAD).unwrap();
        std::fs::write(dir.path().join("slide.png"), "not a PNG").unwrap();
        let path = dir.path().join("scene.ron");
        std::fs::write(
            &path,
            "Scene(\n    mesh: \"mesh.obj\",\n    camera: Camera(eye: (0, 0, -5), target: (0, 0, 0), up: (0, 1, 0), fov_y: 40),\n    lights: [Spot(position: (0, 2, 0), target: (0, 0, 0), intensity: (1, 1, 1), texture: \"slide.png\")],\n)\n",
        )
        .unwrap();
        let message = match load_scene(&path) {
            Ok(_) => panic!("a text file is no image"),
            Err(e) => e.to_string(),
        };
        (message, path, dir)
    };
    assert!(
        message.contains("slide.png") && message.contains("texture"),
        "{message}"
    );
}

#[test]
fn nan_or_infinite_positions_are_refused() {
    assert_error(
        "    lights: [Point(position: (0, NaN, 0), intensity: (1, 1, 1))],",
        4,
        &["lights[0]", "position", "finite"],
    );
    assert_error(
        "    lights: [Spot(position: (0, 1, 0), target: (inf, 0, 0), intensity: (1, 1, 1))],",
        4,
        &["target", "finite"],
    );
    assert_error(
        "    lights: [Point(position: (0, 1e30, 0), intensity: (1, 1, 1))],",
        4,
        &["position", "overflows"],
    );
}

#[test]
fn negative_or_nan_light_colours_are_refused() {
    assert_error(
        "    lights: [Point(position: (0, 1, 0), intensity: (1, -1, 1))],",
        4,
        &["intensity", "not negative"],
    );
    assert_error(
        "    lights: [Directional(direction: (0, -1, 0), irradiance: (NaN, 1, 1))],",
        4,
        &["irradiance"],
    );
    assert_error(
        "    environment: Environment(color: (1, 1, -0.5)),",
        4,
        &["color", "not negative"],
    );
}

#[test]
fn degenerate_directions_are_refused() {
    assert_error(
        "    lights: [Directional(direction: (0, 0, 0), irradiance: (1, 1, 1))],",
        4,
        &["direction", "nonzero"],
    );
    assert_error(
        "    lights: [Spot(position: (1, 1, 1), target: (1, 1, 1), intensity: (1, 1, 1))],",
        4,
        &["target must differ"],
    );
}

#[test]
fn an_environment_needs_exactly_one_of_file_and_color() {
    assert_error(
        "    environment: Environment(scale: 2),",
        4,
        &["file", "color"],
    );
    assert_error(
        "    environment: Environment(file: \"sky.exr\", color: (1, 1, 1)),",
        4,
        &["not both"],
    );
    assert_error(
        "    environment: Environment(color: (1, 1, 1), scale: -1),",
        4,
        &["scale"],
    );
    assert_error(
        "    environment: Environment(color: (1, 1, 1), to_world: [Rotate(axis: (0, 0, 0), angle: 3)]),",
        4,
        &["axis"],
    );
}

#[test]
fn a_missing_or_unreadable_environment_image_names_the_image_and_the_scene_line() {
    let (message, path, dir) = error_of("    environment: Environment(file: \"sky.exr\"),");
    let image = dir.path().join("sky.exr");
    assert!(
        message.contains(&format!("{}:4", path.display())),
        "{message}"
    );
    assert!(message.contains(&image.display().to_string()), "{message}");
    // A file that is no image.
    let (message, _, dir) = {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("mesh.obj"), QUAD).unwrap();
        std::fs::write(dir.path().join("sky.exr"), "not an image").unwrap();
        let path = dir.path().join("scene.ron");
        std::fs::write(&path, "Scene(\n    mesh: \"mesh.obj\",\n    camera: Camera(eye: (0, 0, -5), target: (0, 0, 0), up: (0, 1, 0), fov_y: 40),\n    environment: Environment(file: \"sky.exr\"),\n)\n").unwrap();
        (load_scene(&path).unwrap_err().to_string(), path, dir)
    };
    assert!(
        message.contains(&dir.path().join("sky.exr").display().to_string()),
        "{message}"
    );
}
