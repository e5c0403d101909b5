// Thin dielectric: a sheet of index ior (outside 1) too thin to see its two faces apart, as
// Mitsuba 3's thindielectric (src/material/thin_dielectric/): light reflects with the
// interreflected reflectance R' = R + T^2 R / (1 - R^2) = 2R / (1 + R) or passes straight
// through with 1 - R' tinted tf, without refraction. Both lobes are delta and two-sided (eval
// and pdf are 0). Local frame: normal +z on wo's side.

fn thin_dielectric_reflectance(b: Bsdf, cos: f32) -> f32 {
    let r = fresnel_dielectric(cos, b.ior).r;
    return r * 2.0 / (1.0 + r);
}

// u_lobe < R' reflects (weight 1), else passes through (weight tf); pdf is the lobe's
// probability.
fn thin_dielectric_sample(b: Bsdf, outside: bool, wo: vec3<f32>, u: vec2<f32>, u_lobe: f32)
    -> BsdfSample {
    if wo.z <= 0.0 {
        return BsdfSample(vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(0.0), 0.0, false, 1.0);
    }
    let r = thin_dielectric_reflectance(b, wo.z);
    if u_lobe < r {
        return BsdfSample(vec3<f32>(-wo.x, -wo.y, wo.z), vec3<f32>(1.0), r, true, 1.0);
    }
    return BsdfSample(-wo, b.tf, 1.0 - r, true, 1.0);
}

fn thin_dielectric_eval(b: Bsdf, outside: bool, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(0.0);
}

fn thin_dielectric_pdf(b: Bsdf, outside: bool, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    return 0.0;
}

fn thin_dielectric_is_delta(b: Bsdf) -> bool {
    return true;
}
