//! Geometric hard cases (docs/design.md §5–§6) on the CPU traversal and through
//! `shaders/lib/bvh.wgsl` on the GPU (lavapipe in CI): watertight closed meshes, the slab test
//! with zero and signed-zero direction components and flat boxes, and degenerate triangles.
//! Every test prints its measured figures (`cargo test --test robust_geometry -- --nocapture`).

mod common;

use common::bvh_gpu::{Answer, Query, compare, gpu, run_on_gpu};
use common::geometry::{IndexedMesh, Mtl, ObjWriter, Rng, grid_cube, icosphere};
use common::render::{assert_clean, image, render_scene};
use glam::Vec3;
use passgraph::scene::bvh::{Bvh, MAX_LEAF_TRIANGLES, is_degenerate};
use passgraph::scene::intersect::{
    PreparedRay, brute_force_any_hit, brute_force_closest_hit, intersect_box, intersect_triangle,
};
use passgraph::scene::{BvhNode, Mesh, Ray, SceneGpu};

fn scene(triangles: &[[Vec3; 3]]) -> SceneGpu {
    SceneGpu::build(&Mesh::from_triangles("test", triangles))
}

/// Leaks of one family of rays: from inside a closed mesh, a ray that finds no hit.
#[derive(Default, Debug)]
struct Leaks {
    rays: usize,
    cpu_closest: usize,
    cpu_any: usize,
    gpu_closest: usize,
    gpu_any: usize,
}

impl Leaks {
    fn total(&self) -> usize {
        self.cpu_closest + self.cpu_any + self.gpu_closest + self.gpu_any
    }
}

/// Casts `queries` (all from inside `mesh`) on the CPU and the GPU and counts the leaks. Rays
/// aimed at a point (`aimed`) must also exit there: from inside a convex mesh the only hit is
/// the exit point, and t = 1 with dir = target - origin.
fn count_leaks(
    name: &str,
    scene: &SceneGpu,
    queries: &[Query],
    answers: &[Answer],
    aimed: bool,
) -> Leaks {
    let mut leaks = Leaks {
        rays: queries.len(),
        ..Leaks::default()
    };
    for (q, a) in queries.iter().zip(answers) {
        let ray = q.ray();
        match scene.closest_hit(&ray, q.tmin, q.tmax) {
            None => leaks.cpu_closest += 1,
            Some(hit) if aimed => {
                // t is a weighted mean of the vertices' depths, all within 1.9 of the origin, so
                // the exit point is off by a few ulps of 1.9: 2e-6 allows 16.
                let point = ray.origin + hit.t * ray.dir;
                let target = ray.origin + ray.dir;
                assert!(
                    (point - target).length() <= 2e-6,
                    "{name}: {ray:?} exits at {point} instead of its target"
                );
            }
            Some(_) => {}
        }
        leaks.cpu_any += usize::from(!scene.any_hit(&ray, q.tmin, q.tmax));
        leaks.gpu_closest += usize::from(a.triangle == u32::MAX);
        leaks.gpu_any += usize::from(a.any == 0);
    }
    eprintln!("{name}: {leaks:?}");
    leaks
}

