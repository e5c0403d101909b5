//! Rendering hard cases on the GPU (lavapipe in CI), issue 4: self-intersection at large
//! offsets and scales, emitters seen from behind and grazing light, the near-coplanar Cornell
//! light, cameras inside geometry or facing nothing, and empty scenes. Figures are printed
//! (`cargo test --test robust_render -- --nocapture`).

mod common;

use common::geometry::{Mtl, ObjWriter, Rng};
use common::render::{PATHTRACER, assert_clean, image, mean, render, render_scene, settings};
use common::root;
use glam::Vec3;
use passgraph::bench::metrics::image_error;
use passgraph::render::session::Session;
use passgraph::scene::camera::project;
use passgraph::scene::{CameraDesc, Ray, load_scene};
use std::path::{Path, PathBuf};

const CORNELL: &str = "scenes/cornell/scene.ron";
/// The Cornell box's size (mm): the scale of "a tiny distance".
const CORNELL_EXTENT: f64 = 556.0;

/// Writes the Cornell box with every vertex and the camera mapped by p -> p * scale + offset
/// (in f64, then rounded once to f32 by the loader), and optionally with its OBJ text edited.
fn cornell_variant(
    dir: &Path,
    scale: f64,
    offset: f64,
    edit: impl Fn(String) -> String,
) -> PathBuf {
    let cornell = root().join("scenes/cornell");
    let map = |v: f64| v * scale + offset;
    let obj: String = std::fs::read_to_string(cornell.join("cornell.obj"))
        .unwrap()
        .lines()
        .map(|line| match line.strip_prefix("v ") {
            Some(rest) => {
                let c: Vec<f64> = rest
                    .split_whitespace()
                    .map(|w| w.parse().unwrap())
                    .collect();
                format!("v {} {} {}\n", map(c[0]), map(c[1]), map(c[2]))
            }
            None => format!("{line}\n"),
        })
        .collect();
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(dir.join("cornell.obj"), edit(obj)).unwrap();
    std::fs::copy(cornell.join("cornell.mtl"), dir.join("cornell.mtl")).unwrap();
    let scene = format!(
        "Scene(\n    mesh: \"cornell.obj\",\n    camera: Camera(eye: ({}, {}, {}), target: ({}, {}, {}), up: (0, 1, 0), fov_y: 39.3077),\n)\n",
        map(278.0),
        map(273.0),
        map(-800.0),
        map(278.0),
        map(273.0),
        map(0.0)
    );
    let path = dir.join("scene.ron");
    std::fs::write(&path, scene).unwrap();
    path
}

/// The census of robust_acne.wgsl: per kind of ray (shadow rays from primary hits, bounce
/// rays, shadow rays from the bounce's hit), (cast, blocked, blocked nearer than `near`,
/// blocked by the plane the ray starts on).
#[derive(Debug)]
struct Census {
    shadow: [u32; 4],
    bounce: [u32; 4],
    second_shadow: [u32; 4],
    /// Shadow rays (from primary hits, from bounce hits) blocked by the light they aim at.
    blocked_by_target: [u32; 2],
}

fn acne_census(scene: &Path, size: u32, seed: u32, frames: u32, near: f64) -> Census {
    let s = settings(
        "tests/fixtures/graphs/robust_acne.ron",
        scene,
        size,
        seed,
        &[format!("acne.near={near:e}").as_str()],
    );
    let session = render(&s, frames);
    let counts: Vec<u32> = bytemuck::pod_collect_to_vec(&session.read_resource("acne").unwrap());
    let kind = |k: usize| [counts[k], counts[k + 1], counts[k + 2], counts[k + 3]];
    Census {
        shadow: kind(0),
        bounce: kind(4),
        second_shadow: kind(8),
        blocked_by_target: [counts[12], counts[13]],
    }
}

