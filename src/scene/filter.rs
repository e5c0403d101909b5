//! The pixel filter (Mitsuba's `rfilter`): how much a film sample at offset (x, y) from a pixel's
//! centre counts toward that pixel, w(x) w(y). Mitsuba splats each sample into every pixel
//! within the filter's radius with those weights and divides by their sum; passgraph instead
//! draws each pixel's sub-pixel offset from the normalised w itself (filter importance
//! sampling, shaders/lib/pixel_filter.wgsl), which has the same expectation,
//! ∫ w(x - p) L(x) dx / ∫ w, without splatting. Mitsuba's film has samples inside the image
//! only, so at the border both integrals run over the image alone: passgraph cuts the filter
//! to the image there too ([`PixelFilter::sample_within`]). [`PixelFilter::sample`] is the CPU
//! mirror.

/// A separable pixel filter, offsets in pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PixelFilter {
    /// Mitsuba's `box` (radius 0.5): uniform over the pixel, as passgraph always sampled.
    Box,
    /// Mitsuba's `gaussian`: exp(-x² / 2σ²) - exp(-8), cut off at 4σ (where it reaches 0).
    Gaussian { stddev: f32 },
    /// Mitsuba's `tent`: 1 - |x| / radius.
    Tent { radius: f32 },
}

/// The `scene_filter` override's values (shaders/lib/pixel_filter.wgsl).
pub const FILTER_BOX: u32 = 0;
pub const FILTER_GAUSSIAN: u32 = 1;
pub const FILTER_TENT: u32 = 2;

/// Where Mitsuba's Gaussian stops: 4 standard deviations.
pub const GAUSSIAN_RADIUS_STDDEVS: f32 = 4.0;

/// The largest stddev or radius, in pixels: beyond it a pixel is an average over most of any
/// image, surely a typo.
pub const MAX_FILTER_SIZE: f32 = 1.0e4;

impl PixelFilter {
    /// The `scene_filter` override.
    pub fn kind(self) -> u32 {
        match self {
            PixelFilter::Box => FILTER_BOX,
            PixelFilter::Gaussian { .. } => FILTER_GAUSSIAN,
            PixelFilter::Tent { .. } => FILTER_TENT,
        }
    }

    /// The `scene_filter_size` override: the Gaussian's stddev, the tent's radius (0 for box).
    pub fn size(self) -> f32 {
        match self {
            PixelFilter::Box => 0.0,
            PixelFilter::Gaussian { stddev } => stddev,
            PixelFilter::Tent { radius } => radius,
        }
    }

    /// Where w reaches 0, in pixels from the centre.
    pub fn radius(self) -> f32 {
        match self {
            PixelFilter::Box => 0.5,
            PixelFilter::Gaussian { stddev } => GAUSSIAN_RADIUS_STDDEVS * stddev,
            PixelFilter::Tent { radius } => radius,
        }
    }

    /// The filter checked: stddev or radius finite, > 0 and at most [`MAX_FILTER_SIZE`].
    pub fn check(self) -> Result<PixelFilter, String> {
        let (name, value) = match self {
            PixelFilter::Box => return Ok(self),
            PixelFilter::Gaussian { stddev } => ("Gaussian stddev", stddev),
            PixelFilter::Tent { radius } => ("Tent radius", radius),
        };
        if value > 0.0 && value <= MAX_FILTER_SIZE {
            Ok(self)
        } else {
            Err(format!(
                "the {name} is {value} pixels; it must be a finite number in (0, {MAX_FILTER_SIZE}]"
            ))
        }
    }

    /// The 1D weight w(x) at `x` pixels from the centre (Mitsuba's `eval`, unnormalised).
    pub fn eval(self, x: f32) -> f32 {
        match self {
            PixelFilter::Box => {
                if x.abs() <= 0.5 {
                    1.0
                } else {
                    0.0
                }
            }
            PixelFilter::Gaussian { stddev } => {
                let alpha = -1.0 / (2.0 * stddev * stddev);
                let r = GAUSSIAN_RADIUS_STDDEVS * stddev;
                ((alpha * x * x).exp() - (alpha * r * r).exp()).max(0.0)
            }
            PixelFilter::Tent { radius } => (1.0 - x.abs() / radius).max(0.0),
        }
    }

