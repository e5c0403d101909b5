//! Error of an image against a reference: the figures speed-against-error reports compare.

use crate::render::image::RgbImage;

/// Per-component statistics of `image - reference`, over every pixel and colour component.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ImageError {
    /// Root mean squared error.
    pub rmse: f64,
    /// Mean of (x - y)^2 / (y^2 + 0.01), comparable with published relMSE figures.
    pub relmse: f64,
    /// Mean of x - y: systematic error.
    pub bias: f64,
    /// Standard error of the mean squared error (for bounds on MSE comparisons).
    pub mse_standard_error: f64,
}

impl ImageError {
    pub fn mse(&self) -> f64 {
        self.rmse * self.rmse
    }
}

/// Compares two images of the same size; `Err` if the sizes differ.
pub fn image_error(image: &RgbImage, reference: &RgbImage) -> Result<ImageError, String> {
    if (image.width, image.height) != (reference.width, reference.height) {
        return Err(format!(
            "image is {}x{} but the reference is {}x{}",
            image.width, image.height, reference.width, reference.height
        ));
    }
    let mut n = 0.0f64;
    let (mut sq, mut sq2, mut rel, mut diff) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (x, y) in image.pixels.iter().zip(&reference.pixels) {
        for k in 0..3 {
            let (x, y) = (f64::from(x[k]), f64::from(y[k]));
            let d = x - y;
            sq += d * d;
            sq2 += d * d * d * d;
            rel += d * d / (y * y + 0.01);
            diff += d;
            n += 1.0;
        }
    }
    let mse = sq / n;
    let variance_of_sq = (sq2 / n - mse * mse).max(0.0);
    Ok(ImageError {
        rmse: mse.sqrt(),
        relmse: rel / n,
        bias: diff / n,
        mse_standard_error: (variance_of_sq / n).sqrt(),
    })
}

/// Averages 2x2 blocks: a 2W x 2H box-filtered image becomes the W x H box-filtered one.
pub fn downsample_2x(image: &RgbImage) -> RgbImage {
    let (w, h) = (image.width / 2, image.height / 2);
    let mut pixels = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let mut p = [0.0f32; 3];
            for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let q = image.pixels[((2 * y + dy) * image.width + 2 * x + dx) as usize];
                for k in 0..3 {
                    p[k] += 0.25 * q[k];
                }
            }
            pixels.push(p);
        }
    }
    RgbImage {
        width: w,
        height: h,
        pixels,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn img(values: &[f32]) -> RgbImage {
        RgbImage {
            width: values.len() as u32,
            height: 1,
            pixels: values.iter().map(|&v| [v; 3]).collect(),
        }
    }

    #[test]
    fn identical_images_have_zero_error() {
        let a = img(&[0.1, 0.5, 2.0]);
        let e = image_error(&a, &a).unwrap();
        assert_eq!((e.rmse, e.relmse, e.bias), (0.0, 0.0, 0.0));
    }

    #[test]
    fn a_constant_offset_is_all_bias() {
        let e = image_error(&img(&[1.5, 1.5]), &img(&[1.0, 1.0])).unwrap();
        assert!((e.rmse - 0.5).abs() < 1e-12);
        assert!((e.bias - 0.5).abs() < 1e-12);
        assert!((e.relmse - 0.25 / 1.01).abs() < 1e-12);
    }

    #[test]
    fn downsampling_averages_blocks() {
        let big = RgbImage {
            width: 2,
            height: 2,
            pixels: vec![[1.0; 3], [2.0; 3], [3.0; 3], [6.0; 3]],
        };
        assert_eq!(downsample_2x(&big).pixels, vec![[3.0; 3]]);
    }

    #[test]
    fn size_mismatch_is_an_error() {
        assert!(image_error(&img(&[1.0]), &img(&[1.0, 2.0])).is_err());
    }
}