/// Rays from `origins` at every vertex and edge midpoint of `mesh`, and `random` rays from
/// random points within `inner_radius` of the centre in uniformly random directions; all
/// through the CPU traversal and bvh.wgsl. Returns (aimed leaks, random leaks).
fn watertight(
    name: &str,
    mesh: &IndexedMesh,
    origins: &[Vec3],
    inner_radius: f32,
    random: usize,
    seed: u64,
) -> (Leaks, Leaks) {
    assert!(mesh.is_closed(), "{name} must be closed");
    let scene = scene(&mesh.triangles());
    assert_eq!(scene.bvh.degenerate_count, 0);
    let gpu = gpu();

    let targets = mesh.vertex_and_edge_targets();
    let aimed: Vec<Query> = origins
        .iter()
        .flat_map(|&o| {
            targets
                .iter()
                .map(move |&t| Query::new(o, t - o, 0.0, f32::MAX))
        })
        .collect();
    let answers = run_on_gpu(&gpu, &scene, &aimed);
    let aimed_leaks = count_leaks(&format!("{name}, aimed"), &scene, &aimed, &answers, true);
    // GPU and CPU agree hit for hit (ties at shared edges may pick the neighbour).
    compare(name, &scene, &aimed, &answers, true);

    let mut rng = Rng(seed);
    let random: Vec<Query> = (0..random)
        .map(|_| Query::new(rng.in_ball(inner_radius), rng.dir(), 0.0, f32::MAX))
        .collect();
    let answers = run_on_gpu(&gpu, &scene, &random);
    let random_leaks = count_leaks(&format!("{name}, random"), &scene, &random, &answers, false);
    (aimed_leaks, random_leaks)
}

#[test]
fn icosphere_rays_at_every_vertex_and_edge_midpoint_and_random_rays_never_leak() {
    let mesh = icosphere(4);
    assert_eq!(mesh.faces.len(), 5120);
    // The inscribed sphere of the subdivided icosahedron has radius > 0.99; origins stay well
    // inside it, including one a hair off the centre (no symmetry to lean on).
    let origins = [
        Vec3::ZERO,
        Vec3::new(1e-7, -1e-7, 3e-8),
        Vec3::new(0.3, -0.2, 0.1),
        Vec3::new(-0.6, 0.55, -0.4),
    ];
    let (aimed, random) = watertight("icosphere(4)", &mesh, &origins, 0.9, 100_000, 41);
    assert_eq!(aimed.rays, 4 * (2562 + 7680));
    assert_eq!(
        aimed.total() + random.total(),
        0,
        "rays leaked out of the icosphere"
    );
}

#[test]
fn cube_rays_at_every_vertex_and_edge_midpoint_and_random_rays_never_leak() {
    // The plain 12-triangle cube (rays through its corners meet three faces and six triangles)
    // and a cube of 8 x 8 grids (many shared edges and vertices lying in one plane).
    let mut rng = Rng(43);
    let mut origins = vec![
        Vec3::ZERO,
        Vec3::new(0.5, -0.25, 0.125),
        Vec3::new(1e-7, 0.0, -1e-7),
    ];
    origins.extend((0..3).map(|_| rng.vec(-0.9, 0.9)));
    for (n, seed) in [(1, 47), (8, 53)] {
        let mesh = grid_cube(n);
        let name = format!("cube {n}x{n}");
        let (aimed, random) = watertight(&name, &mesh, &origins, 0.99, 100_000, seed);
        assert_eq!(
            aimed.total() + random.total(),
            0,
            "rays leaked out of the {name}"
        );
    }
}

/// The closed box [lo, hi] meets {o + t d : t in [tmin, tmax]}: the reference, in f64 and
/// exact for the dyadic coordinates used here. An axis with d = ±0 asks whether o lies in the
/// slab (closed).
fn box_reference(o: Vec3, d: Vec3, lo: Vec3, hi: Vec3, tmin: f64, tmax: f64) -> bool {
    let (mut t0, mut t1) = (tmin, tmax);
    for k in 0..3 {
        let (o, d, lo, hi) = (
            f64::from(o[k]),
            f64::from(d[k]),
            f64::from(lo[k]),
            f64::from(hi[k]),
        );
        if d == 0.0 {
            if o < lo || o > hi {
                return false;
            }
            continue;
        }
        let (a, b) = ((lo - o) / d, (hi - o) / d);
        t0 = t0.max(a.min(b));
        t1 = t1.min(a.max(b));
    }
    t0 <= t1
}

