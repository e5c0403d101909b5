// Ray queries against the threaded BVH: closest_hit and any_hit. src/scene/intersect.rs is the
// CPU twin of this file, operation for operation; tests hold both to a brute-force oracle.
//
// Contract with the including shader:
//   #include "lib/scene.wgsl"     // first: Triangle and BvhNode
//   #include "lib/bvh.wgsl"
//   @group(G) @binding(B) var<storage, read> triangles: array<Triangle>;   // scene.triangles
//   @group(G) @binding(C) var<storage, read> bvh: array<BvhNode>;          // scene.bvh
// `dir` need not be normalised but must be finite and nonzero; hits have t in (tmin, tmax).
// Names other than Hit, closest_hit and any_hit start with `bvh_`.
//
// Nothing here forms an infinity or a NaN from finite input: WGSL lets a GPU return anything
// for an operation that would.

// A hit: ray parameter t, barycentrics u (of p1) and v (of p2), so the point is
// (1 - u - v) p0 + u p1 + v p2, and the triangle's index. On a miss triangle is BVH_NO_HIT
// and t is tmax.
struct Hit {
    t: f32,
    u: f32,
    v: f32,
    triangle: u32,
}

const BVH_NO_HIT: u32 = 0xffffffffu;
// 2 gamma_3 (pbrt): each slab distance is off by at most three roundings. Growing both ends of
// each slab by this much means a box the ray touches is never missed, nor culled when it holds
// a triangle exactly as near as the best hit so far (ties resolve by index).
const BVH_SLAB_SLACK: f32 = 3.5762793e-7;
// Below the smallest normal f32 a direction component counts as 0 (this covers -0): the slab
// test then asks whether the origin lies inside the slab instead of dividing by zero.
const BVH_MIN_NORMAL: f32 = 1.17549435e-38;

struct BvhRay {
    origin: vec3<f32>,
    // 1/dir on moving axes, 0 on flat ones.
    inv_dir: vec3<f32>,
    flat_axes: vec3<bool>,
    // The watertight test's permutation (kz: the dominant axis) and shear
    // (dir[kx]/dir[kz], dir[ky]/dir[kz], 1/dir[kz]).
    kx: u32,
    ky: u32,
    kz: u32,
    shear: vec3<f32>,
}

struct BvhTriangleHit {
    hit: bool,
    t: f32,
    u: f32,
    v: f32,
}

fn bvh_prepare_ray(origin: vec3<f32>, dir: vec3<f32>) -> BvhRay {
    let flat_axes = abs(dir) < vec3<f32>(BVH_MIN_NORMAL);
    // select(if_false, if_true, condition): divide by 1 on flat axes, then store 0 there.
    let safe_dir = select(dir, vec3<f32>(1.0), flat_axes);
    let inv_dir = select(vec3<f32>(1.0) / safe_dir, vec3<f32>(0.0), flat_axes);

    let a = abs(dir);
    var kz = 2u;
    if (a.x >= a.y && a.x >= a.z) {
        kz = 0u;
    } else if (a.y >= a.z) {
        kz = 1u;
    }
    var kx = (kz + 1u) % 3u;
    var ky = (kx + 1u) % 3u;
    // Keeps the winding, so the determinant's sign tells the side.
    if (dir[kz] < 0.0) {
        let k = kx;
        kx = ky;
        ky = k;
    }
    let shear = vec3<f32>(dir[kx] / dir[kz], dir[ky] / dir[kz], 1.0 / dir[kz]);
    return BvhRay(origin, inv_dir, flat_axes, kx, ky, kz, shear);
}

// a * b - c * d with the sign of the exact result, and exactly 0 only when that is (Kahan's
// algorithm; relative error at most 2 ulps when fma is fused). The single-precision stand-in
// for the paper's double-precision fallback, used for every edge function.
fn bvh_difference_of_products(a: f32, b: f32, c: f32, d: f32) -> f32 {
    let cd = c * d;
    let error = fma(-c, d, cd);
    return fma(a, b, -cd) + error;
}

