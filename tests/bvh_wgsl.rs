//! `shaders/lib/bvh.wgsl`: it validates with naga through the include step, and on a GPU
//! (lavapipe in CI) it answers as the CPU traversal in `scene::intersect` does (the same hits,
//! t within rounding; see `compare`). The GPU harness lives in tests/common/bvh_gpu.rs, shared
//! with the robustness suites.

mod common;

use common::bvh_gpu::{Query, check_shader, compare, gpu, run_on_gpu};
use common::geometry::Rng;
use common::root;
use glam::Vec3;
use passgraph::graph::format::{TextureDim, TextureFormat};
use passgraph::graph::interface::{Access, BindingKind};
use passgraph::graph::reflect::reflect;
use passgraph::scene::{DEFAULT_SCENE, Mesh, SceneGpu, load_scene};
use std::path::Path;

#[test]
fn bvh_wgsl_validates_with_naga_when_included_after_scene_wgsl() {
    let source = check_shader();
    let interface = reflect(&source, "main").unwrap_or_else(|e| panic!("{e}"));
    let names: Vec<&str> = interface.bindings.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(names, ["triangles", "bvh", "queries", "answers"]);
    // The scene as texel views (read-only Rgba32Uint storage textures).
    for b in &interface.bindings[..2] {
        assert_eq!(
            b.kind,
            BindingKind::StorageTexture {
                access: Access::Read,
                format: TextureFormat::Rgba32Uint,
                dim: TextureDim::D2,
            },
            "{}",
            b.name
        );
    }
    let overrides: Vec<&str> = interface
        .overrides
        .iter()
        .map(|o| o.name.as_str())
        .collect();
    assert!(overrides.contains(&"scene_node_count"), "{overrides:?}");
    assert!(overrides.contains(&"scene_triangle_count"), "{overrides:?}");
}

#[test]
fn bvh_wgsl_defines_only_its_documented_names() {
    // Every module-scope name except the public four carries the bvh_/Bvh/BVH_ prefix, so
    // including passes cannot collide with helpers.
    let text = std::fs::read_to_string(root().join("shaders/lib/bvh.wgsl")).unwrap();
    for line in text.lines() {
        for keyword in ["fn ", "struct ", "const "] {
            if let Some(rest) = line.strip_prefix(keyword) {
                let name: String = rest
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                let public =
                    ["Hit", "closest_hit", "any_hit", "shadow_hit"].contains(&name.as_str());
                let prefixed =
                    name.starts_with("bvh_") || name.starts_with("Bvh") || name.starts_with("BVH_");
                assert!(public || prefixed, "unprefixed module-scope name '{name}'");
            }
        }
    }
}

/// Rays for a scene within `[lo, hi]`: aimed inside triangles, random, and axis-parallel with
/// signed zeros. (Rays aimed exactly at a silhouette vertex or edge may legitimately be
/// decided differently by the GPU's rounding: those are tested on the closed cube only, where
/// every ray must hit and the exit point is unique.)
fn queries_for(scene: &SceneGpu, lo: Vec3, hi: Vec3, seed: u64) -> Vec<Query> {
    let mut rng = Rng(seed);
    let centre = (lo + hi) * 0.5;
    let extent = (hi - lo).max_element();
    let mut queries = Vec::new();
    let mut push = |origin: Vec3, dir: Vec3, tmin: f32, tmax: f32| {
        queries.push(Query {
            origin: origin.into(),
            tmin,
            dir: dir.into(),
            tmax,
        });
    };
    for t in scene.triangles.iter().take(1500) {
        let [p0, p1, p2] = t.vertices();
        let (a, b) = (0.05 + 0.45 * rng.unit(), 0.05 + 0.45 * rng.unit());
        let target = p0 + a * (p1 - p0) + b * (p2 - p0);
        let origin = centre + rng.vec(-0.3, 0.3) * extent;
        push(origin, target - origin, 0.0, f32::MAX);
    }
    for i in 0..1500 {
        let origin = lo + (hi - lo) * rng.vec(-0.2, 1.2);
        let mut dir = rng.vec(-1.0, 1.0);
        if i % 3 == 0 {
            let axis = i % 9 / 3;
            dir = Vec3::select(
                Vec3::AXES[axis].cmpeq(Vec3::ZERO),
                Vec3::splat(if i % 2 == 0 { 0.0 } else { -0.0 }),
                dir,
            );
        }
        if dir == Vec3::ZERO {
            dir = Vec3::X;
        }
        let tmax = if i % 4 == 0 {
            extent * rng.unit()
        } else {
            f32::MAX
        };
        push(origin, dir, 0.0, tmax);
    }
    queries
}

