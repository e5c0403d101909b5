//! `<transform>`: `lookat`, `translate`, `rotate`, `scale` and `matrix` elements composed as
//! Mitsuba composes them: each element is applied after the ones above it, so its matrix is
//! multiplied on the left (`<scale/><translate/>` scales first, then moves).
//!
//! Matrices are f64 while parsing (a chain of elements keeps its precision) and become f32 only
//! for the renderer.

use glam::{DMat4, DVec3, DVec4};

/// One element of a `<transform>`, parsed.
#[derive(Clone, Debug, PartialEq)]
pub enum TransformOp {
    Translate(DVec3),
    /// Degrees, right-handed about the axis (Mitsuba's `rotate`).
    Rotate {
        axis: DVec3,
        degrees: f64,
    },
    Scale(DVec3),
    /// Row-major as written (`value="m00 m01 m02 m03 m10 ..."`).
    Matrix(DMat4),
    LookAt {
        origin: DVec3,
        target: DVec3,
        up: DVec3,
    },
}

impl TransformOp {
    /// The element's matrix, or why it has none (a zero axis, eye at target, ...).
    pub fn matrix(&self) -> Result<DMat4, String> {
        Ok(match *self {
            TransformOp::Translate(t) => DMat4::from_translation(t),
            TransformOp::Rotate { axis, degrees } => {
                let axis = axis
                    .try_normalize()
                    .ok_or("rotate: the axis (x, y, z) must be a nonzero vector")?;
                DMat4::from_axis_angle(axis, degrees.to_radians())
            }
            TransformOp::Scale(s) => DMat4::from_scale(s),
            TransformOp::Matrix(m) => m,
            TransformOp::LookAt { origin, target, up } => look_at(origin, target, up)?,
        })
    }
}

/// Mitsuba's `look_at`: the camera frame's columns are left = up x dir, the re-orthogonalised
/// up = dir x left, dir = target - origin (normalised), and the origin. Local +z looks at the
/// target and local +x points to the image's left, as Mitsuba's sensors expect.
pub fn look_at(origin: DVec3, target: DVec3, up: DVec3) -> Result<DMat4, String> {
    let dir = (target - origin)
        .try_normalize()
        .ok_or("lookat: origin and target must differ")?;
    let left = up
        .cross(dir)
        .try_normalize()
        .ok_or("lookat: up must not be parallel to target - origin")?;
    let new_up = dir.cross(left);
    Ok(DMat4::from_cols(
        left.extend(0.0),
        new_up.extend(0.0),
        dir.extend(0.0),
        origin.extend(1.0),
    ))
}

/// The elements composed in order: the later element's matrix on the left.
pub fn compose(ops: &[TransformOp]) -> Result<DMat4, String> {
    ops.iter()
        .try_fold(DMat4::IDENTITY, |m, op| Ok(op.matrix()? * m))
}

/// A 16-number row-major matrix (Mitsuba's `<matrix value>`), or 9 numbers for the upper 3x3.
pub fn matrix_from_row_major(values: &[f64]) -> Option<DMat4> {
    match values.len() {
        16 => Some(DMat4::from_cols_array(&values.try_into().ok()?).transpose()),
        9 => {
            let r = |i: usize| DVec4::new(values[3 * i], values[3 * i + 1], values[3 * i + 2], 0.0);
            Some(DMat4::from_cols(r(0), r(1), r(2), DVec4::W).transpose())
        }
        _ => None,
    }
}

/// Whether a matrix is affine (last row 0 0 0 1): Mitsuba's shapes and emitters take only such.
pub fn is_affine(m: &DMat4) -> bool {
    m.row(3).abs_diff_eq(DVec4::W, 1e-12)
}
