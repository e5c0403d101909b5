//! Merging partial files of consecutive sample ranges into the partial of their union
//! (`passgraph merge`; docs/distributed.md, "Merge").
//!
//! [`merge_files`] holds one partial in memory at a time (it reads each file twice: once to
//! check and order them all, once to add it), so many ranges of a large image merge in the
//! memory of one partial (140 bytes a pixel) and the sums (128 bytes a pixel).
//!
//! The inputs are put in a canonical order, by sample range, before anything is added, so
//! the result is the same bit for bit whatever order they are given in. They must be of one
//! render (same fingerprint and size) and tile their union exactly: an overlap would count
//! samples twice, a gap would leave some out; both are refused, naming the files and ranges.
//!
//! Per pixel, channel and colour component, with counts `n_i`, means `m_i` and compensations
//! `c_i`, the merged mean is `t = Σ n_i (m_i + c_i) / Σ n_i`, computed in f64 in range
//! order, and split back into the f32 `mean = t` rounded and `compensation = t - mean`
//! rounded, so a merged partial merges again (hierarchically) like any other. A pixel with
//! no samples anywhere gets 0, as the accumulate pass leaves it.
//!
//! # How close a merge is to the unsplit render
//!
//! Both hold the same f32 samples `x_n` (the range render draws frame `A + k` as the whole
//! render does), so both approximate the exact mean `μ` of the same `N` numbers. The
//! accumulate pass compensates the rounding of `mean + increment` (exactly, up to ~2^-24 of
//! the compensation); the roundings of `x - m`, of `- c` and of the division by `n + 1` are
//! not compensated: at step `n` they move the estimate by at most `3 2^-24 |x_n - m_n| /
//! (n + 1)`, and an error at step `n` weighs `(n + 1) / N` in the final mean, so the error
//! of `mean + compensation` is at most `1.5 2^-23 Σ|x_n - m_n| / N`. For the renderer's
//! non-negative channels `Σ|x_n - m_n| <= Σ x_n + Σ m_n <= N μ (2 + ln N)` (a running mean
//! `m_n` is at most `Σ_{k<n} x_k / n`). A partial's `m_i + c_i` carries the same bound over
//! its own samples (its own running means, `ln n_i <= ln N`), weighted `n_i / N` in the merge;
//! the f64 sum adds ~2^-50 relative; each side's final rounding to f32 half an ulp, at most
//! `2^-24 μ`. So
//!
//! `|M - U| <= (1 + 3 (2 + ln N)) 2^-23 μ`, about `2.3e-6 μ` at N = 64,
//!
//! and the counts and dropped-sample totals are equal exactly. That worst case needs every
//! rounding to go the same way; they do not, and in practice the two differ by the final
//! roundings and little more: tests/partial_merge.rs checks the bound on 4 ranges of 16
//! frames against one render of 64 (32x32, both samplers) and on the CPU over heavy-tailed
//! pixels, and measured at most 2 ulps, with 95 % of values identical (docs/distributed.md).

use super::partial::{Partial, Plane, SampleRange};
use std::path::{Path, PathBuf};

/// Merges partials given with the files they came from (for messages).
pub fn merge(inputs: Vec<(PathBuf, Partial)>) -> Result<Partial, String> {
    let mut inputs = inputs;
    order_and_check(&mut inputs)?;
    let mut sums = Sums::new(inputs[0].1.size);
    for (_, p) in &inputs {
        sums.add(p);
    }
    Ok(sums.finish(&inputs))
}

/// Merges partial files, reading them one at a time (see the module documentation).
pub fn merge_files(paths: &[PathBuf]) -> Result<Partial, String> {
    // The checks need only the headers: each file's pixels are dropped once it is read.
    let mut headers = paths
        .iter()
        .map(|path| {
            let p = Partial::read(path)?;
            if p.progress.is_some() {
                return Err(format!(
                    "{}: a checkpoint of a tiled render stopped inside its range ({}): resume it to the end (`passgraph render --resume`) before merging",
                    show(path),
                    p.holds()
                ));
            }
            Ok((
                path.clone(),
                Partial {
                    planes: Vec::new(),
                    ..p
                },
            ))
        })
        .collect::<Result<Vec<_>, String>>()?;
    order_and_check(&mut headers)?;
    let mut sums = Sums::new(headers[0].1.size);
    for (path, header) in &headers {
        let p = Partial::read(path)?;
        if (p.samples, p.size, &p.fingerprint) != (header.samples, header.size, &header.fingerprint)
        {
            return Err(format!("{}: changed while it was being merged", show(path)));
        }
        sums.add(&p);
    }
    Ok(sums.finish(&headers))
}

