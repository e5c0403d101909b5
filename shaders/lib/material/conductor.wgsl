// Conductor: a mirror tinted by kd, two-sided, as Mitsuba 3's conductor / roughconductor with
// specular_reflectance kd: with fresnel FRESNEL_NONE its material none (Fresnel 1), with
// FRESNEL_CONDUCTOR times the Fresnel term of the complex index eta + i k (behind the
// scene_has_conductor_fresnel override: other scenes run the tinted mirror alone, as before).
// Microfacet-rough when alpha > 0 (GGX or Beckmann by distribution, sample_visible true), a
// delta mirror when alpha = 0. Local frame: normal +z, wo.z >= 0.

// The reflectance at cos(wo, m) = cos_i: kd, times the complex-index Fresnel term when the
// material has one.
fn conductor_reflectance(b: Bsdf, cos_i: f32) -> vec3<f32> {
    if scene_has_conductor_fresnel && b.fresnel == FRESNEL_CONDUCTOR {
        return b.kd * fresnel_conductor(cos_i, b.eta, b.k);
    }
    return b.kd;
}

fn conductor_eval(b: Bsdf, outside: bool, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if b.alpha == 0.0 || wo.z <= 0.0 || wi.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    let a = microfacet_alpha(b.alpha);
    let m = normalize(wo + wi);
    let d = microfacet_d(b.distribution, a, m);
    let g = microfacet_g1(b.distribution, a, wo, m) * microfacet_g1(b.distribution, a, wi, m);
    return conductor_reflectance(b, dot(wo, m)) * (d * g / (4.0 * wo.z));
}

fn conductor_pdf(b: Bsdf, outside: bool, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if b.alpha == 0.0 {
        return 0.0;
    }
    let m = normalize(wo + wi);
    if wo.z <= 0.0 || wi.z <= 0.0 || dot(wo, m) <= 0.0 || dot(wi, m) <= 0.0 {
        return 0.0;
    }
    let a = microfacet_alpha(b.alpha);
    // The visible-normal density times the reflection Jacobian 1 / (4 wi.m), wi.m = wo.m.
    return microfacet_d(b.distribution, a, m) * microfacet_g1(b.distribution, a, wo, m) / (4.0 * wo.z);
}

fn conductor_sample(b: Bsdf, outside: bool, wo: vec3<f32>, u: vec2<f32>, u_lobe: f32)
    -> BsdfSample {
    if wo.z <= 0.0 {
        return BsdfSample(vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(0.0), 0.0, false, 1.0);
    }
    if b.alpha == 0.0 {
        // The delta lobe is chosen with probability 1.
        return BsdfSample(vec3<f32>(-wo.x, -wo.y, wo.z), conductor_reflectance(b, wo.z), 1.0,
            true, 1.0);
    }
    let a = microfacet_alpha(b.alpha);
    let m = microfacet_sample_visible(b.distribution, a, wo, u);
    let wi = 2.0 * dot(wo, m) * m - wo;
    let pdf = conductor_pdf(b, outside, wo, wi);
    if pdf <= 0.0 {
        return BsdfSample(wi, vec3<f32>(0.0), 0.0, false, 1.0);
    }
    // f cos / pdf = F kd G1(wi, m): D and G1(wo, m) cancel.
    let weight = conductor_reflectance(b, dot(wo, m)) * microfacet_g1(b.distribution, a, wi, m);
    return BsdfSample(wi, weight, pdf, false, 1.0);
}

// The smooth mirror is delta.
fn conductor_is_delta(b: Bsdf) -> bool {
    return b.alpha == 0.0;
}
