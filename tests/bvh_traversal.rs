//! The threaded BVH against the brute-force oracle ("every layout and traversal returns exactly
//! the brute-force hit"), on random soups and on the hard cases of docs/design.md §5–§6, plus the
//! layout invariants the stackless GPU loop relies on.

use glam::Vec3;
use passgraph::scene::bvh::{MAX_DEPTH, is_degenerate};
use passgraph::scene::bvh_octants::COPIES;
use passgraph::scene::intersect::{
    PreparedRay, brute_force_any_hit, brute_force_closest_hit, intersect_triangle,
};
use passgraph::scene::{BvhNode, Mesh, Ray, SceneGpu};
use proptest::prelude::*;

/// A small deterministic generator (SplitMix64), so failures reproduce.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    fn unit(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.unit()
    }
    fn vec(&mut self, lo: f32, hi: f32) -> Vec3 {
        Vec3::new(self.range(lo, hi), self.range(lo, hi), self.range(lo, hi))
    }
    /// A direction, not normalised, never zero.
    fn dir(&mut self) -> Vec3 {
        loop {
            let d = self.vec(-1.0, 1.0);
            if d.length_squared() > 1e-4 && d.length_squared() <= 1.0 {
                return d;
            }
        }
    }
    fn index(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
}

fn scene(triangles: &[[Vec3; 3]]) -> SceneGpu {
    SceneGpu::build(&Mesh::from_triangles("test", triangles))
}

/// Asserts the BVH answers `ray` exactly as brute force does, for closest and any hit.
fn assert_matches_oracle(scene: &SceneGpu, ray: &Ray, tmin: f32, tmax: f32) {
    let bvh = scene.closest_hit(ray, tmin, tmax);
    let oracle = brute_force_closest_hit(&scene.triangles, ray, tmin, tmax);
    assert_eq!(
        bvh, oracle,
        "closest hit differs for {ray:?} in ({tmin}, {tmax})"
    );
    let any = scene.any_hit(ray, tmin, tmax);
    let any_oracle = brute_force_any_hit(&scene.triangles, ray, tmin, tmax);
    assert_eq!(
        any, any_oracle,
        "any hit differs for {ray:?} in ({tmin}, {tmax})"
    );
    assert_eq!(any, oracle.is_some());
}

/// Random triangles: centres in [-extent, extent]^3, edges up to `size`.
fn random_soup(rng: &mut Rng, count: usize, extent: f32, size: f32) -> Vec<[Vec3; 3]> {
    (0..count)
        .map(|_| {
            let c = rng.vec(-extent, extent);
            let s = size * rng.unit();
            [c + rng.vec(-s, s), c + rng.vec(-s, s), c + rng.vec(-s, s)]
        })
        .collect()
}

