//! Ray queries on the CPU, mirroring `shaders/lib/bvh.wgsl` operation for operation: the
//! watertight ray/triangle test (Woop, Benthin, Wald 2013), a conservative slab test, and the
//! stackless traversal of the threaded BVH. Also the brute-force oracle the tests compare with.
//!
//! Every computation here avoids infinities and NaN for finite input (within 1e14 of the ray
//! origin), because WGSL lets a GPU return anything for an operation that would produce them.
//! The triangle test also rejects hits nearer than the bound on t's own rounding error, so a
//! ray never hits the surface it leaves (tests/robust_render.rs counts it).

use super::bvh::is_degenerate;
use super::gpu_layout::{BvhNode, Triangle};
use glam::{BVec3, Vec3};

/// A ray `origin + t * dir`. `dir` need not be normalised but must be finite and nonzero.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub origin: Vec3,
    pub dir: Vec3,
}

/// A hit: the ray parameter, the barycentrics of `p1` (`u`) and `p2` (`v`) so that the point is
/// `(1 - u - v) p0 + u p1 + v p2`, and the triangle's index in BVH order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub t: f32,
    pub u: f32,
    pub v: f32,
    pub triangle: u32,
}

/// A hit on one triangle, before it is known which triangle is nearest.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    pub t: f32,
    pub u: f32,
    pub v: f32,
}

/// Room given to both ends of each slab (2 γ₃ in pbrt's notation). Each slab distance is off by
/// at most three roundings, so growing the far end alone would keep the box test from missing
/// a ray that touches the box; growing the near end too keeps a box whose near end rounds up
/// past the nearest hit so far from being culled when it holds an equally near triangle (a
/// neighbour across a shared edge), so ties resolve by index as in brute force.
const SLAB_SLACK: f32 = 2.0 * 3.0 * f32::EPSILON * 0.5 / (1.0 - 3.0 * f32::EPSILON * 0.5);

/// Per-ray values every box and triangle test shares.
#[derive(Clone, Copy, Debug)]
pub struct PreparedRay {
    origin: Vec3,
    /// 1/dir on the axes that are not flat, 0 on flat ones.
    inv_dir: Vec3,
    /// Axes along which the ray does not move (|dir| below the smallest normal f32, which
    /// covers +0 and -0): the slab test asks whether the origin is inside the slab instead
    /// of dividing by zero.
    flat: BVec3,
    /// The watertight test's axis permutation: `kz` is the dominant axis.
    kx: usize,
    ky: usize,
    kz: usize,
    /// The shear that maps the ray onto +z: (dir[kx]/dir[kz], dir[ky]/dir[kz], 1/dir[kz]).
    shear: Vec3,
}

impl PreparedRay {
    pub fn new(ray: &Ray) -> PreparedRay {
        let d = ray.dir;
        let flat = d.abs().cmplt(Vec3::splat(f32::MIN_POSITIVE));
        // Divide by 1 on flat axes: no infinity is ever formed.
        let inv_dir = Vec3::select(
            flat,
            Vec3::ZERO,
            Vec3::ONE / Vec3::select(flat, Vec3::ONE, d),
        );

        let a = d.abs();
        let kz = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        // Keeps the winding, so the sign of the determinant tells the side.
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let shear = Vec3::new(d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]);
        PreparedRay {
            origin: ray.origin,
            inv_dir,
            flat,
            kx,
            ky,
            kz,
            shear,
        }
    }
}

/// `a * b` exactly, as the rounded product and its error (`bvh_two_product` in bvh.wgsl, which
/// gets the same error from exact products of halves because WGSL's fma need not be fused).
fn two_product(a: f32, b: f32) -> (f32, f32) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// `a * b - c * d` with the sign of the exact result, exactly 0 only when that is, and relative
/// error at most 2 ulps: `p_ab - p_cd` is exact when the products are within a factor of 2
/// (Sterbenz) and dominates the error terms otherwise. Swapping `(a, b)` with `(c, d)` negates
/// it exactly, so neighbours across a shared edge see it with opposite signs. The
/// single-precision stand-in for the paper's double-precision fallback, used for every edge
/// function so that no rounding can make two neighbours both miss; bit for bit what bvh.wgsl
/// computes.
fn difference_of_products(a: f32, b: f32, c: f32, d: f32) -> f32 {
    let (ab, ab_error) = two_product(a, b);
    let (cd, cd_error) = two_product(c, d);
    (ab - cd) + (ab_error - cd_error)
}

/// pbrt's gamma(n) = n u / (1 - n u) with u = 2^-24: a bound on the relative error of n
/// roundings. Const-evaluated in f32; bvh.wgsl spells the same f32 values.
const fn gamma(n: f32) -> f32 {
    let u = f32::EPSILON * 0.5;
    n * u / (1.0 - n * u)
}
const GAMMA2: f32 = gamma(2.0);
const GAMMA3: f32 = gamma(3.0);
const GAMMA5: f32 = gamma(5.0);

