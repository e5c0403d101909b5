//! The pinhole camera (docs/design.md §4): eye, target, up and a vertical field of view, turned into the
//! scaled basis the shaders use.

use super::gpu::GpuCamera;
use super::mesh::MAX_COORDINATE;
use glam::Vec3;
use thiserror::Error;

/// A camera as a scene file describes it. Only valid cameras exist (see [`CameraDesc::new`]),
/// so turning one into a [`GpuCamera`] cannot fail.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraDesc {
    eye: Vec3,
    target: Vec3,
    up: Vec3,
    fov_y_degrees: f32,
    /// Unit forward, right = normalize(cross(forward, up)), and up = cross(right, forward).
    basis: [Vec3; 3],
}

#[derive(Clone, Debug, PartialEq, Error)]
pub enum CameraError {
    #[error("eye, target and up must be finite numbers")]
    NonFinite,
    #[error(
        "{what} has a coordinate of {value:e}, beyond ±{max:e} where the renderer's f32 arithmetic overflows"
    )]
    OutOfRange {
        what: &'static str,
        value: f32,
        max: f32,
    },
    #[error("eye and target are the same point, so the camera looks nowhere")]
    EyeAtTarget,
    #[error("up is zero or parallel to the view direction, so it does not orient the image")]
    UpParallelToForward,
    #[error("fov_y is {0} degrees; it must be in (0, 180)")]
    FieldOfView(f32),
}

/// How close to parallel `up` may be to the view direction: below this sine the right vector
/// is mostly rounding error.
const MIN_UP_SINE: f32 = 1e-6;

/// `v` normalised, or `None` for a zero vector. Scaled by its largest component first, so that
/// lengths whose square overflows (1e30) or underflows (1e-30) normalise too.
fn unit(v: Vec3) -> Option<Vec3> {
    let largest = v.abs().max_element();
    if largest == 0.0 || !largest.is_finite() {
        return None;
    }
    (v / largest).try_normalize()
}

impl CameraDesc {
    /// A camera at `eye` looking at `target`, with `up` (any length, not parallel to the view)
    /// orienting the image and a vertical field of view in degrees, in (0, 180).
    pub fn new(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        fov_y_degrees: f32,
    ) -> Result<CameraDesc, CameraError> {
        if !(eye.is_finite() && target.is_finite() && up.is_finite()) {
            return Err(CameraError::NonFinite);
        }
        // Written so that NaN is rejected too.
        if !(fov_y_degrees > 0.0 && fov_y_degrees < 180.0) {
            return Err(CameraError::FieldOfView(fov_y_degrees));
        }
        for (what, p) in [("eye", eye), ("target", target)] {
            if let Some(&value) = p.to_array().iter().find(|c| c.abs() > MAX_COORDINATE) {
                return Err(CameraError::OutOfRange {
                    what,
                    value,
                    max: MAX_COORDINATE,
                });
            }
        }
        let forward = unit(target - eye).ok_or(CameraError::EyeAtTarget)?;
        let up_unit = unit(up).ok_or(CameraError::UpParallelToForward)?;
        let cross = forward.cross(up_unit);
        if cross.length() <= MIN_UP_SINE {
            return Err(CameraError::UpParallelToForward);
        }
        let right = cross.normalize();
        Ok(CameraDesc {
            eye,
            target,
            up,
            fov_y_degrees,
            basis: [forward, right, right.cross(forward)],
        })
    }

    pub fn eye(&self) -> Vec3 {
        self.eye
    }

    pub fn target(&self) -> Vec3 {
        self.target
    }

    pub fn up(&self) -> Vec3 {
        self.up
    }

    pub fn fov_y_degrees(&self) -> f32 {
        self.fov_y_degrees
    }

    /// The unit (forward, right, up) basis; right = normalize(cross(forward, up)).
    pub fn basis(&self) -> [Vec3; 3] {
        self.basis
    }

    /// The GPU camera for a `width` x `height` image: `right` and `up` scaled so that
    /// `normalize(forward + sx * right + sy * up)` with sx, sy in [-1, 1] spans the image.
    /// A zero side counts as 1 (an empty image has no aspect ratio).
    pub fn to_gpu(&self, width: u32, height: u32) -> GpuCamera {
        let [forward, right, up] = self.basis;
        let t = (self.fov_y_degrees.to_radians() * 0.5).tan();
        let aspect = width.max(1) as f32 / height.max(1) as f32;
        GpuCamera::new(self.eye, forward, right * (t * aspect), up * t)
    }
}

impl GpuCamera {
    /// The primary ray direction through image point (`px`, `py`) of a `width` x `height`
    /// image, where `px = x + jx`, `py = y + jy` (x right, y down, jitter in [0, 1)): the CPU
    /// mirror of what the intersect pass computes.
    pub fn ray_direction(&self, width: u32, height: u32, px: f32, py: f32) -> Vec3 {
        let (sx, sy) = screen_coordinates(width, height, px, py);
        (Vec3::from(self.forward) + sx * Vec3::from(self.right) + sy * Vec3::from(self.up))
            .normalize()
    }
}

/// Maps image point (`px`, `py`) to screen coordinates in [-1, 1]: sx grows to the right, sy
/// upwards (image rows go down).
pub fn screen_coordinates(width: u32, height: u32, px: f32, py: f32) -> (f32, f32) {
    (
        2.0 * px / width as f32 - 1.0,
        1.0 - 2.0 * py / height as f32,
    )
}

/// Where a world point lands on screen, in the same coordinates as [`screen_coordinates`]
/// (None if it is not in front of the camera). For tests and tools.
pub fn project(camera: &GpuCamera, point: Vec3) -> Option<(f32, f32)> {
    let d = point - Vec3::from(camera.eye);
    let forward = Vec3::from(camera.forward);
    let right = Vec3::from(camera.right);
    let up = Vec3::from(camera.up);
    let depth = d.dot(forward);
    if depth.is_nan() || depth <= 0.0 {
        return None;
    }
    // forward, right and up are orthogonal, so each coordinate is an independent projection.
    let sx = d.dot(right) / (depth * right.length_squared());
    let sy = d.dot(up) / (depth * up.length_squared());
    Some((sx, sy))
}