/// Checks every invariant of the flattened layout and returns the maximum depth.
fn check_layout(scene: &SceneGpu) -> usize {
    let nodes = &scene.nodes;
    let triangle_count = scene.triangles.len();
    let mut seen = vec![0u32; triangle_count];

    // Parses the subtree at `i`, returning the index after it and its depth.
    fn walk(nodes: &[BvhNode], i: usize, depth: usize, seen: &mut [u32]) -> (usize, usize) {
        let node = &nodes[i];
        let (lo, hi) = (Vec3::from(node.lo), Vec3::from(node.hi));
        assert!(lo.cmple(hi).all(), "node {i} has an inverted box");
        if node.count > 0 {
            for k in node.a..node.a + node.count {
                seen[k as usize] += 1;
            }
            return (i + 1, depth);
        }
        assert!(
            node.a as usize > i,
            "interior node {i}: skip {} <= i",
            node.a
        );
        // The first child is the next node; the second child starts where the first ends.
        let (left_end, left_depth) = walk(nodes, i + 1, depth + 1, seen);
        assert!(left_end < node.a as usize, "node {i} has no second child");
        let (right_end, right_depth) = walk(nodes, left_end, depth + 1, seen);
        assert_eq!(
            node.a as usize, right_end,
            "node {i}: skip is not its subtree's end"
        );
        for child in [i + 1, left_end] {
            let c = &nodes[child];
            assert!(
                lo.cmple(Vec3::from(c.lo)).all() && Vec3::from(c.hi).cmple(hi).all(),
                "node {i} does not contain child {child}"
            );
        }
        (right_end, left_depth.max(right_depth))
    }

    let mut depth = 0;
    if !nodes.is_empty() {
        let (end, d) = walk(nodes, 0, 0, &mut seen);
        assert_eq!(
            end,
            nodes.len(),
            "the root's subtree must be the whole array"
        );
        depth = d;
    }
    let leaves = nodes.iter().filter(|n| n.count > 0).count();
    if leaves > 0 {
        assert_eq!(
            nodes.len(),
            2 * leaves - 1,
            "a binary tree has 2 leaves - 1 nodes"
        );
    }
    for (k, triangle) in scene.triangles.iter().enumerate() {
        let degenerate = is_degenerate(&triangle.vertices());
        let expected = if degenerate { 0 } else { 1 };
        assert_eq!(
            seen[k], expected,
            "triangle {k} (degenerate: {degenerate}) is in {} leaves",
            seen[k]
        );
    }
    // Leaf boxes contain their triangles.
    for node in nodes.iter().filter(|n| n.count > 0) {
        for k in node.a..node.a + node.count {
            for p in scene.triangles[k as usize].vertices() {
                assert!(Vec3::from(node.lo).cmple(p).all() && p.cmple(Vec3::from(node.hi)).all());
            }
        }
    }
    assert_eq!(scene.bvh.node_count, nodes.len());
    assert_eq!(scene.bvh.max_depth, depth);
    assert!(depth <= MAX_DEPTH);
    depth
}

#[test]
fn random_soups_closest_and_any_hit_equal_brute_force() {
    for (seed, count, size) in [(1, 1000, 1.0), (2, 300, 6.0), (3, 2000, 0.3), (4, 50, 10.0)] {
        let mut rng = Rng(seed);
        let triangles = random_soup(&mut rng, count, 10.0, size);
        let scene = scene(&triangles);
        check_layout(&scene);
        let mut hits = 0;
        for r in 0..2500 {
            let ray = if r % 2 == 0 {
                // From outside or inside the soup, anywhere.
                Ray {
                    origin: rng.vec(-15.0, 15.0),
                    dir: rng.dir(),
                }
            } else {
                // Aimed at a random point of a random triangle, so most rays hit something.
                let t = triangles[rng.index(triangles.len())];
                let (a, b) = (rng.unit(), rng.unit());
                let (a, b) = if a + b > 1.0 {
                    (1.0 - a, 1.0 - b)
                } else {
                    (a, b)
                };
                let target = t[0] + a * (t[1] - t[0]) + b * (t[2] - t[0]);
                let origin = rng.vec(-15.0, 15.0);
                Ray {
                    origin,
                    dir: target - origin,
                }
            };
            let tmax = if r % 5 == 0 {
                rng.range(0.0, 2.0)
            } else {
                f32::MAX
            };
            assert_matches_oracle(&scene, &ray, 0.0, tmax);
            hits += usize::from(scene.closest_hit(&ray, 0.0, tmax).is_some());
        }
        assert!(
            hits > 1000,
            "seed {seed}: too few hits ({hits}) to test anything"
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn arbitrary_small_soups_equal_brute_force(
        vertices in prop::collection::vec(
            prop::array::uniform3(prop::array::uniform3(-4i32..=4)), 1..40),
        rays in prop::collection::vec(
            (prop::array::uniform3(-6i32..=6), prop::array::uniform3(-3i32..=3)), 40),
    ) {
        // Small integer coordinates make coincident vertices, shared edges, coplanar and
        // axis-aligned triangles, and rays through vertices and edges common.
        let to_vec = |p: [i32; 3]| Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32);
        let triangles: Vec<[Vec3; 3]> = vertices
            .iter()
            .map(|t| [to_vec(t[0]), to_vec(t[1]), to_vec(t[2])])
            .collect();
        let scene = scene(&triangles);
        check_layout(&scene);
        for (origin, dir) in rays {
            let dir = to_vec(dir);
            if dir == Vec3::ZERO {
                continue;
            }
            let ray = Ray { origin: to_vec(origin) * 0.5, dir };
            assert_matches_oracle(&scene, &ray, 0.0, f32::MAX);
            assert_matches_oracle(&scene, &ray, 0.5, 3.0);
        }
    }
}

#[test]
fn identical_triangles_build_terminates_with_bounded_depth() {
    let t = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
    ];
    let triangles = vec![t; 1000];
    let scene = scene(&triangles);
    let depth = check_layout(&scene);
    // Halving 1000 triangles into leaves of at most 4 takes 8 levels.
    assert!(depth <= 10, "depth {depth}");
    assert!(scene.bvh.max_leaf_triangles <= 4);
    let ray = Ray {
        origin: Vec3::new(0.25, 0.25, -1.0),
        dir: Vec3::Z,
    };
    let hit = scene
        .closest_hit(&ray, 0.0, f32::MAX)
        .expect("the stack is hit");
    assert_matches_oracle(&scene, &ray, 0.0, f32::MAX);
    // All 1000 are equally near: the tie goes to the first in BVH order.
    assert_eq!(hit.triangle, 0);
}

