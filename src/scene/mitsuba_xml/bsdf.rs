//! BSDFs onto passgraph's material models (src/bsdf/, `Material` in src/scene/gpu_layout.rs):
//!
//! | Mitsuba | passgraph |
//! | --- | --- |
//! | `diffuse` | Lambert |
//! | `conductor`, `roughconductor` (ggx) with `material none` (the default) | conductor: Fresnel 1 times `specular_reflectance` |
//! | `plastic`, `roughplastic`, `nonlinear` false (the default) or true (constant reflectance) | plastic, `ior` = int_ior / ext_ior; nonlinear folded into kd |
//! | `dielectric`, `roughdielectric` (ggx) | dielectric, `ior` = int_ior / ext_ior, `tf` = `specular_transmittance` |
//! | `diffuse`, `conductor`, `plastic` and their rough forms, bare | the model, black from behind (a back-face material of reflectance 0) |
//! | `twosided` of one BSDF | the BSDF, both faces alike (passgraph's reflecting models shade both) |
//! | `twosided` of two BSDFs | the first in front, the second behind (a back-face material) |
//! | `mask` | the BSDF with `opacity` (a number or a texture) |
//! | `normalmap`, `bumpmap` | the BSDF with its surface map |
//! | `null` | a thin sheet of index 1 (passes every ray straight through as a bounce, stops shadow rays, may emit: Mitsuba's null interaction) |
//!
//! passgraph's reflecting models shade both faces, as Mitsuba's `twosided`; Mitsuba's bare
//! `diffuse`, `conductor` and `plastic` are black from behind, which passgraph renders with a
//! back-face material ([`Back`], `Mesh::back_materials`): the back of the triangle (its
//! winding's, which is Mitsuba's normal) shades as the other material.
//!
//! The rough models' `distribution` is Beckmann unless the file says ggx (Mitsuba's default);
//! conductors take `eta`/`k` or a named `material` preset (Mitsuba's RGB values,
//! `src/material/conductor/presets.rs`); `thindielectric` is passgraph's thin dielectric.

use super::builder::Builder;
use super::params::ColorParam;
use super::parse::{At, Plugin, Value};
use super::textures::{TextureUse, texture};
use crate::bsdf::fresnel::fresnel_diffuse_reflectance;
use crate::bsdf::microfacet::Distribution;
use crate::material::conductor::presets::{CONDUCTOR_PRESETS, conductor_preset};
use crate::material::plastic::tables::PlasticTable;
use crate::material::{
    MATERIAL_DIELECTRIC, MATERIAL_PLASTIC, Material, NO_TEXTURE, SURFACE_MAP_BUMP,
};
use crate::scene::error::SceneError;
use glam::{DMat3, Vec3};
use std::rc::Rc;

/// A BSDF as a passgraph material.
#[derive(Clone, Debug)]
pub struct Bsdf {
    pub material: Material,
    /// The `to_uv` of the material's textures (all the same), Mitsuba's uv convention.
    pub to_uv: Option<DMat3>,
    /// How the back face shades.
    pub back: Back,
    /// `null`: nothing but (on an emitter) emission.
    pub null: bool,
}

/// What shades a BSDF's back face (the side its shape's normal points away from).
#[derive(Clone, Debug, PartialEq)]
pub enum Back {
    /// The same model (Mitsuba's `twosided` of one BSDF, the dielectrics, null).
    Same,
    /// Nothing: black (Mitsuba's bare reflecting models).
    Black,
    /// Another material (`twosided` of two BSDFs).
    Other(Material),
}

/// Mitsuba's named indices of refraction (`src/render/ior.h`).
const NAMED_IORS: &[(&str, f64)] = &[
    ("vacuum", 1.0),
    ("helium", 1.000036),
    ("hydrogen", 1.000132),
    ("air", 1.000277),
    ("carbon dioxide", 1.00045),
    ("water", 1.3330),
    ("acetone", 1.36),
    ("ethanol", 1.361),
    ("carbon tetrachloride", 1.461),
    ("glycerol", 1.4729),
    ("benzene", 1.501),
    ("silicone oil", 1.52045),
    ("bromine", 1.661),
    ("water ice", 1.31),
    ("fused quartz", 1.458),
    ("pyrex", 1.470),
    ("acrylic glass", 1.49),
    ("polypropylene", 1.49),
    ("bk7", 1.5046),
    ("sodium chloride", 1.544),
    ("amber", 1.55),
    ("pet", 1.5750),
    ("diamond", 2.419),
];

