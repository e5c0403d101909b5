//! Environment images (latitude-longitude radiance), as Mitsuba 3's `envmap` reads them.
//! Interim loader (OpenEXR through `image`); the full one arrives with its own tests.

use glam::Vec3;
use std::path::Path;

/// Linear RGB radiance, row-major, row 0 the image's top row (theta = 0, +y), unscaled.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentImage {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<[f32; 3]>,
}

/// Reads an environment image; the message names the file.
pub fn load_environment_image(path: &Path) -> Result<EnvironmentImage, String> {
    let image = crate::render::image::RgbImage::read_exr(path)?;
    EnvironmentImage::from_texels(image.width, image.height, image.pixels)
        .map_err(|e| format!("{}: {e}", path.display()))
}

impl EnvironmentImage {
    pub fn from_texels(
        width: u32,
        height: u32,
        texels: Vec<[f32; 3]>,
    ) -> Result<EnvironmentImage, String> {
        if width < 2 || height < 3 {
            return Err(format!(
                "the image is {width}x{height}; an environment map needs at least 2x3 texels"
            ));
        }
        if let Some(i) = texels
            .iter()
            .position(|t| t.iter().any(|c| !c.is_finite() || *c < 0.0))
        {
            return Err(format!(
                "texel ({}, {}) is {:?}; radiance must be finite and not negative",
                i % width as usize,
                i / width as usize,
                texels[i]
            ));
        }
        Ok(EnvironmentImage {
            width,
            height,
            texels,
        })
    }

    /// Radiance along the local direction v, as Mitsuba 3's envmap `eval_spectrum`.
    pub fn eval(&self, v: Vec3) -> Vec3 {
        let (w, h) = (self.width as usize, self.height as usize);
        let mut u = v.x.atan2(-v.z) * std::f32::consts::FRAC_1_PI * 0.5 - 0.5 / w as f32;
        let mut t = v.y.clamp(-1.0, 1.0).acos() * std::f32::consts::FRAC_1_PI;
        u -= u.floor();
        t -= t.floor();
        let x = u * w as f32;
        let y = t * (h - 1) as f32;
        let (i, j) = ((x as usize).min(w - 1), (y as usize).min(h - 2));
        let (fx, fy) = (x - i as f32, y - j as f32);
        let at = |i: usize, j: usize| Vec3::from(self.texels[j * w + i % w]);
        let row = |j| at(i, j) * (1.0 - fx) + at(i + 1, j) * fx;
        row(j) * (1.0 - fy) + row(j + 1) * fy
    }
}
