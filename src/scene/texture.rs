//! Image textures: decoded once to linear RGBA f32, looked up as Mitsuba 3's `bitmap` texture
//! does (bilinear, repeat, v = 0 at the image's bottom row), and laid out for the GPU as the
//! `scene.textures` texel view that `shaders/lib/texture.wgsl` reads.

use glam::{Vec2, Vec4};
use std::path::{Path, PathBuf};

/// How an image's integer values become numbers: colour maps (`map_Kd`, `map_Ks`) are sRGB
/// encoded, scalar maps (`map_Pr`, `map_d`) are read raw, as Mitsuba's `raw` flag.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Encoding {
    Srgb,
    Raw,
}

/// How a lookup between texels filters: Mitsuba's bitmap `filter_type`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Filter {
    /// Between the four nearest texel centres (Mitsuba's default; MTL maps always).
    #[default]
    Bilinear,
    /// The texel the point lies in.
    Nearest,
}

/// What texel indices outside the image read: Mitsuba's bitmap `wrap_mode`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Wrap {
    /// The image tiles the plane (Mitsuba's default; MTL maps always).
    #[default]
    Repeat,
    /// Every other tile is mirrored.
    Mirror,
    /// The edge texels extend outward.
    Clamp,
}

impl Wrap {
    /// Texel index `i` of an axis of `size` texels, wrapped (drjit's texture `wrap`).
    pub fn index(self, i: i64, size: i64) -> i64 {
        match self {
            Wrap::Repeat => i.rem_euclid(size),
            Wrap::Clamp => i.clamp(0, size - 1),
            Wrap::Mirror => {
                let r = i.rem_euclid(2 * size);
                if r >= size { 2 * size - 1 - r } else { r }
            }
        }
    }
}

/// A decoded image; `texels` row-major with row 0 the image's top row (as files store it).
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    pub path: PathBuf,
    pub encoding: Encoding,
    pub width: u32,
    pub height: u32,
    pub filter: Filter,
    pub wrap: Wrap,
    /// Linear RGBA; a grey image has r = g = b; alpha is 1 when the image has none.
    pub texels: Vec<[f32; 4]>,
}

/// Mitsuba's `luminance` (Rec. 709 weights): what a scalar lookup of an RGB image returns.
pub const LUMINANCE: [f32; 3] = [0.212_671, 0.715_160, 0.072_169];

/// The sRGB transfer function's inverse (IEC 61966-2-1).
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The decoder's error in one human line: what could not be done and why, without the
/// decoder's internal wording ("Format error decoding Png: CRC error: expected 0x...").
fn decoding_error(e: &image::ImageError) -> String {
    use image::ImageError;
    match e {
        ImageError::Decoding(d) => {
            let format = match d.format_hint() {
                image::error::ImageFormatHint::Exact(f) => format!("{f:?}").to_uppercase(),
                _ => "image".to_string(),
            };
            format!("not a readable {format} file: it is damaged, truncated or not a {format} image")
        }
        ImageError::Unsupported(_) => {
            "an image format or variant this reader does not support (PNG, JPEG, OpenEXR and Radiance .hdr are read)".to_string()
        }
        ImageError::Limits(_) => "the image is too large to decode".to_string(),
        // Decoding reads bytes already in memory: an I/O error is data that ends too soon.
        ImageError::IoError(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
            "the image file ends early: it is truncated".to_string()
        }
        ImageError::IoError(io) => io.to_string(),
        other => other.to_string(),
    }
}

/// Bytes a texel takes once decoded (linear RGBA f32), kept for the render.
const TEXEL_BYTES: u64 = 16;