/// A bound on the rounding error of the t the triangle test computes (Pharr, Jakob and
/// Humphreys, PBR 3rd ed., §3.9.6, with the unscaled depths `max_z` bounding the shear's
/// error, so that the direction need not be normalised): a hit with t no larger than this may
/// lie behind the origin. `max_x`, `max_y`: largest sheared |x|, |y| of the vertices; `max_z`:
/// largest |depth| before scaling by 1/dir[kz]; `max_zt`: after; `max_e`: largest |edge
/// function|; `rcp`: 1 / det.
fn t_error_bound(max_x: f32, max_y: f32, max_z: f32, max_zt: f32, max_e: f32, rcp: f32) -> f32 {
    let delta_x = GAMMA5 * (max_x + max_z);
    let delta_y = GAMMA5 * (max_y + max_z);
    let delta_z = GAMMA3 * max_zt;
    let delta_e = 2.0 * (GAMMA2 * max_x * max_y + delta_y * max_x + delta_x * max_y);
    3.0 * (GAMMA3 * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * rcp.abs()
}

/// The watertight ray/triangle test, two-sided, with no epsilon: a hit with t in (tmin, tmax).
/// A hit nearer than the bound on t's own rounding error ([`t_error_bound`]) is rejected as
/// pbrt does: it may be the surface the ray starts on (self-intersection), and the bound is
/// what a ray origin offset off that surface cannot be trusted to beat (it grows with the
/// triangle's size relative to the origin, e.g. on a floor through a coordinate plane).
pub fn intersect_triangle(
    ray: &PreparedRay,
    vertices: &[Vec3; 3],
    tmin: f32,
    tmax: f32,
) -> Option<TriangleHit> {
    let (kx, ky, kz) = (ray.kx, ray.ky, ray.kz);
    let s = ray.shear;
    let a = vertices[0] - ray.origin;
    let b = vertices[1] - ray.origin;
    let c = vertices[2] - ray.origin;
    let ax = a[kx] - s.x * a[kz];
    let ay = a[ky] - s.y * a[kz];
    let bx = b[kx] - s.x * b[kz];
    let by = b[ky] - s.y * b[kz];
    let cx = c[kx] - s.x * c[kz];
    let cy = c[ky] - s.y * c[kz];

    // Scaled barycentrics: each is the signed area spanned by the origin and one edge.
    let u = difference_of_products(cx, by, cy, bx);
    let v = difference_of_products(ax, cy, ay, cx);
    let w = difference_of_products(bx, ay, by, ax);
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + v + w;
    if det == 0.0 {
        return None;
    }
    let az = s.z * a[kz];
    let bz = s.z * b[kz];
    let cz = s.z * c[kz];
    let t_scaled = u * az + v * bz + w * cz;
    let rcp = 1.0 / det;
    let t = t_scaled * rcp;
    if !(t > tmin && t < tmax) {
        return None;
    }
    let max_x = ax.abs().max(bx.abs()).max(cx.abs());
    let max_y = ay.abs().max(by.abs()).max(cy.abs());
    let max_z = a[kz].abs().max(b[kz].abs()).max(c[kz].abs());
    let max_zt = az.abs().max(bz.abs()).max(cz.abs());
    let max_e = u.abs().max(v.abs()).max(w.abs());
    if t <= t_error_bound(max_x, max_y, max_z, max_zt, max_e, rcp) {
        return None;
    }
    Some(TriangleHit {
        t,
        u: v * rcp,
        v: w * rcp,
    })
}

/// Whether the ray meets the box `[lo, hi]` for some t in [tmin, tmax] (inclusive, so a box
/// touching the current nearest hit is still visited: it may hold an equally near triangle
/// with a smaller index).
pub fn intersect_box(ray: &PreparedRay, lo: Vec3, hi: Vec3, tmin: f32, tmax: f32) -> bool {
    let o = ray.origin;
    let outside = o.cmplt(lo) | o.cmpgt(hi);
    if (ray.flat & outside).any() {
        return false;
    }
    let t_lo = (lo - o) * ray.inv_dir;
    let t_hi = (hi - o) * ray.inv_dir;
    let near = t_lo.min(t_hi);
    let far = t_lo.max(t_hi);
    let near = Vec3::select(ray.flat, Vec3::splat(tmin), near - near.abs() * SLAB_SLACK);
    let far = Vec3::select(ray.flat, Vec3::splat(tmax), far + far.abs() * SLAB_SLACK);
    let t0 = tmin.max(near.max_element());
    let t1 = tmax.min(far.min_element());
    t0 <= t1
}

fn node_box(node: &BvhNode) -> (Vec3, Vec3) {
    (node.lo.into(), node.hi.into())
}

/// The next node when the ray misses `node` (at index `i`). `max` keeps the loop finite even on
/// a malformed or zero-padded node array.
fn miss_link(node: &BvhNode, i: usize) -> usize {
    if node.is_leaf() {
        i + 1
    } else {
        (node.a as usize).max(i + 1)
    }
}

/// The triangles of leaf `node`, clamped to the array.
fn leaf_range(node: &BvhNode, triangle_count: usize) -> std::ops::Range<usize> {
    let first = (node.a as usize).min(triangle_count);
    let end = (node.a as usize)
        .saturating_add(node.count as usize)
        .min(triangle_count);
    first..end
}

/// Whether `candidate` on triangle `index` beats `best`: nearer, or as near with a smaller
/// index, so the answer does not depend on the order triangles are visited in.
fn is_nearer(t: f32, index: u32, best: &Option<Hit>) -> bool {
    match best {
        None => true,
        Some(b) => t < b.t || (t == b.t && index < b.triangle),
    }
}

/// The nearest hit with t in (tmin, tmax) (ties to the smaller triangle index), by the
/// stackless traversal `bvh.wgsl` uses.
pub fn closest_hit(
    nodes: &[BvhNode],
    triangles: &[Triangle],
    ray: &Ray,
    tmin: f32,
    tmax: f32,
) -> Option<Hit> {
    let prepared = PreparedRay::new(ray);
    let mut best: Option<Hit> = None;
    let mut i = 0;
    while i < nodes.len() {
        let node = &nodes[i];
        let (lo, hi) = node_box(node);
        let reach = best.map_or(tmax, |b| b.t);
        if !intersect_box(&prepared, lo, hi, tmin, reach) {
            i = miss_link(node, i);
            continue;
        }
        if node.is_leaf() {
            for k in leaf_range(node, triangles.len()) {
                let vertices = triangles[k].vertices();
                if let Some(h) = intersect_triangle(&prepared, &vertices, tmin, tmax) {
                    if is_nearer(h.t, k as u32, &best) {
                        best = Some(Hit {
                            t: h.t,
                            u: h.u,
                            v: h.v,
                            triangle: k as u32,
                        });
                    }
                }
            }
        }
        i += 1;
    }
    best
}

/// Whether anything is hit with t in (tmin, tmax) (shadow and ambient-occlusion rays).
pub fn any_hit(nodes: &[BvhNode], triangles: &[Triangle], ray: &Ray, tmin: f32, tmax: f32) -> bool {
    any_hit_from(nodes, 0, triangles, ray, tmin, tmax)
}

/// As [`any_hit`], over the subtree at node `root` whose miss links end the traversal (the
/// occluders' subtree, `Bvh::build_with_occluders`).
pub fn any_hit_from(
    nodes: &[BvhNode],
    root: usize,
    triangles: &[Triangle],
    ray: &Ray,
    tmin: f32,
    tmax: f32,
) -> bool {
    let prepared = PreparedRay::new(ray);
    let mut i = root;
    while i < nodes.len() {
        let node = &nodes[i];
        let (lo, hi) = node_box(node);
        if !intersect_box(&prepared, lo, hi, tmin, tmax) {
            i = miss_link(node, i);
            continue;
        }
        if node.is_leaf() {
            for k in leaf_range(node, triangles.len()) {
                let vertices = triangles[k].vertices();
                if intersect_triangle(&prepared, &vertices, tmin, tmax).is_some() {
                    return true;
                }
            }
        }
        i += 1;
    }
    false
}

/// The oracle: the nearest hit over every triangle, by the same triangle test and tie rule.
/// Degenerate triangles are skipped, as the BVH leaves them out of every leaf.
pub fn brute_force_closest_hit(
    triangles: &[Triangle],
    ray: &Ray,
    tmin: f32,
    tmax: f32,
) -> Option<Hit> {
    let prepared = PreparedRay::new(ray);
    let mut best: Option<Hit> = None;
    for (k, triangle) in triangles.iter().enumerate() {
        let vertices = triangle.vertices();
        if is_degenerate(&vertices) {
            continue;
        }
        if let Some(h) = intersect_triangle(&prepared, &vertices, tmin, tmax) {
            if is_nearer(h.t, k as u32, &best) {
                best = Some(Hit {
                    t: h.t,
                    u: h.u,
                    v: h.v,
                    triangle: k as u32,
                });
            }
        }
    }
    best
}

/// The oracle for [`any_hit`].
pub fn brute_force_any_hit(triangles: &[Triangle], ray: &Ray, tmin: f32, tmax: f32) -> bool {
    let prepared = PreparedRay::new(ray);
    triangles.iter().any(|triangle| {
        let vertices = triangle.vertices();
        !is_degenerate(&vertices) && intersect_triangle(&prepared, &vertices, tmin, tmax).is_some()
    })
}
