//! Where a ray's traversal time goes: per-ray counts of node visits, boxes hit, leaves entered,
//! triangle tests and hits, and loop iterations of bvh.wgsl's interleaved loop (one node visit
//! and at most one triangle test each), for the rays the fast graph traces: primary rays,
//! cosine bounces from the primary hit (closest hit) and shadow rays to a point on each light
//! (any hit). SIMD efficiency: lavapipe runs 8 lanes (a row of 8 pixels of an 8x8 workgroup) at
//! the pace of the slowest, so `simd` is the mean over groups of 8 of (max iterations) /
//! (mean iterations).
//!
//! `cargo run --release --example traversal_stats -- SCENE.ron [SIZE] [--unsnapped]` (default
//! 128: a SIZE x SIZE image, one sample per pixel, one bounce and one shadow ray per hit, ray
//! origins offset as shaders/lib/sampling.wgsl does).

use glam::Vec3;
use passgraph::scene::bvh_octants::octant_copies;
use passgraph::scene::intersect::{PreparedRay, intersect_box, intersect_triangle};
use passgraph::scene::{BvhNode, Ray, SceneGpu, Triangle, load_scene};
use std::path::Path;

#[derive(Default, Clone)]
struct Counts {
    nodes: u64,
    boxes_hit: u64,
    leaves_hit: u64,
    triangles: u64,
    triangle_hits: u64,
    iterations: u64,
    /// Per loop iteration: bit 0 a triangle test, bit 1 a node visit.
    trace: Vec<u8>,
}

impl std::ops::AddAssign for Counts {
    fn add_assign(&mut self, o: Counts) {
        self.trace.clear();
        self.nodes += o.nodes;
        self.boxes_hit += o.boxes_hit;
        self.leaves_hit += o.leaves_hit;
        self.triangles += o.triangles;
        self.triangle_hits += o.triangle_hits;
        self.iterations += o.iterations;
    }
}

/// bvh.wgsl's loop, counted: returns the hit (t, triangle) or None.
fn traverse(
    nodes: &[BvhNode],
    triangles: &[Triangle],
    ray: &Ray,
    tmin: f32,
    tmax: f32,
    any: bool,
    c: &mut Counts,
) -> Option<(f32, u32)> {
    let r = PreparedRay::new(ray);
    let mut best: Option<(f32, u32)> = None;
    let (mut node, mut next, mut end) = (0usize, 0usize, 0usize);
    while node < nodes.len() || next < end {
        c.iterations += 1;
        c.trace.push(0);
        if next < end {
            *c.trace.last_mut().unwrap() |= 1;
            let k = next;
            c.triangles += 1;
            if let Some(h) = intersect_triangle(&r, &triangles[k].vertices(), tmin, tmax) {
                c.triangle_hits += 1;
                if best.is_none_or(|b| h.t < b.0 || (h.t == b.0 && (k as u32) < b.1)) {
                    best = Some((h.t, k as u32));
                }
                if any {
                    return best;
                }
            }
            next = k + 1;
        }
        if next < end || node >= nodes.len() {
            continue;
        }
        let n = &nodes[node];
        c.nodes += 1;
        *c.trace.last_mut().unwrap() |= 2;
        let reach = best.map_or(tmax, |b| b.0);
        if !intersect_box(&r, n.lo.into(), n.hi.into(), tmin, reach) {
            node = if n.count > 0 {
                node + 1
            } else {
                (n.a as usize).max(node + 1)
            };
            continue;
        }
        c.boxes_hit += 1;
        if n.count > 0 {
            c.leaves_hit += 1;
            next = n.a as usize;
            end = next + n.count as usize;
        }
        node += 1;
    }
    best
}

