//! The error function and its inverse in f32 (`shaders/lib/erf.wgsl`), for the Beckmann
//! visible-normal sampler: erf by Abramowitz and Stegun 7.1.26 (absolute error below 1.5e-7),
//! erfinv by Giles 2010, "Approximating the erfinv function" (its single-precision branch
//! pair, relative error a few 1e-7), the approximations Mitsuba's and pbrt's samplers use.

/// erf(x).
pub fn erf(x: f32) -> f32 {
    let a = x.abs();
    let t = 1.0 / (1.0 + 0.327_591_1 * a);
    let poly = t
        * (0.254_829_6
            + t * (-0.284_496_74 + t * (1.421_413_7 + t * (-1.453_152_1 + t * 1.061_405_4))));
    let y = 1.0 - poly * (-a * a).exp();
    if x < 0.0 { -y } else { y }
}

/// erfinv(x) for |x| < 1; arguments are clamped a float step inside (-1, 1), where the
/// result is about +-3.8 rather than infinite.
pub fn erfinv(x: f32) -> f32 {
    let x = x.clamp(-0.999_999_9, 0.999_999_9);
    let mut w = -((1.0 - x) * (1.0 + x)).ln();
    let p = if w < 5.0 {
        w -= 2.5;
        let mut p = 2.810_226_4e-8;
        p = 3.432_739_4e-7 + p * w;
        p = -3.523_387_7e-6 + p * w;
        p = -4.391_506_5e-6 + p * w;
        p = 0.000_218_580_87 + p * w;
        p = -0.001_253_725 + p * w;
        p = -0.004_177_681_6 + p * w;
        p = 0.246_640_73 + p * w;
        1.501_409_4 + p * w
    } else {
        w = w.sqrt() - 3.0;
        let mut p = -0.000_200_214_26;
        p = 0.000_100_950_56 + p * w;
        p = 0.001_349_343_2 + p * w;
        p = -0.003_673_428_4 + p * w;
        p = 0.005_739_507_7 + p * w;
        p = -0.007_622_461 + p * w;
        p = 0.009_438_870_5 + p * w;
        p = 1.001_674 + p * w;
        2.832_976_8 + p * w
    };
    p * x
}

#[cfg(test)]
mod tests {
    use super::*;

    /// erf's series in f64, exact to rounding for |x| <= 3 (terms at most e^9 ~ 8e3, so a few
    /// 1e-13 of cancellation).
    fn erf_series(x: f64) -> f64 {
        let (mut term, mut sum) = (x, x);
        for n in 1..200 {
            term *= -x * x / n as f64;
            sum += term / (2 * n + 1) as f64;
        }
        sum * 2.0 / std::f64::consts::PI.sqrt()
    }

    /// Fails on a wrong coefficient: erf against its series within A&S's stated 1.5e-7 plus
    /// f32 rounding (2e-7), and erfinv(erf(x)) = x within Giles's few 1e-7 relative, amplified
    /// by erf's slope 2/sqrt(pi) e^(-x^2) where erf flattens (bound 1e-6 relative for |x| <= 2).
    #[test]
    fn erf_matches_its_series_and_erfinv_inverts_it() {
        for i in -300..=300 {
            let x = i as f64 / 100.0;
            let e = f64::from(erf(x as f32));
            assert!((e - erf_series(x)).abs() < 3.5e-7, "erf({x}): {e}");
            if x.abs() <= 2.0 {
                let back = f64::from(erfinv(erf_series(x) as f32));
                let slope = 2.0 / std::f64::consts::PI.sqrt() * (-x * x).exp();
                let bound = 1e-6 * x.abs() + 1.2e-7 / slope;
                assert!((back - x).abs() <= bound, "erfinv(erf({x})): {back}");
            }
        }
    }
}
