//! The pinhole camera of docs/design.md §4: basis, pixel mapping (rows go down), aspect, field of
//! view, and the inputs that cannot make a camera.

use glam::Vec3;
use passgraph::scene::camera::{project, screen_coordinates};
use passgraph::scene::{CameraDesc, CameraError};

const EYE: Vec3 = Vec3::new(278.0, 273.0, -800.0);
const TARGET: Vec3 = Vec3::new(278.0, 273.0, 0.0);

fn cornell_camera() -> CameraDesc {
    CameraDesc::new(EYE, TARGET, Vec3::Y, 39.3077).unwrap()
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5
}

#[test]
fn basis_is_forward_right_up_with_right_from_cross_forward_up() {
    let [forward, right, up] = cornell_camera().basis();
    assert_eq!(forward, Vec3::Z);
    // cross(+z, +y) = -x.
    assert_eq!(right, -Vec3::X);
    assert_eq!(up, Vec3::Y);
}

#[test]
fn gpu_camera_scales_right_and_up_by_fov_and_aspect() {
    let desc = cornell_camera();
    let camera = desc.to_gpu(200, 100);
    let t = (39.3077f32.to_radians() / 2.0).tan();
    assert_eq!(camera.eye, [278.0, 273.0, -800.0]);
    assert_eq!(camera.forward, [0.0, 0.0, 1.0]);
    assert!(close(Vec3::from(camera.up), Vec3::Y * t));
    assert!(close(Vec3::from(camera.right), -Vec3::X * t * 2.0));
    // Padding, and a pinhole's lens fields, are zero, so the uniform's bytes are deterministic
    // (and what they were before the lens existed).
    assert_eq!(
        (
            camera.aperture_radius,
            camera.focus_distance,
            camera.pad2,
            camera.pad3
        ),
        (0.0, 0.0, 0.0, 0.0)
    );
}

#[test]
fn pixel_rows_go_down_and_columns_go_right() {
    assert_eq!(screen_coordinates(4, 2, 0.0, 0.0), (-1.0, 1.0));
    assert_eq!(screen_coordinates(4, 2, 4.0, 2.0), (1.0, -1.0));
    assert_eq!(screen_coordinates(4, 2, 2.0, 1.0), (0.0, 0.0));
    let desc = cornell_camera();
    let camera = desc.to_gpu(64, 64);
    let [forward, right, up] = desc.basis();
    // The image centre looks straight ahead.
    assert!(close(camera.ray_direction(64, 64, 32.0, 32.0), forward));
    // Top-left pixel corner: left (-right) and up.
    let d = camera.ray_direction(64, 64, 0.0, 0.0);
    assert!(d.dot(right) < 0.0 && d.dot(up) > 0.0);
    // Lower rows look further down.
    let upper = camera.ray_direction(64, 64, 10.5, 5.5);
    let lower = camera.ray_direction(64, 64, 10.5, 50.5);
    assert!(upper.dot(up) > lower.dot(up));
}

#[test]
fn vertical_field_of_view_spans_the_image_height() {
    let desc = CameraDesc::new(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0), Vec3::Y, 60.0).unwrap();
    let camera = desc.to_gpu(300, 100);
    let top = camera.ray_direction(300, 100, 150.0, 0.0);
    let bottom = camera.ray_direction(300, 100, 150.0, 100.0);
    let angle = top.angle_between(bottom).to_degrees();
    assert!((angle - 60.0).abs() < 1e-3, "{angle}");
    // Horizontally the aspect widens it: 2 atan(3 tan 30°).
    let left = camera.ray_direction(300, 100, 0.0, 50.0);
    let right = camera.ray_direction(300, 100, 300.0, 50.0);
    let expected = 2.0 * (3.0 * 30f32.to_radians().tan()).atan().to_degrees();
    assert!((left.angle_between(right).to_degrees() - expected).abs() < 1e-3);
}

#[test]
fn project_inverts_ray_direction() {
    let desc = cornell_camera();
    let camera = desc.to_gpu(128, 96);
    for (px, py) in [(0.0, 0.0), (17.25, 80.5), (64.0, 48.0), (127.9, 1.0)] {
        let d = camera.ray_direction(128, 96, px, py);
        let (sx, sy) = project(&camera, Vec3::from(camera.eye) + 500.0 * d).unwrap();
        let (ex, ey) = screen_coordinates(128, 96, px, py);
        assert!((sx - ex).abs() < 1e-4 && (sy - ey).abs() < 1e-4);
    }
    assert_eq!(
        project(&camera, Vec3::new(278.0, 273.0, -900.0)),
        None,
        "behind the eye"
    );
}

#[test]
fn degenerate_cameras_are_errors() {
    let cases = [
        ((EYE, EYE, Vec3::Y, 40.0), CameraError::EyeAtTarget),
        (
            (EYE, TARGET, Vec3::Z, 40.0),
            CameraError::UpParallelToForward,
        ),
        (
            (EYE, TARGET, -Vec3::Z * 3.0, 40.0),
            CameraError::UpParallelToForward,
        ),
        (
            (EYE, TARGET, Vec3::ZERO, 40.0),
            CameraError::UpParallelToForward,
        ),
        ((EYE, TARGET, Vec3::Y, 0.0), CameraError::FieldOfView(0.0)),
        (
            (EYE, TARGET, Vec3::Y, 180.0),
            CameraError::FieldOfView(180.0),
        ),
        ((EYE, TARGET, Vec3::Y, -5.0), CameraError::FieldOfView(-5.0)),
        (
            (Vec3::splat(f32::NAN), TARGET, Vec3::Y, 40.0),
            CameraError::NonFinite,
        ),
        (
            (EYE, TARGET, Vec3::new(0.0, f32::INFINITY, 0.0), 40.0),
            CameraError::NonFinite,
        ),
    ];
    for ((eye, target, up, fov), expected) in cases {
        assert_eq!(CameraDesc::new(eye, target, up, fov), Err(expected));
    }
    assert!(matches!(
        CameraDesc::new(EYE, TARGET, Vec3::Y, f32::NAN),
        Err(CameraError::FieldOfView(_))
    ));
    // Up need not be perpendicular or unit length.
    let tilted = CameraDesc::new(EYE, TARGET, Vec3::new(0.0, 5.0, 1.0), 40.0).unwrap();
    assert_eq!(tilted.basis()[2], Vec3::Y);
    assert_eq!(tilted.up(), Vec3::new(0.0, 5.0, 1.0));
}

#[test]
fn empty_image_sides_count_as_one_instead_of_dividing_by_zero() {
    let camera = cornell_camera().to_gpu(0, 0);
    assert!(camera.right.iter().chain(&camera.up).all(|c| c.is_finite()));
    assert_eq!(camera, cornell_camera().to_gpu(1, 1));
}
