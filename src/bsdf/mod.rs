//! The CPU twin of the WGSL BSDF library (`shaders/lib/bsdf.wgsl` and the files it names): the
//! same functions on glam vectors in f32, line for line the same maths, so tests can compare
//! them. Conventions as bsdf.wgsl states them: world-space unit directions, `wo` toward the
//! viewer, `wi` toward the light, `n` the shading normal turned to wo's side, `outside` whether
//! wo is on the front side (dielectric only). `eval` is f |n.wi| of the non-delta lobes; a
//! sample's weight is f |n.wi| / pdf; a delta sample's pdf is the probability of having chosen
//! its lobe.

pub mod beckmann;
pub mod conductor;
pub mod conductor_presets;
pub mod dielectric;
pub mod erf;
pub mod frame;
pub mod fresnel;
pub mod ggx;
pub mod lambert;
pub mod metallic_roughness;
pub mod metallic_roughness_table;
pub mod microfacet;
pub mod phong;
pub mod plastic;
pub mod plastic_tables;
pub mod thin_dielectric;

use crate::scene::gpu_layout::{
    Distribution, MATERIAL_CONDUCTOR, MATERIAL_DIELECTRIC, MATERIAL_LAMBERT,
    MATERIAL_METALLIC_ROUGHNESS, MATERIAL_PHONG, MATERIAL_PLASTIC, MATERIAL_THIN_DIELECTRIC,
    Material,
};
use crate::scene::material_tables::NO_TABLE;
use frame::{basis, to_local};
use glam::{Vec2, Vec3};
use plastic_tables::{PlasticTable, TABLE_TEXELS};

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

impl Bsdf {
    /// `m` from a materials view's texels (`texels`, as `SceneGpu::materials_texels` lays them
    /// out), its table read where `m.table` points as the GPU reads it.
    pub fn from_material(m: &Material, texels: &[[f32; 4]]) -> Bsdf {
        let table = (m.table != NO_TABLE && m.kind == MATERIAL_PLASTIC).then(|| {
            let start = m.table as usize;
            PlasticTable::from_texels(&texels[start..start + TABLE_TEXELS])
        });
        Bsdf {
            table,
            kind: m.kind,
            kd: Vec3::from(m.kd),
            ks: Vec3::from(m.ks),
            ns: m.ns,
            alpha: m.alpha,
            ior: m.ior,
            tf: Vec3::from(m.tf),
            distribution: Distribution::from_u32(m.distribution),
            fresnel: m.fresnel,
            eta: Vec3::from(m.eta),
            k: Vec3::from(m.k),
        }
    }
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

pub fn eval(b: &Bsdf, n: Vec3, outside: bool, wo: Vec3, wi: Vec3) -> Vec3 {
    let frame = basis(n);
    match b.kind {
        MATERIAL_LAMBERT => lambert::eval(b, n, wo, wi),
        MATERIAL_PHONG => phong::eval(b, n, wo, wi),
        MATERIAL_CONDUCTOR => conductor::eval(b, to_local(&frame, wo), to_local(&frame, wi)),
        MATERIAL_PLASTIC => plastic::eval(b, to_local(&frame, wo), to_local(&frame, wi)),
        MATERIAL_DIELECTRIC => {
            dielectric::eval(b, outside, to_local(&frame, wo), to_local(&frame, wi))
        }
        MATERIAL_METALLIC_ROUGHNESS => {
            metallic_roughness::eval(b, to_local(&frame, wo), to_local(&frame, wi))
        }
        _ => Vec3::ZERO,
    }
}

pub fn pdf(b: &Bsdf, n: Vec3, outside: bool, wo: Vec3, wi: Vec3) -> f32 {
    let frame = basis(n);
    match b.kind {
        MATERIAL_LAMBERT | MATERIAL_PHONG => lambert::pdf(n, wo, wi),
        MATERIAL_CONDUCTOR => conductor::pdf(b, to_local(&frame, wo), to_local(&frame, wi)),
        MATERIAL_PLASTIC => plastic::pdf(b, to_local(&frame, wo), to_local(&frame, wi)),
        MATERIAL_DIELECTRIC => {
            dielectric::pdf(b, outside, to_local(&frame, wo), to_local(&frame, wi))
        }
        MATERIAL_METALLIC_ROUGHNESS => {
            metallic_roughness::pdf(b, to_local(&frame, wo), to_local(&frame, wi))
        }
        _ => 0.0,
    }
}

/// `u` picks the direction within a lobe, `u_lobe` the lobe (plastic, dielectric,
/// metallic-roughness).
pub fn sample(b: &Bsdf, n: Vec3, outside: bool, wo: Vec3, u: Vec2, u_lobe: f32) -> Sample {
    let frame = basis(n);
    let local = to_local(&frame, wo);
    let mut s = match b.kind {
        MATERIAL_LAMBERT => return lambert::sample(b, n, wo, u),
        MATERIAL_PHONG => return phong::sample(b, n, wo, u),
        MATERIAL_CONDUCTOR => conductor::sample(b, local, u),
        MATERIAL_PLASTIC => plastic::sample(b, local, u, u_lobe),
        MATERIAL_DIELECTRIC => dielectric::sample(b, outside, local, u, u_lobe),
        MATERIAL_THIN_DIELECTRIC => thin_dielectric::sample(b, local, u_lobe),
        MATERIAL_METALLIC_ROUGHNESS => metallic_roughness::sample(b, local, u, u_lobe),
        _ => return Sample::failed(n),
    };
    s.wi = frame * s.wi;
    s
}

/// True when every lobe is delta (smooth conductor, smooth dielectric, thin dielectric).
pub fn is_delta(b: &Bsdf) -> bool {
    (b.alpha == 0.0 && (b.kind == MATERIAL_CONDUCTOR || b.kind == MATERIAL_DIELECTRIC))
        || b.kind == MATERIAL_THIN_DIELECTRIC
}