#[test]
fn triangles_with_one_shared_centroid_match_brute_force() {
    // Different shapes and boxes, one centroid: no SAH plane separates them.
    let mut rng = Rng(7);
    let triangles: Vec<[Vec3; 3]> = (0..500)
        .map(|_| {
            let a = rng.vec(-1.0, 1.0);
            let b = rng.vec(-1.0, 1.0);
            [a, b, -(a + b)]
        })
        .collect();
    let scene = scene(&triangles);
    assert!(check_layout(&scene) <= 12);
    for _ in 0..2000 {
        let ray = Ray {
            origin: rng.vec(-3.0, 3.0),
            dir: rng.dir(),
        };
        assert_matches_oracle(&scene, &ray, 0.0, f32::MAX);
    }
}

#[test]
fn zero_area_and_collinear_triangles_are_never_hit() {
    let p = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    let degenerate = [
        [p(0.0, 0.0, 0.0), p(0.0, 0.0, 0.0), p(0.0, 0.0, 0.0)],
        [p(1.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(1.0, 1.0, 0.0)],
        [p(-1.0, -1.0, 0.0), p(1.0, 1.0, 0.0), p(0.0, 0.0, 0.0)],
        [p(0.0, 0.0, 0.0), p(1.0, 1.0, 1.0), p(2.0, 2.0, 2.0)],
        [p(0.0, 0.0, 0.0), p(0.5, 0.25, 2.0), p(2.0, 1.0, 8.0)],
        [p(3.0, 0.0, 0.0), p(3.0, 0.0, 0.0), p(3.0, 0.0, 0.0)],
    ];
    for t in &degenerate {
        assert!(is_degenerate(t), "{t:?} should count as degenerate");
    }
    // A real triangle among them, so the BVH is not empty.
    let real = [p(10.0, 10.0, 5.0), p(11.0, 10.0, 5.0), p(10.0, 11.0, 5.0)];
    let mut triangles = degenerate.to_vec();
    triangles.push(real);
    let scene = scene(&triangles);
    check_layout(&scene);
    assert_eq!(scene.bvh.degenerate_count, degenerate.len());
    let last_real = scene.triangles.len() - degenerate.len();

    let mut rng = Rng(11);
    for t in &degenerate {
        // Rays through the degenerate triangles' points, from many directions.
        for i in 0..400 {
            let a = rng.unit();
            let target = t[0] + a * (t[1] - t[0]) + rng.unit() * (1.0 - a) * (t[2] - t[0]);
            let target = if i % 4 == 0 { t[i % 3] } else { target };
            let dir = rng.dir();
            let ray = Ray {
                origin: target - 3.0 * dir,
                dir,
            };
            assert_matches_oracle(&scene, &ray, 0.0, f32::MAX);
            if let Some(hit) = scene.closest_hit(&ray, 0.0, f32::MAX) {
                assert!(
                    (hit.triangle as usize) < last_real,
                    "hit a degenerate triangle"
                );
            }
            // Nor does the triangle test itself report coincident-vertex triangles.
            if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                assert_eq!(
                    intersect_triangle(&PreparedRay::new(&ray), t, 0.0, f32::MAX),
                    None
                );
            }
        }
    }
}

