// The pixel filter (src/scene/filter.rs, Mitsuba's rfilter) by filter importance sampling: a
// pixel's film position is drawn from the normalised filter w(x) w(y) around its centre instead
// of uniformly in it, so its plain mean converges to Mitsuba's filter-weighted film,
// ∫ w(x - p) L(x) dx / ∫ w. Box (0): uniform in the pixel, as always. Gaussian (1): Mitsuba's
// exp(-x² / 2σ²) - exp(-8), cut off at 4σ. Tent (2): 1 - |x| / radius. The includer includes
// scene.wgsl (scene_filter, scene_filter_size).

const FILTER_BOX: u32 = 0u;
const FILTER_GAUSSIAN: u32 = 1u;
const FILTER_TENT: u32 = 2u;

// The error function to about 1e-7 (Abramowitz and Stegun 7.1.26; WGSL has none).
fn filter_erf(x: f32) -> f32 {
    let t = 1.0 / (1.0 + 0.3275911 * abs(x));
    let poly = t * (0.254829592 + t * (-0.284496736 + t * (1.421413741 + t * (-1.453152027 + t * 1.061405429))));
    return sign(x) * (1.0 - poly * exp(-x * x));
}

// ∫_0^x w, the truncated Gaussian of stddev s from its centre (odd in x).
fn filter_gaussian_integral(s: f32, x: f32) -> f32 {
    let bias = exp(-8.0);
    return s * 1.2533141 * filter_erf(x * 0.70710678 / s) - bias * x;
}

// The filter's CDF at offset x (0 at -radius, 1 at +radius; not the box's).
fn filter_cdf(x: f32) -> f32 {
    let r = select(scene_filter_size, 4.0 * scene_filter_size, scene_filter == FILTER_GAUSSIAN);
    let c = clamp(x, -r, r);
    if scene_filter == FILTER_GAUSSIAN {
        let s = scene_filter_size;
        return 0.5 + 0.5 * filter_gaussian_integral(s, c) / filter_gaussian_integral(s, r);
    }
    let t = 1.0 - abs(c) / r;
    return select(1.0 - 0.5 * t * t, 0.5 * t * t, c < 0.0);
}

// u in [0, 1) squeezed into the CDF's values over the offsets [lo, hi], so that its inverse CDF
// draws from the filter cut to that interval (renormalised). Where the interval holds the whole
// filter the CDF is exactly 0 and 1 there and u stays as it is, bit for bit.
fn filter_truncate(u: f32, lo: f32, hi: f32) -> f32 {
    let a = filter_cdf(lo);
    return a + u * (filter_cdf(hi) - a);
}

// The inverse CDF of the truncated Gaussian at u in [0, 1): the integral is increasing on
// (-4s, 4s), so Newton steps stay inside a bisection bracket (a step out of it bisects).
fn filter_gaussian_sample(u: f32) -> f32 {
    let s = scene_filter_size;
    let r = 4.0 * s;
    let target_value = (2.0 * u - 1.0) * filter_gaussian_integral(s, r);
    var lo = -r;
    var hi = r;
    var x = 0.0;
    for (var i = 0; i < 16; i++) {
        let f = filter_gaussian_integral(s, x) - target_value;
        if f > 0.0 {
            hi = x;
        } else {
            lo = x;
        }
        let w = exp(-x * x / (2.0 * s * s)) - exp(-8.0);
        let step = x - f / max(w, 1.0e-30);
        x = select(0.5 * (lo + hi), step, step > lo && step < hi);
    }
    return x;
}

// The inverse CDF of the tent at u in [0, 1).
fn filter_tent_sample(u: f32) -> f32 {
    let r = scene_filter_size;
    return select(r * (1.0 - sqrt(2.0 - 2.0 * u)), r * (sqrt(2.0 * u) - 1.0), u < 0.5);
}

// The film position, in pixels from the pixel's top-left corner, of the uniform sample u in
// [0, 1)^2: u itself for the box; the filter's offset from the centre (0.5, 0.5) otherwise,
// which reaches into the neighbours.
fn pixel_filter_position(u: vec2<f32>) -> vec2<f32> {
    if scene_filter == FILTER_GAUSSIAN {
        return vec2<f32>(0.5) + vec2<f32>(filter_gaussian_sample(u.x), filter_gaussian_sample(u.y));
    }
    if scene_filter == FILTER_TENT {
        return vec2<f32>(0.5) + vec2<f32>(filter_tent_sample(u.x), filter_tent_sample(u.y));
    }
    return u;
}

// pixel_filter_position for the pixel whose top-left corner is `corner` in an image of `size`
// pixels, its positions kept inside the image: Mitsuba's film draws samples only inside the
// image and divides each pixel's weighted sum by its weights, so at the border its filter is
// cut to the image and renormalised; so is this one (interior pixels: as before, bit for bit).
fn pixel_filter_position_in_image(u: vec2<f32>, corner: vec2<f32>, size: vec2<f32>) -> vec2<f32> {
    if scene_filter == FILTER_BOX {
        return u;
    }
    // Offsets from the pixel's centre that keep corner + 0.5 + offset within [0, size].
    let lo = -(corner + 0.5);
    let hi = size - corner - 0.5;
    return pixel_filter_position(vec2<f32>(filter_truncate(u.x, lo.x, hi.x), filter_truncate(u.y, lo.y, hi.y)));
}
