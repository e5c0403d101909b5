// glTF 2.0's metallic-roughness material, the BRDF of the specification's Appendix B (the CPU
// twin, src/material/metallic_roughness/, states the formula): a mix by metallic (b.ks.x) of a
// metal (GGX specular, Schlick Fresnel with f0 = the base colour b.kd) and a dielectric (the
// same specular layer with f0 = 0.04 over a Lambertian base that gets what the layer does not
// reflect: (1 - E(wo.z)) (1 - E(wi.z)) / (1 - E_avg), E the layer's albedo from the table at
// b.table in `materials` (src/material/metallic_roughness/table.rs; the twin says why this differs
// from the specification's 1 - F(v.h)).
// alpha = roughness^2; 0 makes the specular layer a delta mirror. Two-sided. Local frame:
// normal +z, wo.z >= 0.

const METALLIC_ROUGHNESS_DIELECTRIC_F0: f32 = 0.04;

// Schlick's (1 - cos)^5, the weight of 1 - f0.
fn schlick_weight(cos_h: f32) -> f32 {
    let c = clamp(1.0 - abs(cos_h), 0.0, 1.0);
    let c2 = c * c;
    return c2 * c2 * c;
}

fn mr_metallic(b: Bsdf) -> f32 {
    return clamp(b.ks.x, 0.0, 1.0);
}

// The specular layer's Fresnel term at cos(wo, h): the dielectric's and the metal's mixed by
// metallic.
fn mr_specular_fresnel(b: Bsdf, cos_h: f32) -> vec3<f32> {
    let f0 = mix(vec3<f32>(METALLIC_ROUGHNESS_DIELECTRIC_F0), b.kd, mr_metallic(b));
    return f0 + (vec3<f32>(1.0) - f0) * schlick_weight(cos_h);
}

// Entry i of row j of the layer's albedo table (64 cosines, 17 texels a row).
fn mr_albedo_entry(b: Bsdf, j: u32, i: u32) -> f32 {
    let t = bitcast<vec4<f32>>(scene_texel(materials, b.table + 17u * j + (i >> 2u)));
    return t[i & 3u];
}

// Linear interpolation's cell and weight for x in [0, 1] over n nodes.
fn mr_cell(x: f32, n: u32) -> vec2<f32> {
    let t = clamp(x, 0.0, 1.0) * f32(n - 1u);
    let i = min(u32(t), n - 2u);
    return vec2<f32>(f32(i), t - f32(i));
}

// The dielectric layer's albedo E(cos, roughness), bilinear.
fn mr_layer_albedo(b: Bsdf, cos: f32) -> f32 {
    let c = mr_cell(cos, 64u);
    let r = mr_cell(sqrt(b.alpha), 32u);
    let i = u32(c.x);
    let j = u32(r.x);
    let a0 = mr_albedo_entry(b, j, i);
    let e0 = a0 + (mr_albedo_entry(b, j, i + 1u) - a0) * c.y;
    let a1 = mr_albedo_entry(b, j + 1u, i);
    let e1 = a1 + (mr_albedo_entry(b, j + 1u, i + 1u) - a1) * c.y;
    return e0 + (e1 - e0) * r.y;
}

// The cosine-weighted average of E, linear between rows.
fn mr_layer_average(b: Bsdf) -> f32 {
    let r = mr_cell(sqrt(b.alpha), 32u);
    let j = u32(r.x);
    let a0 = bitcast<f32>(scene_texel(materials, b.table + 17u * j + 16u).x);
    let a1 = bitcast<f32>(scene_texel(materials, b.table + 17u * (j + 1u) + 16u).x);
    return a0 + (a1 - a0) * r.y;
}

// The base's weight times 1 - metallic.
fn mr_diffuse_weight(b: Bsdf, cos_o: f32, cos_i: f32) -> f32 {
    return (1.0 - mr_metallic(b)) * (1.0 - mr_layer_albedo(b, cos_o))
        * (1.0 - mr_layer_albedo(b, cos_i)) / (1.0 - mr_layer_average(b));
}

