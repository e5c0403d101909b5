//! Textures: `bitmap` (an image file, looked up as Mitsuba's bitmap: bilinear, repeat) and its
//! `to_uv`. passgraph applies a material's `to_uv` to the texture coordinates of the triangles
//! that use it (an affine map of the corners is exact, as the coordinates interpolate
//! linearly), so the textures of one material must share one `to_uv`.

use super::build::Builder;
use super::parse::{At, Plugin};
use crate::scene::error::SceneError;
use crate::scene::texture::{Encoding, Texture};
use glam::{DMat3, DMat4};
use std::rc::Rc;

/// A texture in the builder's list, and the `to_uv` Mitsuba applies to (u, v) before looking
/// it up (2D homogeneous, in Mitsuba's uv convention).
#[derive(Clone, Debug)]
pub struct TextureUse {
    pub index: u32,
    pub to_uv: DMat3,
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
        "checkerboard" => {
            // Not yet: checkerboard (its sharp edges need a nearest-texel lookup, which
            // passgraph's textures do not have; a bilinear image would blur them).
            Err(plugin.not_yet(
                &plugin.at,
                "the checkerboard texture (passgraph's textures are bilinear; its edges need a nearest lookup)",
            ))
        }
        other => Err(plugin.error(format!(
            "texture type '{other}' is not supported (supported: bitmap)"
        ))),
    }
}

fn bitmap(builder: &mut Builder, plugin: &Rc<Plugin>) -> Result<TextureUse, SceneError> {
    let (name, name_at) = plugin
        .string("filename")?
        .ok_or_else(|| plugin.error("a bitmap needs a 'filename'"))?;
    if let Some((filter, at)) = plugin.string("filter_type")? {
        if filter != "bilinear" {
            return Err(plugin.error_at(
                &at,
                format!(
                    "filter_type '{filter}' is not supported (supported: bilinear, the default)"
                ),
            ));
        }
    }
    if let Some((wrap, at)) = plugin.string("wrap_mode")? {
        if wrap != "repeat" {
            return Err(plugin.error_at(
                &at,
                format!("wrap_mode '{wrap}' is not supported (supported: repeat, the default)"),
            ));
        }
    }
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
        .texture(&path, encoding)
        .map_err(|m| plugin.error_at(&name_at, format!("filename '{name}': {m}")))?;
    Ok(TextureUse { index, to_uv })
}

/// Loads an image once per (file, encoding).
pub fn load_texture(path: &std::path::Path, encoding: Encoding) -> Result<Texture, String> {
    Texture::load(path, encoding).map_err(|message| match message.find(" (os error") {
        Some(at) => message[..at].to_string(),
        None => message,
    })
}