#[test]
fn huge_triangle_among_tiny_ones_matches_brute_force() {
    let mut rng = Rng(13);
    let mut triangles = random_soup(&mut rng, 1000, 2.0, 1e-3);
    triangles.push([
        Vec3::new(-1e6, -1e6, 0.5),
        Vec3::new(1e6, -1e6, 0.5),
        Vec3::new(0.0, 1e6, 0.5),
    ]);
    triangles.push([
        Vec3::new(-1e6, -1e6, -1e6),
        Vec3::new(1e6, 1e6, 1e6),
        Vec3::new(1e6, -1e6, 0.0),
    ]);
    let scene = scene(&triangles);
    check_layout(&scene);
    for i in 0..3000 {
        let ray = if i % 2 == 0 {
            let target = triangles[rng.index(1000)][0];
            let origin = rng.vec(-3.0, 3.0);
            Ray {
                origin,
                dir: target - origin,
            }
        } else {
            Ray {
                origin: rng.vec(-2e6, 2e6),
                dir: rng.dir(),
            }
        };
        assert_matches_oracle(&scene, &ray, 0.0, f32::MAX);
    }
}

/// A closed axis-aligned box [-1, 1]^3, each face an n x n grid of quads split into two
/// triangles (alternating diagonals), with every shared vertex bit-identical. Front faces
/// point inward.
fn grid_cube(n: usize) -> Vec<[Vec3; 3]> {
    let mut triangles = Vec::new();
    let coord = |i: usize| -1.0 + 2.0 * i as f32 / n as f32;
    for axis in 0..3 {
        for side in [-1.0f32, 1.0] {
            let point = |i: usize, j: usize| {
                let mut p = [0.0; 3];
                p[axis] = side;
                p[(axis + 1) % 3] = coord(i);
                p[(axis + 2) % 3] = coord(j);
                Vec3::from(p)
            };
            for i in 0..n {
                for j in 0..n {
                    let (a, b, c, d) = (
                        point(i, j),
                        point(i + 1, j),
                        point(i + 1, j + 1),
                        point(i, j + 1),
                    );
                    let (first, second) = if (i + j) % 2 == 0 {
                        ([a, b, c], [a, c, d])
                    } else {
                        ([a, b, d], [b, c, d])
                    };
                    for t in [first, second] {
                        // Wind so the front (counter-clockwise) side faces the inside.
                        let inward = -Vec3::from({
                            let mut q = [0.0; 3];
                            q[axis] = side;
                            q
                        });
                        let n = (t[1] - t[0]).cross(t[2] - t[0]);
                        triangles.push(if n.dot(inward) > 0.0 {
                            t
                        } else {
                            [t[0], t[2], t[1]]
                        });
                    }
                }
            }
        }
    }
    triangles
}

/// A closed UV sphere: poles where many triangles meet in one vertex.
fn uv_sphere(rings: usize, segments: usize, radius: f32) -> Vec<[Vec3; 3]> {
    let mut vertices = vec![Vec3::new(0.0, radius, 0.0)];
    for r in 1..rings {
        let theta = std::f32::consts::PI * r as f32 / rings as f32;
        for s in 0..segments {
            let phi = std::f32::consts::TAU * s as f32 / segments as f32;
            vertices.push(
                radius
                    * Vec3::new(
                        theta.sin() * phi.cos(),
                        theta.cos(),
                        theta.sin() * phi.sin(),
                    ),
            );
        }
    }
    vertices.push(Vec3::new(0.0, -radius, 0.0));
    let south = vertices.len() - 1;
    let ring = |r: usize, s: usize| 1 + (r - 1) * segments + s % segments;
    let mut triangles = Vec::new();
    for s in 0..segments {
        triangles.push([vertices[0], vertices[ring(1, s)], vertices[ring(1, s + 1)]]);
        triangles.push([
            vertices[south],
            vertices[ring(rings - 1, s + 1)],
            vertices[ring(rings - 1, s)],
        ]);
        for r in 1..rings - 1 {
            let (a, b, c, d) = (
                ring(r, s),
                ring(r, s + 1),
                ring(r + 1, s + 1),
                ring(r + 1, s),
            );
            triangles.push([vertices[a], vertices[d], vertices[c]]);
            triangles.push([vertices[a], vertices[c], vertices[b]]);
        }
    }
    triangles
}