#[test]
fn cornell_box_translated_by_1e5_and_scaled_renders_alike_without_shadow_acne() {
    const SIZE: u32 = 64;
    const FRAMES: u32 = 16;
    const SEED: u32 = 11;
    let dir = tempfile::tempdir().unwrap();
    let variants = [
        ("original", 1.0, 0.0),
        ("translated by 1e5", 1.0, 1e5),
        ("scaled by 1e-3", 1e-3, 0.0),
        ("scaled by 1e3", 1e3, 0.0),
    ];
    let mut original_mean = None;
    for (name, scale, offset) in variants {
        let scene = cornell_variant(&dir.path().join(name), scale, offset, |t| t);
        let session = render_scene(&scene, SIZE, SEED, FRAMES);
        assert_clean(&session, FRAMES, name);
        let m = mean(&image(&session, "sum"));
        let reference = *original_mean.get_or_insert(m);
        let relative = (m - reference).abs() / reference;
        // "A tiny distance": 1e-4 of the scene's size. A ray blocked by its own surface is
        // blocked within a few ulps of the coordinates divided by the cosine, far below it.
        let near = 1e-4 * CORNELL_EXTENT * scale;
        let census = acne_census(&scene, SIZE, SEED, FRAMES, near);
        eprintln!(
            "{name}: mean {m:.6} ({:.3} % from the original); rays (cast, blocked, blocked \
             within {near:.2e}, blocked by their own plane): shadow {:?}, bounce {:?}, shadow \
             at the bounce {:?}; shadow rays blocked by their own light {:?}",
            relative * 100.0,
            census.shadow,
            census.bounce,
            census.second_shadow,
            census.blocked_by_target
        );
        // The same seed draws the same samples in every variant, so only the geometry's
        // rounding differs: 1 % (the bound) is far above it and far below acne.
        assert!(relative < 0.01, "{name}: mean {m} vs {reference}");
        for (kind, c) in [
            ("shadow", census.shadow),
            ("bounce", census.bounce),
            ("second shadow", census.second_shadow),
        ] {
            assert!(
                c[0] > 10_000,
                "{name}: too few {kind} rays ({}) to tell",
                c[0]
            );
            // Acne: a ray leaving a plane cannot meet that plane again, so any such block is
            // self-intersection.
            assert_eq!(c[3], 0, "{name}: {kind} rays hit their own surface");
        }
        // A shadow ray ends short of its light sample moved off the light by offset_ray's
        // 16 ulps, more than the few ulps the sample point is rounded by: the light can never
        // occlude itself.
        assert_eq!(
            census.blocked_by_target,
            [0, 0],
            "{name}: a light shadowed itself"
        );
    }
}

/// Pixel-space convex polygon (counter-clockwise or clockwise) for "fully inside/outside"
/// tests: signed distances of a point to each edge line.
struct Polygon(Vec<(f32, f32)>);

impl Polygon {
    /// The screen-space outline of world `points` for `camera` on a `size`² image.
    fn project(camera: &CameraDesc, size: u32, points: &[Vec3]) -> Polygon {
        let gpu = camera.to_gpu(size, size);
        Polygon(
            points
                .iter()
                .map(|&p| {
                    let (sx, sy) = project(&gpu, p).expect("in front of the camera");
                    (
                        (sx + 1.0) * 0.5 * size as f32,
                        (1.0 - sy) * 0.5 * size as f32,
                    )
                })
                .collect(),
        )
    }

    /// The signed distance of (x, y) to each edge, positive inside.
    fn distances(&self, x: f32, y: f32) -> Vec<f32> {
        let n = self.0.len();
        let area: f32 = (0..n)
            .map(|i| {
                let (a, b) = (self.0[i], self.0[(i + 1) % n]);
                a.0 * b.1 - b.0 * a.1
            })
            .sum();
        let orientation = area.signum();
        (0..n)
            .map(|i| {
                let (a, b) = (self.0[i], self.0[(i + 1) % n]);
                let (ex, ey) = (b.0 - a.0, b.1 - a.1);
                orientation * (ex * (y - a.1) - ey * (x - a.0)) / (ex * ex + ey * ey).sqrt()
            })
            .collect()
    }

    /// The pixel square around centre (x, y) lies inside, `margin` pixels from every edge.
    fn contains(&self, x: f32, y: f32, margin: f32) -> bool {
        self.distances(x, y).iter().all(|&d| d >= margin)
    }

    /// The pixel lies beyond one edge by `margin`: no part of it is inside.
    fn excludes(&self, x: f32, y: f32, margin: f32) -> bool {
        self.distances(x, y).iter().any(|&d| d <= -margin)
    }
}

/// The Cornell ceiling cut in a 3 x 3 grid around the light's rectangle (shared vertices, no
/// T-junctions), the centre cell left open, with the light flush in it at the ceiling's height.
fn light_flush_in_a_hole(obj: String) -> String {
    // Drop the ceiling's face (its vertices stay, unused) and lift the light to 548.8.
    assert_eq!(obj.matches("\nf 5 6 7 8\n").count(), 1);
    let mut lifted = 0;
    let mut obj: String = obj
        .replace("\nf 5 6 7 8\n", "\n")
        .lines()
        .map(|line| {
            if line.starts_with("v ") && line.contains(" 548.7 ") {
                lifted += 1;
                format!("{}\n", line.replace(" 548.7 ", " 548.8 "))
            } else {
                format!("{line}\n")
            }
        })
        .collect();
    assert_eq!(lifted, 4, "the light's four vertices");
    obj.push_str("\no ceiling_with_hole\nusemtl white\n");
    let xs = [0.0, 213.0, 343.0, 556.0];
    let zs = [0.0, 227.0, 332.0, 559.2];
    for i in 0..3 {
        for j in 0..3 {
            if (i, j) == (1, 1) {
                continue;
            }
            let (x0, x1, z0, z1) = (xs[i], xs[i + 1], zs[j], zs[j + 1]);
            // The same order as the original ceiling: counter-clockwise seen from below.
            obj.push_str(&format!(
                "v {x1} 548.8 {z0}\nv {x1} 548.8 {z1}\nv {x0} 548.8 {z1}\nv {x0} 548.8 {z0}\nf -4 -3 -2 -1\n"
            ));
        }
    }
    obj
}

