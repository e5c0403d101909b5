//! The rough plastic's per-material tables, as Mitsuba 3's roughplastic precomputes them: the
//! coat's external transmittance over cos theta (64 entries at cos = 0, 1/63, ... 1, read by
//! linear interpolation) and its internal reflectance (a scalar). Both are integrals over the
//! coat's visible normals (GGX or Beckmann); they are computed here in f64 by Mitsuba's own rule (its
//! `eval_transmittance` / `eval_reflectance`: a tensor Gauss-Legendre rule on the visible-normal
//! sampler's unit square, 32 x 32 nodes when the relative index exceeds 1, 128 x 128 otherwise,
//! with Mitsuba's sampler mapping), so they agree with Mitsuba's f32 tables to its rounding.
//!
//! On the GPU a table is 17 texels of the materials view (`TABLE_TEXELS`): the 64
//! transmittances in order, four per texel, then the internal reflectance in the last texel's x.

use crate::bsdf::erf;
use crate::bsdf::microfacet::Distribution;
use crate::bsdf::quadrature::gauss_legendre;
use std::f64::consts::PI;

/// Mitsuba's MI_ROUGH_TRANSMITTANCE_RES.
pub const TRANSMITTANCE_RES: usize = 64;

/// Texels (4 f32 each) a table takes in the materials view.
pub const TABLE_TEXELS: usize = TRANSMITTANCE_RES / 4 + 1;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlasticTable {
    /// The coat's transmittance for light arriving from outside at cos theta = i / 63.
    pub transmittance: [f32; TRANSMITTANCE_RES],
    /// The fraction of the base's light the coat reflects back in (Mitsuba's
    /// m_internal_reflectance).
    pub internal_reflectance: f32,
}

impl PlasticTable {
    /// The tables of a coat with `distribution`'s microfacets of roughness `alpha` (floored as
    /// Mitsuba floors it) and relative index `eta` (inside / outside).
    pub fn compute(distribution: Distribution, alpha: f32, eta: f32) -> PlasticTable {
        let alpha = f64::from(alpha.max(1e-4));
        let coat = Coat {
            distribution,
            alpha,
        };
        let eta = f64::from(eta);
        let mut transmittance = [0.0f32; TRANSMITTANCE_RES];
        let mut reflectance_sum = 0.0;
        for (i, t) in transmittance.iter_mut().enumerate() {
            // Mitsuba's linspace(0, 1, 64) floored at 1e-6, in the xz-plane.
            let mu = (i as f64 / (TRANSMITTANCE_RES - 1) as f64).max(1e-6);
            let wi = [(1.0 - mu * mu).sqrt(), 0.0, mu];
            *t = transmittance_at(coat, wi, eta) as f32;
            reflectance_sum += reflectance_at(coat, wi, 1.0 / eta) * mu;
        }
        // Mitsuba's mean(R(mu) mu) * 2 over the same 64 cosines: the cosine-weighted
        // hemispherical average by an equal-weight rule.
        let internal_reflectance = (2.0 * reflectance_sum / TRANSMITTANCE_RES as f64) as f32;
        PlasticTable {
            transmittance,
            internal_reflectance,
        }
    }

    /// Mitsuba's `lerp_gather` of the transmittance at `cos` in [0, 1].
    pub fn transmittance_at(&self, cos: f32) -> f32 {
        let x = cos * (TRANSMITTANCE_RES - 1) as f32;
        let index = (x as u32).min(TRANSMITTANCE_RES as u32 - 2);
        let v0 = self.transmittance[index as usize];
        let v1 = self.transmittance[index as usize + 1];
        let t = x - index as f32;
        v0 + (v1 - v0) * t
    }

    /// The table as the materials view stores it.
    pub fn texels(&self) -> [[f32; 4]; TABLE_TEXELS] {
        let mut out = [[0.0; 4]; TABLE_TEXELS];
        for (i, t) in self.transmittance.iter().enumerate() {
            out[i / 4][i % 4] = *t;
        }
        out[TABLE_TEXELS - 1][0] = self.internal_reflectance;
        out
    }

    /// The table read back from `TABLE_TEXELS` texels.
    pub fn from_texels(texels: &[[f32; 4]]) -> PlasticTable {
        let mut transmittance = [0.0f32; TRANSMITTANCE_RES];
        for (i, t) in transmittance.iter_mut().enumerate() {
            *t = texels[i / 4][i % 4];
        }
        PlasticTable {
            transmittance,
            internal_reflectance: texels[TABLE_TEXELS - 1][0],
        }
    }
}

type V3 = [f64; 3];

fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn normalize(v: V3) -> V3 {
    let l = dot(v, v).sqrt();
    [v[0] / l, v[1] / l, v[2] / l]
}

