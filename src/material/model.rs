//! What a material model gives the renderer: its CPU twin's four functions, what the shaders
//! need to call its WGSL, and the table it may precompute. One `Model` per folder beside this
//! file; src/material/registry.rs lists them, and the WGSL dispatch is generated from that list
//! (src/material/wgsl.rs).
//!
//! A model named `NAME` keeps its WGSL in `shaders/lib/material/NAME.wgsl` (with the shaders,
//! so that the shader tree a graph resolves its includes in is whole), defining, with `b: Bsdf`
//! and `outside: bool` (wo on the front side):
//!
//! - in [`Space::World`]: `NAME_eval(b, n, outside, wo, wi) -> vec3<f32>`,
//!   `NAME_pdf(b, n, outside, wo, wi) -> f32`, `NAME_sample(b, n, outside, wo, u, u_lobe) ->
//!   BsdfSample`, directions in world space around the shading normal `n`;
//! - in [`Space::Local`]: the same without `n`, directions in the shading frame (normal +z),
//!   the sample's `wi` too;
//! - `NAME_is_delta(b) -> bool`: whether every lobe is delta (light sampling is then skipped).
//!
//! The CPU functions below take world space whatever the model's space.

use super::bsdf::{Bsdf, Sample};
use super::record::Material;
use glam::{Vec2, Vec3};

/// Where a model's WGSL works: world space needs no shading frame (the diffuse models, the
/// common case, skip building one).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Space {
    World,
    Local,
}

/// A model's precomputed table, stored after the records in `scene.materials`
/// (src/material/tables.rs); the record's `table` holds its texel index.
#[derive(Clone, Copy)]
pub struct Table {
    /// The parameters the table depends on (materials with equal keys share one), or `None`
    /// when this material reads no table.
    pub key: fn(&Material) -> Option<[u32; 3]>,
    pub texels: fn(&Material) -> Vec<[f32; 4]>,
}

#[derive(Clone, Copy)]
pub struct Model {
    /// Names the folder, the WGSL functions (`NAME_eval`, ...) and the WGSL constant
    /// `MATERIAL_NAME` (upper case) that holds `kind`.
    pub name: &'static str,
    /// `Material::kind`: the model's index in the registry.
    pub kind: u32,
    pub space: Space,
    /// f |n.wi| of the non-delta lobes: `(b, n, outside, wo, wi)`.
    pub eval: fn(&Bsdf, Vec3, bool, Vec3, Vec3) -> Vec3,
    pub pdf: fn(&Bsdf, Vec3, bool, Vec3, Vec3) -> f32,
    /// `(b, n, outside, wo, u, u_lobe)`: `u` picks the direction within a lobe, `u_lobe` the lobe.
    pub sample: fn(&Bsdf, Vec3, bool, Vec3, Vec2, f32) -> Sample,
    pub is_delta: fn(&Bsdf) -> bool,
    /// Whether its rough lobes follow `Material::distribution` (so a Beckmann one keeps the
    /// Beckmann code in the shaders).
    pub microfacet: bool,
    /// Whether the material has a lobe other than Lambert's (the `scene_has_specular`
    /// override: a scene without one keeps only the diffuse code paths).
    pub specular: fn(&Material) -> bool,
    pub table: Option<Table>,
}

impl Model {
    /// The WGSL constant holding `kind`.
    pub fn constant(&self) -> String {
        format!("MATERIAL_{}", self.name.to_ascii_uppercase())
    }
}