    /// The normalised 1D CDF of w at `x` pixels from the centre, in [0, 1] (what a pixel beside
    /// a sharp edge converges to: tests).
    pub fn cdf(self, x: f64) -> f64 {
        let r = f64::from(self.radius());
        if x <= -r {
            return 0.0;
        }
        if x >= r {
            return 1.0;
        }
        match self {
            PixelFilter::Box => (x + 0.5).clamp(0.0, 1.0),
            PixelFilter::Gaussian { stddev } => {
                // The integral from the centre is odd: half of it from -r to the centre.
                let s = f64::from(stddev);
                0.5 + 0.5 * gaussian_integral(s, x) / gaussian_integral(s, r)
            }
            PixelFilter::Tent { radius } => {
                let t = 1.0 - x.abs() / f64::from(radius);
                let tail = 0.5 * t * t;
                if x < 0.0 { tail } else { 1.0 - tail }
            }
        }
    }

    /// The offset from the pixel's centre, in pixels, that uniform `u` in [0, 1) maps to: the
    /// inverse CDF of w (each axis alone). The CPU mirror of pixel_filter.wgsl's.
    pub fn sample(self, u: f32) -> f32 {
        match self {
            PixelFilter::Box => u - 0.5,
            PixelFilter::Tent { radius } => {
                if u < 0.5 {
                    radius * ((2.0 * u).sqrt() - 1.0)
                } else {
                    radius * (1.0 - (2.0 - 2.0 * u).sqrt())
                }
            }
            PixelFilter::Gaussian { stddev } => {
                let s = f64::from(stddev);
                let r = GAUSSIAN_RADIUS_STDDEVS as f64 * s;
                let total = gaussian_integral(s, r);
                let target = (2.0 * f64::from(u) - 1.0) * total;
                // F is odd and increasing on (-r, r): bisection kept as a bracket, Newton steps
                // inside it.
                let (mut lo, mut hi, mut x) = (-r, r, 0.0);
                for _ in 0..40 {
                    let f = gaussian_integral(s, x) - target;
                    if f > 0.0 {
                        hi = x;
                    } else {
                        lo = x;
                    }
                    let w = f64::from(self.eval(x as f32));
                    let step = x - f / w.max(1e-30);
                    x = if step > lo && step < hi {
                        step
                    } else {
                        0.5 * (lo + hi)
                    };
                }
                x as f32
            }
        }
    }

    /// [`PixelFilter::sample`] cut to offsets in [lo, hi] (renormalised): u squeezed into the
    /// CDF's values there first. The CPU mirror of pixel_filter.wgsl's `filter_truncate`: what
    /// keeps a border pixel's film positions inside the image, as Mitsuba's film does.
    pub fn sample_within(self, u: f32, lo: f32, hi: f32) -> f32 {
        if self == PixelFilter::Box {
            return self.sample(u);
        }
        let (a, b) = (self.cdf(f64::from(lo)), self.cdf(f64::from(hi)));
        self.sample((a + f64::from(u) * (b - a)) as f32)
    }

    /// Mitsuba's `<rfilter>` element.
    pub fn mitsuba_xml(self) -> String {
        match self {
            PixelFilter::Box => "<rfilter type=\"box\"/>".into(),
            PixelFilter::Gaussian { stddev } => format!(
                "<rfilter type=\"gaussian\">\n    <float name=\"stddev\" value=\"{stddev}\"/>\n</rfilter>"
            ),
            PixelFilter::Tent { radius } => format!(
                "<rfilter type=\"tent\">\n    <float name=\"radius\" value=\"{radius}\"/>\n</rfilter>"
            ),
        }
    }
}

/// ∫_0^x (exp(-t² / 2σ²) - exp(-8)) dt, the truncated Gaussian's integral from the centre
/// (odd in x), for |x| <= 4σ.
fn gaussian_integral(stddev: f64, x: f64) -> f64 {
    let bias = (-0.5 * f64::from(GAUSSIAN_RADIUS_STDDEVS).powi(2)).exp();
    stddev * (std::f64::consts::PI / 2.0).sqrt() * erf(x / (stddev * std::f64::consts::SQRT_2))
        - bias * x
}

