//! How long reading a scene takes, alternating files so that the machine's drift hits each
//! alike: per round, each scene is loaded (file parsing, materials and textures: what
//! `load_scene` does, no BVH, no device), and the median and spread of the rounds printed.
//!
//! `cargo run --release --example load_time -- [--rounds N] A.ron B.glb ...` (default 5 rounds)

use std::path::PathBuf;
use std::time::Instant;

fn main() {
    let mut rounds = 5usize;
    let mut scenes: Vec<PathBuf> = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        if a == "--rounds" {
            match args.next().and_then(|n| n.parse().ok()) {
                Some(n) if n > 0 => rounds = n,
                _ => {
                    eprintln!("error: --rounds takes a positive count");
                    std::process::exit(2);
                }
            }
        } else {
            scenes.push(a.into());
        }
    }
    if scenes.is_empty() {
        eprintln!("usage: load_time [--rounds N] SCENE...");
        std::process::exit(2);
    }
    let mut seconds = vec![Vec::new(); scenes.len()];
    let mut triangles = vec![0usize; scenes.len()];
    for _ in 0..rounds {
        for (k, path) in scenes.iter().enumerate() {
            let start = Instant::now();
            match passgraph::scene::load_scene(path) {
                Ok(scene) => triangles[k] = scene.mesh.triangles.len(),
                Err(e) => {
                    eprintln!("error: {e}");
                    std::process::exit(1);
                }
            }
            seconds[k].push(start.elapsed().as_secs_f64());
        }
    }
    println!("scene | triangles | median s | min s | max s ({rounds} rounds, alternating)");
    for (k, path) in scenes.iter().enumerate() {
        let s = &mut seconds[k];
        s.sort_by(f64::total_cmp);
        println!(
            "{} | {} | {:.3} | {:.3} | {:.3}",
            path.display(),
            triangles[k],
            s[s.len() / 2],
            s[0],
            s[s.len() - 1]
        );
    }
}
