//! The camera (docs/design.md §4): eye, target and up, and a projection — perspective (a pinhole,
//! or a thin lens: Mitsuba's `perspective` and `thinlens`, with its `fov` / `fov_axis`) or
//! orthographic (Mitsuba's `orthographic`) — turned into the scaled basis the shaders use.

use super::gpu_layout::GpuCamera;
use glam::{Vec2, Vec3};
use thiserror::Error;

/// The largest coordinate magnitude a camera point (or a vertex) may have. The renderer works
/// in f32 and multiplies coordinate differences (cross products, squared distances): with
/// |c| <= 1e18 those stay below 1.2e37, within f32's 3.4e38.
pub const MAX_COORDINATE: f32 = 1e18;

/// The image axis a perspective camera's field of view spans, as Mitsuba's `fov_axis`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FovAxis {
    X,
    Y,
    Diagonal,
    /// The shorter side (x when the image is taller than wide).
    Smaller,
    /// The longer side.
    Larger,
}

impl FovAxis {
    /// Mitsuba's name for the axis.
    pub fn mitsuba_name(self) -> &'static str {
        match self {
            FovAxis::X => "x",
            FovAxis::Y => "y",
            FovAxis::Diagonal => "diagonal",
            FovAxis::Smaller => "smaller",
            FovAxis::Larger => "larger",
        }
    }
}

/// A thin lens (Mitsuba's `thinlens`): rays start uniformly on a disk of `aperture_radius`
/// around the eye, in the image plane, and pass through the point the pinhole ray of the same
/// image position meets on the focus plane, `focus_distance` along the view direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lens {
    pub aperture_radius: f32,
    pub focus_distance: f32,
}

/// How image positions become rays.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Rays from the eye (or, with a lens, from the aperture) through the image plane;
    /// `fov_degrees` spans `fov_axis`.
    Perspective {
        fov_degrees: f32,
        fov_axis: FovAxis,
        lens: Option<Lens>,
    },
    /// Parallel rays along the view direction from a rectangle around the eye, `width` world
    /// units wide (its height follows the image's aspect ratio). Mitsuba's `orthographic` with
    /// `to_world = lookat(eye, target, up) * scale(width / 2, width / 2, 1)`: its sensor plane
    /// spans x in [-1, 1] before the scale.
    Orthographic { width: f32 },
}

/// What the shaders specialise on: the `scene_camera_kind` override (shaders/lib/camera_ray.wgsl).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CameraKind {
    Pinhole = 0,
    ThinLens = 1,
    Orthographic = 2,
}

impl CameraKind {
    pub fn name(self) -> &'static str {
        match self {
            CameraKind::Pinhole => "pinhole",
            CameraKind::ThinLens => "thin-lens",
            CameraKind::Orthographic => "orthographic",
        }
    }
}

/// A camera as a scene file describes it. Only valid cameras exist (see [`CameraDesc::new`]),
/// so turning one into a [`GpuCamera`] cannot fail.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraDesc {
    eye: Vec3,
    target: Vec3,
    up: Vec3,
    projection: Projection,
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
    #[error("fov is {0} degrees; it must be in (0, 180)")]
    Fov(f32),
    #[error(
        "aperture_radius is {0}; it must be a finite number > 0 (leave out aperture_radius and focus_distance for a pinhole)"
    )]
    ApertureRadius(f32),
    #[error("focus_distance is {0}; it must be a finite number > 0")]
    FocusDistance(f32),
    #[error(
        "aperture_radius needs a focus_distance (the distance along the view at which the lens is sharp)"
    )]
    ApertureWithoutFocus,
    #[error(
        "focus_distance without aperture_radius: a pinhole has no focus (give both for a thin lens, or neither)"
    )]
    FocusWithoutAperture,
    #[error("give the field of view as fov_y or as fov (with fov_axis), not both")]
    FovTwice,
    #[error("the camera needs a field of view: fov_y, or fov (with fov_axis)")]
    FovMissing,
    #[error("fov_axis applies to fov only (fov_y is always the vertical field of view)")]
    FovAxisWithoutFov,
    #[error("an orthographic camera has no field of view (fov_y) to set")]
    FovOfOrthographic,
    #[error("width is {0}; an orthographic camera's width must be a finite number > 0")]
    OrthographicWidth(f32),
    #[error(
        "width has a value of {value:e}, beyond ±{max:e} where the renderer's f32 arithmetic overflows"
    )]
    WidthOutOfRange { value: f32, max: f32 },
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

