//! Environment images: an equirectangular (latitude-longitude) radiance image read from OpenEXR
//! or Radiance `.hdr`, checked once (finite, non-negative, at least Mitsuba's 2x3), and looked up
//! exactly as Mitsuba 3's `envmap` emitter looks it up (`eval_spectrum`, scale 1), which
//! tests/environment_image.rs holds to a table Mitsuba 3.9.0 itself wrote
//! (scripts/envmap-mitsuba-table).
//!
//! # Conventions (Mitsuba's, measured with Mitsuba 3.9.0, `scalar_rgb`)
//! - A local direction `v` (from the scene out to the sky) maps to
//!   `u = atan2(v.x, -v.z) / 2pi`, `t = acos(v.y) / pi`: row 0 (the image's top row) is +y,
//!   the bottom row -y; along a row u = 0 looks along -z, 1/4 along +x, 1/2 (the image's centre)
//!   along +z, 3/4 along -x. The seam (u = 0) is at -z.
//! - Columns are texel-centred (texel x at u = (x + 1/2) / W, a periodic extra column equal to
//!   column 0 closing the seam); rows are vertex-centred (row y at t = y / (H - 1), so rows 0 and
//!   H - 1 sit on the poles). Between them: bilinear. That is why Mitsuba needs 2x3 texels.
//! - `to_world`: Mitsuba evaluates `eval(to_world^-1 * d)` for a world direction d, so the image
//!   content at local direction L appears at world direction `to_world * L`. A `rotate` about
//!   (0, 1, 0) by +90 degrees (right-handed) moves the image's centre from +z to world +x (and
//!   its u = 1/4 content from +x to -z): the sky turns counter-clockwise seen from above (+y).
//! - Loading (Mitsuba's `Bitmap`): OpenEXR values are linear and used as stored (half floats
//!   widened to f32); an alpha channel is dropped without dividing the colour by it; a
//!   luminance-only (Y) image gives r = g = b = Y. Radiance `.hdr` (RGBE) decodes each channel as
//!   `m * 2^(e - 136)` (no half-step offset) and is linear. Both readers here do the same.
//! - Mitsuba accepts NaN, infinite and negative texels without a word; this loader refuses them
//!   (they would poison the importance-sampling distribution and every pixel that sees them).
//!   Note that lossy DWAA/DWAB files often hold small negative texels (the Poly Haven HDRIs in
//!   Debian's blender-data: up to 5053 of 524288 texels, down to -0.0039); clamp such a file to 0
//!   once (as scripts/make-test-hdris does) to use it.
//!
//! # Memory
//! Both readers decode straight into the one texel buffer (12 bytes a texel): an 8192x4096 ZIP
//! float32 EXR loads in 1.7 s (release) with a peak resident size of 400 MB, of which 384 MiB
//! are the texels.
//!
//! # OpenEXR compressions
//! The `exr` crate (1.74) decodes none, RLE, ZIPS, ZIP, PIZ, PXR24, B44, B44A, DWAA and DWAB
//! (its DWA decoder is a port of OpenEXRCore's: bitwise OpenEXR 3.5.3's decoding on the test
//! fixtures, which tests/environment_image.rs checks, and on all eight DWAB HDRIs of Debian's
//! blender-data, measured once). It cannot decode HTJ2K256, HTJ2K32 or the
//! compressions newer OpenEXR releases add (ids 12 and up); such a file gets an error naming it
//! and the compression, with how to convert it.

use glam::Vec3;
use std::fs::File;
use std::io::{BufRead, BufReader, Read};
use std::path::Path;

/// Mitsuba's minimum: two columns (the seam's interpolation) and three rows (two poles and a
/// row between).
pub const MIN_WIDTH: u32 = 2;
pub const MIN_HEIGHT: u32 = 3;

/// An environment image: linear RGB radiance, unscaled.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentImage {
    pub width: u32,
    pub height: u32,
    /// Row-major; row 0 is the image's top row (t = 0, +y).
    pub texels: Vec<[f32; 3]>,
}