/// `--unsnapped`: each box as the build made it before snapping to the grid (the triangles'
/// bounds grown by 2^-21 of their largest coordinate), to see what the grid costs.
fn unsnap(nodes: &mut [BvhNode], triangles: &[Triangle], i: usize) -> (Vec3, Vec3, usize) {
    let node = nodes[i];
    let (lo, hi, end) = if node.count > 0 {
        let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        for t in &triangles[node.a as usize..(node.a + node.count) as usize] {
            for p in t.vertices() {
                (lo, hi) = (lo.min(p), hi.max(p));
            }
        }
        (lo, hi, i + 1)
    } else {
        let (l0, h0, left_end) = unsnap(nodes, triangles, i + 1);
        let (l1, h1, end) = unsnap(nodes, triangles, left_end);
        (l0.min(l1), h0.max(h1), end)
    };
    let pad = Vec3::splat(lo.abs().max(hi.abs()).max_element() / (1u32 << 21) as f32);
    nodes[i].lo = (lo - pad).into();
    nodes[i].hi = (hi + pad).into();
    (lo, hi, end)
}

/// SplitMix64, so runs repeat.
struct Rng(u64);
impl Rng {
    fn unit(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// shaders/lib/sampling.wgsl's offset_ray: 256 ulps along the normal, or n / 65536 near 0.
fn offset_ray(p: Vec3, n: Vec3) -> Vec3 {
    let mut out = p;
    for k in 0..3 {
        let of = (256.0 * n[k]) as i32;
        let of = if p[k] < 0.0 { -of } else { of };
        out[k] = if p[k].abs() < 1.0 / 32.0 {
            p[k] + n[k] / 65536.0
        } else {
            f32::from_bits((p[k].to_bits() as i32).wrapping_add(of) as u32)
        };
    }
    out
}

fn cosine(n: Vec3, u1: f32, u2: f32) -> Vec3 {
    let t = if n.x.abs() > 0.5 { Vec3::Y } else { Vec3::X };
    let a = n.cross(t).normalize();
    let b = n.cross(a);
    let r = u1.sqrt();
    let phi = 2.0 * std::f32::consts::PI * u2;
    (a * (r * phi.cos()) + b * (r * phi.sin()) + n * (1.0 - u1).max(0.0).sqrt()).normalize()
}

struct Kind {
    name: &'static str,
    rays: u64,
    c: Counts,
    /// Per group of 8 lanes: sum of max iterations and of iterations.
    group_max: u64,
    group_sum: u64,
    /// Lockstep over groups of 8 lanes: iterations where some lane tests a triangle / visits a node.
    lock_tri: u64,
    lock_node: u64,
}

impl Kind {
    fn new(name: &'static str) -> Kind {
        Kind {
            name,
            rays: 0,
            c: Counts::default(),
            group_max: 0,
            group_sum: 0,
            lock_tri: 0,
            lock_node: 0,
        }
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let path = args
        .get(1)
        .map_or("scenes/cornell/scene.ron", |s| s.as_str());
    let size: u32 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(128);
    let scene = load_scene(Path::new(path)).expect("scene");
    let mut gpu = SceneGpu::build(&scene.mesh);
    if std::env::args().any(|a| a == "--unsnapped") {
        unsnap(&mut gpu.nodes, &gpu.triangles, 0);
        let root = gpu.occluder_root as usize;
        gpu.octant_nodes = octant_copies(&gpu.nodes, root > 0 && root < gpu.nodes.len());
    }
    let camera = scene.camera.to_gpu(size, size);
    let tris = &gpu.triangles;
    println!(
        "{path}: {} triangles, {} nodes, {} leaves, depth {}, max leaf {}",
        tris.len(),
        gpu.bvh.node_count,
        gpu.bvh.leaf_count,
        gpu.bvh.max_depth,
        gpu.bvh.max_leaf_triangles
    );
    let mut kinds = ["primary", "bounce", "shadow"].map(Kind::new);
    let mut rng = Rng(1);
    let (mut refill_max, mut separate_max, mut lane_sum) = (0u64, 0u64, 0u64);
    for y in 0..size {
        for x0 in (0..size).step_by(8) {
            let mut group: [Vec<Vec<u8>>; 3] = Default::default();
            for g in group.iter_mut() {
                g.resize(8, Vec::new());
            }
            for lane in 0..8 {
                let x = x0 + lane;
                let dir =
                    camera.ray_direction(size, size, x as f32 + rng.unit(), y as f32 + rng.unit());
                let ray = Ray {
                    origin: camera.eye.into(),
                    dir,
                };
                let mut c = Counts::default();
                let hit = traverse(gpu.nodes_for(&ray), tris, &ray, 0.0, 3.0e38, false, &mut c);
                group[0][lane as usize] = c.trace.clone();
                kinds[0].rays += 1;
                kinds[0].c += c;
                let Some((t, k)) = hit else { continue };
                let v = tris[k as usize].vertices();
                let mut n = (v[1] - v[0]).cross(v[2] - v[0]).normalize();
                if n.dot(dir) > 0.0 {
                    n = -n;
                }
                let origin = offset_ray(ray.origin + t * dir, n);
                // Shadow ray to a point on each light.
                for light in &gpu.lights {
                    let (a, b) = (rng.unit(), rng.unit());
                    let (a, b) = if light.is_parallelogram() || a + b <= 1.0 {
                        (a, b)
                    } else {
                        (1.0 - a, 1.0 - b)
                    };
                    let end =
                        Vec3::from(light.p0) + a * Vec3::from(light.e1) + b * Vec3::from(light.e2);
                    let mut c = Counts::default();
                    let shadow = Ray {
                        origin,
                        dir: end - origin,
                    };
                    traverse(
                        gpu.nodes_for(&shadow),
                        tris,
                        &shadow,
                        0.0,
                        1.0 - 1e-4,
                        true,
                        &mut c,
                    );
                    group[2][lane as usize].extend_from_slice(&c.trace);
                    kinds[2].rays += 1;
                    kinds[2].c += c;
                }
                let d = cosine(n, rng.unit(), rng.unit());
                let mut c = Counts::default();
                let bounce = Ray { origin, dir: d };
                traverse(
                    gpu.nodes_for(&bounce),
                    tris,
                    &bounce,
                    0.0,
                    3.0e38,
                    false,
                    &mut c,
                );
                group[1][lane as usize] = c.trace.clone();
                kinds[1].rays += 1;
                kinds[1].c += c;
            }
            // Refill model: each lane runs its rays back to back, the group waits once.
            let totals: Vec<usize> = (0..8)
                .map(|l| group.iter().map(|g| g[l].len()).sum())
                .collect();
            refill_max += 8 * *totals.iter().max().unwrap() as u64;
            separate_max += 8 * group
                .iter()
                .map(|g| g.iter().map(|t| t.len()).max().unwrap())
                .sum::<usize>() as u64;
            lane_sum += totals.iter().sum::<usize>() as u64;
            for (kind, g) in kinds.iter_mut().zip(group) {
                let len = g.iter().map(|t| t.len()).max().unwrap();
                kind.group_max += 8 * len as u64;
                kind.group_sum += g.iter().map(|t| t.len() as u64).sum::<u64>();
                for i in 0..len {
                    let m = g
                        .iter()
                        .fold(0u8, |m, t| m | t.get(i).copied().unwrap_or(0));
                    kind.lock_tri += (m & 1) as u64;
                    kind.lock_node += (m >> 1) as u64;
                }
            }
        }
    }
    println!(
        "per ray:  nodes  boxes_hit  leaves_hit  triangles  tri_hits  iterations  simd(max/mean of 8)  lockstep per ray: tri-iters node-iters"
    );
    for k in &kinds {
        let r = k.rays.max(1) as f64;
        println!(
            "{:8} {:6.2} {:10.2} {:11.2} {:10.2} {:9.2} {:11.2} {:8.2}  {:8.2} {:8.2}  ({} rays)",
            k.name,
            k.c.nodes as f64 / r,
            k.c.boxes_hit as f64 / r,
            k.c.leaves_hit as f64 / r,
            k.c.triangles as f64 / r,
            k.c.triangle_hits as f64 / r,
            k.c.iterations as f64 / r,
            k.group_max as f64 / k.group_sum.max(1) as f64,
            8.0 * k.lock_tri as f64 / r,
            8.0 * k.lock_node as f64 / r,
            k.rays
        );
    }
    println!(
        "all rays of a lane, lockstep cost / lane mean: rays one after the other {:.2}, refilled {:.2}",
        separate_max as f64 / lane_sum as f64,
        refill_max as f64 / lane_sum as f64
    );
}
