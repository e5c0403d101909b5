// Dielectric: a one-sided interface between outside (index 1, where the geometric normal
// points) and inside (index ior), reflection untinted, transmission tinted tf, in radiance
// transport (transmitted radiance scaled by eta_ti^2, the solid angle's compression);
// microfacet-rough (GGX or Beckmann by distribution) when alpha > 0, as Mitsuba 3's
// roughdielectric (sample_visible), a delta interface when
// alpha = 0, as its dielectric. Local frame: normal +z on wo's side; eta is the index across
// the interface relative to wo's side (ior outside, 1 / ior inside), which makes the maths
// that of the outside for either side.

fn dielectric_eta(b: Bsdf, outside: bool) -> f32 {
    return select(1.0 / b.ior, b.ior, outside);
}

// The microfacet normal that takes wo to wi (reflected or refracted), on wo's side.
fn dielectric_half(eta: f32, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    let is_reflection = wo.z * wi.z > 0.0;
    let m = normalize(wo + wi * select(eta, 1.0, is_reflection));
    return select(m, -m, m.z < 0.0);
}

fn dielectric_eval(b: Bsdf, outside: bool, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if b.alpha == 0.0 || wo.z == 0.0 {
        return vec3<f32>(0.0);
    }
    let a = microfacet_alpha(b.alpha);
    let eta = dielectric_eta(b, outside);
    let m = dielectric_half(eta, wo, wi);
    let d = microfacet_d(b.distribution, a, m);
    let f = fresnel_dielectric(dot(wo, m), eta).r;
    let g = microfacet_g1(b.distribution, a, wo, m) * microfacet_g1(b.distribution, a, wi, m);
    if wo.z * wi.z > 0.0 {
        return vec3<f32>(f * d * g / (4.0 * abs(wo.z)));
    }
    // Radiance transport's 1 / eta^2 times the half-vector Jacobian's eta^2 (kept separate,
    // as the model writes them).
    let scale = 1.0 / (eta * eta);
    let denom = dot(wo, m) + eta * dot(wi, m);
    let t = abs(scale * (1.0 - f) * d * g * eta * eta * dot(wo, m) * dot(wi, m)
        / (wo.z * denom * denom));
    return b.tf * t;
}

fn dielectric_pdf(b: Bsdf, outside: bool, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if b.alpha == 0.0 || wo.z == 0.0 {
        return 0.0;
    }
    let a = microfacet_alpha(b.alpha);
    let eta = dielectric_eta(b, outside);
    let is_reflection = wo.z * wi.z > 0.0;
    let m = dielectric_half(eta, wo, wi);
    if dot(wo, m) * wo.z <= 0.0 || dot(wi, m) * wi.z <= 0.0 {
        return 0.0;
    }
    let denom = dot(wo, m) + eta * dot(wi, m);
    let dwh_dwi = select(eta * eta * dot(wi, m) / (denom * denom), 1.0 / (4.0 * dot(wi, m)),
        is_reflection);
    let f = fresnel_dielectric(dot(wo, m), eta).r;
    let lobe = select(1.0 - f, f, is_reflection);
    return microfacet_pdf_visible(b.distribution, a, wo, m) * lobe * abs(dwh_dwi);
}

// Smooth: u_lobe <= F reflects, else refracts; delta, pdf = the chosen lobe's probability.
// Rough: a visible normal, then the same choice by its F.
fn dielectric_sample(b: Bsdf, outside: bool, wo: vec3<f32>, u: vec2<f32>, u_lobe: f32)
    -> BsdfSample {
    let eta = dielectric_eta(b, outside);
    if wo.z == 0.0 {
        return BsdfSample(vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(0.0), 0.0, false, 1.0);
    }
    if b.alpha == 0.0 {
        let fr = fresnel_dielectric(wo.z, eta);
        if u_lobe <= fr.r {
            return BsdfSample(vec3<f32>(-wo.x, -wo.y, wo.z), vec3<f32>(1.0), fr.r, true, 1.0);
        }
        let wi = vec3<f32>(-fr.eta_ti * wo.x, -fr.eta_ti * wo.y, fr.cos_t);
        return BsdfSample(wi, b.tf * (fr.eta_ti * fr.eta_ti), 1.0 - fr.r, true, fr.eta_it);
    }
    let a = microfacet_alpha(b.alpha);
    let m = microfacet_sample_visible(b.distribution, a, wo, u);
    let fr = fresnel_dielectric(dot(wo, m), eta);
    var wi: vec3<f32>;
    var weight: vec3<f32>;
    var eta_sampled = 1.0;
    if u_lobe <= fr.r {
        wi = 2.0 * dot(wo, m) * m - wo;
        weight = vec3<f32>(1.0);
    } else {
        wi = m * (dot(wo, m) * fr.eta_ti + fr.cos_t) - wo * fr.eta_ti;
        weight = b.tf * (fr.eta_ti * fr.eta_ti);
        eta_sampled = fr.eta_it;
    }
    // f cos / pdf = tint G1(wi, m), which is 0 when wi left for the wrong side: a failed sample.
    let g = microfacet_g1(b.distribution, a, wi, m);
    let pdf = dielectric_pdf(b, outside, wo, wi);
    if g <= 0.0 || pdf <= 0.0 {
        return BsdfSample(wi, vec3<f32>(0.0), 0.0, false, 1.0);
    }
    return BsdfSample(wi, weight * g, pdf, false, eta_sampled);
}

// The smooth interface is delta.
fn dielectric_is_delta(b: Bsdf) -> bool {
    return b.alpha == 0.0;
}
