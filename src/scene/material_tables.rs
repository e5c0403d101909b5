//! The `scene.materials` resource's contents: the materials' 128-byte records, then the texels
//! (16 bytes each) of the tables their models need, each material's `table` the texel index of
//! its own. Rough plastic has one (src/bsdf/plastic_tables.rs: Mitsuba 3's roughplastic
//! precomputes the same per material), and materials with equal (distribution, alpha, ior)
//! share it; every metallic-roughness material shares one table of its dielectric layer's
//! albedo (src/bsdf/metallic_roughness_table.rs), present only when the scene has one.

use super::gpu_layout::{Distribution, MATERIAL_METALLIC_ROUGHNESS, MATERIAL_PLASTIC, Material};
use crate::bsdf::metallic_roughness_table::SpecularAlbedoTable;
use crate::bsdf::plastic_tables::PlasticTable;
use std::collections::{BTreeMap, HashMap};

pub use super::gpu_layout::NO_TABLE;

/// The low bits of a record's `kind` word that hold the model (a `MATERIAL_*`); the bits above
/// hold the back-face material's index + 1, 0 when both faces shade alike (lib/scene.wgsl
/// decodes it). So the 128-byte record keeps its size; 2^28 - 1 materials at most, far more
/// than a device holds (each record is 128 bytes).
pub const MATERIAL_KIND_BITS: u32 = 4;

/// Texels (16 bytes) a material record takes.
const MATERIAL_TEXELS: usize = size_of::<Material>() / 16;

/// Whether `m`'s model reads a table: plastic with a rough coat, metallic-roughness.
pub fn needs_table(m: &Material) -> bool {
    (m.kind == MATERIAL_PLASTIC && m.alpha > 0.0) || m.kind == MATERIAL_METALLIC_ROUGHNESS
}

/// The materials with `table` set, and the view's texels: the records' then the tables'.
pub fn materials_texels(materials: &[Material]) -> (Vec<Material>, Vec<[f32; 4]>) {
    materials_texels_with_backs(materials, &BTreeMap::new())
}

/// As [`materials_texels`], with each material's back-face material (`Mesh::back_materials`)
/// packed into its record's `kind` word ([`MATERIAL_KIND_BITS`]).
pub fn materials_texels_with_backs(
    materials: &[Material],
    backs: &BTreeMap<u32, u32>,
) -> (Vec<Material>, Vec<[f32; 4]>) {
    let mut out = materials.to_vec();
    let mut texels: Vec<[f32; 4]> = Vec::new();
    let mut tables: Vec<[f32; 4]> = Vec::new();
    let mut shared: HashMap<(u32, u32, u32), u32> = HashMap::new();
    let mut albedo_table: Option<u32> = None;
    let start = materials.len() * MATERIAL_TEXELS;
    for m in &mut out {
        m.table = NO_TABLE;
        if !needs_table(m) {
            continue;
        }
        if m.kind == MATERIAL_METALLIC_ROUGHNESS {
            m.table = *albedo_table.get_or_insert_with(|| {
                let index = (start + tables.len()) as u32;
                tables.extend(SpecularAlbedoTable::shared().texels());
                index
            });
            continue;
        }
        m.table = *shared
            .entry((m.distribution, m.alpha.to_bits(), m.ior.to_bits()))
            .or_insert_with(|| {
                let index = (start + tables.len()) as u32;
                let distribution = Distribution::from_u32(m.distribution);
                tables.extend(PlasticTable::compute(distribution, m.alpha, m.ior).texels());
                index
            });
    }
    for (i, m) in out.iter().enumerate() {
        let mut record = *m;
        assert!(
            record.kind < 1 << MATERIAL_KIND_BITS,
            "a MATERIAL_* fits its bits"
        );
        if let Some(&back) = backs.get(&(i as u32)) {
            assert!(
                back < (u32::MAX >> MATERIAL_KIND_BITS),
                "back-face material index fits"
            );
            record.kind |= (back + 1) << MATERIAL_KIND_BITS;
        }
        texels.extend(bytemuck::cast_slice::<Material, [f32; 4]>(
            std::slice::from_ref(&record),
        ));
    }
    texels.extend(tables);
    (out, texels)
}

/// The `scene.materials` bytes.
pub fn materials_bytes(materials: &[Material]) -> Vec<u8> {
    materials_bytes_with_backs(materials, &BTreeMap::new())
}

/// The `scene.materials` bytes of materials with back-face materials.
pub fn materials_bytes_with_backs(materials: &[Material], backs: &BTreeMap<u32, u32>) -> Vec<u8> {
    bytemuck::cast_slice(&materials_texels_with_backs(materials, backs).1).to_vec()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::plastic_tables::TABLE_TEXELS;

    fn plastic(alpha: f32, ior: f32) -> Material {
        Material {
            kind: MATERIAL_PLASTIC,
            alpha,
            ior,
            ..Material::DEFAULT
        }
    }

    /// Fails when a table is placed where `table` does not point, is duplicated for equal
    /// parameters, or is given to a model that reads none.
    #[test]
    fn tables_follow_the_materials_shared_by_equal_parameters() {
        let ms = [
            Material::DEFAULT,
            plastic(0.3, 1.5),
            plastic(0.0, 1.5),
            plastic(0.3, 1.5),
            plastic(0.1, 1.33),
        ];
        let (out, texels) = materials_texels(&ms);
        assert_eq!(out[0].table, NO_TABLE);
        assert_eq!(out[2].table, NO_TABLE);
        assert_eq!(out[1].table, (ms.len() * MATERIAL_TEXELS) as u32);
        assert_eq!(out[3].table, out[1].table);
        assert_eq!(out[4].table, out[1].table + TABLE_TEXELS as u32);
        assert_eq!(texels.len(), ms.len() * MATERIAL_TEXELS + 2 * TABLE_TEXELS);
        let read =
            |m: &Material| PlasticTable::from_texels(&texels[m.table as usize..][..TABLE_TEXELS]);
        assert_eq!(
            read(&out[1]),
            PlasticTable::compute(Distribution::Ggx, 0.3, 1.5)
        );
        assert_eq!(
            read(&out[4]),
            PlasticTable::compute(Distribution::Ggx, 0.1, 1.33)
        );
        let records: &[Material] = bytemuck::cast_slice(&texels[..ms.len() * MATERIAL_TEXELS]);
        assert_eq!(records, &out[..]);
    }
}
