// The isotropic Beckmann microfacet distribution (src/bsdf/beckmann.rs), as Mitsuba 3's
// MicrofacetDistribution with type beckmann and sample_visible true: alpha is the RMS slope,
// used as given (floored as Mitsuba floors it: microfacet_alpha), Smith's masking by Mitsuba's
// rational fit, visible normals by Jakob 2014's numerical inversion. Local frame, normal +z.
// Needs lib/erf.wgsl.

const BECKMANN_INV_SQRT_PI: f32 = 0.5641896;

// D(m) = exp(-tan^2 / alpha^2) / (pi alpha^2 cos^4); 0 for m below the horizon.
fn beckmann_d(alpha: f32, m: vec3<f32>) -> f32 {
    if m.z <= 0.0 {
        return 0.0;
    }
    let cos2 = m.z * m.z;
    let xy = (m.x / alpha) * (m.x / alpha) + (m.y / alpha) * (m.y / alpha);
    let d = exp(-xy / cos2) / (PI * alpha * alpha * cos2 * cos2);
    // A tiny D times cos would underflow downstream terms (Mitsuba's cut).
    return select(0.0, d, d * m.z > 1e-20);
}

// Smith's masking G1(v, m) by Mitsuba's rational fit in a = 1 / (alpha tan theta_v) (relative
// error below 0.35 %, exactly 1 from a = 1.6); 0 when v sees m's back.
fn beckmann_g1(alpha: f32, v: vec3<f32>, m: vec3<f32>) -> f32 {
    let xy = alpha * alpha * (v.x * v.x + v.y * v.y);
    var g = 1.0;
    if xy > 0.0 {
        let a = sqrt(v.z * v.z / xy);
        if a < 1.6 {
            g = (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a);
        }
    }
    if dot(v, m) * v.z <= 0.0 {
        g = 0.0;
    }
    return g;
}

// The alpha = 1 distribution's visible slopes seen at cos_theta_i: the x slope by three Newton
// steps on its CDF in the erf domain from an analytic first guess, the y slope by inverting
// the Gaussian's CDF (Mitsuba's sample_visible_11).
fn beckmann_sample_visible_11(cos_theta_i: f32, u_in: vec2<f32>) -> vec2<f32> {
    let sin_theta_i = sqrt(max(0.0, 1.0 - cos_theta_i * cos_theta_i));
    let tan_theta_i = sin_theta_i / cos_theta_i;
    // At normal incidence cot is infinite; 1e7 keeps every term finite and exact in f32
    // (erf(1e7) = 1, exp(-1e14) = 0) on every device.
    let cot_theta_i = cos_theta_i / max(sin_theta_i, 1e-7);
    let maxval = erf_approx(cot_theta_i);
    let u = clamp(u_in, vec2<f32>(1e-6), vec2<f32>(1.0 - 1e-6));
    var x = maxval - (maxval + 1.0) * erf_approx(sqrt(-log(u.x)));
    let target_cdf = u.x * (1.0 + maxval + BECKMANN_INV_SQRT_PI * tan_theta_i
        * exp(-cot_theta_i * cot_theta_i));
    for (var i = 0; i < 3; i++) {
        let slope = erfinv_approx(x);
        let value = 1.0 + x + BECKMANN_INV_SQRT_PI * tan_theta_i * exp(-slope * slope)
            - target_cdf;
        let derivative = 1.0 - slope * tan_theta_i;
        x -= value / derivative;
    }
    return vec2<f32>(erfinv_approx(x), erfinv_approx(2.0 * u.y - 1.0));
}

// A normal from the distribution of normals visible from wi (wi.z > 0): stretch wi by alpha,
// sample the alpha = 1 slopes, rotate them to wi's azimuth and unstretch. Its density is
// beckmann_pdf_visible (up to the masking fit).
fn beckmann_sample_visible(alpha: f32, wi: vec3<f32>, u: vec2<f32>) -> vec3<f32> {
    let wi_p = normalize(vec3<f32>(alpha * wi.x, alpha * wi.y, wi.z));
    let lensq = wi_p.x * wi_p.x + wi_p.y * wi_p.y;
    // Below 1e-12 (|xy| < 1e-6) wi's azimuth is rounding noise: a fixed one makes the same u
    // give the same direction on every device.
    var cos_phi = 1.0;
    var sin_phi = 0.0;
    if lensq > 1e-12 {
        let inv = 1.0 / sqrt(lensq);
        cos_phi = wi_p.x * inv;
        sin_phi = wi_p.y * inv;
    }
    let s = beckmann_sample_visible_11(wi_p.z, u);
    let slope_x = (cos_phi * s.x - sin_phi * s.y) * alpha;
    let slope_y = (sin_phi * s.x + cos_phi * s.y) * alpha;
    return normalize(vec3<f32>(-slope_x, -slope_y, 1.0));
}

// Density of the visible normals: D(m) G1(wi, m) |wi.m| / wi.z.
fn beckmann_pdf_visible(alpha: f32, wi: vec3<f32>, m: vec3<f32>) -> f32 {
    return beckmann_d(alpha, m) * beckmann_g1(alpha, wi, m) * abs(dot(wi, m)) / wi.z;
}