/// Whether `x` is finite and > 0 (false for NaN).
fn positive(x: f32) -> bool {
    x > 0.0 && x.is_finite()
}

impl Projection {
    /// The projection checked: fields of view in (0, 180) degrees, lens and width finite and
    /// positive.
    fn check(self) -> Result<Projection, CameraError> {
        match self {
            Projection::Perspective {
                fov_degrees, lens, ..
            } => {
                // Written so that NaN is rejected too.
                if !(fov_degrees > 0.0 && fov_degrees < 180.0) {
                    return Err(CameraError::Fov(fov_degrees));
                }
                if let Some(lens) = lens {
                    if !positive(lens.aperture_radius) {
                        return Err(CameraError::ApertureRadius(lens.aperture_radius));
                    }
                    if !positive(lens.focus_distance) {
                        return Err(CameraError::FocusDistance(lens.focus_distance));
                    }
                }
            }
            Projection::Orthographic { width } => {
                if !positive(width) {
                    return Err(CameraError::OrthographicWidth(width));
                }
                if width > MAX_COORDINATE {
                    return Err(CameraError::WidthOutOfRange {
                        value: width,
                        max: MAX_COORDINATE,
                    });
                }
            }
        }
        Ok(self)
    }
}

/// tan of half the horizontal and vertical fields of view for a `fov_degrees` field spanning
/// `axis` of an image of `aspect` = width / height: Mitsuba's `parse_fov` (which finds the x
/// field of view) followed by its perspective projection (y = x / aspect).
pub fn fov_tangents(fov_degrees: f32, axis: FovAxis, aspect: f32) -> (f32, f32) {
    let t = (fov_degrees.to_radians() * 0.5).tan();
    let axis = match axis {
        FovAxis::Smaller if aspect > 1.0 => FovAxis::Y,
        FovAxis::Smaller => FovAxis::X,
        FovAxis::Larger if aspect > 1.0 => FovAxis::X,
        FovAxis::Larger => FovAxis::Y,
        a => a,
    };
    match axis {
        FovAxis::X => (t, t / aspect),
        // As the pinhole camera always computed it (so its images stay bit for bit).
        FovAxis::Y => (t * aspect, t),
        _ => {
            // The image diagonal: tx^2 + ty^2 = t^2 with ty = tx / aspect.
            let tx = t / (1.0 + 1.0 / (aspect * aspect)).sqrt();
            (tx, tx / aspect)
        }
    }
}

impl CameraDesc {
    /// A pinhole camera at `eye` looking at `target`, with `up` (any length, not parallel to
    /// the view) orienting the image and a vertical field of view in degrees, in (0, 180).
    pub fn new(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        fov_y_degrees: f32,
    ) -> Result<CameraDesc, CameraError> {
        // Written so that NaN is rejected too.
        if !(fov_y_degrees > 0.0 && fov_y_degrees < 180.0) {
            return Err(CameraError::FieldOfView(fov_y_degrees));
        }
        CameraDesc::with_projection(
            eye,
            target,
            up,
            Projection::Perspective {
                fov_degrees: fov_y_degrees,
                fov_axis: FovAxis::Y,
                lens: None,
            },
        )
    }