const EXR_MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];

/// Reads an OpenEXR (`.exr`) or Radiance (`.hdr`) environment image, recognised by its content,
/// and checks it as [`EnvironmentImage::from_texels`] does. Every error names the file.
pub fn load_environment_image(path: &Path) -> Result<EnvironmentImage, String> {
    let name = path.display();
    let mut magic = [0u8; 4];
    let read = File::open(path)
        .and_then(|mut f| read_prefix(&mut f, &mut magic))
        .map_err(|e| format!("{name}: cannot read the environment image: {e}"))?;
    let (width, height, texels) = if read == 4 && magic == EXR_MAGIC {
        read_exr(path)?
    } else if read >= 2 && &magic[..2] == b"#?" {
        read_hdr(path)?
    } else {
        return Err(format!(
            "{name}: not an OpenEXR (.exr) or Radiance (.hdr) image; an environment image must \
             hold linear radiance in one of these formats"
        ));
    };
    EnvironmentImage::from_texels(width, height, texels).map_err(|e| format!("{name}: {e}"))
}

/// Reads up to `buf.len()` bytes (fewer only at the end of the file).
fn read_prefix(file: &mut File, buf: &mut [u8]) -> std::io::Result<usize> {
    let mut n = 0;
    while n < buf.len() {
        match file.read(&mut buf[n..])? {
            0 => break,
            k => n += k,
        }
    }
    Ok(n)
}

impl EnvironmentImage {
    /// An environment image from linear texels (row 0 the top row), checked: `width * height`
    /// texels, at least [`MIN_WIDTH`] x [`MIN_HEIGHT`], every channel finite and >= 0.
    pub fn from_texels(width: u32, height: u32, texels: Vec<[f32; 3]>) -> Result<Self, String> {
        if width < MIN_WIDTH || height < MIN_HEIGHT {
            return Err(format!(
                "the environment image is {width}x{height} texels; it needs at least \
                 {MIN_WIDTH}x{MIN_HEIGHT} (Mitsuba's envmap minimum: rows are interpolated \
                 from pole to pole)"
            ));
        }
        if texels.len() as u64 != width as u64 * height as u64 {
            return Err(format!(
                "{} texels for a {width}x{height} environment image",
                texels.len()
            ));
        }
        check_texels(width, &texels)?;
        Ok(EnvironmentImage {
            width,
            height,
            texels,
        })
    }

    /// The radiance arriving along the unit local direction `v` (pointing from the scene out to
    /// the sky), as Mitsuba's `envmap` `eval_spectrum` computes it with scale 1: f32 arithmetic
    /// in Mitsuba's order, so the two agree to rounding.
    pub fn eval(&self, v: Vec3) -> Vec3 {
        let (w, h) = (self.width, self.height);
        let mut u = v.x.atan2(-v.z) * std::f32::consts::FRAC_1_PI * 0.5;
        // t in [0, 1]. Mitsuba wraps t as u (uv -= floor(uv)), which matters only at t = 1, a
        // value its acos never reaches at v.y = -1 but libm's does (acos(-1) * 1/pi rounds to
        // 1): clamped, the south pole reads the bottom row, as Mitsuba's does.
        let t = (v.y.clamp(-1.0, 1.0).acos() * std::f32::consts::FRAC_1_PI).min(1.0);
        // Texel-centred columns: Mitsuba's half-texel shift, then u wraps.
        u -= 0.5 / w as f32;
        u -= u.floor();
        let (x, y) = (u * w as f32, t * (h - 1) as f32);
        let (px, py) = ((x as u32).min(w - 1), (y as u32).min(h - 2));
        let (fx, fy) = (x - px as f32, y - py as f32);
        // Column w is the periodic padding: column 0.
        let next = if px + 1 == w { 0 } else { px + 1 };
        let texel =
            |cx: u32, cy: u32| Vec3::from(self.texels[cy as usize * w as usize + cx as usize]);
        let row = |cy: u32| texel(px, cy) * (1.0 - fx) + texel(next, cy) * fx;
        row(py) * (1.0 - fy) + row(py + 1) * fy
    }
}

