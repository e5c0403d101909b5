//! glTF 2.0's metallic-roughness material (`shaders/lib/material/metallic_roughness.wgsl`), the BRDF
//! of the specification's Appendix B: a mix by `metallic` of a metal (GGX specular, Schlick
//! Fresnel with f0 = base colour) and a dielectric (the same GGX specular layer with f0 = 0.04
//! over a Lambertian base of the base colour, weighted by what the layer lets through):
//!
//! f = (1 - metallic) (W base / pi + F(0.04) D V) + metallic F(base) D V,
//!
//! F(f0) = f0 + (1 - f0) (1 - |wo.h|)^5, D the GGX distribution of alpha = roughness^2 and
//! V = G1(wo) G1(wi) / (4 |n.wo| |n.wi|) (the specification's separable Smith term). `kd` is
//! the base colour, `ks.x` the metallic factor, `alpha` roughness^2; alpha = 0 makes the
//! specular layer a delta mirror. Two-sided. Local frame: normal +z, wo.z >= 0.
//!
//! The one departure from Appendix B is the base's weight W. The specification's 1 - F(wo.h)
//! creates energy: a white smooth dielectric seen at cos 0.05 reflects 1.72 times what it
//! receives (0.78 mirrored plus nearly all the diffuse), 1.3 at cos 0.2, and roughness only
//! lessens it (1.31 at roughness 0.3); a path tracer compounds that excess over bounces.
//! Weighting by the macro normal's Fresnel term instead loses light (a white dielectric of
//! roughness 1 at cos 0.05 reflected 0.26). So the base gets exactly what the rough specular
//! layer does not reflect, the albedo-scaling coupling of Kulla and Conty (2017), reciprocal:
//!
//! W = (1 - E(wo.z)) (1 - E(wi.z)) / (1 - E_avg),
//!
//! E the layer's directional albedo (table.rs) and E_avg its cosine-weighted
//! average, so the white dielectric conserves energy (up to the table's interpolation), as
//! Blender's Principled BSDF, which its glTF importer maps onto, does too. Head-on and smooth,
//! W = 0.96^2 / 0.912 = 1.01 against the specification's 0.96.

pub mod table;

use crate::bsdf::frame::sample_cosine;
use crate::bsdf::ggx::{ggx_alpha, ggx_d, ggx_g1, ggx_sample_visible};
use crate::material::bsdf::{Bsdf, Sample, in_local_frame, sample_in_local_frame};
use crate::material::model::{Model, Space, Table};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;
use table::SpecularAlbedoTable;

// The dielectric's reflectance at normal incidence lives with the table computed from it.
pub use table::DIELECTRIC_F0;

pub const KIND: u32 = 6;

/// glTF 2.0's metallic-roughness BRDF: kd the base colour, ks.x the metallic factor, alpha
/// roughness^2. Every such material shares one table of its dielectric layer's albedo.
pub const MODEL: Model = Model {
    name: "metallic_roughness",
    kind: KIND,
    space: Space::Local,
    eval: |b, n, _, wo, wi| in_local_frame(n, wo, wi, |wo, wi| eval(b, wo, wi)),
    pdf: |b, n, _, wo, wi| in_local_frame(n, wo, wi, |wo, wi| pdf(b, wo, wi)),
    sample: |b, n, _, wo, u, u_lobe| sample_in_local_frame(n, wo, |wo| sample(b, wo, u, u_lobe)),
    is_delta: |_| false,
    microfacet: false,
    specular: |_| true,
    table: Some(Table {
        key: |_| Some([0; 3]),
        texels: |_| SpecularAlbedoTable::shared().texels(),
    }),
};

/// Schlick's (1 - cos)^5, the weight of 1 - f0.
fn schlick_weight(cos: f32) -> f32 {
    let c = (1.0 - cos.abs()).clamp(0.0, 1.0);
    let c2 = c * c;
    c2 * c2 * c
}

fn metallic(b: &Bsdf) -> f32 {
    b.ks.x.clamp(0.0, 1.0)
}

/// The specular layer's Fresnel term at cos(wo, h): the mix of the dielectric's and the
/// metal's by metallic.
fn specular_fresnel(b: &Bsdf, cos: f32) -> Vec3 {
    let f0 = Vec3::splat(DIELECTRIC_F0).lerp(b.kd, metallic(b));
    f0 + (Vec3::ONE - f0) * schlick_weight(cos)
}