/// The fraction of light arriving along `wi` (outside, z > 0) that the rough interface of
/// relative index `eta` transmits: Mitsuba's `eval_transmittance`.
fn transmittance_at(coat: Coat, wi: V3, eta: f64) -> f64 {
    integrate(eta, |u| {
        let m = coat.sample_visible(wi, u);
        let (f, cos_t, eta_ti) = fresnel(dot(wi, m), eta);
        let k = dot(wi, m) * eta_ti + cos_t;
        let wo = [
            m[0] * k - wi[0] * eta_ti,
            m[1] * k - wi[1] * eta_ti,
            m[2] * k - wi[2] * eta_ti,
        ];
        if wo[2] * wi[2] >= 0.0 {
            0.0
        } else {
            coat.smith_g1(wo, m) * (1.0 - f)
        }
    })
}

/// The fraction of light arriving along `wi` that the rough interface of relative index `eta`
/// reflects once: Mitsuba's `eval_reflectance`.
fn reflectance_at(coat: Coat, wi: V3, eta: f64) -> f64 {
    integrate(eta, |u| {
        let m = coat.sample_visible(wi, u);
        let c = dot(wi, m);
        let wo = [
            2.0 * c * m[0] - wi[0],
            2.0 * c * m[1] - wi[1],
            2.0 * c * m[2] - wi[2],
        ];
        if wo[2] <= 0.0 || wi[2] <= 0.0 {
            0.0
        } else {
            coat.smith_g1(wo, m) * fresnel(c, eta).0
        }
    })
}

/// Mitsuba's rule: Gauss-Legendre on [0, 1]^2, 32 nodes a side for eta > 1, 128 otherwise
/// (total internal reflection makes the integrand's edge sharper).
fn integrate(eta: f64, f: impl Fn([f64; 2]) -> f64) -> f64 {
    let (nodes, weights) = gauss_legendre(if eta > 1.0 { 32 } else { 128 });
    let mut sum = 0.0;
    for (x, wx) in nodes.iter().zip(&weights) {
        for (y, wy) in nodes.iter().zip(&weights) {
            sum += f([0.5 * x + 0.5, 0.5 * y + 0.5]) * wx * wy * 0.25;
        }
    }
    sum
}

/// The coat's microfacets.
#[derive(Clone, Copy)]
struct Coat {
    distribution: Distribution,
    alpha: f64,
}

impl Coat {
    fn sample_visible(self, wi: V3, u: [f64; 2]) -> V3 {
        match self.distribution {
            Distribution::Ggx => sample_visible(self.alpha, wi, u),
            Distribution::Beckmann => beckmann_sample_visible(self.alpha, wi, u),
        }
    }

    fn smith_g1(self, v: V3, m: V3) -> f64 {
        match self.distribution {
            Distribution::Ggx => smith_g1(self.alpha, v, m),
            Distribution::Beckmann => beckmann_smith_g1(self.alpha, v, m),
        }
    }
}

/// Mitsuba's Beckmann visible-normal sampler for `wi` in the xz-plane with x >= 0 (its
/// azimuth rotation the identity): the stretched incidence's alpha = 1 slopes (Jakob 2014's
/// three Newton steps from Mitsuba's first guess, on the same clamped square), unstretched.
fn beckmann_sample_visible(alpha: f64, wi: V3, u: [f64; 2]) -> V3 {
    let inv_sqrt_pi = 1.0 / PI.sqrt();
    let wi_p = normalize([alpha * wi[0], alpha * wi[1], wi[2]]);
    let cos_theta = wi_p[2];
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let tan_theta = sin_theta / cos_theta;
    let cot_theta = cos_theta / sin_theta.max(1e-7);
    let maxval = erf(cot_theta);
    let u = u.map(|c| c.clamp(1e-6, 1.0 - 1e-6));
    let mut x = maxval - (maxval + 1.0) * erf((-u[0].ln()).sqrt());
    let target = u[0] * (1.0 + maxval + inv_sqrt_pi * tan_theta * (-cot_theta * cot_theta).exp());
    for _ in 0..3 {
        let slope = erfinv(x);
        let value = 1.0 + x + inv_sqrt_pi * tan_theta * (-slope * slope).exp() - target;
        x -= value / (1.0 - slope * tan_theta);
    }
    let slope = [erfinv(x) * alpha, erfinv(2.0 * u[1] - 1.0) * alpha];
    normalize([-slope[0], -slope[1], 1.0])
}

