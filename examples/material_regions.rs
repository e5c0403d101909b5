//! The material regions tests/materials_accuracy.rs measures, as JSON for scripts that compare
//! images outside the Rust tests (scripts/cycles-compare): by material name, the indices
//! (y * width + x, row 0 at the top) of the pixels whose 3 x 3 grid of rays across the pixel's
//! footprint all hit triangles of that one material (the CPU twin of the BVH).
//!
//! `cargo run --release --example material_regions -- SCENE.ron [SIZE] > regions.json`
//! (default SIZE 128: a SIZE x SIZE image). The regions are `passgraph::scene::regions`'s.

use passgraph::scene::load_scene;
use passgraph::scene::regions::material_regions;
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
    let regions = material_regions(&scene, size, size);
    let body: Vec<String> = regions
        .iter()
        .map(|(name, pixels)| {
            let list: Vec<String> = pixels.iter().map(|p| p.to_string()).collect();
            format!("  {:?}: [{}]", name, list.join(", "))
        })
        .collect();
    println!("{{\n{}\n}}", body.join(",\n"));
}