/// Axis directions with every sign of zero in the other components, plus diagonals in a
/// coordinate plane (a zero component with either sign).
fn signed_zero_directions() -> Vec<Vec3> {
    let mut dirs = Vec::new();
    for axis in 0..3 {
        for sign in [1.0f32, -1.0] {
            for zeros in 0..4 {
                let mut d = [0.0f32; 3];
                d[axis] = sign;
                d[(axis + 1) % 3] = if zeros & 1 == 0 { 0.0 } else { -0.0 };
                d[(axis + 2) % 3] = if zeros & 2 == 0 { 0.0 } else { -0.0 };
                dirs.push(Vec3::from(d));
            }
            for other in [1.0f32, -1.0] {
                for zero in [0.0f32, -0.0] {
                    let mut d = [0.0f32; 3];
                    d[axis] = sign;
                    d[(axis + 1) % 3] = other;
                    d[(axis + 2) % 3] = zero;
                    dirs.push(Vec3::from(d));
                }
            }
        }
    }
    dirs
}

/// Asserts intersect_box equals the exact reference for every box, every origin on the lattice
/// of quarter steps from -0.5 to 1.5 (on faces, edges and corners, inside and outside) and
/// every direction, over three t ranges; returns (cases, hits).
fn assert_slab_test_is_exact(boxes: &[(Vec3, Vec3)], dirs: &[Vec3]) -> (usize, usize) {
    let lattice: Vec<f32> = (-2..=6).map(|i| i as f32 * 0.25).collect();
    let (mut cases, mut hits) = (0usize, 0usize);
    for &(lo, hi) in boxes {
        for &x in &lattice {
            for &y in &lattice {
                for &z in &lattice {
                    let o = Vec3::new(x, y, z);
                    for &d in dirs {
                        let ray = PreparedRay::new(&Ray { origin: o, dir: d });
                        for (tmin, tmax) in [(0.0f32, f32::MAX), (0.0, 0.5), (0.25, 1.0)] {
                            let got = intersect_box(&ray, lo, hi, tmin, tmax);
                            let want =
                                box_reference(o, d, lo, hi, f64::from(tmin), f64::from(tmax));
                            assert!(
                                got == want,
                                "box {lo}..{hi}, origin {o}, dir {d:?}, t in [{tmin}, {tmax}]: \
                                 {got}, exact {want}"
                            );
                            cases += 1;
                            hits += usize::from(got);
                        }
                    }
                }
            }
        }
    }
    (cases, hits)
}

#[test]
fn slab_test_with_signed_zero_directions_on_faces_and_flat_boxes_matches_exact_reference() {
    // A solid box, boxes flat along each axis, a box flat along two axes (a segment) and a
    // point. Origins on the lattice of quarter steps: exactly on faces, edges and corners,
    // inside, and outside each box.
    let boxes = [
        (Vec3::ZERO, Vec3::ONE),
        (Vec3::new(0.0, 0.0, 0.5), Vec3::new(1.0, 1.0, 0.5)),
        (Vec3::new(0.5, 0.0, 0.0), Vec3::new(0.5, 1.0, 1.0)),
        (Vec3::new(0.0, 0.5, 0.0), Vec3::new(1.0, 0.5, 1.0)),
        (Vec3::new(0.0, 0.5, 0.5), Vec3::new(1.0, 0.5, 0.5)),
        (Vec3::splat(0.5), Vec3::splat(0.5)),
    ];
    let (cases, hits) = assert_slab_test_is_exact(&boxes, &signed_zero_directions());
    eprintln!("slab test: {cases} cases equal the exact reference ({hits} hits)");
}