/// Rays from inside a closed mesh aimed exactly at its vertices and edge midpoints: none may
/// slip through a crack.
fn assert_watertight(triangles: &[[Vec3; 3]], origins: &[Vec3]) {
    let scene = scene(triangles);
    check_layout(&scene);
    let mut targets = Vec::new();
    for t in triangles {
        for k in 0..3 {
            targets.push(t[k]);
            targets.push((t[k] + t[(k + 1) % 3]) * 0.5);
        }
    }
    let mut rays = 0;
    for &origin in origins {
        for &target in &targets {
            let ray = Ray {
                origin,
                dir: target - origin,
            };
            assert!(
                scene.closest_hit(&ray, 0.0, f32::MAX).is_some(),
                "ray leaked: {ray:?}"
            );
            assert!(
                scene.any_hit(&ray, 0.0, f32::MAX),
                "shadow ray leaked: {ray:?}"
            );
            assert_matches_oracle(&scene, &ray, 0.0, f32::MAX);
            rays += 1;
        }
    }
    assert!(rays >= 2000, "only {rays} rays");
}

#[test]
fn rays_through_shared_edges_and_vertices_of_a_closed_cube_never_leak() {
    let mut rng = Rng(17);
    let mut origins = vec![
        Vec3::ZERO,
        Vec3::new(0.5, -0.25, 0.125),
        Vec3::new(1e-7, 0.0, -1e-7),
    ];
    origins.extend((0..5).map(|_| rng.vec(-0.9, 0.9)));
    assert_watertight(&grid_cube(4), &origins);
}

#[test]
fn rays_through_the_poles_and_seams_of_a_closed_sphere_never_leak() {
    let mut rng = Rng(19);
    let mut origins = vec![Vec3::ZERO];
    origins.extend((0..4).map(|_| rng.vec(-0.5, 0.5)));
    assert_watertight(&uv_sphere(12, 24, 1.0), &origins);
}

#[test]
fn axis_parallel_rays_with_signed_zero_components_match_brute_force() {
    // Axis-aligned geometry puts ray origins exactly on box planes.
    let mut triangles = grid_cube(3);
    let mut rng = Rng(23);
    triangles.extend(random_soup(&mut rng, 200, 3.0, 1.0));
    let scene = scene(&triangles);
    check_layout(&scene);
    let grid = |rng: &mut Rng| (rng.index(13) as f32 - 6.0) / 3.0;
    let mut hits = 0;
    for i in 0..4000 {
        let axis = i % 3;
        let sign = if (i / 3) % 2 == 0 { 1.0 } else { -1.0 };
        let mut dir = [0.0f32; 3];
        dir[axis] = sign;
        // The other components: +0 or -0.
        for (k, c) in dir.iter_mut().enumerate() {
            if k != axis && rng.unit() < 0.5 {
                *c = -0.0;
            }
        }
        let origin = Vec3::new(grid(&mut rng), grid(&mut rng), grid(&mut rng));
        let origin = if i % 4 == 0 {
            rng.vec(-2.0, 2.0)
        } else {
            origin
        };
        let ray = Ray {
            origin,
            dir: Vec3::from(dir),
        };
        assert_matches_oracle(&scene, &ray, 0.0, f32::MAX);
        hits += usize::from(scene.any_hit(&ray, 0.0, f32::MAX));
    }
    assert!(hits > 1000, "{hits}");
}

#[test]
fn inside_the_grid_cube_every_axis_parallel_ray_hits_a_wall() {
    let scene = scene(&grid_cube(4));
    for &x in &[-0.5f32, 0.0, 0.5] {
        for &y in &[-0.5f32, 0.0, 0.5] {
            for dir in [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z] {
                let dir = Vec3::select(dir.cmpeq(Vec3::ZERO), Vec3::splat(-0.0), dir);
                let ray = Ray {
                    origin: Vec3::new(x, y, 0.0),
                    dir,
                };
                let hit = scene.closest_hit(&ray, 0.0, f32::MAX).expect("wall");
                let expected = 1.0 - ray.origin.dot(dir);
                assert!((hit.t - expected).abs() < 1e-6, "{ray:?}: t = {}", hit.t);
            }
        }
    }
}

