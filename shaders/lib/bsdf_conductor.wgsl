// Conductor: a mirror tinted by kd (Fresnel 1 times kd: Mitsuba 3's conductor / roughconductor
// with material none and specular_reflectance kd), two-sided; GGX-rough when alpha > 0
// (distribution ggx, sample_visible true), a delta mirror when alpha = 0. Local frame: normal
// +z, wo.z >= 0.

fn conductor_eval(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if b.alpha == 0.0 || wo.z <= 0.0 || wi.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    let a = ggx_alpha(b.alpha);
    let m = normalize(wo + wi);
    let d = ggx_d(a, m);
    let g = ggx_g1(a, wo, m) * ggx_g1(a, wi, m);
    return b.kd * (d * g / (4.0 * wo.z));
}

fn conductor_pdf(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if b.alpha == 0.0 {
        return 0.0;
    }
    let m = normalize(wo + wi);
    if wo.z <= 0.0 || wi.z <= 0.0 || dot(wo, m) <= 0.0 || dot(wi, m) <= 0.0 {
        return 0.0;
    }
    let a = ggx_alpha(b.alpha);
    // The visible-normal density times the reflection Jacobian 1 / (4 wi.m), wi.m = wo.m.
    return ggx_d(a, m) * ggx_g1(a, wo, m) / (4.0 * wo.z);
}

fn conductor_sample(b: Bsdf, wo: vec3<f32>, u: vec2<f32>) -> BsdfSample {
    if wo.z <= 0.0 {
        return BsdfSample(vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(0.0), 0.0, false);
    }
    if b.alpha == 0.0 {
        // The delta lobe is chosen with probability 1.
        return BsdfSample(vec3<f32>(-wo.x, -wo.y, wo.z), b.kd, 1.0, true);
    }
    let a = ggx_alpha(b.alpha);
    let m = ggx_sample_visible(a, wo, u);
    let wi = 2.0 * dot(wo, m) * m - wo;
    let pdf = conductor_pdf(b, wo, wi);
    if pdf <= 0.0 {
        return BsdfSample(wi, vec3<f32>(0.0), 0.0, false);
    }
    // f cos / pdf = kd G1(wi, m): D and G1(wo, m) cancel.
    return BsdfSample(wi, b.kd * ggx_g1(a, wi, m), pdf, false);
}