/// Refuses NaN, infinite and negative channels, naming the first such texel and the count.
fn check_texels(width: u32, texels: &[[f32; 3]]) -> Result<(), String> {
    let bad = |t: &[f32; 3]| t.iter().any(|c| !(c.is_finite() && *c >= 0.0));
    let Some(first) = texels.iter().position(bad) else {
        return Ok(());
    };
    let (mut nan, mut infinite, mut negative) = (0usize, 0usize, 0usize);
    for t in texels.iter().filter(|t| bad(t)) {
        if t.iter().any(|c| c.is_nan()) {
            nan += 1;
        } else if t.iter().any(|c| c.is_infinite()) {
            infinite += 1;
        } else {
            negative += 1;
        }
    }
    let (x, y) = (first as u32 % width, first as u32 / width);
    let [r, g, b] = texels[first];
    let hint = if negative > 0 {
        "; lossy (DWAA/DWAB) files often hold small negative values: clamp them to 0 once"
    } else {
        ""
    };
    Err(format!(
        "texel (x {x}, y {y}) (row 0 at the top) is ({r}, {g}, {b}): radiance must be finite and \
         non-negative; {} texels are not ({nan} NaN, {infinite} infinite, {negative} negative){hint}",
        nan + infinite + negative
    ))
}

/// OpenEXR compressions by their header id, and whether the `exr` crate decodes them.
fn exr_compression_name(id: u8) -> (&'static str, bool) {
    match id {
        0 => ("NO", true),
        1 => ("RLE", true),
        2 => ("ZIPS", true),
        3 => ("ZIP", true),
        4 => ("PIZ", true),
        5 => ("PXR24", true),
        6 => ("B44", true),
        7 => ("B44A", true),
        8 => ("DWAA", true),
        9 => ("DWAB", true),
        10 => ("HTJ2K256", false),
        11 => ("HTJ2K32", false),
        // As OpenEXR 3.5 numbers them.
        12 => ("LJ2K", false),
        13 => ("ZSTD", false),
        _ => ("an unknown", false),
    }
}

/// The `compression` attribute of the file's first header, read without decoding anything
/// else; `None` where the header is cut short or malformed (the decoder then says why).
fn exr_compression_id(path: &Path) -> Option<u8> {
    let mut r = BufReader::new(File::open(path).ok()?);
    let mut start = [0u8; 8];
    r.read_exact(&mut start).ok()?;
    let mut field = Vec::new();
    // Each attribute: name\0 type\0 size (i32 LE) value; an empty name ends the header.
    for _ in 0..1024 {
        field.clear();
        r.read_until(0, &mut field).ok()?;
        let name = field.clone();
        if name == [0] {
            return None;
        }
        field.clear();
        r.read_until(0, &mut field).ok()?;
        let mut size = [0u8; 4];
        r.read_exact(&mut size).ok()?;
        let size = u32::from_le_bytes(size);
        if name == b"compression\0" && size == 1 {
            let mut id = [0u8];
            r.read_exact(&mut id).ok()?;
            return Some(id[0]);
        }
        std::io::copy(&mut (&mut r).take(size as u64), &mut std::io::sink()).ok()?;
    }
    None
}

