//! Textures: `bitmap` (an image file, looked up as Mitsuba's bitmap with its `filter_type` and
//! `wrap_mode`) and `checkerboard` (a 2x2 image looked up nearest, repeated: exactly
//! Mitsuba's checks), with their `to_uv`. passgraph applies a material's `to_uv` to the texture coordinates of the triangles
//! that use it (an affine map of the corners is exact, as the coordinates interpolate
//! linearly), so the textures of one material must share one `to_uv`.

use super::builder::Builder;
use super::parse::{At, Plugin};
use crate::scene::error::SceneError;
use crate::scene::texture::{Encoding, Filter, Texture, Wrap};
use glam::{DMat3, DMat4};
use std::rc::Rc;

/// A texture in the builder's list, and the `to_uv` Mitsuba applies to (u, v) before looking
/// it up (2D homogeneous, in Mitsuba's uv convention).
#[derive(Clone, Debug)]
pub struct TextureUse {
    pub index: u32,
    pub to_uv: DMat3,
    /// Bilinear and repeat (what a bump map's slope, computed bilinearly, assumes).
    pub default_lookup: bool,
}

/// A `to_uv` transform as a 2D affine map: Mitsuba uses the x and y rows and the translation
/// column of the 4x4 matrix.
fn to_uv_2d(m: &DMat4, plugin: &Plugin, at: &At) -> Result<DMat3, SceneError> {
    let c = |r: usize, col: usize| m.col(col)[r];
    // A to_uv that mixes in z (a 3D rotation) does not map the uv plane to itself.
    if c(0, 2) != 0.0 || c(1, 2) != 0.0 {
        return Err(plugin.error_at(
            at,
            "to_uv mixes z into u or v; only 2D maps (scale, translate, rotate about z) apply to texture coordinates",
        ));
    }
    Ok(DMat3::from_cols(
        glam::DVec3::new(c(0, 0), c(1, 0), 0.0),
        glam::DVec3::new(c(0, 1), c(1, 1), 0.0),
        glam::DVec3::new(c(0, 3), c(1, 3), 1.0),
    ))
}

/// A nested texture used as a colour (`raw` false: sRGB images decoded) or as numbers (a
/// normal or bump map, an opacity: as the file's `raw` says, like Mitsuba).
pub fn texture(builder: &mut Builder, plugin: &Rc<Plugin>) -> Result<TextureUse, SceneError> {
    match plugin.kind.as_str() {
        "bitmap" => bitmap(builder, plugin),
        "checkerboard" => checkerboard(builder, plugin),
        other => Err(plugin.error(format!(
            "texture type '{other}' is not supported (supported: bitmap)"
        ))),
    }
}

fn bitmap(builder: &mut Builder, plugin: &Rc<Plugin>) -> Result<TextureUse, SceneError> {
    let (name, name_at) = plugin
        .string("filename")?
        .ok_or_else(|| plugin.error("a bitmap needs a 'filename'"))?;
    let filter = match plugin.string("filter_type")? {
        None => Filter::Bilinear,
        Some((f, at)) => match f.as_str() {
            "bilinear" => Filter::Bilinear,
            "nearest" => Filter::Nearest,
            other => {
                return Err(plugin.error_at(
                    &at,
                    format!(
                        "filter_type '{other}' is not supported (supported: bilinear, nearest)"
                    ),
                ));
            }
        },
    };
    let wrap = match plugin.string("wrap_mode")? {
        None => Wrap::Repeat,
        Some((w, at)) => {
            match w.as_str() {
                "repeat" => Wrap::Repeat,
                "mirror" => Wrap::Mirror,
                "clamp" => Wrap::Clamp,
                other => {
                    return Err(plugin.error_at(
                    &at,
                    format!("wrap_mode '{other}' is not supported (supported: repeat, mirror, clamp)"),
                ));
                }
            }
        }
    };
    let raw = plugin.boolean_or("raw", false)?;
    // Mitsuba's `accel` picks its own lookup code, not the result.
    plugin.accept("accel");
    let to_uv = match plugin.transform("to_uv")? {
        Some((m, at)) => to_uv_2d(&m, plugin, &at)?,
        None => DMat3::IDENTITY,
    };
    plugin.finish()?;
    let path = builder
        .resolve(&name, &name_at)
        .ok_or_else(|| plugin.error_at(&name_at, format!("filename '{name}': file not found")))?;
    let encoding = if raw { Encoding::Raw } else { Encoding::Srgb };
    let index = builder
        .texture(&path, encoding, filter, wrap)
        .map_err(|m| plugin.error_at(&name_at, format!("filename '{name}': {m}")))?;
    Ok(TextureUse {
        index,
        to_uv,
        default_lookup: filter == Filter::Bilinear && wrap == Wrap::Repeat,
    })
}

/// Mitsuba's checkerboard: color0 where u and v (each modulo 1) are both below or both above
/// 1/2, color1 elsewhere. A 2x2 texture read nearest and repeated gives exactly that: column
/// floor(2u), row floor(2 v_mitsuba) (passgraph's lookup row is Mitsuba's v).
fn checkerboard(builder: &mut Builder, plugin: &Rc<Plugin>) -> Result<TextureUse, SceneError> {
    let c0 = plugin.constant_color("color0", [0.4; 3])?;
    let c1 = plugin.constant_color("color1", [0.2; 3])?;
    let to_uv = match plugin.transform("to_uv")? {
        Some((m, at)) => to_uv_2d(&m, plugin, &at)?,
        None => DMat3::IDENTITY,
    };
    plugin.finish()?;
    let t = |c: [f64; 3]| [c[0] as f32, c[1] as f32, c[2] as f32, 1.0];
    let mut texture = Texture::from_texels(2, 2, vec![t(c0), t(c1), t(c1), t(c0)]);
    texture.path = plugin.at.path.to_path_buf();
    texture.filter = Filter::Nearest;
    Ok(TextureUse {
        index: builder.add_texture(texture),
        to_uv,
        default_lookup: false,
    })
}
