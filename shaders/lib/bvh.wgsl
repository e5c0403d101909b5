// Ray queries against the threaded BVH: closest_hit and any_hit. src/scene/intersect.rs is the
// CPU twin of this file's box and triangle tests, operation for operation, but for the
// triangle test's certain-miss shortcut and the box test of rays with no flat axis
// (bvh_intersect_box_moving, on grid cells, which may enter a box the exact test misses by a
// hair), neither of which can change an answer; it visits the same nodes and triangles (but
// for those hairs), with each leaf's triangles tested right away rather than interleaved with
// node visits (bvh_step), which cannot change an answer either: ties resolve by triangle
// index. Tests hold both to a brute-force oracle.
//
// Contract with the including shader:
//   #include "lib/provided_scene.wgsl"  // first: Triangle, BvhNode, the texel-view readers,
//   #include "lib/bvh.wgsl"              // the overrides scene_triangle_count and
//                                        // scene_node_count, and `triangles` and `bvh`
//   #include "lib/cutout_map.wgsl"   // cut-outs from `map_d` textures (binds scene.shading and
//                                    // scene.textures), or "lib/cutout_map_none.wgsl" (none)
// `dir` need not be normalised but must be finite and nonzero; hits have t in (tmin, tmax)
// and beyond the bound on t's own rounding error (see bvh_intersect_triangle). Names other
// than Hit, closest_hit, any_hit and shadow_hit start with `bvh_`.
//
// Nothing here forms an infinity or a NaN from finite input (vertices within 1e14 of the ray
// origin): WGSL lets a GPU return anything for an operation that would. The edge functions'
// exactness does not depend on whether the compiler fuses multiply-adds or rewrites float
// algebra (see bvh_two_product). On lavapipe the GPU finds the CPU twin's hits, with t within
// 64 ulps of the farthest vertex's distance (WGSL allows fused multiply-adds and inexact
// division), except that at a shared edge or vertex it may pick the neighbour
// (tests/bvh_wgsl.rs, tests/robust_geometry.rs).

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
// 2^-20 (16 u): more than the relative rounding of a grid cell's slab distance (1/dir's, by
// up to 2.5 ulps on a GPU, the difference's, the products', the sum's and the slack's own).
const BVH_CELL_SLACK: f32 = 9.536743e-7;
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
    // The grid node boxes lie on, and what bvh_intersect_box_moving needs: the slab distance
    // of grid cell q is q * cell_scale + cell_offset, within a bound on its rounding; the near
    // (far) end of each slab is the cell at bit near_shift (far_shift) of a packed node's bounds.
    grid: BvhGrid,
    cell_scale: vec3<f32>,
    near_offset: vec3<f32>,
    far_offset: vec3<f32>,
    near_shift: vec3<u32>,
    far_shift: vec3<u32>,
    // The first node of the BVH's copy for the direction (src/scene/bvh_octants.rs: each copy
    // stores the child nearer for its octant first).
    base: u32,
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
    bvh_zero = select(0u, 1u, all(dir == vec3<f32>(0.0)));
    let grid = scene_bvh_grid(bvh);
    let cell_scale = grid.step * inv_dir;
    let cell_offset = (grid.origin - origin) * inv_dir;
    let cell_slack = BVH_CELL_SLACK * (65536.0 * abs(cell_scale) + abs(cell_offset));
    // Along a negative direction the high cell is the near one.
    let near_shift = select(vec3<u32>(0u), vec3<u32>(16u), cell_scale < vec3<f32>(0.0));
    return BvhRay(origin, inv_dir, flat_axes, kx, ky, kz, shear, grid, cell_scale,
                  cell_offset - cell_slack, cell_offset + cell_slack, near_shift,
                  vec3<u32>(16u) - near_shift, scene_node_count * bvh_copy(dir));
}

