//! Splits an image's error against a reference into what more samples remove and what they do
//! not, from two renders with independent seeds: per pixel and component, with weights
//! w = 1 / (ref^2 + 0.01) (relMSE's),
//!
//! - variance: w (A - B)^2 / 2, the expected relMSE of one render around its own mean;
//! - residual: w ((A + B)/2 - ref)^2 - w (A - B)^2 / 4, the part of the pair's error their noise
//!   does not explain: bias squared plus the reference's own noise (0 in expectation for an
//!   unbiased renderer against an exact reference);
//! - tail: the share of the variance in the 0.1 % largest terms. Near 1, the error is a few
//!   rare high-energy samples (fireflies) and one render's relMSE says little about its
//!   expectation; the median over renders falls below it.
//!
//! Where the residual is, by 8x8 blocks of the image (its largest five). A reference given as
//! two independent halves (`REF_A.exr,REF_B.exr`) is their mean, and its own noise,
//! w (R_a - R_b)^2 / 4, is measured and taken from the residual: what is left is bias^2.
//!
//! `cargo run --release --example error_split -- REF.exr[,REF_B.exr] A.exr B.exr`

use passgraph::render::image::RgbImage;
use std::path::Path;

fn read(path: &str) -> RgbImage {
    RgbImage::read_exr(Path::new(path)).unwrap_or_else(|e| {
        eprintln!("error: {path}: {e}");
        std::process::exit(1)
    })
}

/// The mean of one or two images of one size (checked by the caller).
fn mean_of(images: &[RgbImage]) -> RgbImage {
    let mut mean = images[0].clone();
    if let [_, b] = images {
        if b.pixels.len() == mean.pixels.len() {
            for (p, q) in mean.pixels.iter_mut().zip(&b.pixels) {
                for k in 0..3 {
                    p[k] = 0.5 * (p[k] + q[k]);
                }
            }
        }
    }
    mean
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [reference, a, b] = &args[..] else {
        eprintln!("usage: error_split REF.exr[,REF_B.exr] A.exr B.exr");
        std::process::exit(2)
    };
    let halves: Vec<RgbImage> = reference.split(',').map(read).collect();
    if halves.len() > 2 {
        eprintln!(
            "error: a reference is one EXR or two halves, not {}",
            halves.len()
        );
        std::process::exit(2);
    }
    let r = mean_of(&halves);
    let (a_img, b_img) = (read(a), read(b));
    for (name, image) in [(a, &a_img), (b, &b_img)]
        .into_iter()
        .chain(halves.iter().map(|h| (reference, h)))
    {
        if (image.width, image.height) != (r.width, r.height) {
            eprintln!(
                "error: {name} is {}x{}, the reference {}x{}",
                image.width, image.height, r.width, r.height
            );
            std::process::exit(1);
        }
    }
    let n = (r.pixels.len() * 3) as f64;
    let (mut rel_a, mut rel_b, mut rel_mean) = (0.0f64, 0.0f64, 0.0f64);
    let mut variance_terms = Vec::with_capacity(r.pixels.len() * 3);
    let mut residual_per_pixel = Vec::with_capacity(r.pixels.len());
    for ((y, x), z) in r.pixels.iter().zip(&a_img.pixels).zip(&b_img.pixels) {
        let mut residual = 0.0;
        for k in 0..3 {
            let (y, x, z) = (f64::from(y[k]), f64::from(x[k]), f64::from(z[k]));
            let w = 1.0 / (y * y + 0.01);
            let mean = 0.5 * (x + z);
            rel_a += w * (x - y) * (x - y);
            rel_b += w * (z - y) * (z - y);
            rel_mean += w * (mean - y) * (mean - y);
            let v = w * (x - z) * (x - z) / 2.0;
            variance_terms.push(v);
            residual += w * (mean - y) * (mean - y) - v / 2.0;
        }
        residual_per_pixel.push(residual);
    }
    let variance: f64 = variance_terms.iter().sum::<f64>() / n;
    let residual: f64 = residual_per_pixel.iter().sum::<f64>() / n;
    variance_terms.sort_by(|p, q| q.total_cmp(p));
    let top = (variance_terms.len() / 1000).max(1);
    let tail = variance_terms[..top].iter().sum::<f64>() / (variance * n);
    println!(
        "relMSE A {:.4e}, B {:.4e}, of their mean {:.4e}",
        rel_a / n,
        rel_b / n,
        rel_mean / n
    );
    println!("variance (relMSE of one render from noise) {variance:.4e}");
    println!("residual (bias^2 + reference noise) {residual:.4e}");
    if let [ra, rb] = &halves[..] {
        let mut noise = 0.0f64;
        for ((y, p), q) in r.pixels.iter().zip(&ra.pixels).zip(&rb.pixels) {
            for k in 0..3 {
                let (y, d) = (f64::from(y[k]), f64::from(p[k]) - f64::from(q[k]));
                noise += d * d / 4.0 / (y * y + 0.01);
            }
        }
        noise /= n;
        println!(
            "reference noise (its halves) {noise:.4e}; bias^2 = residual - it: {:.4e}",
            residual - noise
        );
    }
    println!("tail: the largest 0.1 % of terms carry {tail:.2} of the variance");
    let (w, h) = (r.width as usize, r.height as usize);
    let mut blocks = Vec::new();
    for by in 0..h / 8 {
        for bx in 0..w / 8 {
            let mut s = 0.0;
            for y in by * 8..by * 8 + 8 {
                for x in bx * 8..bx * 8 + 8 {
                    s += residual_per_pixel[y * w + x];
                }
            }
            blocks.push((s, bx * 8, by * 8));
        }
    }
    blocks.sort_by(|p, q| q.0.total_cmp(&p.0));
    let total = residual * n;
    for (s, x, y) in blocks.iter().take(5) {
        println!(
            "  residual block x {x}..{} y {y}..{}: {:.3} of it",
            x + 8,
            y + 8,
            s / total
        );
    }
}