#[test]
fn slab_test_of_rays_without_a_flat_axis_matches_exact_reference() {
    // Rays with no zero direction component take the cheaper test (one growth of the farthest
    // near and the nearest far distance). On the lattice of quarter steps, with faces, edges
    // and corners touched exactly and direction components from 1e-30 to 1e30, it must still
    // give the exact answer.
    let boxes = [
        (Vec3::ZERO, Vec3::ONE),
        (Vec3::new(0.0, 0.0, 0.5), Vec3::new(1.0, 1.0, 0.5)),
        (Vec3::new(0.0, 0.5, 0.5), Vec3::new(1.0, 0.5, 0.5)),
        (Vec3::splat(0.5), Vec3::splat(0.5)),
        (Vec3::new(-0.25, 0.25, 0.5), Vec3::new(0.75, 1.5, 1.25)),
    ];
    let mut dirs = Vec::new();
    for base in [
        Vec3::ONE,
        Vec3::new(1.0, 2.0, 4.0),
        Vec3::new(3.0, 1.0, 0.5),
        Vec3::new(1.0, 1e-20, 1e-20),
        Vec3::new(1e-30, 1.0, 1e30),
    ] {
        for signs in 0..8 {
            let flip = |bit: i32| if signs & bit == 0 { 1.0 } else { -1.0 };
            dirs.push(base * Vec3::new(flip(1), flip(2), flip(4)));
        }
    }
    let (cases, hits) = assert_slab_test_is_exact(&boxes, &dirs);
    eprintln!("slab test without flat axes: {cases} cases ({hits} hits)");
}

/// Recomputes every node's box as the exact bounds of its triangles (no padding), so leaves
/// of axis-aligned triangles are exactly flat boxes.
fn unpad(scene: &mut SceneGpu) {
    fn bounds(
        nodes: &mut [BvhNode],
        triangles: &[passgraph::scene::Triangle],
        i: usize,
    ) -> (Vec3, Vec3, usize) {
        let node = nodes[i];
        let (lo, hi, end) = if node.count > 0 {
            let mut lo = Vec3::INFINITY;
            let mut hi = Vec3::NEG_INFINITY;
            for t in &triangles[node.a as usize..(node.a + node.count) as usize] {
                for p in t.vertices() {
                    lo = lo.min(p);
                    hi = hi.max(p);
                }
            }
            (lo, hi, i + 1)
        } else {
            let (l0, h0, left_end) = bounds(nodes, triangles, i + 1);
            let (l1, h1, end) = bounds(nodes, triangles, left_end);
            (l0.min(l1), h0.max(h1), end)
        };
        nodes[i].lo = lo.into();
        nodes[i].hi = hi.into();
        (lo, hi, end)
    }
    let triangles = scene.triangles.clone();
    bounds(&mut scene.nodes, &triangles, 0);
}

