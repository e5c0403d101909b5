//! A material at one shading point, as every model's CPU twin reads it (`Bsdf` and `BsdfSample`
//! in shaders/lib/bsdf.wgsl), and the step from world space into a model's shading frame.
//! Conventions as bsdf.wgsl states them: world-space unit directions, `wo` toward the viewer,
//! `wi` toward the light, `n` the shading normal turned to wo's side, `outside` whether wo is on
//! the front side (dielectric only). `eval` is f |n.wi| of the non-delta lobes; a sample's
//! weight is f |n.wi| / pdf; a delta sample's pdf is the probability of having chosen its lobe.

use crate::bsdf::frame::{basis, to_local};
use crate::bsdf::microfacet::Distribution;
use crate::material::plastic::tables::PlasticTable;
use glam::Vec3;

/// A material at one shading point, textures applied (`Bsdf` in bsdf.wgsl).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bsdf {
    pub kind: u32,
    pub kd: Vec3,
    pub ks: Vec3,
    pub ns: f32,
    /// Microfacet alpha; 0: smooth (delta).
    pub alpha: f32,
    pub ior: f32,
    pub tf: Vec3,
    /// The rough lobes' microfacet distribution.
    pub distribution: Distribution,
    /// The conductor's Fresnel term (`FRESNEL_NONE` or `FRESNEL_CONDUCTOR`) and complex index.
    pub fresnel: u32,
    pub eta: Vec3,
    pub k: Vec3,
    /// The rough plastic's tables (bsdf.wgsl holds their texel index in the materials view,
    /// `table`); `None` for every other model and for smooth plastic.
    pub table: Option<PlasticTable>,
}

/// A sampled direction (`BsdfSample` in bsdf.wgsl).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    pub wi: Vec3,
    /// f |n.wi| / pdf; zero when the sample failed.
    pub weight: Vec3,
    /// Solid-angle density, or for a delta sample the probability of its lobe; 0 on failure.
    pub pdf: f32,
    pub delta: bool,
}

impl Sample {
    pub fn failed(wi: Vec3) -> Sample {
        Sample {
            wi,
            weight: Vec3::ZERO,
            pdf: 0.0,
            delta: false,
        }
    }
}

/// `f(wo, wi)` of a model written in the shading frame around `n` (normal +z), as the WGSL
/// dispatch calls it (`wo * frame`).
pub fn in_local_frame<T>(n: Vec3, wo: Vec3, wi: Vec3, f: impl FnOnce(Vec3, Vec3) -> T) -> T {
    let frame = basis(n);
    f(to_local(&frame, wo), to_local(&frame, wi))
}

/// A local-frame model's sample of `wo`, its direction turned back to world space.
pub fn sample_in_local_frame(n: Vec3, wo: Vec3, f: impl FnOnce(Vec3) -> Sample) -> Sample {
    let frame = basis(n);
    let mut s = f(to_local(&frame, wo));
    s.wi = frame * s.wi;
    s
}