/// Refuses, from the file's header alone, an image whose decoding would not fit in the memory
/// the machine has free: decoding holds the texels twice at its peak (the decoder's RGBA f32
/// image and the texture's), and uploading them a third time. Without this a 12k x 12k image
/// took 9 GB and ended in the driver's "Out of Memory".
fn check_memory(bytes: &[u8]) -> Result<(), String> {
    let Ok((width, height)) = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|_| ())
        .and_then(|r| r.into_dimensions().map_err(|_| ()))
    else {
        // Decoding itself will say what is wrong.
        return Ok(());
    };
    let need = 3 * u64::from(width) * u64::from(height) * TEXEL_BYTES;
    match available_memory() {
        Some(budget) if need > budget => Err(format!(
            "a {width}x{height} image needs about {} to decode and upload as linear RGBA f32 \
             texels ({TEXEL_BYTES} bytes each, three copies at the peak), more than the {} of \
             memory available: scale it down (e.g. to {}x{})",
            gib(need),
            gib(budget),
            width / 2,
            height / 2
        )),
        _ => Ok(()),
    }
}

/// The memory the system can give without swapping (Linux: MemAvailable); `None` elsewhere.
fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let kib: u64 = text
        .lines()
        .find_map(|l| l.strip_prefix("MemAvailable:"))?
        .split_whitespace()
        .next()?
        .parse()
        .ok()?;
    Some(kib * 1024)
}

fn gib(bytes: u64) -> String {
    format!("{:.1} GiB", bytes as f64 / (1u64 << 30) as f64)
}

impl Texture {
    /// Reads a PNG or JPEG. Integer images are normalised to [0, 1] and, for
    /// [`Encoding::Srgb`], decoded from sRGB (alpha stays linear); float images are linear.
    /// The error is the decoder's or the file system's message, for the caller to place.
    pub fn load(path: &Path, encoding: Encoding) -> Result<Texture, String> {
        let bytes = std::fs::read(path).map_err(|e| e.to_string())?;
        Texture::decode(&bytes, path, encoding)
    }

    /// Decodes an image file's bytes (PNG, JPEG, EXR, HDR: by their content) as [`Texture::load`]
    /// does; `path` names where they came from.
    pub fn decode(bytes: &[u8], path: &Path, encoding: Encoding) -> Result<Texture, String> {
        check_memory(bytes)?;
        let image = image::load_from_memory(bytes).map_err(|e| decoding_error(&e))?;
        let integer = !matches!(
            image.color(),
            image::ColorType::Rgb32F | image::ColorType::Rgba32F
        );
        let (width, height) = (image.width(), image.height());
        if width == 0 || height == 0 {
            return Err("the image is empty".to_string());
        }
        let decode = |c: f32| {
            if integer && encoding == Encoding::Srgb {
                srgb_to_linear(c)
            } else {
                c
            }
        };
        let texels = image
            .to_rgba32f()
            .pixels()
            .map(|p| [decode(p[0]), decode(p[1]), decode(p[2]), p[3]])
            .collect();
        Ok(Texture {
            path: path.to_path_buf(),
            encoding,
            width,
            height,
            filter: Filter::Bilinear,
            wrap: Wrap::Repeat,
            texels,
        })
    }

    /// A texture from linear texels (row 0 the top row), for tests and generated scenes.
    pub fn from_texels(width: u32, height: u32, texels: Vec<[f32; 4]>) -> Texture {
        assert_eq!(texels.len(), (width * height) as usize);
        Texture {
            path: PathBuf::new(),
            encoding: Encoding::Raw,
            width,
            height,
            filter: Filter::Bilinear,
            wrap: Wrap::Repeat,
            texels,
        }
    }

    fn texel(&self, x: i64, y: i64) -> Vec4 {
        let x = self.wrap.index(x, i64::from(self.width)) as usize;
        let y = self.wrap.index(y, i64::from(self.height)) as usize;
        Vec4::from(self.texels[y * self.width as usize + x])
    }

    /// The header word `shaders/lib/texture.wgsl` reads the lookup from: bit 0 nearest,
    /// bits 1-2 the wrap mode (0 repeat, 1 mirror, 2 clamp).
    pub fn mode_bits(&self) -> u32 {
        let filter = match self.filter {
            Filter::Bilinear => 0,
            Filter::Nearest => 1,
        };
        let wrap = match self.wrap {
            Wrap::Repeat => 0,
            Wrap::Mirror => 1,
            Wrap::Clamp => 2,
        };
        filter | wrap << 1
    }