#[test]
fn cornell_light_under_the_ceiling_shows_no_leak_or_z_fighting_against_a_flush_light() {
    // 128 pixels across: the light, seen almost edge-on, is then 22 x 4.5 pixels.
    const SIZE: u32 = 128;
    const FRAMES: u32 = 16;
    let dir = tempfile::tempdir().unwrap();
    let shipped = root().join(CORNELL);
    let flush = cornell_variant(&dir.path().join("flush"), 1.0, 0.0, light_flush_in_a_hole);
    let ke = [18.387f32, 13.9873, 6.75357];

    let ship_1 = render_scene(&shipped, SIZE, 1, FRAMES);
    let ship_2 = render_scene(&shipped, SIZE, 2, FRAMES);
    let flush_1 = render_scene(&flush, SIZE, 1, FRAMES);
    let flush_2 = render_scene(&flush, SIZE, 2, FRAMES);
    for (name, s) in [("shipped", &ship_1), ("flush", &flush_1)] {
        assert_clean(s, FRAMES, name);
        // The light's two triangles form one parallelogram light.
        assert_eq!(s.scene().light_count, 1);
    }

    // Z-fighting: every pixel wholly inside the light's outline sees its front face on every
    // sample (L0 exactly Ke), every pixel of the ceiling wholly outside it never does (L0
    // exactly 0). Leaks: the ceiling is behind the light's plane or in it, so it receives no
    // direct light at all (exactly 0), in both scenes.
    let camera = load_scene(&shipped).unwrap().camera;
    let corners = |y: f32| {
        [
            (343.0, 227.0),
            (343.0, 332.0),
            (213.0, 332.0),
            (213.0, 227.0),
        ]
        .map(|(x, z)| Vec3::new(x, y, z))
    };
    let ceiling = Polygon::project(
        &camera,
        SIZE,
        &[(556.0, 0.0), (556.0, 559.2), (0.0, 559.2), (0.0, 0.0)]
            .map(|(x, z)| Vec3::new(x, 548.8, z)),
    );
    for (name, s, y) in [("shipped", &ship_1, 548.7), ("flush", &flush_1, 548.8)] {
        let light = Polygon::project(&camera, SIZE, &corners(y));
        let l0 = image(s, "l0");
        let direct = image(s, "direct");
        let (mut inside, mut outside) = (0, 0);
        for py in 0..SIZE {
            for px in 0..SIZE {
                let (x, y) = (px as f32 + 0.5, py as f32 + 0.5);
                let i = (py * SIZE + px) as usize;
                // The margin covers the whole jittered pixel square (half-diagonal 0.71) and
                // the 0.1 mm between the two lights' outlines (0.01 pixel).
                if light.contains(x, y, 0.75) {
                    assert_eq!(
                        l0.pixels[i], ke,
                        "{name}: pixel ({px}, {py}) inside the light"
                    );
                    inside += 1;
                } else if light.excludes(x, y, 0.75) && ceiling.contains(x, y, 0.75) {
                    assert_eq!(
                        l0.pixels[i], [0.0; 3],
                        "{name}: ceiling pixel ({px}, {py}) sees light"
                    );
                    assert_eq!(
                        direct.pixels[i], [0.0; 3],
                        "{name}: ceiling pixel ({px}, {py}) is lit"
                    );
                    outside += 1;
                }
            }
        }
        eprintln!(
            "{name}: {inside} pixels inside the light all exactly Ke; {outside} ceiling pixels with no L0 and no direct light"
        );
        assert!(inside > 30 && outside > 1000, "too few pixels to tell");
    }

    // The whole image: the two scenes agree within the noise. For independent renders a, b,
    // E[MSE(a, b)] = var(a) + var(b) + bias^2, so a difference between the scenes would show as
    // MSE(shipped 1, flush 2) exceeding MSE(shipped 1, shipped 2), beyond five standard errors
    // of both (the bound of tests/render_accuracy.rs).
    for c in ["sum", "l0+direct", "indirect"] {
        let a = image(&ship_1, c);
        let between_scenes = image_error(&a, &image(&flush_2, c)).unwrap();
        let between_seeds = image_error(&a, &image(&ship_2, c)).unwrap();
        let bound = between_seeds.mse()
            + 5.0 * (between_scenes.mse_standard_error + between_seeds.mse_standard_error);
        eprintln!(
            "{c}: RMSE shipped vs flush {:.5}, shipped vs shipped (other seed) {:.5}, bound {:.5}",
            between_scenes.rmse,
            between_seeds.rmse,
            bound.sqrt()
        );
        assert!(
            between_scenes.mse() <= bound,
            "{c}: the scenes differ beyond the noise"
        );
    }
    // And with the same seed, where the noise cancels: the flush light is 0.1 mm farther from
    // every lit point, which changes 1/d^2 by 2 x 0.1 / d: 0.04 % at the box's typical 500 mm,
    // at most 0.2 % at the nearest points (100 mm). So 0.1 %. Not L0: lifting the light shifts
    // its outline on screen by ~0.02 pixel, which flips the odd primary sample at its edge
    // between light (Ke) and ceiling (0), about one pixel's worth of L0 per frame whichever
    // the sampler, a real difference of 0.1-1 % of L0 that the checks above bound instead.
    for c in ["direct", "indirect"] {
        let a = image(&ship_1, c);
        let same_seed = (mean(&image(&flush_1, c)) - mean(&a)).abs() / mean(&a);
        eprintln!("{c}: same seed, means {:.4} % apart", same_seed * 100.0);
        assert!(
            same_seed < 0.001,
            "{c}: means differ by {:.3} %",
            same_seed * 100.0
        );
    }
}