#[test]
fn axis_parallel_rays_through_exactly_flat_boxes_hit_what_they_should_on_cpu_and_gpu() {
    // The 4x4 grid cube [-1, 1]^3 and a square [-0.5, 0.5]^2 at z = 0 inside it; every
    // coordinate is dyadic, so hits are exact. Boxes recomputed without padding: every leaf is
    // flat, and so is the square's whole subtree.
    let mut triangles = grid_cube(4).triangles();
    let square = [
        Vec3::new(-0.5, -0.5, 0.0),
        Vec3::new(0.5, -0.5, 0.0),
        Vec3::new(0.5, 0.5, 0.0),
        Vec3::new(-0.5, 0.5, 0.0),
    ];
    triangles.push([square[0], square[1], square[2]]);
    triangles.push([square[0], square[2], square[3]]);
    let mut scene = scene(&triangles);
    unpad(&mut scene);
    let flat = scene
        .nodes
        .iter()
        .filter(|n| (0..3).any(|k| n.lo[k] == n.hi[k]))
        .count();
    assert!(flat * 2 > scene.nodes.len(), "most boxes should be flat");

    // Origins on the lattice of quarter steps inside and on the cube (on the square's plane,
    // its edges and corners, the cube's faces, edges and corners), axis directions with
    // signed zeros.
    let lattice: Vec<f32> = (-4..=4).map(|i| i as f32 * 0.25).collect();
    let mut queries = Vec::new();
    for &x in &lattice {
        for &y in &lattice {
            for &z in &lattice {
                for d in signed_zero_directions() {
                    queries.push(Query::new(Vec3::new(x, y, z), d, 0.0, f32::MAX));
                }
            }
        }
    }
    let answers = run_on_gpu(&gpu(), &scene, &queries);
    let (mut expected_hits, mut checked) = (0, 0);
    for (q, a) in queries.iter().zip(&answers) {
        let ray = q.ray();
        assert!(
            [a.t, a.u, a.v].iter().all(|v| v.is_finite()),
            "GPU answer not finite for {ray:?}: {a:?}"
        );
        let cpu = scene.closest_hit(&ray, 0.0, f32::MAX);
        assert_eq!(
            cpu,
            brute_force_closest_hit(&scene.triangles, &ray, 0.0, f32::MAX)
        );
        assert_eq!(
            scene.any_hit(&ray, 0.0, f32::MAX),
            brute_force_any_hit(&scene.triangles, &ray, 0.0, f32::MAX)
        );
        // Axis-parallel rays from strictly inside the cube: the expected hit in closed form.
        let o = ray.origin;
        let d = ray.dir;
        let axis = d.abs().max_position();
        if d.abs().element_sum() != 1.0 || o.abs().max_element() >= 1.0 {
            continue;
        }
        let s = d[axis];
        let wall = 1.0 - o[axis] * s;
        let to_square = -o.z * s;
        let on_square = o.x.abs() <= 0.5 && o.y.abs() <= 0.5;
        let t = if axis == 2 && on_square && to_square > 0.0 {
            to_square
        } else {
            wall
        };
        let hit = cpu.unwrap_or_else(|| panic!("no hit for {ray:?}"));
        // t = t_scaled * (1 / det) with exact dyadic operands: the reciprocal and the product
        // round (WGSL allows the GPU's reciprocal 2.5 ulps), so within 4 ulps.
        let tolerance = 4.0 * f32::EPSILON * t;
        assert!(
            (hit.t - t).abs() <= tolerance,
            "{ray:?}: t {} vs {t}",
            hit.t
        );
        assert!(
            (a.t - t).abs() <= tolerance,
            "GPU, {ray:?}: t {} vs {t}",
            a.t
        );
        checked += 1;
        expected_hits += 1;
    }
    compare("flat boxes", &scene, &queries, &answers, true);
    eprintln!(
        "flat boxes: {} axis-parallel rays, all finite on the GPU, {} checked against the \
         closed-form hit, {flat} of {} boxes flat",
        queries.len(),
        checked,
        scene.nodes.len()
    );
    assert!(expected_hits > 1000);
}

/// Triangles of every degenerate kind, with the count that must be degenerate first.
fn degenerate_kinds() -> (Vec<[Vec3; 3]>, Vec<[Vec3; 3]>) {
    let p = Vec3::new;
    let base = p(300.0, 200.0, 250.0);
    // A normal whose squared components are subnormal (each ~5e-39): with the denormals a GPU
    // may flush, its length would be 0 and normalising it NaN.
    let s = 2.65e-10f32;
    let degenerate = vec![
        // Zero area: coincident vertices, all three equal, collinear, collinear far away.
        [base, base, base + p(1.0, 0.0, 0.0)],
        [base; 3],
        [base, base + p(1.0, 1.0, 1.0), base + p(2.0, 2.0, 2.0)],
        [p(1e6, 0.0, 0.0), p(-1e6, 0.0, 0.0), p(0.0, 0.0, 0.0)],
        // A normal too small to normalise on a GPU that flushes subnormals.
        [Vec3::ZERO, p(s, -s, 0.0), p(s, 0.0, -s)],
        // A normal whose squared length overflows f32 (edges ~1e19; loading such a mesh
        // warns that it is not rendered).
        [p(-1e19, -1e19, 0.0), p(1e19, -1e19, 0.0), p(0.0, 1e19, 0.0)],
    ];
    let mut valid = Vec::new();
    // Slivers at Cornell-box coordinates: sides ~2e-4 (about 7 ulps there), and a needle
    // 100 long and 2e-4 wide.
    for i in 0..20 {
        let c = base + p(i as f32 * 3.0, 0.0, 0.0);
        valid.push([c, c + p(2e-4, 0.0, 0.0), c + p(0.0, 2e-4, 1e-4)]);
        valid.push([c, c + p(100.0, 0.0, 0.0), c + p(50.0, 2e-4, 0.0)]);
    }
    // Duplicates: one triangle 50 times.
    for _ in 0..50 {
        valid.push([
            p(100.0, 100.0, 300.0),
            p(200.0, 100.0, 300.0),
            p(100.0, 200.0, 300.0),
        ]);
    }
    // Huge: 10^6 across, one of them enclosing everything else's box.
    valid.push([
        p(-1e6, -1e6, 600.0),
        p(1e6, -1e6, 600.0),
        p(0.0, 1e6, 600.0),
    ]);
    valid.push([p(-1e6, -1.0, -1e6), p(0.0, -1.0, 1e6), p(1e6, -1.0, -1e6)]);
    (degenerate, valid)
}