    /// The CPU twin of `texture_bilinear` in `shaders/lib/texture.wgsl`: Mitsuba 3's bitmap
    /// lookup. Its texture space has v pointing down the rows (its OBJ loader stores 1 - v),
    /// texel centres at half-integers: p = (u, 1 - v) * size - 0.5, the four texels around p
    /// weighted by p's fraction, their indices wrapped.
    /// With [`Filter::Nearest`], the texel (u, 1 - v) * size lies in.
    pub fn bilinear(&self, uv: Vec2) -> Vec4 {
        let size = Vec2::new(self.width as f32, self.height as f32);
        if self.filter == Filter::Nearest {
            let p = (Vec2::new(uv.x, 1.0 - uv.y) * size).floor();
            return self.texel(p.x as i64, p.y as i64);
        }
        let p = Vec2::new(uv.x, 1.0 - uv.y).mul_add(size, Vec2::splat(-0.5));
        let i = p.floor();
        let w1 = p - i;
        let w0 = Vec2::ONE - w1;
        let (x, y) = (i.x as i64, i.y as i64);
        (self.texel(x, y) * w0.x + self.texel(x + 1, y) * w1.x) * w0.y
            + (self.texel(x, y + 1) * w0.x + self.texel(x + 1, y + 1) * w1.x) * w1.y
    }

    /// The CPU twin of `texture_gradient` in `shaders/lib/texture.wgsl`: the derivative of the
    /// bilinear lookup of the luminance with respect to (u, v), as Mitsuba 3's bitmap
    /// `eval_1_grad` (the four texels' luminance differences, times the resolution). Mitsuba's
    /// v runs down the rows (1 - v), so its v derivative is this one's negative.
    pub fn luminance_gradient(&self, uv: Vec2) -> Vec2 {
        let size = Vec2::new(self.width as f32, self.height as f32);
        let p = Vec2::new(uv.x, 1.0 - uv.y).mul_add(size, Vec2::splat(-0.5));
        let i = p.floor();
        let w1 = p - i;
        let w0 = Vec2::ONE - w1;
        let (x, y) = (i.x as i64, i.y as i64);
        let f = |dx: i64, dy: i64| self.texel(x + dx, y + dy).truncate().dot(LUMINANCE.into());
        let (f00, f10, f01, f11) = (f(0, 0), f(1, 0), f(0, 1), f(1, 1));
        let d_row = w0.y.mul_add(f10 - f00, w1.y * (f11 - f01));
        let d_column = w0.x.mul_add(f01 - f00, w1.x * (f11 - f10));
        Vec2::new(size.x * d_row, -size.y * d_column)
    }
}

/// The length of [`textures_bytes`], counted without building it.
pub fn textures_byte_len(textures: &[Texture]) -> usize {
    let texels: usize = textures
        .iter()
        .map(|t| size_of_val(t.texels.as_slice()))
        .sum();
    (16 * textures.len() + texels).max(16)
}

/// The `scene.textures` buffer: one header texel per texture (first texel, width, height, the
/// lookup's [`Texture::mode_bits`]),
/// then every texture's texels (linear RGBA f32, row 0 the image's top row). One zero texel
/// when there are none, so that the view can be bound.
pub fn textures_bytes(textures: &[Texture]) -> Vec<u8> {
    let mut header: Vec<[u32; 4]> = Vec::with_capacity(textures.len());
    let mut first = textures.len() as u32;
    for t in textures {
        header.push([first, t.width, t.height, t.mode_bits()]);
        first += t.width * t.height;
    }
    let mut bytes: Vec<u8> = bytemuck::cast_slice(&header).to_vec();
    for t in textures {
        bytes.extend_from_slice(bytemuck::cast_slice(&t.texels));
    }
    if bytes.is_empty() {
        bytes.resize(16, 0);
    }
    bytes
}

#[cfg(test)]
mod tests {
    use super::*;

    fn checker() -> Texture {
        // 2 x 2: top row red, green; bottom row blue, white.
        Texture::from_texels(
            2,
            2,
            vec![
                [1.0, 0.0, 0.0, 1.0],
                [0.0, 1.0, 0.0, 1.0],
                [0.0, 0.0, 1.0, 1.0],
                [1.0, 1.0, 1.0, 1.0],
            ],
        )
    }

