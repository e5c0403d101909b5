//! How fast the BVH builds and how good the tree is: per round, `Bvh::build` over a scene's
//! triangles (no hull test, no device), then the median and spread of the rounds' build times,
//! the build rate, the node count and the tree's SAH cost (the expected node visits and
//! triangle tests of a ray through the root box, in units of one triangle test, with the build's
//! own node cost; a ray-independent quality figure beside `traversal_stats`' counts), and a
//! fingerprint of the tree (a builder change meant to keep the tree must keep it).
//!
//! `cargo run --release --example bvh_build -- [--rounds N] [--threads T] SCENE`
//! (default 5 rounds, rayon's default thread count)

use glam::Vec3;
use passgraph::scene::bvh::Bvh;
use std::time::Instant;

fn main() {
    let mut rounds = 5usize;
    let mut threads = 0usize;
    let mut scene = None;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut count = |what: &str| match args.next().and_then(|n| n.parse().ok()) {
            Some(n) if n > 0 => n,
            _ => {
                eprintln!("error: {what} takes a positive count");
                std::process::exit(2);
            }
        };
        match a.as_str() {
            "--rounds" => rounds = count("--rounds"),
            "--threads" => threads = count("--threads"),
            _ => scene = Some(std::path::PathBuf::from(a)),
        }
    }
    let Some(scene) = scene else {
        eprintln!("usage: bvh_build [--rounds N] [--threads T] SCENE");
        std::process::exit(2);
    };
    let scene = match passgraph::scene::load_scene(&scene) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    };
    let triangles: Vec<[Vec3; 3]> = scene.mesh.triangles.iter().map(|t| t.vertices).collect();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool");
    let mut ms = Vec::new();
    let mut bvh = None;
    for _ in 0..rounds {
        let start = Instant::now();
        let built = pool.install(|| Bvh::build(&triangles));
        ms.push(start.elapsed().as_secs_f64() * 1e3);
        bvh = Some(built);
    }
    let bvh = bvh.expect("one round at least");
    ms.sort_by(f64::total_cmp);
    let median = ms[ms.len() / 2];
    println!(
        "{} triangles, {} threads: build {:.1} ms median ({:.1}-{:.1}), {:.2} M triangles/s; \
         {} nodes ({:.2} per triangle), depth {}; SAH cost {:.2}; tree {:016x}",
        triangles.len(),
        pool.current_num_threads(),
        median,
        ms[0],
        ms[ms.len() - 1],
        triangles.len() as f64 / median / 1e3,
        bvh.stats.node_count,
        bvh.stats.node_count as f64 / triangles.len() as f64,
        bvh.stats.max_depth,
        passgraph::scene::bvh::sah_cost(&bvh),
        fingerprint(&bvh),
    );
}

/// FNV-1a over the nodes' bytes and the triangle order: equal for two builds of one mesh
/// exactly when they made the same tree, so a change to the builder that should not change the
/// tree can be checked on any scene.
fn fingerprint(bvh: &Bvh) -> u64 {
    let bytes = bytemuck::cast_slice::<_, u8>(&bvh.nodes)
        .iter()
        .chain(bytemuck::cast_slice::<_, u8>(&bvh.order));
    bytes.fold(0xcbf29ce484222325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x100000001b3)
    })
}
