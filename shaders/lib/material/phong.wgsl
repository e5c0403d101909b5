// The seed's normalised Blinn-Phong, f = kd / pi + ks (ns + 8) / (8 pi) max(0, n.h)^ns,
// sampled by the cosine as the seed samples it. No Mitsuba twin.

fn phong_eval(b: Bsdf, n: vec3<f32>, outside: bool, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    let cos_o = dot(n, wo);
    let cos_i = dot(n, wi);
    if cos_o <= 0.0 || cos_i <= 0.0 {
        return vec3<f32>(0.0);
    }
    let h = normalize(wo + wi);
    let lobe = (b.ns + 8.0) / (8.0 * PI) * pow(max(0.0, dot(n, h)), b.ns);
    return (b.kd * (1.0 / PI) + b.ks * lobe) * cos_i;
}

// Sampled by the cosine, as Lambert.
fn phong_pdf(b: Bsdf, n: vec3<f32>, outside: bool, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    return lambert_pdf(b, n, outside, wo, wi);
}

fn phong_sample(b: Bsdf, n: vec3<f32>, outside: bool, wo: vec3<f32>, u: vec2<f32>,
    u_lobe: f32) -> BsdfSample {
    let wi = sample_cosine(n, u.x, u.y);
    let pdf = lambert_pdf(b, n, outside, wo, wi);
    if pdf <= 0.0 {
        return BsdfSample(wi, vec3<f32>(0.0), 0.0, false, 1.0);
    }
    return BsdfSample(wi, phong_eval(b, n, outside, wo, wi) / pdf, pdf, false, 1.0);
}

fn phong_is_delta(b: Bsdf) -> bool {
    return false;
}
