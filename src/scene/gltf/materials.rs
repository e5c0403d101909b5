//! glTF materials as passgraph's: `pbrMetallicRoughness` onto the metallic-roughness BRDF
//! (`MATERIAL_METALLIC_ROUGHNESS`, src/material/metallic_roughness/), `KHR_materials_transmission`
//! (+ `KHR_materials_ior`) onto the rough dielectric, the normal map, emission and the alpha
//! modes onto cut-outs.
//!
//! The shaders look textures up as they are (a texture replaces the value; one UV set), so each
//! glTF texture use is baked into a texture of its own once: base colour times its factor
//! (sRGB decoded), roughness (G) and metallic (B) times theirs as grey images, alpha times its
//! factor (thresholded at the cut-off for MASK), the normal map with its scale applied.

use super::resources::image_bytes;
use crate::material::{MATERIAL_DIELECTRIC, MATERIAL_METALLIC_ROUGHNESS, Material, NO_TEXTURE};
use crate::scene::texture::{Encoding, Filter, Texture, Wrap, srgb_to_linear};
use glam::{Mat3, Vec2, Vec3};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Which channel of a glTF image a baked texture holds, with the factor applied.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Bake {
    /// RGB of the sRGB image times the factor's bits.
    BaseColor([u32; 3]),
    /// Alpha times the factor; thresholded at the cut-off when it is `Some`.
    Alpha(u32, Option<u32>),
    /// G times the roughness factor.
    Roughness(u32),
    /// B times the metallic factor.
    Metallic(u32),
    /// The tangent-space normal with x and y times the scale.
    Normal(u32),
}

/// The scene's textures as the materials bake them, each made once.
pub struct Textures<'a> {
    pub textures: Vec<Texture>,
    baked: HashMap<(usize, Bake, Filter, Wrap), u32>,
    images: HashMap<usize, Texture>,
    path: &'a Path,
    folder: &'a Path,
    buffers: &'a [Vec<u8>],
}