/// The error function, to about 1e-7 (Abramowitz and Stegun 7.1.26), as the shader's.
pub fn erf(x: f64) -> f64 {
    let t = 1.0 / (1.0 + 0.3275911 * x.abs());
    let poly = t
        * (0.254829592
            + t * (-0.284496736 + t * (1.421413741 + t * (-1.453152027 + t * 1.061405429))));
    let y = 1.0 - poly * (-x * x).exp();
    if x < 0.0 { -y } else { y }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FILTERS: [PixelFilter; 4] = [
        PixelFilter::Box,
        PixelFilter::Gaussian { stddev: 0.5 },
        PixelFilter::Gaussian { stddev: 1.3 },
        PixelFilter::Tent { radius: 1.5 },
    ];

    #[test]
    fn sample_inverts_the_cdf() {
        for f in FILTERS {
            for i in 0..100 {
                let u = (i as f32 + 0.5) / 100.0;
                let x = f.sample(u);
                assert!(x.abs() <= f.radius(), "{f:?} {u} -> {x}");
                let back = f.cdf(f64::from(x));
                assert!(
                    (back - f64::from(u)).abs() < 2e-6,
                    "{f:?}: cdf({x}) = {back}, u {u}"
                );
            }
        }
    }

    #[test]
    fn the_cdf_is_the_integral_of_eval() {
        // A midpoint sum of w against the closed-form CDF: catches a wrong bias or radius.
        for f in FILTERS {
            let r = f.radius();
            let n = 20000;
            let dx = 2.0 * r / n as f32;
            let w: Vec<f64> = (0..n)
                .map(|i| f64::from(f.eval(-r + (i as f32 + 0.5) * dx)) * f64::from(dx))
                .collect();
            let total: f64 = w.iter().sum();
            let mut sum = 0.0;
            for (i, wi) in w.iter().enumerate() {
                sum += wi;
                if i % 1000 == 999 {
                    let x = f64::from(-r + (i + 1) as f32 * dx);
                    assert!((sum / total - f.cdf(x)).abs() < 1e-4, "{f:?} at {x}");
                }
            }
        }
    }

    #[test]
    fn samples_cut_to_an_interval_stay_in_it_with_the_renormalised_cdf() {
        // A border pixel: the image ends 0.5 px to the left of its centre (and 0.2 px into the
        // filter on the right for the wide ones).
        for f in FILTERS.into_iter().filter(|f| *f != PixelFilter::Box) {
            let (lo, hi) = (-0.5f32, 0.2 * f.radius() + 0.5);
            let (a, b) = (f.cdf(f64::from(lo)), f.cdf(f64::from(hi)));
            for i in 0..100 {
                let u = (i as f32 + 0.5) / 100.0;
                let x = f.sample_within(u, lo, hi);
                assert!(x >= lo - 1e-5 && x <= hi + 1e-5, "{f:?} {u} -> {x}");
                let back = (f.cdf(f64::from(x)) - a) / (b - a);
                assert!(
                    (back - f64::from(u)).abs() < 1e-5,
                    "{f:?}: renormalised cdf({x}) = {back}, u {u}"
                );
            }
            // An interval holding the whole filter leaves the samples as they were.
            let r = f.radius();
            assert_eq!(f.sample_within(0.3, -r - 1.0, r + 1.0), f.sample(0.3));
        }
    }

    #[test]
    fn gaussian_matches_mitsuba_constants() {
        // Mitsuba's gaussian with stddev 0.5: radius 2, w(1) = exp(-2) - exp(-8).
        let g = PixelFilter::Gaussian { stddev: 0.5 };
        assert_eq!(g.radius(), 2.0);
        assert!((g.eval(1.0) - ((-2.0f32).exp() - (-8.0f32).exp())).abs() < 1e-7);
        assert_eq!(g.eval(2.0), 0.0);
    }

    #[test]
    fn bad_sizes_are_refused() {
        for v in [0.0, -1.0, f32::NAN, f32::INFINITY, 2.0e4] {
            assert!(PixelFilter::Gaussian { stddev: v }.check().is_err(), "{v}");
            assert!(PixelFilter::Tent { radius: v }.check().is_err(), "{v}");
        }
        assert!(PixelFilter::Tent { radius: 1.0 }.check().is_ok());
    }
}