/// An index of refraction: a number, or one of Mitsuba's names.
fn ior(plugin: &Plugin, name: &str, default: &str) -> Result<f64, SceneError> {
    let Some(p) = plugin.property(name) else {
        return named_ior(plugin, default, &plugin.at);
    };
    let v = match &p.value {
        Value::String(s) => return named_ior(plugin, s, &p.at),
        Value::Float(v) => *v,
        Value::Integer(v) => *v as f64,
        other => {
            return Err(plugin.error_at(
                &p.at,
                format!(
                    "{name} is a <{}>; it must be a <float> or a <string> (a named IOR)",
                    other.tag()
                ),
            ));
        }
    };
    if !(v.is_finite() && v > 0.0) {
        return Err(plugin.error_at(&p.at, format!("{name} {v} must be a positive number")));
    }
    Ok(v)
}

fn named_ior(plugin: &Plugin, name: &str, at: &At) -> Result<f64, SceneError> {
    NAMED_IORS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|&(_, v)| v)
        .ok_or_else(|| {
            let names: Vec<&str> = NAMED_IORS.iter().map(|(n, _)| *n).collect();
            plugin.error_at(
                at,
                format!(
                    "'{name}' is not one of Mitsuba's named IORs ({})",
                    names.join(", ")
                ),
            )
        })
}

fn f32s(c: [f64; 3]) -> [f32; 3] {
    c.map(|v| v as f32)
}

/// Keeps the one `to_uv` the material's textures may have.
fn join_to_uv(
    plugin: &Plugin,
    at: &At,
    current: &mut Option<DMat3>,
    t: &TextureUse,
) -> Result<(), SceneError> {
    match current {
        None => *current = Some(t.to_uv),
        Some(m) if m.abs_diff_eq(t.to_uv, 1e-12) => {}
        Some(_) => {
            return Err(plugin.error_at(
                at,
                "this texture's to_uv differs from another texture's of the same material; passgraph applies one to_uv per material",
            ));
        }
    }
    Ok(())
}

/// A colour parameter as (constant, texture index).
fn color_or_texture(
    builder: &mut Builder,
    plugin: &Plugin,
    name: &str,
    default: [f64; 3],
    to_uv: &mut Option<DMat3>,
) -> Result<([f32; 3], u32), SceneError> {
    match plugin.color(name)? {
        None => Ok((f32s(default), NO_TEXTURE)),
        Some(ColorParam::Constant(c)) => {
            if c.iter().any(|v| !v.is_finite() || *v < 0.0) {
                return Err(plugin.error(format!("{name} {c:?} must be finite and not negative")));
            }
            Ok((f32s(c), NO_TEXTURE))
        }
        Some(ColorParam::Texture(t, at)) => {
            let used = texture(builder, &t)?;
            join_to_uv(plugin, &at, to_uv, &used)?;
            Ok(([1.0; 3], used.index))
        }
    }
}

/// The `distribution` of a rough model: Mitsuba's default is Beckmann.
fn distribution(plugin: &Plugin) -> Result<Distribution, SceneError> {
    let (name, at) = match plugin.string("distribution")? {
        Some(d) => d,
        None => return Ok(Distribution::Beckmann),
    };
    Distribution::from_mitsuba_name(&name).ok_or_else(|| {
        plugin.error_at(
            &at,
            format!("distribution '{name}' is not one of Mitsuba's (beckmann, ggx)"),
        )
    })
}

/// `alpha`, or `alpha_u` = `alpha_v` (passgraph's GGX is isotropic); Mitsuba's default 0.1.
fn alpha(plugin: &Plugin) -> Result<f32, SceneError> {
    let (u, v) = (plugin.float("alpha_u")?, plugin.float("alpha_v")?);
    let a = match (plugin.float("alpha")?, u, v) {
        (Some(a), None, None) => a,
        (None, None, None) => 0.1,
        (None, Some(u), Some(v)) if u == v => u,
        (None, Some(u), Some(v)) => {
            return Err(plugin.error(format!(
                "alpha_u {u} and alpha_v {v} differ: anisotropic roughness is not supported (passgraph's GGX is isotropic)"
            )));
        }
        _ => {
            return Err(plugin.error("give alpha, or both alpha_u and alpha_v (equal), not a mix"));
        }
    };
    if plugin
        .children
        .iter()
        .any(|c| c.name.as_deref() == Some("alpha"))
    {
        return Err(plugin.error("a textured alpha is not supported, only a number"));
    }
    if !(a.is_finite() && a > 0.0 && a <= 1.0) {
        return Err(plugin.error(format!("alpha {a} must be in (0, 1]")));
    }
    // Mitsuba's sample_visible changes how directions are drawn, not the BSDF.
    plugin.accept("sample_visible");
    Ok(a as f32)
}

