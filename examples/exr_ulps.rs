//! How far apart two linear EXR images of the same size are, in units in the last place:
//! jobs/test compares the image merged from sample chunks with the unsplit render this way.
//!
//!     cargo run --example exr_ulps -- A.exr B.exr [--max-ulps N | --samples N]
//!
//! Prints the largest distance in ulps over all pixels and components (the number of f32
//! values between the two, so 0 means bitwise equal), where it is, the largest absolute
//! difference, and how many components differ at all. Exits 1 if the largest distance is
//! above `--max-ulps` (default 0: bitwise equal), or, with `--samples N`, if a component of B
//! is further from A than the bound docs/distributed.md ("Merge") derives for a merge of N
//! samples against their unsplit render, `(1 + 3 (2 + ln N)) 2^-23 |A|`; 2 on a usage or read
//! error.

use passgraph::render::image::RgbImage;
use std::path::PathBuf;
use std::process::ExitCode;

/// The f32 values between `a` and `b` (0 if equal, including +0 and -0); `u64::MAX` if one is
/// NaN and the other not.
fn ulps(a: f32, b: f32) -> u64 {
    if a == b || (a.is_nan() && b.is_nan()) {
        return 0;
    }
    if a.is_nan() || b.is_nan() {
        return u64::MAX;
    }
    // Map the floats onto a line of integers where neighbours differ by one.
    let key = |x: f32| {
        let bits = i64::from(x.to_bits() as i32);
        if bits < 0 {
            i64::from(i32::MIN) - bits
        } else {
            bits
        }
    };
    key(a).abs_diff(key(b))
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut files = Vec::new();
    let mut max_ulps = 0u64;
    let mut samples: Option<u32> = None;
    let mut i = 0;
    while i < args.len() {
        if args[i] == "--max-ulps" || args[i] == "--samples" {
            let Some(n) = args.get(i + 1).and_then(|v| v.parse::<u32>().ok()) else {
                eprintln!("exr_ulps: {} needs a non-negative integer", args[i]);
                return ExitCode::from(2);
            };
            if args[i] == "--samples" {
                samples = Some(n.max(1));
            } else {
                max_ulps = u64::from(n);
            }
            i += 2;
        } else {
            files.push(PathBuf::from(&args[i]));
            i += 1;
        }
    }
    let [a_path, b_path] = files.as_slice() else {
        eprintln!("usage: exr_ulps A.exr B.exr [--max-ulps N | --samples N]");
        return ExitCode::from(2);
    };
    let read = |p: &PathBuf| RgbImage::read_exr(p).map_err(|e| eprintln!("exr_ulps: {e}"));
    let (Ok(a), Ok(b)) = (read(a_path), read(b_path)) else {
        return ExitCode::from(2);
    };
    if [a.width, a.height] != [b.width, b.height] {
        eprintln!(
            "exr_ulps: {} is {}x{} but {} is {}x{}",
            a_path.display(),
            a.width,
            a.height,
            b_path.display(),
            b.width,
            b.height
        );
        return ExitCode::from(2);
    }
    // The merge bound's factor: |B - A| <= factor * |A| (docs/distributed.md, "Merge").
    let factor = samples.map(|n| (1.0 + 3.0 * (2.0 + f64::from(n).ln())) / f64::from(1u32 << 23));
    let (mut worst, mut worst_at, mut max_abs, mut differing) = (0u64, (0, 0, 0), 0f32, 0usize);
    // The largest |B - A| / (factor * |A|): above 1 is outside the bound.
    let mut worst_of_bound = 0f64;
    for (n, (pa, pb)) in a.pixels.iter().zip(&b.pixels).enumerate() {
        for k in 0..3 {
            if let Some(factor) = factor {
                let diff = (f64::from(pa[k]) - f64::from(pb[k])).abs();
                if diff > 0.0 {
                    let bound = factor * f64::from(pa[k]).abs();
                    worst_of_bound = worst_of_bound.max(if bound > 0.0 {
                        diff / bound
                    } else {
                        f64::INFINITY
                    });
                }
            }
            let d = ulps(pa[k], pb[k]);
            if d > 0 {
                differing += 1;
                max_abs = max_abs.max((pa[k] - pb[k]).abs());
            }
            if d > worst {
                worst = d;
                worst_at = (n as u32 % a.width, n as u32 / a.width, k);
            }
        }
    }
    let total = a.pixels.len() * 3;
    if worst == 0 {
        println!("bitwise equal ({}x{})", a.width, a.height);
    } else {
        let (x, y, k) = worst_at;
        let pa = a.pixels[(y * a.width + x) as usize][k];
        let pb = b.pixels[(y * a.width + x) as usize][k];
        println!(
            "max {worst} ulps at pixel ({x}, {y}) {} ({pa:e} against {pb:e}); max absolute difference {max_abs:e}; {differing} of {total} components differ",
            ["R", "G", "B"][k]
        );
    }
    if let (Some(n), Some(factor)) = (samples, factor) {
        println!(
            "bound for {n} samples: (1 + 3 (2 + ln {n})) 2^-23 = {factor:.3e} relative; the largest difference is {:.3} of it",
            worst_of_bound
        );
        if worst_of_bound > 1.0 {
            eprintln!("exr_ulps: B is outside the bound for a merge of {n} samples");
            return ExitCode::from(1);
        }
    } else if worst > max_ulps {
        eprintln!("exr_ulps: {worst} ulps is above the bound of {max_ulps}");
        return ExitCode::from(1);
    }
    ExitCode::SUCCESS
}
