// Generated from the material registry (src/material/registry.rs) by src/material/wgsl.rs:
// do not edit. `cargo test --lib material::wgsl` rewrites it when the registry changes.

// The record's kind word holds the model in its low MATERIAL_KIND_BITS and above them the
// back face's material + 1, or 0 where both faces shade alike (src/material/tables.rs).
const MATERIAL_KIND_BITS: u32 = 4u;

// Material::kind of each model; bit 1 << kind of scene_material_kinds.
const MATERIAL_LAMBERT: u32 = 0u;
const MATERIAL_PHONG: u32 = 1u;
const MATERIAL_CONDUCTOR: u32 = 2u;
const MATERIAL_PLASTIC: u32 = 3u;
const MATERIAL_DIELECTRIC: u32 = 4u;
const MATERIAL_THIN_DIELECTRIC: u32 = 5u;
const MATERIAL_METALLIC_ROUGHNESS: u32 = 6u;
