// Lambert: f = kd / pi, two-sided (Mitsuba 3's twosided + diffuse). World space; n faces wo.

fn lambert_eval(b: Bsdf, n: vec3<f32>, outside: bool, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    let cos_o = dot(n, wo);
    let cos_i = dot(n, wi);
    if cos_o <= 0.0 || cos_i <= 0.0 {
        return vec3<f32>(0.0);
    }
    return b.kd * (cos_i / PI);
}

fn lambert_pdf(b: Bsdf, n: vec3<f32>, outside: bool, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    let cos_o = dot(n, wo);
    let cos_i = dot(n, wi);
    if cos_o <= 0.0 || cos_i <= 0.0 {
        return 0.0;
    }
    return cos_i / PI;
}

fn lambert_sample(b: Bsdf, n: vec3<f32>, outside: bool, wo: vec3<f32>, u: vec2<f32>,
    u_lobe: f32) -> BsdfSample {
    let wi = sample_cosine(n, u.x, u.y);
    let pdf = lambert_pdf(b, n, outside, wo, wi);
    if pdf <= 0.0 {
        return BsdfSample(wi, vec3<f32>(0.0), 0.0, false, 1.0);
    }
    // f cos / pdf: the cosines and pi cancel.
    return BsdfSample(wi, b.kd, pdf, false, 1.0);
}

fn lambert_is_delta(b: Bsdf) -> bool {
    return false;
}