    /// A camera at `eye` looking at `target`, `up` orienting the image, with any projection.
    pub fn with_projection(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        projection: Projection,
    ) -> Result<CameraDesc, CameraError> {
        if !(eye.is_finite() && target.is_finite() && up.is_finite()) {
            return Err(CameraError::NonFinite);
        }
        let projection = projection.check()?;
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
            projection,
            basis: [forward, right, right.cross(forward)],
        })
    }

    /// This camera (its projection and lens) moved to look from `eye` at `target`: what the
    /// viewer and camera paths make.
    pub fn moved(&self, eye: Vec3, target: Vec3, up: Vec3) -> Result<CameraDesc, CameraError> {
        CameraDesc::with_projection(eye, target, up, self.projection)
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

    pub fn projection(&self) -> Projection {
        self.projection
    }

    /// What the shaders specialise on.
    pub fn kind(&self) -> CameraKind {
        match self.projection {
            Projection::Perspective { lens: None, .. } => CameraKind::Pinhole,
            Projection::Perspective { lens: Some(_), .. } => CameraKind::ThinLens,
            Projection::Orthographic { .. } => CameraKind::Orthographic,
        }
    }

    /// The lens, if the camera has one.
    pub fn lens(&self) -> Option<Lens> {
        match self.projection {
            Projection::Perspective { lens, .. } => lens,
            Projection::Orthographic { .. } => None,
        }
    }

    /// The vertical field of view in degrees of a `width` x `height` image (perspective
    /// cameras; None for an orthographic one).
    pub fn fov_y_degrees_for(&self, width: u32, height: u32) -> Option<f32> {
        match self.projection {
            Projection::Perspective {
                fov_degrees: fov,
                fov_axis: FovAxis::Y,
                ..
            } => Some(fov),
            Projection::Perspective {
                fov_degrees,
                fov_axis,
                ..
            } => {
                let (_, ty) = fov_tangents(fov_degrees, fov_axis, aspect(width, height));
                Some(2.0 * ty.atan().to_degrees())
            }
            Projection::Orthographic { .. } => None,
        }
    }

    /// The unit (forward, right, up) basis; right = normalize(cross(forward, up)).
    pub fn basis(&self) -> [Vec3; 3] {
        self.basis
    }

    /// The GPU camera for a `width` x `height` image: `right` and `up` scaled so that
    /// `forward + sx * right + sy * up` with sx, sy in [-1, 1] spans the image (perspective),
    /// or that `eye + sx * right + sy * up` does (orthographic, in world units).
    /// A zero side counts as 1 (an empty image has no aspect ratio).
    pub fn to_gpu(&self, width: u32, height: u32) -> GpuCamera {
        let [forward, right, up] = self.basis;
        let aspect = aspect(width, height);
        match self.projection {
            Projection::Perspective {
                fov_degrees,
                fov_axis,
                lens,
            } => {
                let (tx, ty) = fov_tangents(fov_degrees, fov_axis, aspect);
                let mut camera = GpuCamera::new(self.eye, forward, right * tx, up * ty);
                if let Some(lens) = lens {
                    camera.aperture_radius = lens.aperture_radius;
                    camera.focus_distance = lens.focus_distance;
                }
                camera
            }
            Projection::Orthographic { width } => {
                let half = 0.5 * width;
                GpuCamera::new(self.eye, forward, right * half, up * (half / aspect))
            }
        }
    }

    /// The primary ray through image point (`px`, `py`) of a `width` x `height` image (x
    /// right, y down, in pixels), starting at lens sample `lens` in [0, 1)^2 (unused without a
    /// lens): the CPU mirror of shaders/lib/camera_ray.wgsl. Returns (origin, unit direction).
    pub fn ray(&self, width: u32, height: u32, px: f32, py: f32, lens: Vec2) -> (Vec3, Vec3) {
        let camera = self.to_gpu(width, height);
        let (sx, sy) = screen_coordinates(width, height, px, py);
        let forward = Vec3::from(camera.forward);
        let right = Vec3::from(camera.right);
        let up = Vec3::from(camera.up);
        let eye = Vec3::from(camera.eye);
        match self.kind() {
            CameraKind::Orthographic => (eye + sx * right + sy * up, forward),
            CameraKind::Pinhole => (eye, camera.ray_direction(width, height, px, py)),
            CameraKind::ThinLens => {
                let d = forward + sx * right + sy * up;
                let disk = camera.aperture_radius * square_to_disk_concentric(lens);
                let offset = disk.x * right.normalize() + disk.y * up.normalize();
                // forward is a unit vector, so d reaches the focus plane at focus_distance * d.
                let focus = camera.focus_distance * d;
                (eye + offset, (focus - offset).normalize())
            }
        }
    }
}

/// width / height, a zero side counting as 1.
fn aspect(width: u32, height: u32) -> f32 {
    width.max(1) as f32 / height.max(1) as f32
}

/// Shirley and Chiu's concentric map of the unit square onto the unit disk (as Mitsuba's
/// `square_to_uniform_disk_concentric`): uniform, and it keeps the sampler's strata compact.
pub fn square_to_disk_concentric(u: Vec2) -> Vec2 {
    let a = 2.0 * u - Vec2::ONE;
    if a == Vec2::ZERO {
        return Vec2::ZERO;
    }
    let (r, phi) = if a.x.abs() > a.y.abs() {
        (a.x, std::f32::consts::FRAC_PI_4 * (a.y / a.x))
    } else {
        (
            a.y,
            std::f32::consts::FRAC_PI_2 - std::f32::consts::FRAC_PI_4 * (a.x / a.y),
        )
    };
    Vec2::new(r * phi.cos(), r * phi.sin())
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