    #[test]
    fn an_image_too_large_for_memory_is_refused_from_its_header_before_decoding() {
        // A PNG header claiming 100000 x 100000 RGB texels (160 GB as RGBA f32), no data.
        let mut ihdr = b"IHDR".to_vec();
        ihdr.extend_from_slice(&100_000u32.to_be_bytes());
        ihdr.extend_from_slice(&100_000u32.to_be_bytes());
        ihdr.extend_from_slice(&[8, 2, 0, 0, 0]);
        let mut crc = flate2::Crc::new();
        crc.update(&ihdr);
        let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
        png.extend_from_slice(&13u32.to_be_bytes());
        png.extend_from_slice(&ihdr);
        png.extend_from_slice(&crc.sum().to_be_bytes());
        // An empty IDAT, where the decoder's header reading stops.
        let mut crc = flate2::Crc::new();
        crc.update(b"IDAT");
        png.extend_from_slice(&0u32.to_be_bytes());
        png.extend_from_slice(b"IDAT");
        png.extend_from_slice(&crc.sum().to_be_bytes());
        let e = Texture::decode(&png, Path::new("huge.png"), Encoding::Srgb).unwrap_err();
        assert!(
            e.starts_with("a 100000x100000 image needs about 447.0 GiB")
                && e.contains("of memory available: scale it down (e.g. to 50000x50000)"),
            "{e}"
        );
    }

    #[test]
    fn a_damaged_png_is_one_human_line_not_the_decoders_internals() {
        let mut png = Vec::new();
        image::RgbaImage::from_pixel(4, 4, image::Rgba([10, 20, 30, 255]))
            .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
            .unwrap();
        // A flipped byte in the image data: its chunk's CRC no longer matches.
        let at = png.len() - 20;
        png[at] ^= 0x40;
        let e = Texture::decode(&png, Path::new("wall.png"), Encoding::Srgb).unwrap_err();
        assert_eq!(
            e,
            "not a readable PNG file: it is damaged, truncated or not a PNG image"
        );
        let e = Texture::decode(&png[..30], Path::new("wall.png"), Encoding::Srgb).unwrap_err();
        assert_eq!(e, "the image file ends early: it is truncated");
    }

    #[test]
    fn texel_centres_return_the_texel_and_v_zero_is_the_bottom_row() {
        let t = checker();
        assert_eq!(
            t.bilinear(Vec2::new(0.25, 0.75)),
            Vec4::new(1.0, 0.0, 0.0, 1.0)
        );
        assert_eq!(
            t.bilinear(Vec2::new(0.75, 0.75)),
            Vec4::new(0.0, 1.0, 0.0, 1.0)
        );
        assert_eq!(
            t.bilinear(Vec2::new(0.25, 0.25)),
            Vec4::new(0.0, 0.0, 1.0, 1.0)
        );
        assert_eq!(
            t.bilinear(Vec2::new(1.25, -0.75)),
            Vec4::new(0.0, 0.0, 1.0, 1.0)
        );
    }

    #[test]
    fn between_centres_it_blends_and_wraps_across_the_edge() {
        let t = checker();
        // u = 0: halfway between the left column and (wrapped) the right column.
        let c = t.bilinear(Vec2::new(0.0, 0.75));
        assert!(
            (c - Vec4::new(0.5, 0.5, 0.0, 1.0)).abs().max_element() < 1e-6,
            "{c}"
        );
    }

    #[test]
    fn srgb_decoding_matches_the_standard() {
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert!((srgb_to_linear(1.0) - 1.0).abs() < 1e-6);
        assert!((srgb_to_linear(0.5) - 0.214_041).abs() < 1e-5);
    }

    #[test]
    fn the_layout_has_a_header_texel_per_texture() {
        let bytes = textures_bytes(&[checker(), checker()]);
        let words: &[u32] = bytemuck::cast_slice(&bytes);
        assert_eq!(&words[..8], &[2, 2, 2, 0, 6, 2, 2, 0]);
        assert_eq!(bytes.len(), 16 * (2 + 8));
        assert_eq!(textures_bytes(&[]).len(), 16);
    }
}