impl<'a> Textures<'a> {
    pub fn new(path: &'a Path, folder: &'a Path, buffers: &'a [Vec<u8>]) -> Textures<'a> {
        Textures {
            textures: Vec::new(),
            baked: HashMap::new(),
            images: HashMap::new(),
            path,
            folder,
            buffers,
        }
    }

    /// The image of `texture`, decoded once (raw: colour textures decode sRGB when baked).
    fn image(&mut self, texture: &gltf::Texture<'_>) -> Result<&Texture, String> {
        let image = texture.source();
        let index = image.index();
        if !self.images.contains_key(&index) {
            let mut what = match image.name() {
                Some(n) => format!("image {index} ('{n}')"),
                None => format!("image {index}"),
            };
            if let gltf::image::Source::Uri { uri, .. } = image.source() {
                if !uri.starts_with("data:") {
                    what += &format!(" ({uri})");
                }
            }
            let bytes = image_bytes(&image, self.folder, self.buffers)
                .map_err(|e| format!("{what}: {e}"))?;
            let label = PathBuf::from(format!("{}#image{index}", self.path.display()));
            let decoded = Texture::decode(&bytes, &label, Encoding::Raw)
                .map_err(|e| format!("{what} does not decode: {e}"))?;
            self.images.insert(index, decoded);
        }
        Ok(&self.images[&index])
    }

    /// The index of `texture` baked as `bake`.
    fn bake(&mut self, texture: &gltf::Texture<'_>, bake: Bake) -> Result<u32, String> {
        let sampler = texture.sampler();
        let filter = match sampler.mag_filter() {
            Some(gltf::texture::MagFilter::Nearest) => Filter::Nearest,
            _ => Filter::Bilinear,
        };
        // One wrap mode for both axes: wrapS (they are the same in nearly every file).
        let wrap = match sampler.wrap_s() {
            gltf::texture::WrappingMode::ClampToEdge => Wrap::Clamp,
            gltf::texture::WrappingMode::MirroredRepeat => Wrap::Mirror,
            gltf::texture::WrappingMode::Repeat => Wrap::Repeat,
        };
        let key = (texture.source().index(), bake, filter, wrap);
        if let Some(&i) = self.baked.get(&key) {
            return Ok(i);
        }
        let image = self.image(texture)?;
        let texels = image
            .texels
            .iter()
            .map(|&[r, g, b, a]| baked_texel(bake, [r, g, b, a]))
            .collect();
        let encoding = match bake {
            Bake::BaseColor(_) => Encoding::Srgb,
            _ => Encoding::Raw,
        };
        let t = Texture {
            path: image.path.clone(),
            encoding,
            width: image.width,
            height: image.height,
            filter,
            wrap,
            texels,
        };
        self.textures.push(t);
        let i = (self.textures.len() - 1) as u32;
        self.baked.insert(key, i);
        Ok(i)
    }
}

fn baked_texel(bake: Bake, [r, g, b, a]: [f32; 4]) -> [f32; 4] {
    let grey = |v: f32| [v, v, v, 1.0];
    match bake {
        Bake::BaseColor(f) => {
            let f = f.map(f32::from_bits);
            [
                srgb_to_linear(r) * f[0],
                srgb_to_linear(g) * f[1],
                srgb_to_linear(b) * f[2],
                1.0,
            ]
        }
        Bake::Alpha(f, cutoff) => {
            let alpha = a * f32::from_bits(f);
            match cutoff {
                Some(c) => grey(if alpha >= f32::from_bits(c) { 1.0 } else { 0.0 }),
                None => grey(alpha),
            }
        }
        Bake::Roughness(f) => grey(g * f32::from_bits(f)),
        Bake::Metallic(f) => grey(b * f32::from_bits(f)),
        Bake::Normal(s) => {
            let s = f32::from_bits(s);
            let n = Vec3::new((2.0 * r - 1.0) * s, (2.0 * g - 1.0) * s, 2.0 * b - 1.0);
            let n = n.normalize_or(Vec3::Z);
            let c = (n + Vec3::ONE) * 0.5;
            [c.x, c.y, c.z, 1.0]
        }
    }
}

/// A material and what the loader must do with its primitives' texture coordinates.
pub struct Converted {
    pub material: Material,
    /// KHR_texture_transform's matrix, applied to glTF UVs (before v is flipped).
    pub uv_transform: Option<Mat3>,
    pub warnings: Vec<String>,
}

/// The glTF 2.0 default material (no `material` on a primitive): white, metallic 1,
/// roughness 1, as the specification defines it.
pub fn default_material() -> Material {
    metallic_roughness([1.0; 3], 1.0, 1.0)
}

fn metallic_roughness(base: [f32; 3], metallic: f32, roughness: f32) -> Material {
    Material {
        kind: MATERIAL_METALLIC_ROUGHNESS,
        kd: base,
        ks: [metallic; 3],
        alpha: roughness * roughness,
        ..Material::DEFAULT
    }
}

fn transform_of(info: &gltf::texture::Info<'_>) -> Option<Mat3> {
    let t = info.texture_transform()?;
    Some(texture_matrix(t.offset(), t.rotation(), t.scale()))
}

/// KHR_texture_transform's matrix, translation * rotation * scale, its rotation turning
/// (1, 0) to (cos, -sin): the extension's example (offset (0, 1), rotation 90 degrees, scale
/// 0.5: the lower left quadrant) holds only with that sign.
pub fn texture_matrix([ox, oy]: [f32; 2], rotation: f32, [sx, sy]: [f32; 2]) -> Mat3 {
    let (s, c) = rotation.sin_cos();
    let translation = Mat3::from_cols(Vec3::X, Vec3::Y, Vec3::new(ox, oy, 1.0));
    let rotation = Mat3::from_cols(Vec3::new(c, -s, 0.0), Vec3::new(s, c, 0.0), Vec3::Z);
    let scale = Mat3::from_diagonal(Vec3::new(sx, sy, 1.0));
    translation * rotation * scale
}

/// Applies a texture transform to a glTF UV.
pub fn transform_uv(m: &Mat3, uv: Vec2) -> Vec2 {
    (*m * uv.extend(1.0)).truncate()
}

/// The material's name for messages.
pub fn describe(material: &gltf::Material<'_>) -> String {
    match (material.index(), material.name()) {
        (Some(i), Some(n)) => format!("material {i} ('{n}')"),
        (Some(i), None) => format!("material {i}"),
        (None, _) => "the default material".to_string(),
    }
}

/// Converts one glTF material; `textures` receives its baked textures.
pub fn convert(
    material: &gltf::Material<'_>,
    textures: &mut Textures<'_>,
) -> Result<Converted, String> {
    let what = describe(material);
    let mut warnings = Vec::new();
    let pbr = material.pbr_metallic_roughness();
    let [r, g, b, a] = pbr.base_color_factor();
    let metallic = pbr.metallic_factor();
    let roughness = pbr.roughness_factor();
    for (name, v) in [
        ("baseColorFactor", r),
        ("baseColorFactor", g),
        ("baseColorFactor", b),
        ("baseColorFactor", a),
        ("metallicFactor", metallic),
        ("roughnessFactor", roughness),
    ] {
        if !(0.0..=1.0).contains(&v) {
            return Err(format!("{what}: {name} has {v}; it must be in [0, 1]"));
        }
    }
    let mut m = metallic_roughness([r, g, b], metallic, roughness);
    let mut infos: Vec<(&str, Option<Mat3>, u32)> = Vec::new();
    let bake = |textures: &mut Textures<'_>, info: &gltf::texture::Info<'_>, bake: Bake| {
        textures
            .bake(&info.texture(), bake)
            .map_err(|e| format!("{what}: {e}"))
    };
    if let Some(info) = pbr.base_color_texture() {
        m.map_kd = bake(
            textures,
            &info,
            Bake::BaseColor([r, g, b].map(f32::to_bits)),
        )?;
        infos.push(("baseColorTexture", transform_of(&info), info.tex_coord()));
    }
    if let Some(info) = pbr.metallic_roughness_texture() {
        m.map_pr = bake(textures, &info, Bake::Roughness(roughness.to_bits()))?;
        m.map_ks = bake(textures, &info, Bake::Metallic(metallic.to_bits()))?;
        infos.push((
            "metallicRoughnessTexture",
            transform_of(&info),
            info.tex_coord(),
        ));
    }
    if let Some(normal) = material.normal_texture() {
        m.surface_map = textures
            .bake(&normal.texture(), Bake::Normal(normal.scale().to_bits()))
            .map_err(|e| format!("{what}: {e}"))?;
        // The normal texture's info has no KHR_texture_transform accessor in the gltf crate;
        // it is read from the JSON extension below.
        infos.push((
            "normalTexture",
            normal_transform(&normal),
            normal.tex_coord(),
        ));
    }
    match material.alpha_mode() {
        gltf::material::AlphaMode::Opaque => {}
        mode => {
            let cutoff = match mode {
                gltf::material::AlphaMode::Mask => Some(material.alpha_cutoff().unwrap_or(0.5)),
                _ => None,
            };
            match pbr.base_color_texture() {
                Some(info) => {
                    m.map_d = bake(
                        textures,
                        &info,
                        Bake::Alpha(a.to_bits(), cutoff.map(f32::to_bits)),
                    )?;
                }
                None => {
                    m.opacity = match cutoff {
                        Some(c) => f32::from(u8::from(a >= c)),
                        None => a,
                    }
                }
            }
        }
    }
    let strength = material.emissive_strength().unwrap_or(1.0);
    if !(strength.is_finite() && strength >= 0.0) {
        return Err(format!(
            "{what}: KHR_materials_emissive_strength is {strength}; it must be a finite number >= 0"
        ));
    }
    let mut emission = Vec3::from(material.emissive_factor()) * strength;
    if let Some(info) = material.emissive_texture() {
        // Emission is one radiance per material (emissive triangles are lights of constant
        // radiance): the texture's mean stands for it, and the user is told.
        let image = textures
            .image(&info.texture())
            .map_err(|e| format!("{what}: {e}"))?;
        let n = image.texels.len() as f32;
        let mean = image.texels.iter().fold(Vec3::ZERO, |s, t| {
            s + Vec3::new(
                srgb_to_linear(t[0]),
                srgb_to_linear(t[1]),
                srgb_to_linear(t[2]),
            )
        }) / n;
        emission *= mean;
        warnings.push(format!(
            "{what}: emissiveTexture is not supported (emission is one colour per material): the material emits emissiveFactor times the texture's mean, {:.3} {:.3} {:.3}",
            mean.x, mean.y, mean.z
        ));
    }
    m.ke = emission.to_array();
    if let Some(t) = material.transmission() {
        let factor = t.transmission_factor();
        if t.transmission_texture().is_some() {
            warnings.push(format!(
                "{what}: transmissionTexture is not supported: transmission is transmissionFactor ({factor}) everywhere"
            ));
        }
        if factor > 0.0 && factor < 1.0 {
            warnings.push(format!(
                "{what}: transmissionFactor {factor} is rounded to {}: passgraph's dielectric transmits all or nothing",
                if factor >= 0.5 { 1 } else { 0 }
            ));
        }
        if factor >= 0.5 {
            let ior = material.ior().unwrap_or(1.5);
            if !(ior.is_finite() && ior >= 1.0) {
                return Err(format!(
                    "{what}: KHR_materials_ior is {ior}; it must be a finite number >= 1"
                ));
            }
            m = Material {
                kind: MATERIAL_DIELECTRIC,
                ior,
                alpha: roughness * roughness,
                tf: [r, g, b],
                kd: [1.0; 3],
                ks: [1.0; 3],
                ke: m.ke,
                surface_map: m.surface_map,
                map_pr: m.map_pr,
                ..Material::DEFAULT
            };
        }
    }
    let mut transforms = infos.iter().map(|&(_, t, _)| t);
    let uv_transform = transforms.next().flatten();
    if transforms.any(|t| t != uv_transform) {
        warnings.push(format!(
            "{what}: its textures have different KHR_texture_transforms; passgraph has one UV set per material and uses the first texture's"
        ));
    }
    for (name, _, set) in &infos {
        if *set != 0 {
            warnings.push(format!(
                "{what}: {name} uses TEXCOORD_{set}; passgraph reads TEXCOORD_0 only and looks it up there"
            ));
        }
    }
    if m.map_pr == NO_TEXTURE && m.kind == MATERIAL_DIELECTRIC && m.alpha == 0.0 {
        // A smooth glass: the delta dielectric.
        m.alpha = 0.0;
    }
    Ok(Converted {
        material: m,
        uv_transform,
        warnings,
    })
}

/// KHR_texture_transform on a normal texture, read from its JSON (the gltf crate exposes the
/// extension on `texture::Info` only).
fn normal_transform(normal: &gltf::material::NormalTexture<'_>) -> Option<Mat3> {
    let ext = normal.extension_value("KHR_texture_transform")?;
    let pair = |key: &str, default: [f32; 2]| -> [f32; 2] {
        ext.get(key)
            .and_then(|v| v.as_array())
            .and_then(|a| Some([a.first()?.as_f64()? as f32, a.get(1)?.as_f64()? as f32]))
            .unwrap_or(default)
    };
    let rotation = ext.get("rotation").and_then(|v| v.as_f64()).unwrap_or(0.0) as f32;
    Some(texture_matrix(
        pair("offset", [0.0, 0.0]),
        rotation,
        pair("scale", [1.0, 1.0]),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_normal_texel_bakes_its_scale_and_stays_unit_length() {
        let flat = baked_texel(Bake::Normal(2.0f32.to_bits()), [0.5, 0.5, 1.0, 1.0]);
        assert!((Vec3::new(flat[0], flat[1], flat[2]) - Vec3::new(0.5, 0.5, 1.0)).length() < 1e-6);
        let tilted = baked_texel(Bake::Normal(0.0f32.to_bits()), [1.0, 0.5, 0.5, 1.0]);
        // Scale 0 flattens any map to the unperturbed normal.
        assert!((tilted[0] - 0.5).abs() < 1e-6 && (tilted[2] - 1.0).abs() < 1e-6);
    }

    #[test]
    fn mask_alpha_thresholds_at_the_cutoff() {
        let cut = Some(0.5f32.to_bits());
        assert_eq!(
            baked_texel(Bake::Alpha(1.0f32.to_bits(), cut), [0.0, 0.0, 0.0, 0.49])[0],
            0.0
        );
        assert_eq!(
            baked_texel(Bake::Alpha(1.0f32.to_bits(), cut), [0.0, 0.0, 0.0, 0.5])[0],
            1.0
        );
        assert_eq!(
            baked_texel(Bake::Alpha(0.5f32.to_bits(), None), [0.0, 0.0, 0.0, 0.5])[0],
            0.25
        );
    }

    #[test]
    fn the_texture_transform_maps_the_unit_square_as_the_extensions_example() {
        // offset (0, 1), rotation 90 degrees, scale 0.5: "the lower left quadrant of the
        // source image, rotated clockwise 90 degrees" (v runs down the image).
        let m = texture_matrix([0.0, 1.0], std::f32::consts::FRAC_PI_2, [0.5, 0.5]);
        for (uv, expected) in [
            ((0.0, 0.0), (0.0, 1.0)),
            ((1.0, 0.0), (0.0, 0.5)),
            ((0.0, 1.0), (0.5, 1.0)),
            ((1.0, 1.0), (0.5, 0.5)),
        ] {
            let got = transform_uv(&m, Vec2::new(uv.0, uv.1));
            assert!(
                (got - Vec2::new(expected.0, expected.1)).length() < 1e-6,
                "{uv:?} -> {got}"
            );
        }
    }
}