/// Beckmann Smith G1 by Mitsuba's rational fit, with its orientation rule.
fn beckmann_smith_g1(alpha: f64, v: V3, m: V3) -> f64 {
    let xy = alpha * alpha * (v[0] * v[0] + v[1] * v[1]);
    if dot(v, m) * v[2] <= 0.0 {
        return 0.0;
    }
    if xy == 0.0 {
        return 1.0;
    }
    let a = (v[2] * v[2] / xy).sqrt();
    if a >= 1.6 {
        return 1.0;
    }
    (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a)
}

/// erf and erfinv as the sampler computes them (src/bsdf/erf.rs, in f32): Mitsuba's f32
/// approximations are of the same grade (a few 1e-7), which moves the rule's normals by that
/// and the tables' values far less than the 1e-5 they are checked to.
fn erf(x: f64) -> f64 {
    f64::from(erf::erf(x as f32))
}

fn erfinv(x: f64) -> f64 {
    f64::from(erf::erfinv(x as f32))
}

/// Mitsuba's GGX visible-normal sampler (stretch, `sample_visible_11` through the concentric
/// disk, unstretch), for `wi` in the xz-plane with x >= 0 so that its azimuth rotation is the
/// identity. Its mapping from the square, not only its density, decides the rule's value.
fn sample_visible(alpha: f64, wi: V3, u: [f64; 2]) -> V3 {
    let wi_p = normalize([alpha * wi[0], alpha * wi[1], wi[2]]);
    let cos_theta = wi_p[2];
    let (px, py) = square_to_disk_concentric(u);
    let s = 0.5 * (1.0 + cos_theta);
    let py = (1.0 - s) * (1.0 - px * px).max(0.0).sqrt() + s * py;
    let z = (1.0 - px * px - py * py).max(0.0).sqrt();
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let norm = 1.0 / (sin_theta * py + cos_theta * z);
    let slope = [(cos_theta * py - sin_theta * z) * norm, px * norm];
    normalize([-slope[0] * alpha, -slope[1] * alpha, 1.0])
}

/// Mitsuba's `square_to_uniform_disk_concentric` (Shirley-Chiu, Cline's form).
fn square_to_disk_concentric(u: [f64; 2]) -> (f64, f64) {
    let x = 2.0 * u[0] - 1.0;
    let y = 2.0 * u[1] - 1.0;
    if x == 0.0 && y == 0.0 {
        return (0.0, 0.0);
    }
    let quadrant_1_or_3 = x.abs() < y.abs();
    let (r, rp) = if quadrant_1_or_3 { (y, x) } else { (x, y) };
    let mut phi = 0.25 * PI * rp / r;
    if quadrant_1_or_3 {
        phi = 0.5 * PI - phi;
    }
    (r * phi.cos(), r * phi.sin())
}

/// GGX Smith G1 with Mitsuba's orientation rule.
fn smith_g1(alpha: f64, v: V3, m: V3) -> f64 {
    let xy = alpha * alpha * (v[0] * v[0] + v[1] * v[1]);
    if dot(v, m) * v[2] <= 0.0 {
        return 0.0;
    }
    if xy == 0.0 {
        return 1.0;
    }
    2.0 / (1.0 + (1.0 + xy / (v[2] * v[2])).sqrt())
}

/// Mitsuba's `fresnel`: (F, signed cos of the transmitted direction, eta_ti).
fn fresnel(cos_i: f64, eta: f64) -> (f64, f64, f64) {
    let outside = cos_i >= 0.0;
    let (eta_it, eta_ti) = if outside {
        (eta, 1.0 / eta)
    } else {
        (1.0 / eta, eta)
    };
    let cos_t_sqr = 1.0 - (1.0 - cos_i * cos_i) * eta_ti * eta_ti;
    let ci = cos_i.abs();
    let ct = cos_t_sqr.max(0.0).sqrt();
    let a_s = (ci - eta_it * ct) / (ci + eta_it * ct);
    let a_p = (ct - eta_it * ci) / (ct + eta_it * ci);
    let mut r = 0.5 * (a_s * a_s + a_p * a_p);
    if eta == 1.0 {
        r = 0.0;
    } else if ci == 0.0 {
        r = 1.0;
    }
    (r, if outside { -ct } else { ct }, eta_ti)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Near-smooth coats approach the smooth interface: transmittance 1 - F(cos).
    #[test]
    fn a_near_smooth_coat_transmits_one_minus_fresnel() {
        let t = PlasticTable::compute(Distribution::Ggx, 1e-4, 1.5);
        for (i, &v) in t.transmittance.iter().enumerate().skip(1) {
            let mu = i as f64 / 63.0;
            let expected = 1.0 - fresnel(mu, 1.5).0;
            assert!(
                (f64::from(v) - expected).abs() < 2e-3,
                "cos {mu}: {v} vs {expected}"
            );
        }
    }
}
