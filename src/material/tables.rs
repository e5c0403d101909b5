//! The `scene.materials` resource's contents: the materials' 128-byte records, then the texels
//! (16 bytes each) of the tables their models precompute (`Model::table`), each material's
//! `table` the texel index of its own. Materials of one model with equal table keys share a
//! table: rough plastics of equal (distribution, alpha, ior), every metallic-roughness
//! material; a table is present only when a material reads it.

use super::model::Table;
use super::record::{Material, NO_TABLE};
use super::registry::{MATERIAL_KIND_BITS, model};
use std::collections::{BTreeMap, HashMap};

/// Texels (16 bytes) a material record takes.
const MATERIAL_TEXELS: usize = size_of::<Material>() / 16;

/// The table `m` reads, and its key, if its model gives it one.
fn table_of(m: &Material) -> Option<(Table, [u32; 3])> {
    let table = model(m.kind)?.table?;
    Some((table, (table.key)(m)?))
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
    let mut shared: HashMap<(u32, [u32; 3]), u32> = HashMap::new();
    let start = materials.len() * MATERIAL_TEXELS;
    for m in &mut out {
        m.table = NO_TABLE;
        let Some((table, key)) = table_of(m) else {
            continue;
        };
        m.table = *shared.entry((m.kind, key)).or_insert_with(|| {
            let index = (start + tables.len()) as u32;
            tables.extend((table.texels)(m));
            index
        });
    }
    for (i, m) in out.iter().enumerate() {
        let mut record = *m;
        assert!(
            record.kind < 1 << MATERIAL_KIND_BITS,
            "a model's kind fits its bits"
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
    use crate::bsdf::microfacet::Distribution;
    use crate::material::metallic_roughness::table::{
        SpecularAlbedoTable, TABLE_TEXELS as ALBEDO_TEXELS,
    };
    use crate::material::plastic::tables::{PlasticTable, TABLE_TEXELS};
    use crate::material::registry::{MATERIAL_METALLIC_ROUGHNESS, MATERIAL_PLASTIC};

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

    /// Fails when the metallic-roughness albedo table is given to each such material apart,
    /// or to a scene without one.
    #[test]
    fn one_albedo_table_serves_every_metallic_roughness_material() {
        let mr = |alpha| Material {
            kind: MATERIAL_METALLIC_ROUGHNESS,
            alpha,
            ..Material::DEFAULT
        };
        let ms = [mr(0.1), Material::DEFAULT, mr(0.5)];
        let (out, texels) = materials_texels(&ms);
        let start = (ms.len() * MATERIAL_TEXELS) as u32;
        assert_eq!(
            (out[0].table, out[1].table, out[2].table),
            (start, NO_TABLE, start)
        );
        assert_eq!(texels.len(), ms.len() * MATERIAL_TEXELS + ALBEDO_TEXELS);
        assert_eq!(
            texels[start as usize..],
            SpecularAlbedoTable::shared().texels()[..]
        );
        let (_, without) = materials_texels(&[Material::DEFAULT]);
        assert_eq!(without.len(), MATERIAL_TEXELS);
    }
}