fn grid_cube() -> Vec<[Vec3; 3]> {
    // A closed box whose faces are 3 x 3 grids: many shared edges and vertices.
    let mut triangles = Vec::new();
    let c = |i: usize| -1.0 + 2.0 * i as f32 / 3.0;
    for axis in 0..3 {
        for side in [-1.0f32, 1.0] {
            let p = |i: usize, j: usize| {
                let mut v = [0.0; 3];
                v[axis] = side;
                v[(axis + 1) % 3] = c(i);
                v[(axis + 2) % 3] = c(j);
                Vec3::from(v)
            };
            for i in 0..3 {
                for j in 0..3 {
                    triangles.push([p(i, j), p(i + 1, j), p(i + 1, j + 1)]);
                    triangles.push([p(i, j), p(i + 1, j + 1), p(i, j + 1)]);
                }
            }
        }
    }
    triangles
}

#[test]
fn bvh_wgsl_on_the_gpu_matches_the_cpu_traversal() {
    let gpu = gpu();
    let cornell = load_scene(&root().join(DEFAULT_SCENE)).unwrap().to_gpu();
    let mut rng = Rng(5);
    let soup: Vec<[Vec3; 3]> = (0..3000)
        .map(|_| {
            let c = rng.vec(-10.0, 10.0);
            [
                c + rng.vec(-1.0, 1.0),
                c + rng.vec(-1.0, 1.0),
                c + rng.vec(-1.0, 1.0),
            ]
        })
        .collect();
    let soup = SceneGpu::build(&Mesh::from_triangles("soup", &soup));
    let cube = SceneGpu::build(&Mesh::from_triangles("cube", &grid_cube()));
    let scenes = [
        ("cornell", &cornell, Vec3::ZERO, Vec3::splat(556.0)),
        ("soup", &soup, Vec3::splat(-10.0), Vec3::splat(10.0)),
        ("cube", &cube, Vec3::splat(-1.0), Vec3::splat(1.0)),
    ];
    for (seed, (name, scene, lo, hi)) in scenes.into_iter().enumerate() {
        let queries = queries_for(scene, lo, hi, seed as u64);
        let answers = run_on_gpu(&gpu, scene, &queries);
        compare(name, scene, &queries, &answers, false);
    }

    // From inside the closed cube, through its shared vertices and edges: nothing leaks.
    let mut queries = Vec::new();
    for origin in [Vec3::ZERO, Vec3::new(0.3, -0.2, 0.1)] {
        for t in &cube.triangles {
            for k in 0..3 {
                let [a, b] = [t.vertices()[k], t.vertices()[(k + 1) % 3]];
                for target in [a, (a + b) * 0.5] {
                    queries.push(Query {
                        origin: origin.into(),
                        tmin: 0.0,
                        dir: (target - origin).into(),
                        tmax: f32::MAX,
                    });
                }
            }
        }
    }
    let answers = run_on_gpu(&gpu, &cube, &queries);
    assert!(
        answers.iter().all(|a| a.triangle != u32::MAX && a.any == 1),
        "a ray leaked out of the cube on the GPU"
    );
    compare("cube from inside", &cube, &queries, &answers, true);
}

#[test]
fn bvh_wgsl_terminates_on_a_zero_padded_node_buffer() {
    let gpu = gpu();
    // What the executor binds for a scene whose buffers are empty: one zeroed element each.
    let empty = SceneGpu::build(&Mesh::from_triangles(Path::new("empty"), &[]));
    let padded = SceneGpu {
        triangles: vec![Default::default()],
        nodes: vec![Default::default()],
        ..empty
    };
    let queries = [
        Query {
            origin: [0.0; 3],
            tmin: 0.0,
            dir: [1.0, 0.0, 0.0],
            tmax: f32::MAX,
        },
        Query {
            origin: [-1.0, 0.0, 0.0],
            tmin: 0.0,
            dir: [1.0, -0.0, 0.0],
            tmax: 10.0,
        },
    ];
    for a in run_on_gpu(&gpu, &padded, &queries) {
        assert_eq!((a.triangle, a.any), (u32::MAX, 0));
    }
}
