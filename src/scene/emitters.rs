//! Lights that are not emissive triangles: point, spot and directional lights (Mitsuba 3's
//! `point`, `spot`, `directional`) and the environment (`constant`, `envmap`), and how they join
//! the scene's light list. Every emitter is one entry of `scene.lights` with its selection
//! weight in `scene.light_power`, after the area lights, so light selection and next-event
//! estimation cover them all; the environment's sampling tables follow the weights.

use super::environment::Environment;
use super::lights::{
    LIGHT_AREA, LIGHT_DIRECTIONAL, LIGHT_POINT, LIGHT_SPOT, LIGHT_SPOT_TEXTURED, LIGHT_TAG, Light,
};
use super::texture::{LUMINANCE, Texture};
use glam::Vec3;

/// A delta light, as the scene file describes it (validated by the loader).
#[derive(Clone, Debug, PartialEq)]
pub enum AnalyticLight {
    /// Radiant intensity `intensity` (W/sr per channel) in every direction from `position`.
    Point { position: Vec3, intensity: Vec3 },
    /// Mitsuba's spot: `intensity` along the axis toward `target`, full out to `beam_width`
    /// degrees off it, falling linearly in angle to 0 at `cutoff_angle`; with a `texture`, the
    /// intensity times the image projected over the cone, oriented by the lookat frame of
    /// (position, target, up) as Mitsuba's `to_world` (see [`spot_uv`]).
    Spot {
        position: Vec3,
        target: Vec3,
        /// Not along the axis; only a texture's orientation depends on it.
        up: Vec3,
        intensity: Vec3,
        cutoff_angle: f32,
        beam_width: f32,
        texture: Option<Texture>,
    },
    /// Irradiance `irradiance` on surfaces facing it, arriving along `direction` (the way the
    /// light travels, unit length).
    Directional { direction: Vec3, irradiance: Vec3 },
}

/// What a scene adds to its emissive triangles.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Emitters {
    pub lights: Vec<AnalyticLight>,
    pub environment: Option<Environment>,
}

pub(super) fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::from(LUMINANCE))
}

pub(super) fn record(kind: u32, p0: Vec3, e1: Vec3, e2: Vec3, second: u32, first: u32) -> Light {
    Light {
        p0: p0.into(),
        material: LIGHT_TAG + kind,
        e1: e1.into(),
        second,
        e2: e2.into(),
        first,
    }
}

/// The orthonormal pair perpendicular to the unit vector n (Duff et al. 2017, "Building an
/// Orthonormal Basis, Revisited"), as `spot_basis` in shaders/lib/emitters.wgsl: a textured
/// spot's record stores its frame as an angle in this basis, which both sides rebuild alike.
pub fn spot_basis(n: Vec3) -> (Vec3, Vec3) {
    let sign = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        Vec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

/// Mitsuba's lookat frame of a spot (`Transform::look_at`): x = normalize(up x axis),
/// y = axis x x, z the unit axis toward the target.
pub fn spot_frame(position: Vec3, target: Vec3, up: Vec3) -> (Vec3, Vec3, Vec3) {
    let z = (target - position).normalize();
    let x = up.cross(z).normalize();
    (x, z.cross(x), z)
}

/// Where the unit direction `d` leaving a spot meets its texture, as Mitsuba's spot
/// `direction_to_uv`: 0.5 + 0.5 (x, y) / (z tan(cutoff)) in the lookat frame, with v = 0 at
/// the image's top row (so `Texture::bilinear` takes (u, 1 - v)).
pub fn spot_uv(frame: (Vec3, Vec3, Vec3), cutoff_degrees: f32, d: Vec3) -> glam::Vec2 {
    let (x, y, z) = frame;
    let scale = 0.5 / (d.dot(z) * cutoff_degrees.to_radians().tan());
    glam::Vec2::new(0.5 + d.dot(x) * scale, 0.5 + d.dot(y) * scale)
}

impl AnalyticLight {
    /// Where the light is, for a light at a point of the scene.
    pub fn position(&self) -> Option<Vec3> {
        match *self {
            AnalyticLight::Point { position, .. } | AnalyticLight::Spot { position, .. } => {
                Some(position)
            }
            AnalyticLight::Directional { .. } => None,
        }
    }

    /// The `scene.lights` record (see `Light` in shaders/lib/scene.wgsl) and the selection
    /// weight: an estimate of the irradiance it gives, as an area light's power / d^2 is (the
    /// shader divides point and spot weights by d^2). A textured spot's image, times its
    /// intensity, joins `textures`.
    pub(super) fn gpu(&self, textures: &mut Vec<Texture>) -> (Light, f32) {
        match *self {
            AnalyticLight::Point {
                position,
                intensity,
            } => (
                record(LIGHT_POINT, position, intensity, Vec3::ZERO, 0, 0),
                luminance(intensity),
            ),
            AnalyticLight::Spot {
                position,
                target,
                up,
                intensity,
                cutoff_angle,
                beam_width,
                ref texture,
            } => {
                let axis = (target - position).normalize();
                let (cutoff, beam) = (
                    cutoff_angle.to_radians().to_bits(),
                    beam_width.to_radians().to_bits(),
                );
                let Some(texture) = texture else {
                    return (
                        record(LIGHT_SPOT, position, intensity, axis, cutoff, beam),
                        luminance(intensity),
                    );
                };
                // The record has no room for both the intensity and the texture, so the
                // texture carries it (bilinear lookups are linear: the same values), and e1
                // holds the texture's index and the frame's x axis as (cos, sin) in
                // spot_basis(axis), over tan(cutoff) (the uv's scale, computed here in full
                // precision), from which the shader rebuilds x and y = axis x x.
                let (x, _, _) = spot_frame(position, target, up);
                let uv_scale = f64::from(cutoff_angle).to_radians().tan() as f32;
                let (t, b) = spot_basis(axis);
                let index = textures.len() as u32;
                let texels: Vec<[f32; 4]> = texture
                    .texels
                    .iter()
                    .map(|c| {
                        let c = Vec3::new(c[0], c[1], c[2]) * intensity;
                        [c.x, c.y, c.z, 1.0]
                    })
                    .collect();
                let mean = texels
                    .iter()
                    .map(|c| luminance(Vec3::new(c[0], c[1], c[2])))
                    .sum::<f32>()
                    / texels.len() as f32;
                let mut copy = Texture::from_texels(texture.width, texture.height, texels);
                (copy.filter, copy.wrap) = (texture.filter, texture.wrap);
                textures.push(copy);
                (
                    record(
                        LIGHT_SPOT_TEXTURED,
                        position,
                        Vec3::new(
                            f32::from_bits(index),
                            x.dot(t) / uv_scale,
                            x.dot(b) / uv_scale,
                        ),
                        axis,
                        cutoff,
                        beam,
                    ),
                    mean,
                )
            }
            AnalyticLight::Directional {
                direction,
                irradiance,
            } => (
                record(LIGHT_DIRECTIONAL, Vec3::ZERO, irradiance, direction, 0, 0),
                luminance(irradiance),
            ),
        }
    }
}

/// Bit `1 << LIGHT_AREA` alone: a scene lit by its emissive triangles only.
pub const AREA_LIGHTS_ONLY: u32 = 1 << LIGHT_AREA;