// The copy a ray along dir traverses, as bvh_octants.rs's copy_of: the copies are the octants
// with an even number of negative signs (bit k: dir[k] < 0); another octant takes the copy with
// the sign of its smallest component (the first of equal ones) flipped.
fn bvh_copy(dir: vec3<f32>) -> u32 {
    var o = select(0u, 1u, dir.x < 0.0) | select(0u, 2u, dir.y < 0.0) | select(0u, 4u, dir.z < 0.0);
    if (countOneBits(o) & 1u) == 1u {
        let a = abs(dir);
        var k = 2u;
        if a.x <= a.y && a.x <= a.z {
            k = 0u;
        } else if a.y <= a.z {
            k = 1u;
        }
        o ^= 1u << k;
    }
    return o >> 1u;
}

// 0 at run time, but not a constant the compiler can see (set by bvh_prepare_ray from the
// direction, which is never zero): see bvh_opaque.
var<private> bvh_zero: u32;

// Returns x, hidden from the compiler's algebra. WGSL lets a compiler treat float arithmetic
// as exact, and Mesa (lavapipe) does: it folds c - (c - a) to a, factors a * b + a * c and
// reorders sums, each of which would undo the exact arithmetic below (the edge functions then
// lose their accuracy: t on a 100 x 2e-4 needle was off by 6.7e4 ulps of its reach).
fn bvh_opaque(x: f32) -> f32 {
    return bitcast<f32>(bitcast<u32>(x) | bvh_zero);
}

// Veltkamp's split: a = hi + lo exactly, each with at most 12 significant bits, so that the
// product of two halves is exact.
fn bvh_split(a: f32) -> vec2<f32> {
    let c = 4097.0 * a;
    let hi = bvh_opaque(c - bvh_opaque(c - a));
    return vec2<f32>(hi, a - hi);
}

// The rounding error of p = a * b, exactly (Dekker's TwoProduct), from the halves of a and b:
// WGSL does not promise that fma is fused (lavapipe's is not), so the error cannot come from
// fma(a, b, -p). Every product here is exact, so fusing any of them changes nothing.
fn bvh_product_error(a: vec2<f32>, b: vec2<f32>, p: f32) -> f32 {
    // Each partial sum is exact in this order only: opaque, so that the compiler neither
    // factors a.x * b.x + a.x * b.y into a.x * b nor reorders the sum.
    let e1 = bvh_opaque(bvh_opaque(a.x * b.x) - p);
    let e2 = bvh_opaque(e1 + bvh_opaque(a.x * b.y));
    let e3 = bvh_opaque(e2 + bvh_opaque(a.y * b.x));
    return e3 + a.y * b.y;
}

// a * b - c * d from the values and their splits, with the sign of the exact result, exactly 0
// only when that is, and relative error at most 2 ulps: (p_ab - p_cd) is exact when the
// products are within a factor of 2 of each other (Sterbenz) and dominates the error terms
// otherwise. Swapping (a, b) with (c, d) negates the result exactly, so two triangles sharing
// an edge always see it with opposite signs. The single-precision stand-in for the paper's
// double-precision fallback, used for every edge function; src/scene/intersect.rs computes the
// same bits.
fn bvh_difference_of_products(
    a: f32, sa: vec2<f32>, b: f32, sb: vec2<f32>,
    c: f32, sc: vec2<f32>, d: f32, sd: vec2<f32>,
) -> f32 {
    // Opaque products: a GPU with a fused fma could otherwise contract p_ab - p_cd into
    // fma(a, b, -p_cd), which already holds a * b's error and would count it twice.
    let ab = bvh_opaque(a * b);
    let cd = bvh_opaque(c * d);
    let error = bvh_product_error(sa, sb, ab) - bvh_product_error(sc, sd, cd);
    return bvh_opaque(ab - cd) + bvh_opaque(error);
}

// pbrt's gamma(n) = n u / (1 - n u), u = 2^-24: the relative error of n roundings (the same
// f32 values as src/scene/intersect.rs).
const BVH_GAMMA2: f32 = 1.192093e-7;
const BVH_GAMMA3: f32 = 1.7881396e-7;
const BVH_GAMMA5: f32 = 2.980233e-7;
// 4 u (u = 2^-24), more than the relative error of a difference of two rounded products
// (2 u (1 + u)), and 4x the smallest normal f32 for products flushed to zero.
const BVH_SIGN_SLACK: f32 = 2.3841858e-7;
const BVH_SIGN_TINY: f32 = 4.7019774e-38;

