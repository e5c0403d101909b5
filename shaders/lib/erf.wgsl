// The error function and its inverse in f32 (src/bsdf/erf.rs), for the Beckmann visible-normal
// sampler: erf by Abramowitz and Stegun 7.1.26 (absolute error below 1.5e-7), erfinv by Giles
// 2010 (its single-precision pair of branches), as Mitsuba's and pbrt's samplers approximate
// them.

fn erf_approx(x: f32) -> f32 {
    let a = abs(x);
    let t = 1.0 / (1.0 + 0.3275911 * a);
    let poly = t * (0.2548296 + t * (-0.28449674 + t * (1.4214137 + t * (-1.4531521
        + t * 1.0614054))));
    let y = 1.0 - poly * exp(-a * a);
    return select(y, -y, x < 0.0);
}

// For |x| < 1; arguments are clamped a float step inside (-1, 1), where the result is about
// +-3.8 rather than infinite.
fn erfinv_approx(x_in: f32) -> f32 {
    let x = clamp(x_in, -0.9999999, 0.9999999);
    var w = -log((1.0 - x) * (1.0 + x));
    var p: f32;
    if w < 5.0 {
        w = w - 2.5;
        p = 2.8102264e-8;
        p = 3.4327394e-7 + p * w;
        p = -3.5233877e-6 + p * w;
        p = -4.3915065e-6 + p * w;
        p = 0.00021858087 + p * w;
        p = -0.001253725 + p * w;
        p = -0.0041776816 + p * w;
        p = 0.24664073 + p * w;
        p = 1.5014094 + p * w;
    } else {
        w = sqrt(w) - 3.0;
        p = -0.00020021426;
        p = 0.00010095056 + p * w;
        p = 0.0013493432 + p * w;
        p = -0.0036734284 + p * w;
        p = 0.0057395077 + p * w;
        p = -0.007622461 + p * w;
        p = 0.0094388705 + p * w;
        p = 1.001674 + p * w;
        p = 2.8329768 + p * w;
    }
    return p * x;
}