/// Decodes an OpenEXR image's R, G, B channels (or Y, as grey) straight into the texel buffer.
fn read_exr(path: &Path) -> Result<(u32, u32, Vec<[f32; 3]>), String> {
    use exr::prelude::*;
    let name = path.display();
    if let Some(id) = exr_compression_id(path) {
        let (compression, readable) = exr_compression_name(id);
        if !readable {
            return Err(format!(
                "{name}: {compression} compression (OpenEXR compression id {id}) is not one the \
                 reader (the `exr` crate) can decode; it reads none, RLE, ZIPS, ZIP, PIZ, PXR24, \
                 B44(A) and DWAA/DWAB. Convert the file once, e.g. `oiiotool {name} --compression \
                 zip -o out.exr`, or with Python's OpenEXR (pip install OpenEXR): `f = \
                 OpenEXR.File(\"{name}\"); f.header()[\"compression\"] = \
                 OpenEXR.ZIP_COMPRESSION; f.write(\"out.exr\")`"
            ));
        }
    }
    let meta = MetaData::read_from_file(path, false)
        .map_err(|e| format!("{name}: cannot read the OpenEXR header: {e}"))?;
    let has = |channel: &str| {
        meta.headers.iter().any(|h| {
            h.channels
                .list
                .iter()
                .any(|c| c.name.to_string() == channel)
        })
    };
    let decode_error =
        |e: exr::error::Error| format!("{name}: cannot decode the OpenEXR image: {e}");
    let create = |size: Vec2<usize>, _: &_| (size, vec![[0f32; 3]; size.width() * size.height()]);
    let pixels = if has("R") && has("G") && has("B") {
        read()
            .no_deep_data()
            .largest_resolution_level()
            .rgb_channels(
                create,
                |(size, texels): &mut (Vec2<usize>, Vec<[f32; 3]>),
                 p: Vec2<usize>,
                 (r, g, b): (f32, f32, f32)| {
                    texels[p.y() * size.width() + p.x()] = [r, g, b]
                },
            )
            .first_valid_layer()
            .all_attributes()
            .from_file(path)
            .map_err(decode_error)?
            .layer_data
            .channel_data
            .pixels
    } else if has("Y") && !has("RY") && !has("BY") {
        read()
            .no_deep_data()
            .largest_resolution_level()
            .specific_channels()
            .required("Y")
            .collect_pixels(
                |size: Vec2<usize>, _: &_| (size, vec![[0f32; 3]; size.width() * size.height()]),
                |(size, texels): &mut (Vec2<usize>, Vec<[f32; 3]>),
                 p: Vec2<usize>,
                 (y,): (f32,)| { texels[p.y() * size.width() + p.x()] = [y; 3] },
            )
            .first_valid_layer()
            .all_attributes()
            .from_file(path)
            .map_err(decode_error)?
            .layer_data
            .channel_data
            .pixels
    } else {
        let channels: Vec<String> = meta
            .headers
            .iter()
            .flat_map(|h| h.channels.list.iter().map(|c| c.name.to_string()))
            .collect();
        return Err(format!(
            "{name}: the OpenEXR image has channels [{}]; an environment image needs R, G and B \
             (or Y alone)",
            channels.join(", ")
        ));
    };
    let (size, texels) = pixels;
    let dim = |n: usize| u32::try_from(n).map_err(|_| format!("{name}: the image is too large"));
    Ok((dim(size.width())?, dim(size.height())?, texels))
}

/// Decodes a Radiance RGBE image (flat or run-length encoded) straight into the texel buffer.
fn read_hdr(path: &Path) -> Result<(u32, u32, Vec<[f32; 3]>), String> {
    use image::ImageDecoder;
    let name = path.display();
    let error = |e: image::ImageError| format!("{name}: cannot decode the Radiance HDR image: {e}");
    let file = File::open(path).map_err(|e| format!("{name}: {e}"))?;
    let mut reader = BufReader::new(file);
    // The first line is `#?` and the writing program's name: `#?RADIANCE` (Radiance), `#?RGBE`
    // (Bruce Walter's rgbe.c, which Mitsuba and others write). The decoder wants the former.
    let mut program = Vec::new();
    reader
        .read_until(b'\n', &mut program)
        .map_err(|e| format!("{name}: {e}"))?;
    let reader = std::io::Cursor::new(&b"#?RADIANCE\n"[..]).chain(reader);
    let decoder = image::codecs::hdr::HdrDecoder::new(reader).map_err(error)?;
    let (width, height) = decoder.dimensions();
    let mut texels = vec![[0f32; 3]; width as usize * height as usize];
    decoder
        .read_image(bytemuck::cast_slice_mut(&mut texels))
        .map_err(error)?;
    Ok((width, height, texels))
}
