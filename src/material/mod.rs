//! Material models in the manner of Mitsuba's plugins: one folder per model holding its CPU
//! twin, the constructor loaders use and its table, described by a [`Model`] (model.rs) and
//! listed in registry.rs; its WGSL is `shaders/lib/material/NAME.wgsl`, with the other shaders
//! (the tree a graph's includes resolve in stays whole). The shaders' kind constants and BSDF
//! dispatch are generated from the list (wgsl.rs), so adding a model touches its folder, its
//! WGSL file and the registry. Below them: the record every model shares (record.rs), the shading-point view
//! (bsdf.rs), the CPU dispatch (dispatch.rs) and the packing of records and tables
//! (tables.rs). The microfacet, Fresnel and frame maths the models share is `crate::bsdf`.

pub mod bsdf;
pub mod dispatch;
pub mod model;
pub mod record;
pub mod registry;
pub mod tables;
pub mod wgsl;

pub mod conductor;
pub mod dielectric;
pub mod lambert;
pub mod metallic_roughness;
pub mod phong;
pub mod plastic;
pub mod thin_dielectric;

pub use bsdf::{Bsdf, Sample};
pub use dispatch::{eval, is_delta, pdf, sample};
pub use model::{Model, Space, Table};
pub use record::{
    FRESNEL_CONDUCTOR, FRESNEL_NONE, Material, NO_TABLE, NO_TEXTURE, SURFACE_MAP_BUMP,
};
pub use registry::{
    MATERIAL_CONDUCTOR, MATERIAL_DIELECTRIC, MATERIAL_KIND_BITS, MATERIAL_LAMBERT,
    MATERIAL_METALLIC_ROUGHNESS, MATERIAL_PHONG, MATERIAL_PLASTIC, MATERIAL_THIN_DIELECTRIC,
    MODELS, model,
};
pub use tables::{materials_bytes, materials_bytes_with_backs, materials_texels};