// The probability of sampling the specular layer, from both layers' albedos at wo (the metal's
// by its Fresnel term at the normal).
fn mr_specular_probability(b: Bsdf, wo: vec3<f32>) -> f32 {
    let e = mr_layer_albedo(b, wo.z);
    let f0 = b.kd;
    let metal = f0 + (vec3<f32>(1.0) - f0) * schlick_weight(wo.z);
    let w_s = (1.0 - mr_metallic(b)) * e + mr_metallic(b) * (metal.x + metal.y + metal.z) / 3.0;
    let w_d = (1.0 - mr_metallic(b)) * (1.0 - e) * (b.kd.x + b.kd.y + b.kd.z) / 3.0;
    return select(w_s / (w_s + w_d), 1.0, w_d <= 0.0);
}

fn mr_diffuse(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    return b.kd * (mr_diffuse_weight(b, wo.z, wi.z) * wi.z / PI);
}

// F D G1 G1 / (4 |n.wo|): the rough specular layer's f |n.wi|.
fn mr_specular(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    let a = ggx_alpha(b.alpha);
    let m = normalize(wo + wi);
    let g = ggx_g1(a, wo, m) * ggx_g1(a, wi, m);
    return mr_specular_fresnel(b, dot(wo, m)) * (ggx_d(a, m) * g / (4.0 * wo.z));
}

fn metallic_roughness_eval(b: Bsdf, outside: bool, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    if b.alpha == 0.0 {
        return mr_diffuse(b, wo, wi);
    }
    return mr_specular(b, wo, wi) + mr_diffuse(b, wo, wi);
}

fn mr_specular_pdf(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    let m = normalize(wo + wi);
    if dot(wo, m) <= 0.0 || dot(wi, m) <= 0.0 {
        return 0.0;
    }
    let a = ggx_alpha(b.alpha);
    // The visible-normal density times the reflection Jacobian 1 / (4 wo.m).
    return ggx_d(a, m) * ggx_g1(a, wo, m) / (4.0 * wo.z);
}

fn metallic_roughness_pdf(b: Bsdf, outside: bool, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let p_s = mr_specular_probability(b, wo);
    let diffuse = (1.0 - p_s) * (wi.z / PI);
    if b.alpha == 0.0 {
        return diffuse;
    }
    return p_s * mr_specular_pdf(b, wo, wi) + diffuse;
}

// u_lobe below the specular probability samples the specular layer (a visible GGX normal, or
// the mirror direction when alpha = 0: a delta of pdf p_s), otherwise the base by the cosine; a
// rough sample's pdf is the mixture's.
fn metallic_roughness_sample(b: Bsdf, outside: bool, wo: vec3<f32>, u: vec2<f32>,
    u_lobe: f32) -> BsdfSample {
    if wo.z <= 0.0 {
        return BsdfSample(vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(0.0), 0.0, false, 1.0);
    }
    let p_s = mr_specular_probability(b, wo);
    if b.alpha == 0.0 && u_lobe < p_s {
        return BsdfSample(vec3<f32>(-wo.x, -wo.y, wo.z), mr_specular_fresnel(b, wo.z) / p_s, p_s,
            true, 1.0);
    }
    var wi: vec3<f32>;
    if u_lobe < p_s {
        let m = ggx_sample_visible(ggx_alpha(b.alpha), wo, u);
        wi = 2.0 * dot(wo, m) * m - wo;
    } else {
        wi = sample_cosine(vec3<f32>(0.0, 0.0, 1.0), u.x, u.y);
    }
    let pdf = metallic_roughness_pdf(b, outside, wo, wi);
    if wi.z <= 0.0 || pdf <= 0.0 {
        return BsdfSample(wi, vec3<f32>(0.0), 0.0, false, 1.0);
    }
    return BsdfSample(wi, metallic_roughness_eval(b, outside, wo, wi) / pdf, pdf, false, 1.0);
}

// The diffuse base is never delta.
fn metallic_roughness_is_delta(b: Bsdf) -> bool {
    return false;
}