/// The dielectric layer's albedo seen from `cos`.
fn layer_albedo(b: &Bsdf, cos: f32) -> f32 {
    SpecularAlbedoTable::shared().albedo(cos, b.alpha.sqrt())
}

/// The base's weight W (module doc) times 1 - metallic.
fn diffuse_weight(b: &Bsdf, cos_o: f32, cos_i: f32) -> f32 {
    let average = SpecularAlbedoTable::shared().average(b.alpha.sqrt());
    (1.0 - metallic(b)) * (1.0 - layer_albedo(b, cos_o)) * (1.0 - layer_albedo(b, cos_i))
        / (1.0 - average)
}

/// The probability of sampling the specular layer, from both layers' albedos at wo (the
/// metal's by its Fresnel term at the normal): the same for eval, pdf and sample.
pub fn specular_probability(b: &Bsdf, wo: Vec3) -> f32 {
    let e = layer_albedo(b, wo.z);
    let metal = specular_fresnel(&Bsdf { ks: Vec3::X, ..*b }, wo.z);
    let w_s = (1.0 - metallic(b)) * e + metallic(b) * (metal.x + metal.y + metal.z) / 3.0;
    let w_d = (1.0 - metallic(b)) * (1.0 - e) * (b.kd.x + b.kd.y + b.kd.z) / 3.0;
    if w_d <= 0.0 {
        return 1.0;
    }
    w_s / (w_s + w_d)
}

/// The diffuse base's f |n.wi|.
fn diffuse(b: &Bsdf, wo: Vec3, wi: Vec3) -> Vec3 {
    b.kd * (diffuse_weight(b, wo.z, wi.z) * wi.z / PI)
}

/// The rough specular layer's f |n.wi| = F D G1 G1 / (4 |n.wo|).
fn specular(b: &Bsdf, wo: Vec3, wi: Vec3) -> Vec3 {
    let a = ggx_alpha(b.alpha);
    let m = (wo + wi).normalize();
    let g = ggx_g1(a, wo, m) * ggx_g1(a, wi, m);
    specular_fresnel(b, wo.dot(m)) * (ggx_d(a, m) * g / (4.0 * wo.z))
}

pub fn eval(b: &Bsdf, wo: Vec3, wi: Vec3) -> Vec3 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return Vec3::ZERO;
    }
    if b.alpha == 0.0 {
        return diffuse(b, wo, wi);
    }
    specular(b, wo, wi) + diffuse(b, wo, wi)
}

/// The reflection of a visible-normal sample's density, 1 / (4 wo.m) times the density of m.
fn specular_pdf(b: &Bsdf, wo: Vec3, wi: Vec3) -> f32 {
    let m = (wo + wi).normalize();
    if wo.dot(m) <= 0.0 || wi.dot(m) <= 0.0 {
        return 0.0;
    }
    let a = ggx_alpha(b.alpha);
    ggx_d(a, m) * ggx_g1(a, wo, m) / (4.0 * wo.z)
}

pub fn pdf(b: &Bsdf, wo: Vec3, wi: Vec3) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let p_s = specular_probability(b, wo);
    let diffuse = (1.0 - p_s) * (wi.z / PI);
    if b.alpha == 0.0 {
        return diffuse;
    }
    p_s * specular_pdf(b, wo, wi) + diffuse
}

/// `u_lobe` below the specular probability samples the specular layer (a visible GGX normal,
/// or the mirror direction when alpha = 0: a delta whose pdf is that probability), otherwise
/// the base by the cosine; a rough sample's pdf is the mixture's.
pub fn sample(b: &Bsdf, wo: Vec3, u: Vec2, u_lobe: f32) -> Sample {
    if wo.z <= 0.0 {
        return Sample::failed(Vec3::Z);
    }
    let p_s = specular_probability(b, wo);
    if b.alpha == 0.0 && u_lobe < p_s {
        return Sample {
            wi: Vec3::new(-wo.x, -wo.y, wo.z),
            weight: specular_fresnel(b, wo.z) / p_s,
            pdf: p_s,
            delta: true,
        };
    }
    let wi = if u_lobe < p_s {
        let m = ggx_sample_visible(ggx_alpha(b.alpha), wo, u);
        2.0 * wo.dot(m) * m - wo
    } else {
        sample_cosine(Vec3::Z, u.x, u.y)
    };
    let pdf = pdf(b, wo, wi);
    if wi.z <= 0.0 || pdf <= 0.0 {
        return Sample::failed(wi);
    }
    Sample {
        wi,
        weight: eval(b, wo, wi) / pdf,
        pdf,
        delta: false,
    }
}
