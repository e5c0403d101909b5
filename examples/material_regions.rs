//! The material regions tests/materials_accuracy.rs measures, as JSON for scripts that compare
//! images outside the Rust tests (scripts/cycles-compare): by material name, the indices
//! (y * width + x, row 0 at the top) of the pixels whose 3 x 3 grid of rays across the pixel's
//! footprint all hit triangles of that one material (the CPU twin of the BVH).
//!
//! `cargo run --release --example material_regions -- SCENE.ron [SIZE] > regions.json`
//! (default SIZE 128: a SIZE x SIZE image). Keep in step with `material_regions` in
//! tests/materials_accuracy.rs.

use passgraph::scene::{Ray, load_scene};
use std::collections::BTreeMap;
use std::path::Path;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(scene_path) = args.first() else {
        eprintln!("usage: material_regions SCENE.ron [SIZE]");
        std::process::exit(2);
    };
    let size: u32 = match args.get(1).map(|s| s.parse()) {
        None => 128,
        Some(Ok(n)) if n > 0 => n,
        Some(_) => {
            eprintln!("error: SIZE must be a positive integer");
            std::process::exit(2);
        }
    };
    let scene = load_scene(Path::new(scene_path)).unwrap_or_else(|e| {
        eprintln!("error: {e}");
        std::process::exit(1);
    });
    let gpu = scene.to_gpu();
    let camera = scene.camera.to_gpu(size, size);
    let mut regions: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    for y in 0..size {
        for x in 0..size {
            let mut material = None;
            let mut uniform = true;
            for jy in [0.05, 0.5, 0.95] {
                for jx in [0.05, 0.5, 0.95] {
                    let dir = camera.ray_direction(size, size, x as f32 + jx, y as f32 + jy);
                    let ray = Ray {
                        origin: camera.eye.into(),
                        dir,
                    };
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
            if let (true, Some(Some(m))) = (uniform, material) {
                let name = scene.mesh.material_names[m as usize].clone();
                regions
                    .entry(name)
                    .or_default()
                    .push((y * size + x) as usize);
            }
        }
    }
    let body: Vec<String> = regions
        .iter()
        .map(|(name, pixels)| {
            let list: Vec<String> = pixels.iter().map(|p| p.to_string()).collect();
            format!("  {:?}: [{}]", name, list.join(", "))
        })
        .collect();
    println!("{{\n{}\n}}", body.join(",\n"));
}