/// A rough model's alpha and distribution; a smooth one's (0, unused).
fn roughness(plugin: &Plugin, rough: bool) -> Result<(f32, Distribution), SceneError> {
    if rough {
        Ok((alpha(plugin)?, distribution(plugin)?))
    } else {
        Ok((0.0, Distribution::Ggx))
    }
}

/// The material of a `<bsdf>` plugin.
pub fn bsdf(builder: &mut Builder, plugin: &Rc<Plugin>) -> Result<Bsdf, SceneError> {
    let mut to_uv = None;
    let mut back = Back::Black;
    let mut null = false;
    let material = match plugin.kind.as_str() {
        "diffuse" => {
            let (kd, map_kd) =
                color_or_texture(builder, plugin, "reflectance", [0.5; 3], &mut to_uv)?;
            Material {
                map_kd,
                ..Material::diffuse(kd)
            }
        }
        "conductor" | "roughconductor" => {
            let rough = plugin.kind == "roughconductor";
            // The complex index: eta and k as written, else the `material` preset (Mitsuba's
            // default "none": Fresnel 1, the tint alone).
            let preset = match plugin.string("material")? {
                None => None,
                Some((name, _)) if name == "none" => None,
                Some((name, at)) => Some(conductor_preset(&name).ok_or_else(|| {
                    plugin.error_at(
                        &at,
                        format!(
                            "conductor material '{name}' is not one of Mitsuba's presets ({}, none)",
                            CONDUCTOR_PRESETS
                                .iter()
                                .map(|p| p.0)
                                .collect::<Vec<_>>()
                                .join(", ")
                        ),
                    )
                })?),
            };
            let ior = match (plugin.has("eta"), plugin.has("k")) {
                (false, false) => preset,
                _ => {
                    let (eta, k) = preset.unwrap_or((Vec3::ZERO, Vec3::ONE));
                    let eta = plugin.constant_color("eta", eta.as_dvec3().to_array())?;
                    let k = plugin.constant_color("k", k.as_dvec3().to_array())?;
                    if eta.iter().chain(&k).any(|v| !v.is_finite() || *v < 0.0) {
                        return Err(plugin.error(format!(
                            "eta {eta:?} and k {k:?} must be finite and not negative"
                        )));
                    }
                    Some((Vec3::from(f32s(eta)), Vec3::from(f32s(k))))
                }
            };
            let (kd, map_kd) = color_or_texture(
                builder,
                plugin,
                "specular_reflectance",
                [1.0; 3],
                &mut to_uv,
            )?;
            let (alpha, dist) = roughness(plugin, rough)?;
            Material {
                map_kd,
                ..Material::conductor(kd, alpha, dist, ior)
            }
        }
        "plastic" | "roughplastic" => {
            let rough = plugin.kind == "roughplastic";
            let eta = ior(plugin, "int_ior", "polypropylene")? / ior(plugin, "ext_ior", "air")?;
            let nonlinear = plugin.boolean("nonlinear")?.unwrap_or(false);
            let (mut kd, map_kd) =
                color_or_texture(builder, plugin, "diffuse_reflectance", [0.5; 3], &mut to_uv)?;
            let (alpha, dist) = roughness(plugin, rough)?;
            if nonlinear {
                if map_kd != NO_TEXTURE {
                    let at = plugin.property("nonlinear").map(|p| p.at.clone());
                    return Err(plugin.error_at(
                        at.as_ref().unwrap_or(&plugin.at),
                        "nonlinear true with a textured diffuse_reflectance is not supported (passgraph folds nonlinear into a constant reflectance)",
                    ));
                }
                kd = nonlinear_as_linear(kd, internal_reflectance(alpha, dist, eta as f32));
            }
            let (ks, map_ks) = color_or_texture(
                builder,
                plugin,
                "specular_reflectance",
                [1.0; 3],
                &mut to_uv,
            )?;
            Material {
                kind: MATERIAL_PLASTIC,
                distribution: dist as u32,
                ks,
                map_ks,
                ior: eta as f32,
                alpha,
                map_kd,
                ..Material::diffuse(kd)
            }
        }
        "dielectric" | "roughdielectric" => {
            let rough = plugin.kind == "roughdielectric";
            let eta = ior(plugin, "int_ior", "bk7")? / ior(plugin, "ext_ior", "air")?;
            let reflectance = plugin.constant_color("specular_reflectance", [1.0; 3])?;
            if reflectance != [1.0; 3] {
                return Err(plugin.error(
                    "specular_reflectance other than 1 is not supported (passgraph's dielectric reflects by Fresnel alone)",
                ));
            }
            let tf = plugin.constant_color("specular_transmittance", [1.0; 3])?;
            let (alpha, dist) = roughness(plugin, rough)?;
            back = Back::Same;
            Material {
                kind: MATERIAL_DIELECTRIC,
                distribution: dist as u32,
                ior: eta as f32,
                tf: f32s(tf),
                alpha,
                ..Material::diffuse([0.0; 3])
            }
        }
        "thindielectric" => {
            let eta = ior(plugin, "int_ior", "bk7")? / ior(plugin, "ext_ior", "air")?;
            let reflectance = plugin.constant_color("specular_reflectance", [1.0; 3])?;
            if reflectance != [1.0; 3] {
                return Err(plugin.error(
                    "specular_reflectance other than 1 is not supported (passgraph's thin dielectric reflects by Fresnel alone)",
                ));
            }
            let tf = plugin.constant_color("specular_transmittance", [1.0; 3])?;
            // Both faces alike, as Mitsuba's.
            back = Back::Same;
            Material::thin_dielectric(eta as f32, f32s(tf))
        }
        "twosided" => {
            let inner = plugin.children_of("bsdf");
            if !matches!(inner.len(), 1 | 2) {
                return Err(plugin.error("twosided needs one or two nested <bsdf>s"));
            }
            let mut sides = Vec::new();
            for side in &inner {
                let b = bsdf(builder, &side.plugin)?;
                if b.material.kind == MATERIAL_DIELECTRIC || b.null {
                    return Err(plugin.error_at(
                        &side.at,
                        format!("twosided around a {} is not supported (supported: diffuse, conductor, plastic and their rough and adapted forms)", side.plugin.kind),
                    ));
                }
                sides.push((b, &side.at));
            }
            plugin.finish()?;
            let mut front = sides.remove(0).0;
            front.back = match sides.pop() {
                None => Back::Same,
                Some((b, at)) => {
                    // Mitsuba's twosided shows the second BSDF from behind as if from its front.
                    // The triangles carry one set of uvs, so both sides must map them alike.
                    if b.to_uv.is_some() && front.to_uv.is_some() && b.to_uv != front.to_uv {
                        return Err(plugin.error_at(
                            at,
                            "the two sides' textures have different to_uv (passgraph's triangles have one set of uvs)",
                        ));
                    }
                    if b.material.has_opacity() {
                        return Err(plugin.error_at(
                            at,
                            "a mask on the back BSDF of a twosided is not supported (put the mask around the twosided)",
                        ));
                    }
                    front.to_uv = front.to_uv.or(b.to_uv);
                    Back::Other(b.material)
                }
            };
            return Ok(front);
        }
        "mask" => {
            let inner = single_inner(plugin)?;
            let mut b = bsdf(builder, &inner.plugin)?;
            if b.material.has_opacity() || b.null {
                return Err(plugin.error("a mask inside a mask or around null is not supported"));
            }
            // A mixture with a null interaction, as Mitsuba's: the mesh's null masks are the
            // materials with an opacity (build.rs).
            match plugin.color("opacity")? {
                None => b.material.opacity = 0.5,
                Some(ColorParam::Constant(c)) => {
                    if c[0] != c[1] || c[1] != c[2] || !(0.0..=1.0).contains(&c[0]) {
                        return Err(
                            plugin.error(format!("opacity {c:?} must be one number in [0, 1]"))
                        );
                    }
                    b.material.opacity = c[0] as f32;
                }
                Some(ColorParam::Texture(t, at)) => {
                    let used = texture(builder, &t)?;
                    join_to_uv(plugin, &at, &mut b.to_uv, &used)?;
                    b.material.map_d = used.index;
                }
            }
            plugin.finish()?;
            return Ok(b);
        }
        "normalmap" | "bumpmap" => {
            let inner = single_inner(plugin)?;
            let mut b = bsdf(builder, &inner.plugin)?;
            if b.material.surface_map != NO_TEXTURE || b.null {
                return Err(plugin.error(
                    "a normal or bump map around another, or around null, is not supported",
                ));
            }
            let bump = plugin.kind == "bumpmap";
            let texture_child = if bump {
                // Mitsuba's bumpmap takes its one nested texture whatever its name.
                let list = plugin.children_of("texture");
                match list[..] {
                    [one] => one,
                    _ => {
                        return Err(
                            plugin.error("a bumpmap needs one nested <texture> (the height field)")
                        );
                    }
                }
            } else {
                plugin
                    .named_child("normalmap")
                    .filter(|c| c.plugin.class == "texture")
                    .ok_or_else(|| {
                        plugin.error("a normalmap needs a nested <texture name=\"normalmap\">")
                    })?
            };
            let used = texture(builder, &texture_child.plugin)?;
            if bump && !used.default_lookup {
                return Err(plugin.error_at(
                    &texture_child.at,
                    "a bump map's height field must be a bitmap looked up bilinear with wrap_mode repeat (passgraph's slope assumes them)",
                ));
            }
            join_to_uv(plugin, &texture_child.at, &mut b.to_uv, &used)?;
            // passgraph models Mitsuba's defaults for these two (flipping normals that face
            // away, and the shadowing of the terminator); the other settings it does not model.
            for name in ["flip_invalid_normals", "use_shadowing_function"] {
                if plugin.boolean(name)? == Some(false) {
                    return Err(plugin.error(format!(
                        "{name} false is not supported (passgraph models Mitsuba's default, true)"
                    )));
                }
            }
            if bump {
                let scale = plugin.float_or("scale", 1.0)?;
                if !scale.is_finite() {
                    return Err(plugin.error("scale must be finite"));
                }
                b.material.surface_map = used.index | SURFACE_MAP_BUMP;
                b.material.bump_scale = scale as f32;
            } else {
                b.material.surface_map = used.index;
            }
            plugin.finish()?;
            return Ok(b);
        }
        "null" => {
            // Mitsuba's path integrator spends a bounce at each crossing of a null surface, does
            // no next-event estimation there and stops shadow rays at it (the light behind
            // comes through BSDF samples); it may emit. A thin sheet of index 1 is all of
            // that: Fresnel 0, so every sample passes straight through (a delta event of
            // weight 1), an occluder to shadow rays, and its emission is the material's.
            null = true;
            back = Back::Same;
            Material::thin_dielectric(1.0, [1.0; 3])
        }
        other => {
            return Err(plugin.error(format!(
                "BSDF type '{other}' is not supported (supported: diffuse, conductor, roughconductor, plastic, roughplastic, dielectric, roughdielectric, twosided, mask, normalmap, bumpmap, null)"
            )));
        }
    };
    plugin.finish()?;
    Ok(Bsdf {
        material,
        to_uv,
        back,
        null,
    })
}

/// The fraction of the base's light the coat reflects back inside (Mitsuba's `m_fdr_int` of
/// the smooth plastic, `m_internal_reflectance` of the rough one, which passgraph's tables hold).
fn internal_reflectance(alpha: f32, distribution: Distribution, eta: f32) -> f32 {
    if alpha > 0.0 {
        PlasticTable::compute(distribution, alpha, eta).internal_reflectance
    } else {
        fresnel_diffuse_reflectance(1.0 / eta)
    }
}

/// The linear model's reflectance that equals Mitsuba's `nonlinear` one: its diffuse term is
/// kd / (1 - kd R) where the linear one's is kd / (1 - R), per channel, so
/// kd' = kd (1 - R) / (1 - kd R).
fn nonlinear_as_linear(kd: [f32; 3], r: f32) -> [f32; 3] {
    kd.map(|d| d * (1.0 - r) / (1.0 - d * r))
}

fn single_inner(plugin: &Plugin) -> Result<&super::parse::Child, SceneError> {
    plugin
        .child_of("bsdf")?
        .ok_or_else(|| plugin.error(format!("{} needs a nested <bsdf>", plugin.kind)))
}
