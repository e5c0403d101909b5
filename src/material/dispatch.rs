//! The CPU twin of the WGSL BSDF library's dispatch (`bsdf_eval`, `bsdf_pdf`, `bsdf_sample`,
//! `bsdf_is_delta`, generated into shaders/lib/material_models.wgsl): a material's scattering
//! by its model's functions, in world space. Unknown kinds scatter nothing, as on the GPU.

use super::bsdf::{Bsdf, Sample};
use super::plastic::tables::{PlasticTable, TABLE_TEXELS};
use super::record::{Material, NO_TABLE};
use super::registry::{MATERIAL_PLASTIC, model};
use crate::bsdf::microfacet::Distribution;
use glam::{Vec2, Vec3};

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

pub fn eval(b: &Bsdf, n: Vec3, outside: bool, wo: Vec3, wi: Vec3) -> Vec3 {
    model(b.kind).map_or(Vec3::ZERO, |m| (m.eval)(b, n, outside, wo, wi))
}

pub fn pdf(b: &Bsdf, n: Vec3, outside: bool, wo: Vec3, wi: Vec3) -> f32 {
    model(b.kind).map_or(0.0, |m| (m.pdf)(b, n, outside, wo, wi))
}

/// `u` picks the direction within a lobe, `u_lobe` the lobe (plastic, dielectric,
/// metallic-roughness).
pub fn sample(b: &Bsdf, n: Vec3, outside: bool, wo: Vec3, u: Vec2, u_lobe: f32) -> Sample {
    model(b.kind).map_or(Sample::failed(n), |m| {
        (m.sample)(b, n, outside, wo, u, u_lobe)
    })
}

/// True when every lobe is delta (smooth conductor, smooth dielectric, thin dielectric).
pub fn is_delta(b: &Bsdf) -> bool {
    model(b.kind).is_some_and(|m| (m.is_delta)(b))
}