#[test]
fn packed_nodes_decode_exactly_to_the_node_boxes() {
    // What the GPU decodes (origin + q * step in f32) must be the box the CPU twin traverses,
    // at any scale and distance from the origin.
    let mut rng = Rng(7);
    for (offset, extent, size) in [
        (Vec3::ZERO, 1.0, 0.05),
        (Vec3::new(1e6, -3e5, 2e4), 10.0, 0.5),
        (Vec3::splat(-2e-3), 1e-3, 1e-4),
        (Vec3::new(3e12, 0.0, -1e13), 1e9, 1e7),
    ] {
        let soup: Vec<[Vec3; 3]> = random_soup(&mut rng, 500, extent, size)
            .into_iter()
            .map(|t| t.map(|p| p + offset))
            .collect();
        let scene = scene(&soup);
        let bytes = scene.bvh_bytes();
        assert_eq!(bytes.len(), 32 + 16 * COPIES * scene.nodes.len());
        assert_eq!(scene.octant_nodes.len(), COPIES * scene.nodes.len());
        let grid = scene.grid;
        for node in &scene.octant_nodes {
            let packed = grid.encode(node);
            for k in 0..3 {
                let decode = |q: u32| q as f32 * grid.step[k] + grid.origin[k];
                assert_eq!(
                    decode(packed.bounds[k] & 0xffff),
                    node.lo[k],
                    "{offset}: lo"
                );
                assert_eq!(decode(packed.bounds[k] >> 16), node.hi[k], "{offset}: hi");
            }
            assert_eq!(packed.link & 0x0fff_ffff, node.a);
            assert_eq!(packed.link >> 28, node.count);
        }
        for _ in 0..200 {
            let ray = Ray {
                origin: offset + rng.vec(-extent, 2.0 * extent),
                dir: rng.dir(),
            };
            assert_matches_oracle(&scene, &ray, 0.0, f32::MAX);
        }
    }
}

#[test]
fn empty_and_all_degenerate_soups_have_no_nodes_and_no_hits() {
    for triangles in [vec![], vec![[Vec3::ONE; 3]; 5]] {
        let scene = scene(&triangles);
        assert!(scene.nodes.is_empty());
        let ray = Ray {
            origin: Vec3::ZERO,
            dir: Vec3::ONE,
        };
        assert_eq!(scene.closest_hit(&ray, 0.0, f32::MAX), None);
        assert!(!scene.any_hit(&ray, 0.0, f32::MAX));
    }
}

#[test]
fn zero_padded_node_array_still_terminates() {
    // What an executor padding an empty buffer would bind: one all-zero node.
    let nodes = [BvhNode::default()];
    let ray = Ray {
        origin: Vec3::ZERO,
        dir: Vec3::X,
    };
    assert_eq!(
        passgraph::scene::intersect::closest_hit(&nodes, &[], &ray, 0.0, 1.0),
        None
    );
    assert!(!passgraph::scene::intersect::any_hit(
        &nodes,
        &[],
        &ray,
        0.0,
        1.0
    ));
}

#[test]
fn sah_build_of_a_100k_soup_is_valid_and_shallow() {
    let mut rng = Rng(29);
    let triangles = random_soup(&mut rng, 100_000, 100.0, 1.0);
    let scene = scene(&triangles);
    let depth = check_layout(&scene);
    eprintln!(
        "100k soup: {} nodes, {} leaves, depth {}, largest leaf {}, built in {:?}",
        scene.bvh.node_count,
        scene.bvh.leaf_count,
        depth,
        scene.bvh.max_leaf_triangles,
        scene.bvh.build_time
    );
    assert!(depth < 40, "depth {depth}");
    assert!(scene.bvh.max_leaf_triangles <= 4);
    for _ in 0..200 {
        let ray = Ray {
            origin: rng.vec(-120.0, 120.0),
            dir: rng.dir(),
        };
        assert_eq!(
            scene.closest_hit(&ray, 0.0, f32::MAX),
            brute_force_closest_hit(&scene.triangles, &ray, 0.0, f32::MAX)
        );
    }
}
