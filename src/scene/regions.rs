//! Image regions by material: which pixels of a `width` x `height` render of a scene see one
//! material only. What per-material accuracy is measured over (tests/materials_accuracy.rs,
//! examples/material_regions.rs for scripts).

use super::description::Scene;
use super::intersect::Ray;
use std::collections::BTreeMap;

/// The region of pixels that see no surface, only the environment.
pub const ENVIRONMENT_REGION: &str = "(environment)";

/// Pixel indices (y * width + x, row 0 at the top) by material name: a pixel counts when a
/// 3 x 3 grid of rays across its footprint (the CPU twin of the BVH) all hit triangles of that
/// one material, so edges, where a pixel mixes materials, are left out. Pixels whose rays all
/// leave the scene are under [`ENVIRONMENT_REGION`].
pub fn material_regions(scene: &Scene, width: u32, height: u32) -> BTreeMap<String, Vec<usize>> {
    let gpu = scene.to_gpu();
    let mut regions: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    for y in 0..height {
        for x in 0..width {
            let mut material = None;
            let mut uniform = true;
            for jy in [0.05, 0.5, 0.95] {
                for jx in [0.05, 0.5, 0.95] {
                    // Through the lens's centre: a region is what the pinhole sees sharply.
                    let (origin, dir) = scene.camera.ray(
                        width,
                        height,
                        x as f32 + jx,
                        y as f32 + jy,
                        glam::Vec2::splat(0.5),
                    );
                    let ray = Ray { origin, dir };
                    let m = gpu
                        .closest_hit(&ray, 0.0, f32::MAX)
                        .map(|h| gpu.triangles[h.triangle as usize].material);
                    if material.is_none() {
                        material = Some(m);
                    } else if material != Some(m) {
                        uniform = false;
                    }
                }
            }
            let name = match (uniform, material) {
                (true, Some(Some(m))) => scene.mesh.material_names[m as usize].clone(),
                (true, Some(None)) => ENVIRONMENT_REGION.to_string(),
                _ => continue,
            };
            regions
                .entry(name)
                .or_default()
                .push((y * width + x) as usize);
        }
    }
    regions
}