#[test]
fn degenerate_triangles_build_and_are_never_returned_on_cpu_or_gpu() {
    let (degenerate, valid) = degenerate_kinds();
    for t in &degenerate {
        assert!(is_degenerate(t), "{t:?} must count as degenerate");
    }
    for t in &valid {
        assert!(!is_degenerate(t), "{t:?} is a valid triangle");
    }
    // Degenerate triangles first in the input, so an index mix-up would show.
    let mut triangles = degenerate.clone();
    triangles.extend(&valid);
    let scene = scene(&triangles);
    assert_eq!(scene.bvh.degenerate_count, degenerate.len());
    let first_degenerate = scene.triangles.len() - degenerate.len();

    // Rays at every triangle's vertices, centroid and an edge midpoint, from random
    // directions 10 away (farther for the huge ones); at the overflowing triangle, from the
    // middle of the scene.
    let mut rng = Rng(59);
    let mut queries = Vec::new();
    for t in &triangles {
        let targets = [
            t[0],
            t[1],
            t[2],
            (t[0] + t[1] + t[2]) / 3.0,
            (t[0] + t[1]) * 0.5,
        ];
        for target in targets {
            for _ in 0..8 {
                let dir = rng.dir();
                let far = target.abs().max_element();
                let query = if far < 1e7 {
                    let back = 10.0 + far * 1e-3;
                    Query::new(target - back * dir, dir, 0.0, f32::MAX)
                } else {
                    let origin = Vec3::new(300.0, 200.0, 250.0) + 10.0 * dir;
                    Query::new(origin, target - origin, 0.0, f32::MAX)
                };
                queries.push(query);
            }
        }
    }
    let answers = run_on_gpu(&gpu(), &scene, &queries);
    let mut hits = 0;
    for (q, a) in queries.iter().zip(&answers) {
        let ray = q.ray();
        let cpu = scene.closest_hit(&ray, 0.0, f32::MAX);
        assert_eq!(
            cpu,
            brute_force_closest_hit(&scene.triangles, &ray, 0.0, f32::MAX)
        );
        if let Some(hit) = cpu {
            assert!(
                (hit.triangle as usize) < first_degenerate,
                "CPU returned a degenerate triangle"
            );
            hits += 1;
        }
        assert!(
            a.triangle == u32::MAX || (a.triangle as usize) < first_degenerate,
            "GPU returned degenerate triangle {} for {ray:?}",
            a.triangle
        );
        assert!(
            [a.t, a.u, a.v].iter().all(|v| v.is_finite()),
            "{ray:?}: {a:?}"
        );
    }
    // Every ray here is aimed at a vertex or edge, and the slivers are a few ulps wide, so
    // the GPU's rounding can decide a ray the other way than the CPU. Where they differ, the
    // GPU's hit must still lie inside the (valid) triangle it names. How far the GPU's t is from
    // the CPU's on that same triangle is measured in units of f32::EPSILON x reach (the
    // farthest vertex from the origin: t is a weighted mean of the vertices' depths).
    let (mut differ, mut worst) = (0, 0.0f32);
    for (q, a) in queries.iter().zip(&answers) {
        let ray = q.ray();
        let cpu = scene.closest_hit(&ray, 0.0, f32::MAX);
        let same = match cpu {
            Some(h) => (h.triangle, h.t) == (a.triangle, a.t),
            None => a.triangle == u32::MAX,
        };
        if same || a.triangle == u32::MAX {
            differ += usize::from(!same);
            continue;
        }
        differ += 1;
        assert!(
            a.u >= 0.0 && a.v >= 0.0 && a.u + a.v <= 1.0 + 4.0 * f32::EPSILON,
            "GPU barycentrics out of the triangle: {a:?}"
        );
        let vertices = scene.triangles[a.triangle as usize].vertices();
        if let Some(h) = intersect_triangle(&PreparedRay::new(&ray), &vertices, 0.0, f32::MAX) {
            let reach = vertices
                .iter()
                .map(|p| (*p - ray.origin).length() / ray.dir.length())
                .fold(h.t, f32::max);
            worst = worst.max((a.t - h.t).abs() / (f32::EPSILON * reach));
        }
    }
    // The GPU's edge functions are exact (no fused fma needed), so its t is within the same
    // rounding bound as the CPU's, 64 ulps of the reach (as tests/bvh_wgsl.rs allows).
    assert!(worst <= 64.0, "GPU t off by {worst} x EPSILON x reach");
    eprintln!(
        "degenerate: {} kinds rejected, {} valid slivers/duplicates/huge kept; {} rays ({hits} \
         CPU hits), none returned a degenerate triangle on the CPU or the GPU; {differ} answered \
         differently by the GPU, whose t is at most {worst:.0} x EPSILON x reach from the \
         CPU's on the same triangle",
        degenerate.len(),
        valid.len(),
        queries.len()
    );
}

