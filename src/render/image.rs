//! Linear RGB images: combining result planes, and writing PNG (sRGB, clamped) or EXR (linear
//! float32) whole or not at all.

use super::channels::Channel;
use crate::atomic_write::write_atomic;
use std::path::Path;

/// A linear RGB float image, rows top to bottom.
#[derive(Clone, Debug, PartialEq)]
pub struct RgbImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[f32; 3]>,
}

impl RgbImage {
    /// Adds the selected planes of the accumulation buffer (planes of width*height vec4: mean
    /// RGB and sample count).
    pub fn from_result(
        result: &[[f32; 4]],
        width: u32,
        height: u32,
        channels: &[Channel],
    ) -> RgbImage {
        let plane = (width * height) as usize;
        let pixels = (0..plane)
            .map(|i| {
                let mut rgb = [0.0f32; 3];
                for c in channels {
                    let v = result[c.layer() * plane + i];
                    for k in 0..3 {
                        rgb[k] += v[k];
                    }
                }
                rgb
            })
            .collect();
        RgbImage {
            width,
            height,
            pixels,
        }
    }

    /// Mean of each colour component over the image.
    pub fn mean(&self) -> [f64; 3] {
        let mut sum = [0.0f64; 3];
        for p in &self.pixels {
            for k in 0..3 {
                sum[k] += f64::from(p[k]);
            }
        }
        let n = self.pixels.len().max(1) as f64;
        sum.map(|s| s / n)
    }

    /// Reads a linear reference: an OpenEXR file (checked by its content, not its name; a PNG
    /// is sRGB-encoded and clamped, so comparing against it would measure the encoding).
    pub fn read_exr(path: &Path) -> Result<RgbImage, String> {
        let cannot =
            |e: &dyn std::fmt::Display| format!("{}: cannot read image: {e}", path.display());
        let reader = image::ImageReader::open(path)
            .map_err(|e| cannot(&e))?
            .with_guessed_format()
            .map_err(|e| cannot(&e))?;
        if reader.format() != Some(image::ImageFormat::OpenExr) {
            return Err(format!(
                "{}: not an OpenEXR image{}; a reference must hold linear values (.exr)",
                path.display(),
                reader
                    .format()
                    .map_or(String::new(), |f| format!(" (it is {f:?})"))
            ));
        }
        let img = reader.decode().map_err(|e| cannot(&e))?;
        let rgb = img.to_rgb32f();
        let image = RgbImage {
            width: rgb.width(),
            height: rgb.height(),
            pixels: rgb.pixels().map(|p| p.0).collect(),
        };
        // Every error figure would be NaN: refuse it here, before anything is rendered.
        if let Some(i) = image
            .pixels
            .iter()
            .position(|p| !p.iter().all(|v| v.is_finite()))
        {
            let w = image.width.max(1) as usize;
            return Err(format!(
                "{}: pixel ({}, {}) is {:?}, not finite; a reference must hold finite values",
                path.display(),
                i % w,
                i / w,
                image.pixels[i]
            ));
        }
        Ok(image)
    }

    /// Writes `.png` (sRGB-encoded, clamped to [0, 1]) or `.exr` (linear float32 RGB).
    pub fn write(&self, path: &Path) -> Result<(), String> {
        let bytes = self.encode_for(path)?;
        write_atomic(path, &bytes).map_err(|e| format!("{}: cannot write: {e}", path.display()))
    }

    /// The file's bytes for `path`'s type (see [`output_format`]).
    pub fn encode_for(&self, path: &Path) -> Result<Vec<u8>, String> {
        self.encode(output_format(path)?)
    }

    fn encode(&self, format: image::ImageFormat) -> Result<Vec<u8>, String> {
        let mut out = std::io::Cursor::new(Vec::new());
        let encoded = if format == image::ImageFormat::Png {
            let data: Vec<u8> = self
                .pixels
                .iter()
                .flat_map(|p| p.map(|v| (linear_to_srgb(v) * 255.0 + 0.5) as u8))
                .collect();
            image::RgbImage::from_raw(self.width, self.height, data)
                .ok_or("image size does not match its pixels")?
                .write_to(&mut out, format)
        } else {
            let data: Vec<f32> = self.pixels.iter().flatten().copied().collect();
            image::Rgb32FImage::from_raw(self.width, self.height, data)
                .ok_or("image size does not match its pixels")?
                .write_to(&mut out, format)
        };
        encoded.map_err(|e| e.to_string())?;
        Ok(out.into_inner())
    }
}

/// The image type an output path asks for by its extension: `.png` or `.exr`.
pub fn output_format(path: &Path) -> Result<image::ImageFormat, String> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase());
    match ext.as_deref() {
        Some("png") => Ok(image::ImageFormat::Png),
        Some("exr") => Ok(image::ImageFormat::OpenExr),
        _ => Err(format!(
            "{}: unknown image type; use .png (sRGB) or .exr (linear float)",
            path.display()
        )),
    }
}

/// Checks, before any rendering, that an image can be written at `path`: a known type, in an
/// existing directory, not over a directory.
pub fn check_output_path(path: &Path) -> Result<(), String> {
    output_format(path)?;
    crate::atomic_write::check_target(path)
        .map_err(|e| format!("{}: cannot write: {e}", path.display()))
}

/// The sRGB transfer function on a clamped linear value.
pub fn linear_to_srgb(v: f32) -> f32 {
    let v = if v.is_finite() {
        v.clamp(0.0, 1.0)
    } else {
        0.0
    };
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exr_round_trips_linear_values_exactly() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("x.exr");
        let img = RgbImage {
            width: 2,
            height: 1,
            pixels: vec![[0.25, 1.5, 0.0], [18.387, 13.9873, 6.75357]],
        };
        img.write(&path).unwrap();
        assert_eq!(RgbImage::read_exr(&path).unwrap(), img);
    }

    #[test]
    fn a_reference_holding_nan_or_infinity_is_refused_naming_the_pixel() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("ref.exr");
        let mut img = RgbImage {
            width: 3,
            height: 2,
            pixels: vec![[0.5; 3]; 6],
        };
        for bad in [f32::NAN, f32::INFINITY] {
            img.pixels[4] = [0.5, bad, 0.5];
            img.write(&path).unwrap();
            let e = RgbImage::read_exr(&path).unwrap_err();
            assert!(
                e.contains("ref.exr: pixel (1, 1) is") && e.contains("not finite"),
                "{e}"
            );
        }
    }

    #[test]
    fn srgb_encoding_clamps_and_hits_the_endpoints() {
        assert_eq!(linear_to_srgb(-1.0), 0.0);
        assert_eq!(linear_to_srgb(0.0), 0.0);
        assert!((linear_to_srgb(1.0) - 1.0).abs() < 1e-6);
        assert!((linear_to_srgb(0.5) - 0.735_357).abs() < 1e-5);
        assert_eq!(linear_to_srgb(f32::NAN), 0.0);
    }

    #[test]
    fn unknown_extension_is_an_error_and_writes_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("x.bmp");
        let img = RgbImage {
            width: 1,
            height: 1,
            pixels: vec![[0.0; 3]],
        };
        assert!(img.write(&path).is_err());
        assert!(!path.exists());
    }
}
