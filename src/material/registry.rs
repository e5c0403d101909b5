//! The material models, in `Material::kind` order: adding a model is a folder beside this file
//! and its WGSL in shaders/lib/material/ (src/material/model.rs says what they hold), and a
//! line here. The kinds' WGSL constants and the
//! shaders' dispatch are generated from this list (src/material/wgsl.rs).

use super::model::Model;
use super::record::{Material, NO_TEXTURE};
use super::{conductor, dielectric, lambert, metallic_roughness, phong, plastic, thin_dielectric};
use crate::bsdf::microfacet::Distribution;

pub const MODELS: [Model; 7] = [
    lambert::MODEL,
    phong::MODEL,
    conductor::MODEL,
    plastic::MODEL,
    dielectric::MODEL,
    thin_dielectric::MODEL,
    metallic_roughness::MODEL,
];

/// `Material::kind` of each model, for the loaders that choose one.
pub const MATERIAL_LAMBERT: u32 = lambert::KIND;
pub const MATERIAL_PHONG: u32 = phong::KIND;
pub const MATERIAL_CONDUCTOR: u32 = conductor::KIND;
pub const MATERIAL_PLASTIC: u32 = plastic::KIND;
pub const MATERIAL_DIELECTRIC: u32 = dielectric::KIND;
pub const MATERIAL_THIN_DIELECTRIC: u32 = thin_dielectric::KIND;
pub const MATERIAL_METALLIC_ROUGHNESS: u32 = metallic_roughness::KIND;

/// The low bits of a record's `kind` word that hold the model; the bits above hold the
/// back-face material's index + 1, 0 when both faces shade alike (lib/scene.wgsl decodes it).
/// So the 128-byte record keeps its size; 2^28 - 1 materials at most, far more than a device
/// holds (each record is 128 bytes).
pub const MATERIAL_KIND_BITS: u32 = 4;

const _: () = assert!(MODELS.len() <= 1 << MATERIAL_KIND_BITS);

/// The model of kind `kind`, if there is one.
pub fn model(kind: u32) -> Option<&'static Model> {
    MODELS.get(kind as usize)
}

impl Material {
    /// Whether a rough lobe of this material samples the Beckmann distribution (what the
    /// `scene_has_beckmann` override keeps in the shaders).
    pub fn uses_beckmann(&self) -> bool {
        let rough = self.alpha > 0.0 || self.map_pr != NO_TEXTURE;
        let microfacet = model(self.kind).is_some_and(|m| m.microfacet);
        rough && microfacet && self.distribution == Distribution::Beckmann as u32
    }

    /// Whether the model has a lobe other than Lambert's (Phong with ks > 0 or any GGX or
    /// smooth model).
    pub fn is_specular(&self) -> bool {
        model(self.kind).is_none_or(|m| (m.specular)(self))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fails when a model's `kind` is not its place in the list (the GPU indexes nothing by
    /// position, but the kinds' constants and `model()` do), or two models share a name.
    #[test]
    fn each_model_sits_at_its_kind_and_names_are_distinct() {
        for (i, m) in MODELS.iter().enumerate() {
            assert_eq!(m.kind as usize, i, "{} is listed at {i}", m.name);
            assert!(
                m.name.bytes().all(|c| c.is_ascii_lowercase() || c == b'_'),
                "{}: a model's name is a WGSL identifier prefix",
                m.name
            );
        }
        let mut names: Vec<_> = MODELS.iter().map(|m| m.name).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), MODELS.len());
    }
}
