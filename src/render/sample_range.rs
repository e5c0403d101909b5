//! A range of samples (frame indices) of an accumulation: what `render --samples A..B`
//! renders, a partial file holds and a checkpoint has done.

use std::fmt;

/// Frame indices `start..end` of an accumulation (`end` excluded; never empty).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct SampleRange {
    pub start: u32,
    pub end: u32,
}

impl SampleRange {
    pub fn len(self) -> u32 {
        self.end - self.start
    }

    pub fn is_empty(self) -> bool {
        self.end <= self.start
    }

    /// Whether the range is an aligned block of a power-of-two length (A a multiple of B - A):
    /// with the Sobol sampler such a range's samples are a stratified net on their own.
    pub fn is_power_of_two_aligned(self) -> bool {
        let len = self.len();
        len.is_power_of_two() && self.start.is_multiple_of(len)
    }
}

impl fmt::Display for SampleRange {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "{}..{}", self.start, self.end)
    }
}

impl std::str::FromStr for SampleRange {
    type Err = String;

    /// `A..B` with A < B (the command line's `--samples`).
    fn from_str(s: &str) -> Result<SampleRange, String> {
        let bad = || format!("'{s}' is not a sample range A..B (whole numbers, A < B), e.g. 0..64");
        let (a, b) = s.trim().split_once("..").ok_or_else(bad)?;
        let a: u32 = a.trim().parse().map_err(|_| bad())?;
        let b: u32 = b.trim().parse().map_err(|_| bad())?;
        if a >= b {
            return Err(format!("'{s}' is an empty sample range: A..B needs A < B"));
        }
        Ok(SampleRange { start: a, end: b })
    }
}