/// A unit emitter in the plane y = 0 facing +y, a diffuse quad in its plane beside it, a
/// diffuse floor behind it (y = -1) and, with `wall`, a diffuse wall at x = 2 above the plane
/// (lit on its -x side).
fn emitter_scene(dir: &Path, eye: Vec3, target: Vec3, wall: bool) -> PathBuf {
    let p = Vec3::new;
    let mut obj = ObjWriter::new(&[
        Mtl {
            name: "white",
            kd: [0.8; 3],
            ke: [0.0; 3],
        },
        Mtl {
            name: "light",
            kd: [0.8; 3],
            ke: [4.0, 2.0, 1.0],
        },
    ]);
    // Counter-clockwise seen from +y.
    obj.material("light").polygon(&[
        p(-1.0, 0.0, -1.0),
        p(-1.0, 0.0, 1.0),
        p(1.0, 0.0, 1.0),
        p(1.0, 0.0, -1.0),
    ]);
    obj.material("white")
        .polygon(&[
            p(-3.0, 0.0, -1.0),
            p(-3.0, 0.0, 1.0),
            p(-1.0, 0.0, 1.0),
            p(-1.0, 0.0, -1.0),
        ])
        .polygon(&[
            p(-4.0, -1.0, -4.0),
            p(-4.0, -1.0, 4.0),
            p(4.0, -1.0, 4.0),
            p(4.0, -1.0, -4.0),
        ]);
    if wall {
        obj.polygon(&[
            p(2.0, 0.0, -1.0),
            p(2.0, 1.0, -1.0),
            p(2.0, 1.0, 1.0),
            p(2.0, 0.0, 1.0),
        ]);
    }
    obj.write(dir, eye, target, Vec3::Y, 60.0)
}

#[test]
fn emitters_seen_from_behind_and_points_behind_or_grazing_them_add_nothing() {
    const SIZE: u32 = 48;
    const FRAMES: u32 = 8;
    let dir = tempfile::tempdir().unwrap();
    // From below: the emitter's back, the back of the quad in its plane and the floor behind
    // it. Nothing there can receive light from the only emitter, nor see its front.
    let below = emitter_scene(
        &dir.path().join("below"),
        Vec3::new(0.5, -0.5, -3.0),
        Vec3::new(0.0, 0.0, 0.0),
        false,
    );
    let session = render_scene(&below, SIZE, 3, FRAMES);
    assert_clean(&session, FRAMES, "from below");
    for c in ["l0", "direct", "indirect", "sum"] {
        let img = image(&session, c);
        assert!(
            img.pixels.iter().flatten().all(|&v| v == 0.0),
            "from below: {c} is not black"
        );
    }
    // From above: the emitter's front (L0 = Ke), the quad in its plane (every light sample at
    // cos = 0: grazing), the floor behind the emitter's plane and the wall's side facing away
    // (cos < 0). Direct light is exactly 0 everywhere; L0 is Ke on the emitter and 0 elsewhere.
    let above = emitter_scene(
        &dir.path().join("above"),
        Vec3::new(3.5, 2.0, -3.0),
        Vec3::new(0.0, 0.0, 0.0),
        true,
    );
    let session = render_scene(&above, SIZE, 4, FRAMES);
    assert_clean(&session, FRAMES, "from above");
    let direct = image(&session, "direct");
    assert!(
        direct.pixels.iter().flatten().all(|&v| v == 0.0),
        "from above: direct light at cos <= 0"
    );
    let l0 = image(&session, "l0");
    let ke = [4.0f32, 2.0, 1.0];
    let full = l0.pixels.iter().filter(|p| **p == ke).count();
    assert!(
        l0.pixels
            .iter()
            .all(|p| (0..3).all(|k| p[k] >= 0.0 && p[k] <= ke[k]))
    );
    let lit = image(&session, "indirect")
        .pixels
        .iter()
        .filter(|p| p[0] > 0.0)
        .count();
    eprintln!(
        "emitter from below: {} pixels, all channels exactly 0; from above: direct exactly 0 \
         everywhere, {full} pixels see the emitter's front (L0 = Ke), {lit} pixels have \
         indirect light (via the wall's lit side)",
        SIZE * SIZE
    );
    assert!(full > 50, "the emitter's front should be in view");
}

