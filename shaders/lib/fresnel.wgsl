// Fresnel reflectance of a dielectric interface, as Mitsuba 3's `fresnel` and
// `fresnel_diffuse_reflectance` (include/mitsuba/render/fresnel.h).

// F and the refraction's quantities at cos_i = cos(wi, normal), eta = inside / outside index
// (the normal points outside). cos_i < 0 is light arriving from inside.
struct Fresnel {
    // Reflectance (1 under total internal reflection).
    r: f32,
    // Signed cosine of the transmitted direction (opposite side to cos_i; 0 under TIR).
    cos_t: f32,
    // Relative index along the travel direction, and its reciprocal (the tangential scale of
    // the refracted direction).
    eta_it: f32,
    eta_ti: f32,
}

fn fresnel_dielectric(cos_i: f32, eta: f32) -> Fresnel {
    let outside = cos_i >= 0.0;
    let eta_it = select(1.0 / eta, eta, outside);
    let eta_ti = select(eta, 1.0 / eta, outside);
    let cos_t_sqr = 1.0 - (1.0 - cos_i * cos_i) * (eta_ti * eta_ti);
    let ci = abs(cos_i);
    let ct = sqrt(max(0.0, cos_t_sqr));
    let a_s = (ci - eta_it * ct) / (ci + eta_it * ct);
    let a_p = (ct - eta_it * ci) / (ct + eta_it * ci);
    var r = 0.5 * (a_s * a_s + a_p * a_p);
    // Matched indices reflect nothing; exactly grazing light reflects fully.
    if eta == 1.0 {
        r = 0.0;
    } else if ci == 0.0 {
        r = 1.0;
    }
    let cos_t = select(ct, -ct, cos_i >= 0.0);
    return Fresnel(r, cos_t, eta_it, eta_ti);
}

// The hemispherical average of F for a cosine-weighted hemisphere (fits by Egan and Hilgeman
// 1973 for eta < 1, d'Eon and Irving 2011 otherwise).
fn fresnel_diffuse_reflectance(eta: f32) -> f32 {
    let inv_eta = 1.0 / eta;
    let approx_1 = 0.0636 * inv_eta + (eta * (eta * -1.4399 + 0.7099) + 0.6681);
    let approx_2 = 0.919317 + inv_eta * (-3.4793 + inv_eta * (6.75335 + inv_eta
        * (-7.80989 + inv_eta * (4.98554 + inv_eta * -1.36881))));
    return select(approx_2, approx_1, eta < 1.0);
}

// Unpolarised reflectance of a conductor of complex relative index eta + i k at cos_i (0..1),
// per channel: Mitsuba 3's fresnel_conductor (after Moeller, "Optics", 1988).
fn fresnel_conductor(cos_i: f32, eta: vec3<f32>, k: vec3<f32>) -> vec3<f32> {
    let cos2 = cos_i * cos_i;
    let sin2 = 1.0 - cos2;
    let sin4 = sin2 * sin2;
    let temp_1 = eta * eta - k * k - vec3<f32>(sin2);
    let a2_plus_b2 = sqrt(max(vec3<f32>(0.0), temp_1 * temp_1 + 4.0 * k * k * eta * eta));
    let a = sqrt(max(vec3<f32>(0.0), 0.5 * (a2_plus_b2 + temp_1)));
    let term_1 = a2_plus_b2 + vec3<f32>(cos2);
    let term_2 = 2.0 * cos_i * a;
    let r_s = (term_1 - term_2) / (term_1 + term_2);
    let term_3 = a2_plus_b2 * cos2 + vec3<f32>(sin4);
    let term_4 = term_2 * sin2;
    let r_p = r_s * (term_3 - term_4) / (term_3 + term_4);
    return 0.5 * (r_s + r_p);
}
