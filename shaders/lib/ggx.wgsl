// The isotropic GGX (Trowbridge-Reitz) microfacet distribution, as Mitsuba 3's
// MicrofacetDistribution with type ggx and sample_visible true. Vectors are in the local frame
// of the macro-surface (normal +z).

// Mitsuba's floor on alpha: below it the distribution is a delta the float maths cannot hold.
fn ggx_alpha(alpha: f32) -> f32 {
    return max(alpha, 1e-4);
}

// D(m).
fn ggx_d(alpha: f32, m: vec3<f32>) -> f32 {
    let a2 = alpha * alpha;
    let t = (m.x * m.x) / a2 + (m.y * m.y) / a2 + m.z * m.z;
    let d = 1.0 / (PI * a2 * t * t);
    // A tiny D times cos would underflow downstream terms.
    return select(0.0, d, d * m.z > 1e-20);
}

// Smith's masking G1(v, m); 0 when v sees m's back (or m faces away from v's side).
fn ggx_g1(alpha: f32, v: vec3<f32>, m: vec3<f32>) -> f32 {
    let xy = alpha * alpha * (v.x * v.x + v.y * v.y);
    let tan2 = xy / (v.z * v.z);
    var g = 2.0 / (1.0 + sqrt(1.0 + tan2));
    if xy == 0.0 {
        g = 1.0;
    }
    if dot(v, m) * v.z <= 0.0 {
        g = 0.0;
    }
    return g;
}

// A microfacet normal from the distribution of normals visible from wi (wi.z > 0), by Heitz
// 2018, "Sampling the GGX Distribution of Visible Normals". Its density is ggx_pdf_visible.
fn ggx_sample_visible(alpha: f32, wi: vec3<f32>, u: vec2<f32>) -> vec3<f32> {
    let vh = normalize(vec3<f32>(alpha * wi.x, alpha * wi.y, wi.z));
    let lensq = vh.x * vh.x + vh.y * vh.y;
    // Below 1e-12 (|xy| < 1e-6) wi's azimuth is rounding noise: a fixed tangent makes the same u
    // give the same direction on every device.
    var t1 = vec3<f32>(1.0, 0.0, 0.0);
    if lensq > 1e-12 {
        t1 = vec3<f32>(-vh.y, vh.x, 0.0) / sqrt(lensq);
    }
    let t2 = cross(vh, t1);
    let r = sqrt(u.x);
    let phi = 2.0 * PI * u.y;
    let p1 = r * cos(phi);
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * sqrt(max(0.0, 1.0 - p1 * p1)) + s * (r * sin(phi));
    let nh = p1 * t1 + p2 * t2 + sqrt(max(0.0, 1.0 - p1 * p1 - p2 * p2)) * vh;
    return normalize(vec3<f32>(alpha * nh.x, alpha * nh.y, max(0.0, nh.z)));
}

// Density of ggx_sample_visible: D(m) G1(wi, m) |wi.m| / wi.z.
fn ggx_pdf_visible(alpha: f32, wi: vec3<f32>, m: vec3<f32>) -> f32 {
    return ggx_d(alpha, m) * ggx_g1(alpha, wi, m) * abs(dot(wi, m)) / wi.z;
}