// Watertight ray/triangle test (Woop, Benthin, Wald 2013), two-sided, no epsilon.
fn bvh_intersect_triangle(
    ray: BvhRay,
    p0: vec3<f32>,
    p1: vec3<f32>,
    p2: vec3<f32>,
    tmin: f32,
    tmax: f32,
) -> BvhTriangleHit {
    var result = BvhTriangleHit(false, 0.0, 0.0, 0.0);
    let s = ray.shear;
    let a = p0 - ray.origin;
    let b = p1 - ray.origin;
    let c = p2 - ray.origin;
    let ax = a[ray.kx] - s.x * a[ray.kz];
    let ay = a[ray.ky] - s.y * a[ray.kz];
    let bx = b[ray.kx] - s.x * b[ray.kz];
    let by = b[ray.ky] - s.y * b[ray.kz];
    let cx = c[ray.kx] - s.x * c[ray.kz];
    let cy = c[ray.ky] - s.y * c[ray.kz];

    // Scaled barycentrics: the signed areas spanned by the origin and each edge.
    let u = bvh_difference_of_products(cx, by, cy, bx);
    let v = bvh_difference_of_products(ax, cy, ay, cx);
    let w = bvh_difference_of_products(bx, ay, by, ax);
    if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) {
        return result;
    }
    let det = u + v + w;
    if (det == 0.0) {
        return result;
    }
    let az = s.z * a[ray.kz];
    let bz = s.z * b[ray.kz];
    let cz = s.z * c[ray.kz];
    let t_scaled = u * az + v * bz + w * cz;
    let rcp = 1.0 / det;
    let t = t_scaled * rcp;
    if (!(t > tmin && t < tmax)) {
        return result;
    }
    result = BvhTriangleHit(true, t, v * rcp, w * rcp);
    return result;
}

// Whether the ray meets [lo, hi] for some t in [tmin, tmax], inclusive: a box touching the
// nearest hit so far may hold an equally near triangle with a smaller index.
fn bvh_intersect_box(ray: BvhRay, lo: vec3<f32>, hi: vec3<f32>, tmin: f32, tmax: f32) -> bool {
    let o = ray.origin;
    let outside = (o < lo) | (o > hi);
    if (any(ray.flat_axes & outside)) {
        return false;
    }
    let t_lo = (lo - o) * ray.inv_dir;
    let t_hi = (hi - o) * ray.inv_dir;
    let near_raw = min(t_lo, t_hi);
    let far_raw = max(t_lo, t_hi);
    let near = select(near_raw - abs(near_raw) * BVH_SLAB_SLACK, vec3<f32>(tmin), ray.flat_axes);
    let far = select(far_raw + abs(far_raw) * BVH_SLAB_SLACK, vec3<f32>(tmax), ray.flat_axes);
    let t0 = max(tmin, max(near.x, max(near.y, near.z)));
    let t1 = min(tmax, min(far.x, min(far.y, far.z)));
    return t0 <= t1;
}

// The node after `node` (at index i) when its box is missed. Interior nodes jump to their
// skip link; max() keeps every step increasing even on a zero-padded node array.
fn bvh_miss_link(node: BvhNode, i: u32) -> u32 {
    if (node.count > 0u) {
        return i + 1u;
    }
    return max(node.a, i + 1u);
}

// The nearest hit with t in (tmin, tmax); ties go to the smaller triangle index, so the
// answer does not depend on the order triangles are visited in.
fn closest_hit(origin: vec3<f32>, dir: vec3<f32>, tmin: f32, tmax: f32) -> Hit {
    let ray = bvh_prepare_ray(origin, dir);
    var best = Hit(tmax, 0.0, 0.0, BVH_NO_HIT);
    let node_count = arrayLength(&bvh);
    let triangle_count = arrayLength(&triangles);
    var i = 0u;
    // Every step increases i, so this runs at most node_count times.
    while (i < node_count) {
        let node = bvh[i];
        if (!bvh_intersect_box(ray, node.lo, node.hi, tmin, best.t)) {
            i = bvh_miss_link(node, i);
            continue;
        }
        if (node.count > 0u) {
            let first = min(node.a, triangle_count);
            let end = first + min(node.count, triangle_count - first);
            for (var k = first; k < end; k = k + 1u) {
                let tri = triangles[k];
                let h = bvh_intersect_triangle(ray, tri.p0, tri.p1, tri.p2, tmin, tmax);
                if (h.hit && (h.t < best.t || (h.t == best.t && k < best.triangle))) {
                    best = Hit(h.t, h.u, h.v, k);
                }
            }
        }
        i = i + 1u;
    }
    return best;
}

// Whether anything is hit with t in (tmin, tmax): shadow and ambient-occlusion rays.
fn any_hit(origin: vec3<f32>, dir: vec3<f32>, tmin: f32, tmax: f32) -> bool {
    let ray = bvh_prepare_ray(origin, dir);
    let node_count = arrayLength(&bvh);
    let triangle_count = arrayLength(&triangles);
    var i = 0u;
    while (i < node_count) {
        let node = bvh[i];
        if (!bvh_intersect_box(ray, node.lo, node.hi, tmin, tmax)) {
            i = bvh_miss_link(node, i);
            continue;
        }
        if (node.count > 0u) {
            let first = min(node.a, triangle_count);
            let end = first + min(node.count, triangle_count - first);
            for (var k = first; k < end; k = k + 1u) {
                let tri = triangles[k];
                if (bvh_intersect_triangle(ray, tri.p0, tri.p1, tri.p2, tmin, tmax).hit) {
                    return true;
                }
            }
        }
        i = i + 1u;
    }
    return false;
}