#[test]
fn camera_inside_the_tall_block_is_enclosed_so_its_black_image_is_right() {
    // tests/render_accuracy.rs renders from inside the tall block and finds every channel 0.
    // That only means something if the camera is enclosed: every ray from its eye must end on
    // the block or on the floor under it.
    let scene = load_scene(&root().join("tests/data/inside_block/scene.ron")).unwrap();
    let gpu = scene.to_gpu();
    let eye = scene.camera.eye();
    let (lo, hi) = (Vec3::new(265.0, 0.0, 247.0), Vec3::new(472.0, 330.0, 456.0));
    assert!(eye.cmpgt(lo).all() && eye.cmplt(hi).all());
    let mut rng = Rng(67);
    for _ in 0..10_000 {
        let ray = Ray {
            origin: eye,
            dir: rng.dir(),
        };
        let hit = gpu
            .closest_hit(&ray, 0.0, f32::MAX)
            .expect("a ray escaped the block");
        let p = ray.origin + hit.t * ray.dir;
        assert!(
            p.cmpge(lo - 1e-3).all() && p.cmple(hi + 1e-3).all(),
            "{ray:?} ends at {p}"
        );
    }
}

#[test]
fn camera_facing_away_from_everything_renders_exact_zeros_without_losing_samples() {
    const FRAMES: u32 = 8;
    let dir = tempfile::tempdir().unwrap();
    // The Cornell box behind the camera: every primary ray misses.
    let scene = cornell_variant(dir.path(), 1.0, 0.0, |t| t);
    let text = std::fs::read_to_string(&scene)
        .unwrap()
        .replace("target: (278, 273, 0)", "target: (278, 273, -1800)");
    std::fs::write(&scene, text).unwrap();
    let session = render_scene(&scene, 32, 5, FRAMES);
    assert_clean(&session, FRAMES, "facing away");
    let result = session.result().unwrap();
    assert!(result.iter().all(|p| p[..3] == [0.0; 3]));
    eprintln!(
        "facing away: {} pixels x {FRAMES} frames, all exactly 0, 0 dropped",
        32 * 32
    );
}

