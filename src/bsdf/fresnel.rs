//! Fresnel reflectance of a dielectric interface (`shaders/lib/fresnel.wgsl`), as Mitsuba 3's
//! `fresnel` and `fresnel_diffuse_reflectance`; a conductor's, as its `fresnel_conductor`.

use glam::Vec3;

/// F and the refraction's quantities at `cos_i` for relative index `eta` (inside / outside; the
/// normal points outside). `cos_i < 0`: light arriving from inside.
#[derive(Clone, Copy, Debug)]
pub struct Fresnel {
    /// Reflectance (1 under total internal reflection).
    pub r: f32,
    /// Signed cosine of the transmitted direction (0 under TIR).
    pub cos_t: f32,
    /// Relative index along the travel direction, and its reciprocal.
    pub eta_it: f32,
    pub eta_ti: f32,
}

pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> Fresnel {
    let outside = cos_i >= 0.0;
    let eta_it = if outside { eta } else { 1.0 / eta };
    let eta_ti = if outside { 1.0 / eta } else { eta };
    let cos_t_sqr = 1.0 - (1.0 - cos_i * cos_i) * (eta_ti * eta_ti);
    let ci = cos_i.abs();
    let ct = cos_t_sqr.max(0.0).sqrt();
    let a_s = (ci - eta_it * ct) / (ci + eta_it * ct);
    let a_p = (ct - eta_it * ci) / (ct + eta_it * ci);
    let mut r = 0.5 * (a_s * a_s + a_p * a_p);
    // Matched indices reflect nothing; exactly grazing light reflects fully.
    if eta == 1.0 {
        r = 0.0;
    } else if ci == 0.0 {
        r = 1.0;
    }
    let cos_t = if cos_i >= 0.0 { -ct } else { ct };
    Fresnel {
        r,
        cos_t,
        eta_it,
        eta_ti,
    }
}

/// The cosine-weighted hemispherical average of F (Egan and Hilgeman 1973 for eta < 1, d'Eon
/// and Irving 2011 otherwise).
pub fn fresnel_diffuse_reflectance(eta: f32) -> f32 {
    let inv_eta = 1.0 / eta;
    let approx_1 = 0.0636 * inv_eta + (eta * (eta * -1.4399 + 0.7099) + 0.6681);
    let approx_2 = 0.919317
        + inv_eta
            * (-3.4793
                + inv_eta
                    * (6.75335 + inv_eta * (-7.80989 + inv_eta * (4.98554 + inv_eta * -1.36881))));
    if eta < 1.0 { approx_1 } else { approx_2 }
}

/// Unpolarised reflectance of a conductor of complex relative index eta + i k at `cos_i`
/// (0..1), per channel: Mitsuba 3's `fresnel_conductor` (after Moeller, "Optics", 1988).
pub fn fresnel_conductor(cos_i: f32, eta: Vec3, k: Vec3) -> Vec3 {
    let cos2 = cos_i * cos_i;
    let sin2 = 1.0 - cos2;
    let sin4 = sin2 * sin2;
    let temp_1 = eta * eta - k * k - Vec3::splat(sin2);
    let a2_plus_b2 = (temp_1 * temp_1 + 4.0 * k * k * eta * eta)
        .max(Vec3::ZERO)
        .sqrt();
    let a = (0.5 * (a2_plus_b2 + temp_1)).max(Vec3::ZERO).sqrt();
    let term_1 = a2_plus_b2 + Vec3::splat(cos2);
    let term_2 = 2.0 * cos_i * a;
    let r_s = (term_1 - term_2) / (term_1 + term_2);
    let term_3 = a2_plus_b2 * cos2 + Vec3::splat(sin4);
    let term_4 = term_2 * sin2;
    let r_p = r_s * (term_3 - term_4) / (term_3 + term_4);
    0.5 * (r_s + r_p)
}
