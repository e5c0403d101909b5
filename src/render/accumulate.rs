//! The accumulate pass's running mean, on the CPU, in the shader's exact f32 arithmetic
//! (`shaders/accumulate.wgsl`, `mean_step`): for tests and for reasoning about long
//! accumulations.
//!
//! The plain update `m += (x - m) / (n + 1)` rounds `m + d` once per frame, by up to half an
//! ulp of the mean, and the error of frame k still weighs k / n after n frames. Random
//! roundings add up like a random walk, about `sqrt(n / 3) / sqrt(12)` ulps: measured after
//! 10^6 frames of uniform noise, up to 3.3e-5 relative. Worse, when the increments repeat
//! (a mostly black pixel with rare fireflies) the roundings repeat too and add up linearly:
//! 1.1e-3 relative. The compensated update carries each rounding error in a second f32 and
//! feeds it back, which keeps the mean within about half an ulp of the exact mean at any frame
//! count (measured: 3.5e-8). tests/robust_accumulate.rs holds both to these figures.

/// One running mean as the accumulate pass stores it: `mean` (the `result` buffer) and the
/// rounding error it carries (the `compensation` buffer), so that `mean + compensation` is the
/// mean of the samples seen to within a few ulps of `compensation`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CompensatedMean {
    pub mean: f32,
    pub compensation: f32,
}

impl CompensatedMean {
    /// Adds sample `x` to a mean of `n` samples, as `mean_step` in `accumulate.wgsl`:
    /// the increment, the exact rounding error of `mean + d` (Knuth's TwoSum), and the sum
    /// renormalised so that `mean` is the f32 nearest to `mean + compensation` (Fast2Sum).
    pub fn step(self, x: f32, n: f32) -> CompensatedMean {
        let (m, c) = (self.mean, self.compensation);
        let d = ((x - m) - c) / (n + 1.0);
        let s = m + d;
        let b = s - m;
        let e = (m - (s - b)) + (d - b);
        let t = c + e;
        let mean = s + t;
        CompensatedMean {
            mean,
            compensation: t - (mean - s),
        }
    }
}

/// The plain running-mean update `m + (x - m) / (n + 1)` in f32, which the accumulate pass
/// used before it was compensated: kept to measure what compensation buys.
pub fn plain_mean_step(m: f32, x: f32, n: f32) -> f32 {
    m + (x - m) / (n + 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_sample_is_the_mean_and_constant_signals_stay_exact() {
        let mut m = CompensatedMean::default().step(0.1, 0.0);
        assert_eq!(
            m,
            CompensatedMean {
                mean: 0.1,
                compensation: 0.0
            }
        );
        for n in 1..1000 {
            m = m.step(0.1, n as f32);
        }
        assert_eq!(m.mean, 0.1);
    }

    #[test]
    fn compensation_recovers_what_the_plain_update_loses() {
        // 1 followed by many samples of 1 + 2^-24 (half an ulp of 1): the plain mean never
        // moves, the compensated one reaches the exact mean's nearest f32.
        let tiny = 1.0 + f32::EPSILON;
        let (mut plain, mut compensated) = (1.0f32, CompensatedMean::default().step(1.0, 0.0));
        for n in 1..100_000 {
            plain = plain_mean_step(plain, tiny, n as f32);
            compensated = compensated.step(tiny, n as f32);
        }
        assert_eq!(plain, 1.0);
        assert_eq!(compensated.mean, tiny);
    }
}
