//! The material record every model shares: `shaders/lib/scene.wgsl`'s `Material`, byte for
//! byte (128 bytes, 8 texels), and the constants its fields hold. Each model (a folder beside
//! this file) reads the fields it documents; the record stays one size so the GPU indexes it.

use crate::bsdf::microfacet::Distribution;
use bytemuck::{Pod, Zeroable};

/// A material's `table` when it has none (src/material/tables.rs gives plastic and
/// metallic-roughness materials their albedo tables).
pub const NO_TABLE: u32 = u32::MAX;

/// A material's texture index when it has none.
pub const NO_TEXTURE: u32 = u32::MAX;

/// The bit of `Material::surface_map` that makes its texture a bump map (a height field)
/// rather than a tangent-space normal map; texture indices stay far below it.
pub const SURFACE_MAP_BUMP: u32 = 1 << 31;

/// `Material::fresnel`: the conductor's Fresnel term is 1 (kd alone).
pub const FRESNEL_NONE: u32 = 0;
/// `Material::fresnel`: the conductor's Fresnel term is that of the complex index eta + i k.
pub const FRESNEL_CONDUCTOR: u32 = 1;

/// A material: its model (`kind`, one of the `MATERIAL_*` constants: a model of
/// `super::registry::MODELS`, whose folder states its maths) and the model's parameters, as
/// `shaders/lib/scene.wgsl`'s `Material` (8 texels). Which MTL keys give which kind:
/// src/scene/obj.rs. `ke` is emitted radiance (front face only) whatever the kind.
///
/// - Lambert: f = kd / pi.
/// - Phong (the seed's normalised Blinn-Phong): f = kd/pi + ks (ns + 8)/(8 pi) max(0, n.h)^ns.
/// - Conductor: microfacets of roughness `alpha` (0: a perfect mirror), Fresnel = kd, or with
///   `fresnel` [`FRESNEL_CONDUCTOR`] kd times the complex-index Fresnel of `eta` + i `k`.
/// - Plastic: diffuse kd under a dielectric microfacet coat of index `ior`, specular tint ks.
/// - Dielectric: one-sided glass of index `ior` (the front face is outside), transmittance tf.
/// - Thin dielectric: a two-sided sheet of index `ior`, reflecting 2R / (1 + R) and passing the
///   rest straight through tinted tf (always smooth).
///
/// The rough models' microfacets follow `distribution` ([`Distribution`]: GGX by default).
///
/// `map_*` index `scene.textures` (or [`NO_TEXTURE`]): a texture replaces kd, ks or the
/// roughness r (alpha = r²); `map_d` and `opacity` < 1 cut the surface out. `surface_map`
/// perturbs the shading normal (MTL `norm`, `map_Bump`: src/scene/surface_map.rs).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Material {
    pub kd: [f32; 3],
    pub ns: f32,
    pub ks: [f32; 3],
    pub kind: u32,
    pub ke: [f32; 3],
    /// GGX alpha = r²; 0 is the smooth (delta) case.
    pub alpha: f32,
    pub tf: [f32; 3],
    pub ior: f32,
    pub map_kd: u32,
    pub map_ks: u32,
    pub map_pr: u32,
    pub map_d: u32,
    /// MTL `d`: 1 opaque; below 1 the fraction of light the surface stops.
    pub opacity: f32,
    /// The texel index in `scene.materials` of the model's table (rough plastic's), or
    /// [`NO_TABLE`]: src/material/tables.rs sets it.
    pub table: u32,
    /// A normal map's texture index, or a bump map's with [`SURFACE_MAP_BUMP`] set, or
    /// [`NO_TEXTURE`]: the two free words of the last texel, so the struct keeps its size.
    pub surface_map: u32,
    /// The bump map's height scale (MTL `-bm`, Mitsuba's `bumpmap` `scale`).
    pub bump_scale: f32,
    /// A conductor's complex index of refraction eta + i k (per RGB channel), read when
    /// `fresnel` is [`FRESNEL_CONDUCTOR`].
    pub eta: [f32; 3],
    /// The rough models' microfacet distribution: a [`Distribution`] as u32.
    pub distribution: u32,
    pub k: [f32; 3],
    /// A conductor's Fresnel term: [`FRESNEL_NONE`] (1: the tint kd alone, Mitsuba's material
    /// none) or [`FRESNEL_CONDUCTOR`].
    pub fresnel: u32,
}

const _: () = assert!(size_of::<Material>() == 128);

impl Material {
    /// The same material with its rough lobes' microfacets from `distribution`.
    pub fn with_distribution(self, distribution: Distribution) -> Material {
        Material {
            distribution: distribution as u32,
            ..self
        }
    }

    pub fn is_emissive(&self) -> bool {
        self.ke.iter().any(|&c| c > 0.0)
    }

    /// Whether the surface is not all there: an opacity below 1 or an opacity map (`map_d`),
    /// a cut-out or a null mask (`Mesh::null_masks`).
    pub fn has_opacity(&self) -> bool {
        self.opacity < 1.0 || self.map_d != NO_TEXTURE
    }
}