#[test]
fn equal_centroids_build_terminates_with_logarithmic_depth() {
    // The build bins triangles by the centre of their bounding box. 10^5 copies of one
    // triangle, and 10^4 different triangles [p, -p, q] with |q| <= |p| per axis, whose boxes
    // [-|p|, |p|] are all centred on the origin: no plane separates any of them, so the build
    // halves by count.
    let t = [Vec3::ZERO, Vec3::X, Vec3::Y];
    let mut rng = Rng(61);
    let centred: Vec<[Vec3; 3]> = (0..10_000)
        .map(|_| {
            let p = rng.vec(0.1, 1.0);
            [p, -p, p * rng.vec(-1.0, 1.0)]
        })
        .collect();
    for (name, triangles) in [
        ("10^5 identical", vec![t; 100_000]),
        ("10^4 centred", centred),
    ] {
        let bvh = Bvh::build(&triangles);
        let n = triangles.len() - bvh.stats.degenerate_count;
        // Halving n by count reaches leaves of at most MAX_LEAF_TRIANGLES after
        // ceil(log2(n / MAX_LEAF_TRIANGLES)) levels.
        let bound = (n as f64 / MAX_LEAF_TRIANGLES as f64).log2().ceil() as usize;
        eprintln!(
            "{name}: depth {} (bound {bound}), {} nodes, largest leaf {}, built in {:?}",
            bvh.stats.max_depth,
            bvh.stats.node_count,
            bvh.stats.max_leaf_triangles,
            bvh.stats.build_time
        );
        assert!(n > triangles.len() * 99 / 100);
        assert!(
            bvh.stats.max_depth <= bound,
            "{name}: depth {}",
            bvh.stats.max_depth
        );
        assert!(bvh.stats.max_leaf_triangles <= MAX_LEAF_TRIANGLES);
    }
}