#[test]
fn empty_mesh_is_a_load_error_and_an_all_degenerate_mesh_renders_black() {
    let dir = tempfile::tempdir().unwrap();
    // No triangle at all: the loader's error, naming the mesh, through the render path.
    let empty = dir.path().join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    std::fs::write(empty.join("mesh.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
    std::fs::write(
        empty.join("scene.ron"),
        "Scene(mesh: \"mesh.obj\", camera: Camera(eye: (0, 0, -5), target: (0, 0, 0), up: (0, 1, 0), fov_y: 40))",
    )
    .unwrap();
    let error = Session::new(&settings(PATHTRACER, empty.join("scene.ron"), 16, 0, &[]))
        .err()
        .expect("an empty mesh must not load");
    let message = error.to_string();
    assert!(
        message.contains("no triangles") && message.contains("mesh.obj"),
        "{message}"
    );

    // Triangles, but none with area: nothing to hit, no light, no BVH node; the GPU gets
    // padded buffers and must still produce exact zeros.
    let p = Vec3::new;
    let mut obj = ObjWriter::new(&[Mtl {
        name: "light",
        kd: [0.5; 3],
        ke: [1.0; 3],
    }]);
    obj.material("light").triangles(&[
        [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(2.0, 0.0, 0.0)],
        [p(0.0, 1.0, 0.0); 3],
    ]);
    let scene = obj.write(
        &dir.path().join("degenerate"),
        p(0.5, 0.0, -5.0),
        p(0.5, 0.0, 0.0),
        Vec3::Y,
        40.0,
    );
    let session = render_scene(&scene, 16, 0, 4);
    assert_eq!(
        (session.scene().light_count, session.scene().nodes.len()),
        (0, 0)
    );
    assert_clean(&session, 4, "all degenerate");
    assert!(session.result().unwrap().iter().all(|p| p[..3] == [0.0; 3]));
    eprintln!("empty mesh: \"{message}\"; all-degenerate mesh: black, 0 lights, 0 BVH nodes");
}

#[test]
fn non_finite_vertex_stops_the_render_with_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("mesh.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 nan 0\nv 0 1 inf\nf 1 2 3\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("scene.ron"),
        "Scene(mesh: \"mesh.obj\", camera: Camera(eye: (0, 0, -5), target: (0, 0, 0), up: (0, 1, 0), fov_y: 40))",
    )
    .unwrap();
    let error = Session::new(&settings(
        PATHTRACER,
        dir.path().join("scene.ron"),
        16,
        0,
        &[],
    ))
    .err()
    .expect("a NaN vertex must not load");
    let message = error.to_string();
    let at = format!("{}:3", dir.path().join("mesh.obj").display());
    assert!(
        message.contains(&at) && message.contains("nan"),
        "{message}"
    );
    eprintln!("NaN vertex: \"{message}\"");
}

#[test]
fn huge_ground_triangle_seen_up_close_has_no_shadow_acne() {
    // A ground triangle 2e6 across, hit within a few units of the origin: its vertices are
    // 1e6 away, so every computation on it rounds at the scale of 1e6 (ulp 0.06), while the
    // shading points' own coordinates are small. A tilted one too, and a light above.
    let p = Vec3::new;
    let mut obj = ObjWriter::new(&[
        Mtl {
            name: "white",
            kd: [0.8; 3],
            ke: [0.0; 3],
        },
        Mtl {
            name: "light",
            kd: [0.8; 3],
            ke: [5.0; 3],
        },
    ]);
    obj.material("white").triangles(&[
        [p(-1e6, 0.0, -1e6), p(0.0, 0.0, 1e6), p(1e6, 0.0, -1e6)],
        [p(-1e6, -3e5, 1e6), p(1e6, -3e5, 1e6), p(0.0, 3e5, -1e6)],
    ]);
    obj.material("light").polygon(&[
        p(-5.0, 50.0, -5.0),
        p(5.0, 50.0, -5.0),
        p(5.0, 50.0, 5.0),
        p(-5.0, 50.0, 5.0),
    ]);
    let dir = tempfile::tempdir().unwrap();
    let scene = obj.write(
        dir.path(),
        p(0.3, 2.0, -6.0),
        p(0.0, 0.0, 0.0),
        Vec3::Y,
        60.0,
    );
    let census = acne_census(&scene, 64, 7, 8, 1e-4 * 10.0);
    eprintln!("huge ground: {census:?}");
    // Open sky: few bounces find a second surface, so only the first two kinds are many.
    assert!(census.shadow[0] > 10_000 && census.bounce[0] > 10_000);
    for (kind, c) in [
        ("shadow", census.shadow),
        ("bounce", census.bounce),
        ("second shadow", census.second_shadow),
    ] {
        assert_eq!(c[3], 0, "{kind} rays hit their own surface");
    }
}

/// The form factor from a point to the part of a parallel rectangle, h above it, between its
/// foot and the corner at (a, b) from the foot (Howell's catalogue, B-3); odd in a and in b, so
/// four of them with signs make any rectangle.
fn corner_form_factor(a: f64, b: f64, h: f64) -> f64 {
    let (a, b) = (a / h, b / h);
    let (sa, sb) = ((1.0 + a * a).sqrt(), (1.0 + b * b).sqrt());
    (a / sa * (b / sa).atan() + b / sb * (a / sb).atan()) / (2.0 * std::f64::consts::PI)
}

/// The form factor from (x, y) to the rectangle [x0, x1] x [y0, y1] parallel to it, h away.
fn rectangle_form_factor(x: f64, y: f64, [x0, x1, y0, y1]: [f64; 4], h: f64) -> f64 {
    corner_form_factor(x1 - x, y1 - y, h)
        - corner_form_factor(x0 - x, y1 - y, h)
        - corner_form_factor(x1 - x, y0 - y, h)
        + corner_form_factor(x0 - x, y0 - y, h)
}

#[test]
fn rectangle_form_factor_matches_a_quadrature_and_its_limits() {
    // Under the middle of a huge rectangle: the whole hemisphere, 1. Under an edge: half.
    let huge = [-1e9, 1e9, -1e9, 1e9];
    assert!((rectangle_form_factor(0.0, 0.0, huge, 1.0) - 1.0).abs() < 1e-8);
    assert!((rectangle_form_factor(1e9, 0.0, huge, 1.0) - 0.5).abs() < 1e-8);
    // Against a midpoint quadrature of cos cos / (pi r^2) over the rectangle.
    let rect = [0.3, 1.7, -0.4, 0.9];
    let (x, y, h) = (-0.2, 0.1, 0.35);
    let n = 2000;
    let (w, l) = (rect[1] - rect[0], rect[3] - rect[2]);
    let mut sum = 0.0;
    for i in 0..n {
        for j in 0..n {
            let dx = rect[0] + (i as f64 + 0.5) * w / n as f64 - x;
            let dy = rect[2] + (j as f64 + 0.5) * l / n as f64 - y;
            let r2 = dx * dx + dy * dy + h * h;
            sum += h * h / (std::f64::consts::PI * r2 * r2);
        }
    }
    let quadrature = sum * w * l / (n * n) as f64;
    let exact = rectangle_form_factor(x, y, rect, h);
    assert!(
        (quadrature - exact).abs() < 1e-6 * exact,
        "{quadrature} {exact}"
    );
}

/// A light 100 x 100 mm, `gap` in front of a white wall at z = `wall` and facing it; the
/// camera looks straight at the wall along the light's right edge, 1 mm across, so the left
/// half of the image is the light's back and the right half the wall beyond the edge, lit
/// through the gap only. Returns the scene and the wall's direct light per pixel, from the
/// form factor over each pixel's footprint (8 x 8 sub-pixel rays of the CPU camera; rays that
/// meet the light first give 0), in the f32-rounded geometry the renderer sees, as seen from
/// `nearer` in front of the wall (0: from the wall itself).
fn light_in_a_gap(dir: &Path, wall: f64, gap: f64, nearer: f64, size: u32) -> (PathBuf, Vec<f64>) {
    const ALBEDO: f32 = 0.8;
    let (edge, middle) = (300.0, 250.0);
    let light = [edge - 100.0, edge, middle - 50.0, middle + 50.0];
    let p = |x: f64, y: f64, z: f64| Vec3::new(x as f32, y as f32, z as f32);
    let mut obj = ObjWriter::new(&[
        Mtl {
            name: "white",
            kd: [ALBEDO; 3],
            ke: [0.0; 3],
        },
        Mtl {
            name: "light",
            kd: [ALBEDO; 3],
            ke: [1.0; 3],
        },
    ]);
    // Counter-clockwise seen from the camera (-z); the light's front faces the wall (+z).
    obj.material("white").polygon(&[
        p(edge - 300.0, middle - 300.0, wall),
        p(edge - 300.0, middle + 300.0, wall),
        p(edge + 300.0, middle + 300.0, wall),
        p(edge + 300.0, middle - 300.0, wall),
    ]);
    let light_z = wall - gap;
    obj.material("light").polygon(&[
        p(light[0], light[2], light_z),
        p(light[1], light[2], light_z),
        p(light[1], light[3], light_z),
        p(light[0], light[3], light_z),
    ]);
    let distance = 100.0f64;
    let fov = (2.0 * (0.5 / distance).atan()).to_degrees() as f32;
    let scene = obj.write(
        dir,
        p(edge, middle, wall - distance),
        p(edge, middle, wall),
        Vec3::Y,
        fov,
    );
    let camera = load_scene(&scene).unwrap().camera;
    let f32_ = |v: f64| v as f32 as f64;
    let light = light.map(f32_);
    let (wall, light_z) = (f32_(wall), f32_(light_z));
    let n = 8;
    let mut expected = Vec::with_capacity((size * size) as usize);
    for py in 0..size {
        for px in 0..size {
            let mut sum = 0.0;
            for (sx, sy) in (0..n * n).map(|k| (k % n, k / n)) {
                let fx = px as f32 + (sx as f32 + 0.5) / n as f32;
                let fy = py as f32 + (sy as f32 + 0.5) / n as f32;
                let (o, d) = camera.ray(size, size, fx, fy, glam::Vec2::ZERO);
                let (o, d) = (o.as_dvec3(), d.as_dvec3());
                let on_light = o + (light_z - o.z) / d.z * d;
                if (light[0]..=light[1]).contains(&on_light.x)
                    && (light[2]..=light[3]).contains(&on_light.y)
                {
                    continue;
                }
                let on_wall = o + (wall - o.z) / d.z * d;
                let f = rectangle_form_factor(on_wall.x, on_wall.y, light, wall - light_z - nearer);
                // Radiance rho / pi * E, E = pi * Le * F.
                sum += ALBEDO as f64 * f;
            }
            expected.push(sum / (n * n) as f64);
        }
    }
    (scene, expected)
}

/// Renders the light in a gap (16 seeds x 32 frames of `set`) and compares the wall's direct
/// light over the lit half and its outer quarter (lit at the most grazing angles) with the
/// form factor seen from `nearer` in front of the wall.
fn assert_light_in_a_gap(dir: &Path, wall: f64, nearer: f64, set: &[&str], what: &str) {
    const SIZE: u32 = 64;
    const FRAMES: u32 = 32;
    const SEEDS: u32 = 16;
    let (scene, expected) = light_in_a_gap(dir, wall, 0.2, nearer, SIZE);
    let lit: Vec<usize> = (0..SIZE as usize).filter(|&x| expected[x] > 0.0).collect();
    assert_eq!(lit.len(), SIZE as usize / 2, "wall at {wall}: {lit:?}");
    let outer: Vec<usize> = if lit[0] == 0 {
        lit[..lit.len() / 2].to_vec()
    } else {
        lit[lit.len() / 2..].to_vec()
    };
    let band_sum = |img: &[f64], cols: &[usize]| -> f64 {
        (0..SIZE as usize)
            .flat_map(|y| cols.iter().map(move |&x| y * SIZE as usize + x))
            .map(|i| img[i])
            .sum()
    };
    let mut totals = Vec::new();
    for seed in 0..SEEDS {
        let session = render(&settings(PATHTRACER, &scene, SIZE, 100 + seed, set), FRAMES);
        assert_clean(&session, FRAMES, "light in a gap");
        let direct: Vec<f64> = image(&session, "direct")
            .pixels
            .iter()
            .map(|p| p[0] as f64)
            .collect();
        let dark = (0..SIZE as usize * SIZE as usize)
            .filter(|i| expected[*i] == 0.0)
            .map(|i| direct[i])
            .fold(0.0, f64::max);
        assert_eq!(dark, 0.0, "wall at {wall}, {what}: the light's back is lit");
        totals.push([band_sum(&direct, &lit), band_sum(&direct, &outer)]);
    }
    for (k, (band, cols)) in [("lit half", &lit), ("outer quarter", &outer)]
        .into_iter()
        .enumerate()
    {
        let want = band_sum(&expected, cols);
        let n = totals.len() as f64;
        let mean = totals.iter().map(|t| t[k]).sum::<f64>() / n;
        let var = totals.iter().map(|t| (t[k] - mean).powi(2)).sum::<f64>() / (n - 1.0);
        let se = (var / n).sqrt();
        eprintln!(
            "light 0.2 mm before a wall at z = {wall}, {what}, {band}: rendered {mean:.5} +- \
             {se:.5}, form factor from {nearer:.3e} before the wall {want:.5}, ratio {:.5} \
             ({:+.1} standard errors)",
            mean / want,
            (mean - want) / se
        );
        // Six standard errors of 16 seeds (a false failure once in ~40,000 runs: Student's
        // t, 15 degrees of freedom), plus the sub-pixel quadrature's error (below 1e-5 of
        // the sum: 8 x 8 and 32 x 32 sub-pixel rays agree to 5e-6).
        let bound = 6.0 * se + 1e-5 * want;
        assert!(
            (mean - want).abs() < bound,
            "wall at {wall}, {what}, {band}: rendered {mean} against the form factor's {want} \
             (bound {bound})"
        );
    }
}

#[test]
fn a_light_0_2_mm_in_front_of_a_wall_lights_it_as_the_form_factor_says_at_any_distance_from_the_origin()
 {
    // The wall beside the light's edge sees it only at grazing angles through the gap, and the
    // light's share falls as (h / d)^2 with the distance d from the edge: the estimate must be
    // of the light as seen from the shading point itself. Taken from the ray origin moved off
    // the wall (a few hundred ulps nearer the light), it was 6.3 % too dark in all and 14 % at
    // 0.5 mm from the edge with the wall at z = 559.2 (the Cornell box's back wall), where
    // 256 ulps are 16 um of the 200 um gap. At z = 1e4 the gap is 204 ulps. (Lambertian: light
    // samples alone.)
    let dir = tempfile::tempdir().unwrap();
    for wall in [0.0, 559.2, 1e4] {
        let at = dir.path().join(format!("{wall}"));
        assert_light_in_a_gap(&at, wall, 0.0, &[], "light samples");
    }
}

#[test]
fn bsdf_samples_see_a_light_in_a_gap_from_their_ray_origin_16_ulps_and_the_lift_off_the_wall() {
    // A BSDF-sampled ray leaves from ray_origin: the point lifted by its error bound (pbrt's
    // gamma(7) |p| here, the wall being axis-aligned), then offset_ray's 16 ulps. Whether it
    // meets the light is decided there, so BSDF samples alone (and BSDF samples' share under
    // MIS, which next to an area light is nearly all: glossy surfaces, environments) see the
    // light from that much nearer: a bias of about that over the gap, 0.5 % at z = 559.2 and
    // 8 % at 1e4. This pins it: with Ray Tracing Gems' 256 ulps it was 16x more.
    let dir = tempfile::tempdir().unwrap();
    for wall in [559.2f64, 1e4] {
        let lift = 4.1723268e-7 * wall;
        let lifted = (wall - lift) as f32;
        let step = 16.0 * f64::from(lifted - f32::from_bits(lifted.to_bits() - 1));
        let at = dir.path().join(format!("{wall}"));
        assert_light_in_a_gap(
            &at,
            wall,
            lift + step,
            &["direct.mis_strategy=2"],
            "BSDF samples alone",
        );
    }
}
