// Plastic: a diffuse base kd under a smooth dielectric coat of index ior (outside index 1)
// whose reflection is tinted ks, as Mitsuba 3's plastic with nonlinear false, two-sided. Local
// frame: normal +z, wo.z >= 0.
//
// alpha is ignored: a rough plastic (Mitsuba's roughplastic) needs per-material tables (the
// coat's transmittance over cos theta and its internal reflectance, integrals over the GGX
// visible normals) that Material does not carry yet, so every plastic is the smooth one.

// The probability of sampling the coat's delta reflection rather than the base, from the
// reflectance at wo (f_i): Mitsuba's weights, with the tints' means at this point.
fn plastic_specular_probability(b: Bsdf, f_i: f32) -> f32 {
    let s_mean = (b.ks.x + b.ks.y + b.ks.z) / 3.0;
    let d_mean = (b.kd.x + b.kd.y + b.kd.z) / 3.0;
    // Black tints have no lobe to prefer.
    let w = select(0.5, s_mean / (d_mean + s_mean), d_mean + s_mean > 0.0);
    let p_s = f_i * w;
    let p_d = (1.0 - f_i) * (1.0 - w);
    return select(1.0, p_s / (p_s + p_d), p_s + p_d > 0.0);
}

// The base's light as the coat lets it through: kd / (1 - internal diffuse reflectance), the
// coat's transmission both ways and the 1 / eta^2 of entering and leaving.
fn plastic_diffuse(b: Bsdf, cos_o: f32, cos_i: f32) -> vec3<f32> {
    let eta = b.ior;
    let f_o = fresnel_dielectric(cos_o, eta).r;
    let f_i = fresnel_dielectric(cos_i, eta).r;
    let fdr_int = fresnel_diffuse_reflectance(1.0 / eta);
    let scale = (cos_i / PI) * (1.0 / (eta * eta)) * (1.0 - f_o) * (1.0 - f_i);
    return b.kd / (1.0 - fdr_int) * scale;
}

fn plastic_eval(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    return plastic_diffuse(b, wo.z, wi.z);
}

fn plastic_pdf(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let f_o = fresnel_dielectric(wo.z, b.ior).r;
    return (1.0 - plastic_specular_probability(b, f_o)) * (wi.z / PI);
}

// u_lobe < the specular probability picks the coat's reflection (delta; pdf is that
// probability), otherwise the base by the cosine.
fn plastic_sample(b: Bsdf, wo: vec3<f32>, u: vec2<f32>, u_lobe: f32) -> BsdfSample {
    if wo.z <= 0.0 {
        return BsdfSample(vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(0.0), 0.0, false);
    }
    let f_o = fresnel_dielectric(wo.z, b.ior).r;
    let p_s = plastic_specular_probability(b, f_o);
    if u_lobe < p_s {
        return BsdfSample(vec3<f32>(-wo.x, -wo.y, wo.z), b.ks * (f_o / p_s), p_s, true);
    }
    let wi = sample_cosine(vec3<f32>(0.0, 0.0, 1.0), u.x, u.y);
    let pdf = (1.0 - p_s) * (wi.z / PI);
    if wi.z <= 0.0 || pdf <= 0.0 {
        return BsdfSample(wi, vec3<f32>(0.0), 0.0, false);
    }
    return BsdfSample(wi, plastic_diffuse(b, wo.z, wi.z) / pdf, pdf, false);
}