#[test]
fn image_of_degenerate_triangles_has_no_nan_on_the_gpu() {
    // The degenerate kinds and valid slivers, duplicates and huge triangles in front of a
    // light, some emissive themselves (zero-area emitters must not become lights), seen by a
    // camera whose pixels cover the slivers.
    let (degenerate, valid) = degenerate_kinds();
    let mut obj = ObjWriter::new(&[
        Mtl {
            name: "white",
            kd: [0.8; 3],
            ke: [0.0; 3],
        },
        Mtl {
            name: "light",
            kd: [0.5; 3],
            ke: [10.0; 3],
        },
    ]);
    obj.material("white")
        .triangles(&valid)
        .triangles(&degenerate);
    obj.material("light").triangles(&degenerate[..4]);
    // A light above the slivers, out of the camera's view, facing down (counter-clockwise
    // seen from below).
    let (x0, x1, z0, z1, y) = (200.0, 450.0, 100.0, 300.0, 450.0);
    obj.polygon(&[
        Vec3::new(x0, y, z0),
        Vec3::new(x1, y, z0),
        Vec3::new(x1, y, z1),
        Vec3::new(x0, y, z1),
    ]);
    let dir = tempfile::tempdir().unwrap();
    let eye = Vec3::new(330.0, 200.0, -100.0);
    let path = obj.write(
        dir.path(),
        eye,
        Vec3::new(330.0, 200.0, 250.0),
        Vec3::Y,
        40.0,
    );
    let session = render_scene(&path, 32, 1, 8);
    assert_eq!(
        session.scene().light_count,
        1,
        "only the real light's two triangles emit (one parallelogram light)"
    );
    assert_eq!(
        session.scene().bvh.degenerate_count,
        2 * degenerate.len() - 2
    );
    assert_clean(&session, 8, "degenerate scene");
    let sum = image(&session, "sum");
    let lit = sum.pixels.iter().filter(|p| p[0] > 0.0).count();
    eprintln!("degenerate scene: 32x32 x 8 frames, all finite, 0 dropped, {lit} lit pixels");
    assert!(lit > 100, "the scene should be visible");
}

#[test]
fn a_ray_starting_near_a_surface_sees_it_unless_within_t_rounding_bound() {
    // Hits nearer than the bound on t's own rounding error are rejected (that is what keeps
    // rays from hitting the surface they leave). The price: a ray that starts closer to a
    // surface than that bound does not see it. Measured for a grazing ray (slope 0.1), the
    // worst direction, where the bound is largest: the height above the plane from which the
    // ray sees it must stay within 64 ulps of the triangle's size.
    let p = Vec3::new;
    let cases = [
        (
            "Cornell floor",
            [p(552.8, 0.0, 0.0), p(0.0, 0.0, 0.0), p(0.0, 0.0, 559.2)],
            559.2,
        ),
        (
            "2e6-wide triangle",
            [p(-1e6, 0.0, -1e6), p(0.0, 0.0, 1e6), p(1e6, 0.0, -1e6)],
            2e6,
        ),
    ];
    for (name, triangle, size) in cases {
        let scene = scene(&[triangle]);
        for dir in [
            Vec3::NEG_Y,
            p(0.3, -1.0, 0.2).normalize(),
            p(1.0, -0.1, 0.0).normalize(),
        ] {
            let sees = |height: f32| {
                let origin = p(100.0, 0.0, 100.0) - dir * (height / -dir.y);
                scene
                    .closest_hit(&Ray { origin, dir }, 0.0, f32::MAX)
                    .is_some()
            };
            // Bisection on a log scale between 1e-9 and the triangle's size.
            let (mut lo, mut hi) = (1e-9f32, size);
            assert!(sees(hi));
            for _ in 0..60 {
                let mid = (lo * hi).sqrt();
                if sees(mid) { hi = mid } else { lo = mid }
            }
            eprintln!("{name}, dir {dir}: seen from {hi:.2e} above it");
            assert!(hi <= 64.0 * f32::EPSILON * size, "{name}: blind up to {hi}");
        }
    }
}