// A bound on the rounding error of the triangle test's t (PBR 3rd ed., section 3.9.6, with the
// unscaled depths max_z bounding the shear's error so that dir need not be normalised): a hit
// no farther than this may lie behind the origin.
fn bvh_t_error_bound(max_x: f32, max_y: f32, max_z: f32, max_zt: f32, max_e: f32, rcp: f32) -> f32 {
    let delta_x = BVH_GAMMA5 * (max_x + max_z);
    let delta_y = BVH_GAMMA5 * (max_y + max_z);
    let delta_z = BVH_GAMMA3 * max_zt;
    let delta_e = 2.0 * (BVH_GAMMA2 * max_x * max_y + delta_y * max_x + delta_x * max_y);
    return 3.0 * (BVH_GAMMA3 * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * abs(rcp);
}

// Watertight ray/triangle test (Woop, Benthin, Wald 2013), two-sided, no epsilon. A hit
// nearer than the bound on t's own rounding error is rejected, as in pbrt: it may be the
// surface the ray starts on (self-intersection), however the origin was offset.
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

    // A certain miss first, in plain f32: each edge function's sign is certain where its
    // magnitude exceeds the bound on a product difference's rounding (with or without a fused
    // multiply-add; BVH_SIGN_TINY covers products flushed to zero), and two certain opposite
    // signs are a miss in the exact test below too. Most tests are misses, and skipping the
    // exact arithmetic for them changes no answer.
    let pu = vec2<f32>(cx * by, cy * bx);
    let pv = vec2<f32>(ax * cy, ay * cx);
    let pw = vec2<f32>(bx * ay, by * ax);
    let e = vec3<f32>(pu.x - pu.y, pv.x - pv.y, pw.x - pw.y);
    let bound = BVH_SIGN_SLACK * vec3<f32>(abs(pu.x) + abs(pu.y), abs(pv.x) + abs(pv.y), abs(pw.x) + abs(pw.y)) + BVH_SIGN_TINY;
    if (any(e < -bound) && any(e > bound)) {
        return result;
    }

    // Scaled barycentrics: the signed areas spanned by the origin and each edge. Each
    // coordinate takes part in two of them: split once.
    let sax = bvh_split(ax);
    let say = bvh_split(ay);
    let sbx = bvh_split(bx);
    let sby = bvh_split(by);
    let scx = bvh_split(cx);
    let scy = bvh_split(cy);
    let u = bvh_difference_of_products(cx, scx, by, sby, cy, scy, bx, sbx);
    let v = bvh_difference_of_products(ax, sax, cy, scy, ay, say, cx, scx);
    let w = bvh_difference_of_products(bx, sbx, ay, say, by, sby, ax, sax);
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
    let max_x = max(abs(ax), max(abs(bx), abs(cx)));
    let max_y = max(abs(ay), max(abs(by), abs(cy)));
    let max_z = max(abs(a[ray.kz]), max(abs(b[ray.kz]), abs(c[ray.kz])));
    let max_zt = max(abs(az), max(abs(bz), abs(cz)));
    let max_e = max(abs(u), max(abs(v), abs(w)));
    if (t <= bvh_t_error_bound(max_x, max_y, max_z, max_zt, max_e, rcp)) {
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

// The box test of rays with no flat axis (every 1/dir finite and nonzero: no slab needs the
// origin-inside case), straight from a packed node's grid cells q: the slab distance
// (origin + q step - o) / dir is q * cell_scale + cell_offset (per ray: step * inv_dir, exact
// for a power-of-two step, and (origin - o) * inv_dir), no decoding, and the direction's sign
// says which cell is the near end, so no min and max. Its rounding error is below
// BVH_CELL_SLACK * (65536 |cell_scale| + |cell_offset|) (bvh_prepare_ray): that much widens
// every slab (folded into near_offset and far_offset), so the test never misses a box
// bvh_intersect_box meets, and may enter one it misses by a hair.
fn bvh_intersect_box_moving(ray: BvhRay, node: PackedBvhNode, tmin: f32, tmax: f32) -> bool {
    let near = scene_node_cells(node, ray.near_shift) * ray.cell_scale + ray.near_offset;
    let far = scene_node_cells(node, ray.far_shift) * ray.cell_scale + ray.far_offset;
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

// Where a traversal stands: the next node to visit, and the leaf triangles [next, end) still
// to test.
struct BvhWalk {
    node: u32,
    next: u32,
    end: u32,
}

// Visits one node once the current leaf's triangles are all tested: a leaf whose box the ray
// meets queues its triangles. `flat` (whether the ray has a flat axis) picks the box test.
// Interleaving node visits and single triangle tests keeps SIMD lanes busy: a GPU (or
// lavapipe) runs each iteration at the pace of its slowest lane, and a nested loop over a
// leaf's triangles would make every lane wait for the largest leaf.
fn bvh_step(ray: BvhRay, walk: BvhWalk, tmin: f32, tmax: f32, flat: bool) -> BvhWalk {
    if (walk.next < walk.end || walk.node >= scene_node_count) {
        return walk;
    }
    let i = walk.node;
    let packed = scene_packed_node(bvh, ray.base + i);
    let node = scene_node_links(packed);
    var hit: bool;
    // `flat` is a constant in each inlined copy of the loop: no branch per node.
    if (flat) {
        let box = scene_node(bvh, ray.grid, ray.base + i);
        hit = bvh_intersect_box(ray, box.lo, box.hi, tmin, tmax);
    } else {
        hit = bvh_intersect_box_moving(ray, packed, tmin, tmax);
    }
    if (!hit) {
        return BvhWalk(bvh_miss_link(node, i), walk.next, walk.end);
    }
    if (node.count > 0u) {
        let first = min(node.a, scene_triangle_count);
        return BvhWalk(i + 1u, first, first + min(node.count, scene_triangle_count - first));
    }
    return BvhWalk(i + 1u, walk.next, walk.end);
}

// Whether triangle k, hit at barycentrics (u, v), stops the ray. Cut-out surfaces (MTL d < 1
// or map_d: scene_has_cutouts) let it pass with probability 1 - opacity, decided by a hash of
// the triangle and the ray (as pbrt-v4's stochastic alpha test): the same ray always decides
// the same way, so a shadow ray and the closest-hit ray agree, and over a pixel's jittered rays
// and light samples the surface stops the fraction `opacity` of the light. A negative
// Triangle.opacity names a map_d texture, looked up at the hit (cutout_map_opacity).
fn bvh_stops(ray: BvhRay, k: u32, u: f32, v: f32) -> bool {
    if (!scene_has_cutouts) {
        return true;
    }
    var opacity = bitcast<f32>(scene_texel(triangles, 3u * k + 2u).w);
    if (opacity >= 1.0) {
        return true;
    }
    if (opacity < 0.0) {
        opacity = cutout_map_opacity(u32(-1.0 - opacity), k, u, v);
    }
    let o = bitcast<vec3<u32>>(ray.origin);
    let d = bitcast<vec3<u32>>(ray.inv_dir);
    var h = k * 747796405u + 2891336453u;
    for (var i = 0u; i < 3u; i++) {
        h = bvh_hash(h ^ o[i]);
        h = bvh_hash(h ^ d[i]);
    }
    return f32(h >> 8u) * (1.0 / 16777216.0) < opacity;
}

// PCG's output permutation (rng.wgsl's pcg_hash, which not every includer of this file has).
fn bvh_hash(x: u32) -> u32 {
    let s = x * 747796405u + 2891336453u;
    let w = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
    return (w >> 22u) ^ w;
}

// The nearest hit with t in (tmin, tmax); ties go to the smaller triangle index, so the
// answer does not depend on the order triangles are visited in.
// Rays this invocation traced: passes that count rays add it to their `ray_count` buffer.
var<private> bvh_rays_traced: u32;

fn closest_hit(origin: vec3<f32>, dir: vec3<f32>, tmin: f32, tmax: f32) -> Hit {
    bvh_rays_traced += 1u;
    let ray = bvh_prepare_ray(origin, dir);
    // Two copies of the loop, one per box test: only rays with a flat axis (rare) need the
    // slower one, and a SIMD group runs that copy only if one of its lanes has such a ray.
    if (any(ray.flat_axes)) {
        return bvh_closest_hit(ray, tmin, tmax, true);
    }
    return bvh_closest_hit(ray, tmin, tmax, false);
}

// closest_hit's loop; `flat` says which box test (see bvh_step). Each iteration tests at most
// one triangle and visits at most two nodes: node visits outnumber triangle tests about ten to
// one, and a second visit costs less than another trip round the loop.
fn bvh_closest_hit(ray: BvhRay, tmin: f32, tmax: f32, flat: bool) -> Hit {
    var best = Hit(tmax, 0.0, 0.0, BVH_NO_HIT);
    var walk = BvhWalk(0u, 0u, 0u);
    while (walk.node < scene_node_count || walk.next < walk.end) {
        if (walk.next < walk.end) {
            let k = walk.next;
            let p = scene_triangle_vertices(triangles, k);
            let h = bvh_intersect_triangle(ray, p[0], p[1], p[2], tmin, tmax);
            if (h.hit && (h.t < best.t || (h.t == best.t && k < best.triangle)) && bvh_stops(ray, k, h.u, h.v)) {
                best = Hit(h.t, h.u, h.v, k);
            }
            walk.next = k + 1u;
        }
        walk = bvh_step(ray, bvh_step(ray, walk, tmin, best.t, flat), tmin, best.t, flat);
    }
    return best;
}

// Whether anything is hit with t in (tmin, tmax): ambient-occlusion rays, any ray.
fn any_hit(origin: vec3<f32>, dir: vec3<f32>, tmin: f32, tmax: f32) -> bool {
    return bvh_any_hit_from(0u, origin, dir, tmin, tmax);
}

// Whether a shadow ray, a segment from a point of the scene toward a point of a light, is
// blocked: any_hit over the triangles that can block one, the subtree at scene_occluder_root
// (src/scene/hull.rs says why the others never can).
fn shadow_hit(origin: vec3<f32>, dir: vec3<f32>, tmin: f32, tmax: f32) -> bool {
    return bvh_any_hit_from(scene_occluder_root, origin, dir, tmin, tmax);
}

// any_hit over the subtree at `root`, whose miss links end the traversal.
fn bvh_any_hit_from(root: u32, origin: vec3<f32>, dir: vec3<f32>, tmin: f32, tmax: f32) -> bool {
    bvh_rays_traced += 1u;
    let ray = bvh_prepare_ray(origin, dir);
    if (any(ray.flat_axes)) {
        return bvh_any_hit(ray, root, tmin, tmax, true);
    }
    return bvh_any_hit(ray, root, tmin, tmax, false);
}

// any_hit's loop from node `root`, as bvh_closest_hit's.
fn bvh_any_hit(ray: BvhRay, root: u32, tmin: f32, tmax: f32, flat: bool) -> bool {
    var walk = BvhWalk(root, 0u, 0u);
    while (walk.node < scene_node_count || walk.next < walk.end) {
        if (walk.next < walk.end) {
            let p = scene_triangle_vertices(triangles, walk.next);
            let h = bvh_intersect_triangle(ray, p[0], p[1], p[2], tmin, tmax);
            if (h.hit && bvh_stops(ray, walk.next, h.u, h.v)) {
                return true;
            }
            walk.next = walk.next + 1u;
        }
        walk = bvh_step(ray, bvh_step(ray, walk, tmin, tmax, flat), tmin, tmax, flat);
    }
    return false;
}
