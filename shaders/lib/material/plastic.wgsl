// Plastic: a diffuse base kd under a dielectric coat of index ior (outside index 1) whose
// reflection is tinted ks, as Mitsuba 3's plastic (smooth: b.table is NO_TABLE) and
// roughplastic (GGX or Beckmann of roughness alpha), both with nonlinear false, two-sided.
// Local frame:
// normal +z, wo.z >= 0.
//
// Requires the global `materials`, the scene.materials texel view (texture_storage_2d
// rgba32uint, read): the rough coat's tables live there after the materials, 17 texels from
// b.table (src/material/plastic/tables.rs): the coat's external transmittance at cos theta = i / 63,
// i = 0..63, four per texel, then the internal reflectance in the 17th texel's x.

// The probability of sampling the coat's reflection rather than the base, from the fraction of
// light at wo the coat reflects (f_i: F for the smooth coat, 1 - transmittance for the rough
// one): Mitsuba's weights, with the tints' means at this point.
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

fn plastic_eval(b: Bsdf, outside: bool, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if b.table != NO_TABLE {
        return rough_plastic_eval(b, wo, wi);
    }
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    return plastic_diffuse(b, wo.z, wi.z);
}

fn plastic_pdf(b: Bsdf, outside: bool, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if b.table != NO_TABLE {
        return rough_plastic_pdf(b, wo, wi);
    }
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let f_o = fresnel_dielectric(wo.z, b.ior).r;
    return (1.0 - plastic_specular_probability(b, f_o)) * (wi.z / PI);
}

// u_lobe < the specular probability picks the coat's reflection (delta; pdf is that
// probability), otherwise the base by the cosine.
fn plastic_sample(b: Bsdf, outside: bool, wo: vec3<f32>, u: vec2<f32>, u_lobe: f32)
    -> BsdfSample {
    if b.table != NO_TABLE {
        return rough_plastic_sample(b, wo, u, u_lobe);
    }
    if wo.z <= 0.0 {
        return BsdfSample(vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(0.0), 0.0, false, 1.0);
    }
    let f_o = fresnel_dielectric(wo.z, b.ior).r;
    let p_s = plastic_specular_probability(b, f_o);
    if u_lobe < p_s {
        return BsdfSample(vec3<f32>(-wo.x, -wo.y, wo.z), b.ks * (f_o / p_s), p_s, true, 1.0);
    }
    let wi = sample_cosine(vec3<f32>(0.0, 0.0, 1.0), u.x, u.y);
    let pdf = (1.0 - p_s) * (wi.z / PI);
    if wi.z <= 0.0 || pdf <= 0.0 {
        return BsdfSample(wi, vec3<f32>(0.0), 0.0, false, 1.0);
    }
    return BsdfSample(wi, plastic_diffuse(b, wo.z, wi.z) / pdf, pdf, false, 1.0);
}

// Entry j of the rough coat's transmittance table.
fn rough_plastic_entry(b: Bsdf, j: u32) -> f32 {
    let t = bitcast<vec4<f32>>(scene_texel(materials, b.table + (j >> 2u)));
    return t[j & 3u];
}

// Mitsuba's lerp_gather: the transmittance at cos in [0, 1], linear between the 64 entries.
fn rough_plastic_transmittance(b: Bsdf, cos: f32) -> f32 {
    let x = cos * 63.0;
    let index = min(u32(x), 62u);
    let v0 = rough_plastic_entry(b, index);
    let v1 = rough_plastic_entry(b, index + 1u);
    let t = x - f32(index);
    return v0 + (v1 - v0) * t;
}

// The rough coat's diffuse part: kd / (1 - internal reflectance), the coat's transmittance both
// ways, the 1 / eta^2 of entering and leaving, and the cosine.
fn rough_plastic_diffuse(b: Bsdf, cos_o: f32, cos_i: f32) -> vec3<f32> {
    let t_o = rough_plastic_transmittance(b, cos_o);
    let t_i = rough_plastic_transmittance(b, cos_i);
    let internal = bitcast<f32>(scene_texel(materials, b.table + 16u).x);
    let scale = (1.0 / PI) * (1.0 / (b.ior * b.ior)) * cos_i * t_o * t_i;
    return b.kd / (1.0 - internal) * scale;
}

// The rough coat's specular part: ks F D G / (4 cos_o) (f times cos_i).
fn rough_plastic_specular(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    let a = microfacet_alpha(b.alpha);
    let m = normalize(wo + wi);
    let d = microfacet_d(b.distribution, a, m);
    let f = fresnel_dielectric(dot(wo, m), b.ior).r;
    let g = microfacet_g1(b.distribution, a, wo, m) * microfacet_g1(b.distribution, a, wi, m);
    return b.ks * (f * d * g / (4.0 * wo.z));
}

fn rough_plastic_eval(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    return rough_plastic_specular(b, wo, wi) + rough_plastic_diffuse(b, wo.z, wi.z);
}

fn rough_plastic_pdf(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let p_s = plastic_specular_probability(b, 1.0 - rough_plastic_transmittance(b, wo.z));
    let a = microfacet_alpha(b.alpha);
    let m = normalize(wo + wi);
    // The visible-normal density times the reflection Jacobian 1 / (4 wo.m).
    let specular = microfacet_d(b.distribution, a, m) * microfacet_g1(b.distribution, a, wo, m) / (4.0 * wo.z);
    return p_s * specular + (1.0 - p_s) * (wi.z / PI);
}

// u_lobe below the specular probability reflects wo about a visible microfacet normal, otherwise the
// base is sampled by the cosine; either way the pdf is the mixture's.
fn rough_plastic_sample(b: Bsdf, wo: vec3<f32>, u: vec2<f32>, u_lobe: f32) -> BsdfSample {
    if wo.z <= 0.0 {
        return BsdfSample(vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(0.0), 0.0, false, 1.0);
    }
    let p_s = plastic_specular_probability(b, 1.0 - rough_plastic_transmittance(b, wo.z));
    var wi: vec3<f32>;
    if u_lobe < p_s {
        let m = microfacet_sample_visible(b.distribution, microfacet_alpha(b.alpha), wo, u);
        wi = 2.0 * dot(wo, m) * m - wo;
    } else {
        wi = sample_cosine(vec3<f32>(0.0, 0.0, 1.0), u.x, u.y);
    }
    let pdf = rough_plastic_pdf(b, wo, wi);
    if wi.z <= 0.0 || pdf <= 0.0 {
        return BsdfSample(wi, vec3<f32>(0.0), 0.0, false, 1.0);
    }
    return BsdfSample(wi, rough_plastic_eval(b, wo, wi) / pdf, pdf, false, 1.0);
}

// The diffuse base is never delta.
fn plastic_is_delta(b: Bsdf) -> bool {
    return false;
}
