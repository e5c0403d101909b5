// The materials' BSDFs (placeholder: Lambert and the seed's Blinn-Phong only, sampled by
// cosine; the full library replaces this file).

struct Bsdf {
    kind: u32,
    kd: vec3<f32>,
    ks: vec3<f32>,
    ns: f32,
    alpha: f32,
    ior: f32,
    tf: vec3<f32>,
}

struct BsdfSample {
    wi: vec3<f32>,
    weight: vec3<f32>,
    pdf: f32,
    delta: bool,
}

fn bsdf_from_material(m: Material) -> Bsdf {
    return Bsdf(m.kind, m.kd, m.ks, m.ns, m.alpha, m.ior, m.tf);
}

fn bsdf_is_delta(b: Bsdf) -> bool {
    return false;
}

fn bsdf_eval(b: Bsdf, n: vec3<f32>, outside: bool, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    let cos_i = dot(n, wi);
    if cos_i <= 0.0 {
        return vec3<f32>(0.0);
    }
    var f = b.kd * (1.0 / PI);
    if scene_has_kind(MATERIAL_PHONG) && b.kind == MATERIAL_PHONG {
        let h = normalize(wo + wi);
        f += b.ks * ((b.ns + 8.0) / (8.0 * PI) * pow(max(0.0, dot(n, h)), b.ns));
    }
    return f * cos_i;
}

fn bsdf_pdf(b: Bsdf, n: vec3<f32>, outside: bool, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    return max(dot(n, wi), 0.0) * (1.0 / PI);
}

fn bsdf_sample(b: Bsdf, n: vec3<f32>, outside: bool, wo: vec3<f32>, u: vec2<f32>, u_lobe: f32) -> BsdfSample {
    let wi = sample_cosine(n, u.x, u.y);
    var weight = b.kd;
    if scene_has_kind(MATERIAL_PHONG) && b.kind == MATERIAL_PHONG {
        let h = normalize(wo + wi);
        weight += b.ks * ((b.ns + 8.0) / 8.0 * pow(max(0.0, dot(n, h)), b.ns));
    }
    return BsdfSample(wi, weight, max(dot(n, wi), 0.0) * (1.0 / PI), false);
}