/// Puts the inputs in the canonical order and checks that they are of one render and join
/// without gaps or overlaps (only their headers are read).
fn order_and_check(inputs: &mut [(PathBuf, Partial)]) -> Result<(), String> {
    if inputs.is_empty() {
        return Err("merge needs at least one partial file".to_string());
    }
    // Canonical order. Equal starts sort by end, then by path, only so that the overlap
    // message below is the same whatever order the files came in.
    inputs.sort_by(|(pa, a), (pb, b)| (a.samples, pa).cmp(&(b.samples, pb)));
    let (first_path, first) = &inputs[0];
    for (path, p) in &inputs[1..] {
        if p.size != first.size {
            return Err(format!(
                "{} is {}x{} but {} is {}x{}: partials of one render have one size",
                show(first_path),
                first.size[0],
                first.size[1],
                show(path),
                p.size[0],
                p.size[1]
            ));
        }
        let differences = first.fingerprint.differences(&p.fingerprint);
        if !differences.is_empty() {
            return Err(format!(
                "{} (samples {}) and {} (samples {}) are of different renders; they differ in {}",
                show(first_path),
                first.samples,
                show(path),
                p.samples,
                differences.join(" and ")
            ));
        }
    }
    for j in 1..inputs.len() {
        let ((pa, a), (pb, b)) = (&inputs[j - 1], &inputs[j]);
        if b.samples.start < a.samples.end {
            let both = SampleRange {
                start: b.samples.start,
                end: a.samples.end.min(b.samples.end),
            };
            return Err(format!(
                "{} (samples {}) and {} (samples {}) overlap: samples {both} would count twice",
                show(pa),
                a.samples,
                show(pb),
                b.samples
            ));
        }
        if b.samples.start > a.samples.end {
            let missing = SampleRange {
                start: a.samples.end,
                end: b.samples.start,
            };
            return Err(format!(
                "samples {missing} are missing between {} (samples {}) and {} (samples {}): the ranges must join without a gap",
                show(pa),
                a.samples,
                show(pb),
                b.samples
            ));
        }
    }
    Ok(())
}

/// Per plane, pixel and component, `Σ n_i (m_i + c_i)` in f64, and per plane and pixel
/// `Σ n_i`, added in the canonical order.
struct Sums {
    pixels: usize,
    sums: Vec<Vec<[f64; 3]>>,
    counts: Vec<Vec<u64>>,
}

impl Sums {
    fn new(size: [u32; 2]) -> Sums {
        let pixels = size[0] as usize * size[1] as usize;
        let planes = super::channels::Channel::ALL.len();
        Sums {
            pixels,
            sums: vec![vec![[0.0; 3]; pixels]; planes],
            counts: vec![vec![0; pixels]; planes],
        }
    }

    /// Adds a partial of the size [`Sums::new`] was given (reading checked its planes).
    fn add(&mut self, p: &Partial) {
        for ((sums, counts), plane) in self.sums.iter_mut().zip(&mut self.counts).zip(&p.planes) {
            let pixels = sums.iter_mut().zip(counts.iter_mut());
            for (i, (sum, count)) in pixels.enumerate() {
                let n = plane.count[i];
                *count += u64::from(n);
                let (mean, compensation) = (plane.mean[i], plane.compensation[i]);
                for (k, s) in sum.iter_mut().enumerate() {
                    *s += f64::from(n) * (f64::from(mean[k]) + f64::from(compensation[k]));
                }
            }
        }
    }

    /// The merged partial; `inputs` in the canonical order, checked.
    fn finish(self, inputs: &[(PathBuf, Partial)]) -> Partial {
        let (first, last) = (&inputs[0].1, &inputs[inputs.len() - 1].1);
        let planes = self
            .sums
            .iter()
            .zip(&self.counts)
            .map(|(sums, counts)| {
                let mut plane = Plane {
                    mean: vec![[0.0; 3]; self.pixels],
                    compensation: vec![[0.0; 3]; self.pixels],
                    // Counts are at most the ranges' lengths, and the union is a u32 range.
                    count: counts.iter().map(|&n| n as u32).collect(),
                };
                for (i, (sum, &n)) in sums.iter().zip(counts).enumerate() {
                    // A pixel with no samples anywhere stays 0, as the accumulate pass leaves it.
                    if n == 0 {
                        continue;
                    }
                    for (k, &s) in sum.iter().enumerate() {
                        let t = s / n as f64;
                        let mean = t as f32;
                        plane.mean[i][k] = mean;
                        plane.compensation[i][k] = (t - f64::from(mean)) as f32;
                    }
                }
                plane
            })
            .collect();
        Partial {
            size: first.size,
            samples: SampleRange {
                start: first.samples.start,
                end: last.samples.end,
            },
            dropped: inputs.iter().map(|(_, p)| p.dropped).sum(),
            fingerprint: first.fingerprint.clone(),
            source: format!(
                "merged from {} partials ({}); {}",
                inputs.len(),
                inputs
                    .iter()
                    .map(|(_, p)| p.samples.to_string())
                    .collect::<Vec<_>>()
                    .join(", "),
                first.source
            ),
            planes,
            progress: None,
        }
    }
}

fn show(path: &Path) -> String {
    path.display().to_string()
}
