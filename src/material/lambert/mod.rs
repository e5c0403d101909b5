//! Lambert (`shaders/lib/material/lambert.wgsl`): f = kd / pi, two-sided (Mitsuba 3's twosided + diffuse), and the
//! default material. World space; n faces wo.

use crate::bsdf::frame::sample_cosine;
use crate::bsdf::microfacet::Distribution;
use crate::material::bsdf::{Bsdf, Sample};
use crate::material::model::{Model, Space};
use crate::material::record::{FRESNEL_NONE, Material, NO_TABLE, NO_TEXTURE};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

pub const KIND: u32 = 0;

pub const MODEL: Model = Model {
    name: "lambert",
    kind: KIND,
    space: Space::World,
    eval: |b, n, _, wo, wi| eval(b, n, wo, wi),
    pdf: |_, n, _, wo, wi| pdf(n, wo, wi),
    sample: |b, n, _, wo, u, _| sample(b, n, wo, u),
    is_delta: |_| false,
    microfacet: false,
    specular: |_| false,
    table: None,
};

impl Material {
    /// What faces without a material get: white diffuse, Kd 0.8.
    pub const DEFAULT: Material = Material::diffuse([0.8; 3]);

    pub const fn diffuse(kd: [f32; 3]) -> Material {
        Material {
            kd,
            ns: 0.0,
            ks: [0.0; 3],
            kind: KIND,
            ke: [0.0; 3],
            alpha: 0.0,
            tf: [1.0; 3],
            ior: 1.5,
            map_kd: NO_TEXTURE,
            map_ks: NO_TEXTURE,
            map_pr: NO_TEXTURE,
            map_d: NO_TEXTURE,
            opacity: 1.0,
            table: NO_TABLE,
            surface_map: NO_TEXTURE,
            bump_scale: 1.0,
            eta: [0.0; 3],
            distribution: Distribution::Ggx as u32,
            k: [1.0; 3],
            fresnel: FRESNEL_NONE,
        }
    }
}

impl Default for Material {
    fn default() -> Material {
        Material::DEFAULT
    }
}

pub fn eval(b: &Bsdf, n: Vec3, wo: Vec3, wi: Vec3) -> Vec3 {
    let cos_o = n.dot(wo);
    let cos_i = n.dot(wi);
    if cos_o <= 0.0 || cos_i <= 0.0 {
        return Vec3::ZERO;
    }
    b.kd * (cos_i / PI)
}

pub fn pdf(n: Vec3, wo: Vec3, wi: Vec3) -> f32 {
    let cos_o = n.dot(wo);
    let cos_i = n.dot(wi);
    if cos_o <= 0.0 || cos_i <= 0.0 {
        return 0.0;
    }
    cos_i / PI
}

pub fn sample(b: &Bsdf, n: Vec3, wo: Vec3, u: Vec2) -> Sample {
    let wi = sample_cosine(n, u.x, u.y);
    let pdf = pdf(n, wo, wi);
    if pdf <= 0.0 {
        return Sample::failed(wi);
    }
    // f cos / pdf: the cosines and pi cancel.
    Sample {
        wi,
        weight: b.kd,
        pdf,
        delta: false,
    }
}
