// Reprojection (graphs/pathtracer-reproject.ron): after a camera move, a pixel whose primary hit
// lies on the surface that a pixel of the previous frame saw (that pixel's hit point close to
// its plane, a similar normal, the same material) continues that pixel's accumulation instead
// of restarting. accumulate works in place on `result` as in graphs/pathtracer.ron; three entry
// points around it:
//   snapshot:  on a move only, result and compensation -> snapshot (the previous view's);
//   reproject: on a move only, the snapshot gathered through this frame's hits -> result
//              (zeros where nothing matches); every frame, the guide each pixel continues;
//   commit:    after accumulate, the guides the next frame's reproject reads.
// Without a move (camera == camera_previous) the buffers are left alone: the gather costs
// nothing then (a masked-off loop), only on the frame after a move. After a reset
// (camera_previous all zeros) every pixel restarts.
// A pixel's guide describes the surface its accumulated samples saw: the first sample's hit
// point, normal and material, or "mixed" once a sample lands on another material or plane
// (silhouettes, the light's edge). Only pure pixels lend their history: a mean of light and
// ceiling must not continue on a pixel that now sees only ceiling. Diffuse shading is
// view-independent, so a reused mean is still right; view-dependent light (glossy
// highlights) would ghost.
#include "lib/provided_scene.wgsl"
#include "lib/primary.wgsl"
#include "lib/ray_texture.wgsl"

struct Params {
    // Largest distance of the previous hit point from this hit's plane, relative to this
    // hit's distance from the eye.
    plane_tolerance: f32,
    // Smallest cosine between this hit's normal and the previous one.
    normal_cosine: f32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var rays: texture_storage_2d_array<rgba32float, read>;
// snapshot's input and reproject's output: the accumulation accumulate continues in place.
@group(0) @binding(2) var<storage, read> result: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> compensation: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read_write> result_out: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read_write> compensation_out: array<vec4<f32>>;
// The previous view's accumulation, copied on a move before the gather overwrites it.
@group(0) @binding(6) var<storage, read_write> snapshot: array<vec4<f32>>;
@group(0) @binding(7) var<storage, read_write> snapshot_compensation: array<vec4<f32>>;
// The guides: a hit point, and a geometric normal with w = material index + 2 (1: a miss;
// 0: no sample yet; -1: mixed). reproject reads last frame's, commit writes this frame's.
@group(0) @binding(8) var guide_position: texture_storage_2d<rgba32float, read>;
@group(0) @binding(9) var guide_normal: texture_storage_2d<rgba32float, read>;
@group(0) @binding(10) var guide_position_out: texture_storage_2d<rgba32float, write>;
@group(0) @binding(11) var guide_normal_out: texture_storage_2d<rgba32float, write>;
// The guide of the history each pixel continues (same encoding; w = 0 for a fresh start).
@group(0) @binding(12) var carried_position: texture_storage_2d<rgba32float, write>;
@group(0) @binding(13) var carried_normal: texture_storage_2d<rgba32float, write>;
@group(0) @binding(14) var carried_position_in: texture_storage_2d<rgba32float, read>;
@group(0) @binding(15) var carried_normal_in: texture_storage_2d<rgba32float, read>;

// Planes of `result`: L0, direct, indirect, ambient, sum.
const PLANES: u32 = 5u;

// A pixel and its four neighbours.
const NEIGHBOURHOOD = array<vec2<i32>, 5>(
    vec2<i32>(0, 0), vec2<i32>(1, 0), vec2<i32>(-1, 0), vec2<i32>(0, 1), vec2<i32>(0, -1),
);

struct HitPoint {
    p: vec3<f32>,
    n: vec3<f32>,
    // Material index + 2; 1 for a miss (the guides' encoding).
    material: f32,
}

fn hit_point(pixel: vec2<i32>) -> HitPoint {
    let ray = load_primary(pixel);
    if ray.triangle == NO_HIT {
        return HitPoint(vec3<f32>(0.0), vec3<f32>(0.0), 1.0);
    }
    let tri = scene_triangle(triangles, ray.triangle);
    let p = (1.0 - ray.u - ray.v) * tri.p0 + ray.u * tri.p1 + ray.v * tri.p2;
    let n = normalize(cross(tri.p1 - tri.p0, tri.p2 - tri.p0));
    return HitPoint(p, n, f32(tri.material) + 2.0);
}

fn same_camera(a: Camera, b: Camera) -> bool {
    return all(a.eye == b.eye) && all(a.forward == b.forward) && all(a.right == b.right)
        && all(a.up == b.up);
}

// No source pixel: the history restarts.
const NO_SOURCE = vec2<i32>(-1);

// The pixel of the previous frame whose history pixel `pixel` continues, or NO_SOURCE.
fn source_pixel(pixel: vec2<i32>, size: vec2<u32>) -> vec2<i32> {
    if same_camera(camera, camera_previous) {
        return pixel;
    }
    let x = hit_point(pixel);
    let previous = camera_previous;
    if x.material == 1.0 || all(previous.forward == vec3<f32>(0.0)) {
        return NO_SOURCE;
    }
    // Where x was on the previous image: forward is a unit vector, right and up are scaled
    // so that forward + sx right + sy up spans the image with sx, sy in [-1, 1].
    let d = x.p - previous.eye;
    let depth = dot(d, previous.forward);
    if depth <= 0.0 {
        return NO_SOURCE;
    }
    let sx = dot(d, previous.right) / (dot(previous.right, previous.right) * depth);
    let sy = dot(d, previous.up) / (dot(previous.up, previous.up) * depth);
    let at = vec2<f32>((sx + 1.0) * 0.5 * f32(size.x), (1.0 - sy) * 0.5 * f32(size.y));
    if any(at < vec2<f32>(0.0)) || any(at >= vec2<f32>(size)) {
        return NO_SOURCE;
    }
    let q = vec2<i32>(at);
    // q and its four neighbours: a pixel next to an edge in the previous view may cover the
    // edge now (the view moved by a fraction of a pixel), and its pure history would then
    // stand for a mixed pixel (the light's rim stays full brightness).
    let last = vec2<i32>(size) - 1;
    for (var k = 0; k < 5; k++) {
        let r = clamp(q + NEIGHBOURHOOD[k], vec2<i32>(0), last);
        if !same_surface(x, textureLoad(guide_position, r).xyz, textureLoad(guide_normal, r)) {
            return NO_SOURCE;
        }
    }
    return q;
}

// Whether guide y describes x's surface: the same material and, for hits, a point close to
// x's plane and a similar normal.
fn same_surface(x: HitPoint, y_p: vec3<f32>, y_n: vec4<f32>) -> bool {
    if x.material == 1.0 {
        return y_n.w == 1.0;
    }
    let reach = length(x.p - camera.eye);
    let on_plane = abs(dot(x.n, y_p - x.p)) <= params.plane_tolerance * reach;
    return y_n.w == x.material && on_plane && dot(x.n, y_n.xyz) >= params.normal_cosine;
}

@compute @workgroup_size(8, 8)
fn snapshot_view(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(frame.width, frame.height);
    if any(id.xy >= size) || same_camera(camera, camera_previous) {
        return;
    }
    let plane = size.x * size.y;
    let i = id.y * size.x + id.x;
    for (var c = 0u; c < PLANES; c++) {
        snapshot[c * plane + i] = result[c * plane + i];
        snapshot_compensation[c * plane + i] = compensation[c * plane + i];
    }
}

@compute @workgroup_size(8, 8)
fn reproject(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(frame.width, frame.height);
    if any(id.xy >= size) {
        return;
    }
    let plane = size.x * size.y;
    let i = id.y * size.x + id.x;
    let q = source_pixel(vec2<i32>(id.xy), size);
    let found = q.x >= 0;
    let source = u32(q.y) * size.x + u32(q.x);
    if !same_camera(camera, camera_previous) {
        for (var c = 0u; c < PLANES; c++) {
            var mean = vec4<f32>(0.0);
            var error = vec4<f32>(0.0);
            if found {
                mean = snapshot[c * plane + source];
                error = snapshot_compensation[c * plane + source];
            }
            result_out[c * plane + i] = mean;
            compensation_out[c * plane + i] = error;
        }
    }
    var guide_p = vec4<f32>(0.0);
    var guide_n = vec4<f32>(0.0);
    if found {
        guide_p = textureLoad(guide_position, q);
        guide_n = textureLoad(guide_normal, q);
    }
    textureStore(carried_position, vec2<i32>(id.xy), guide_p);
    textureStore(carried_normal, vec2<i32>(id.xy), guide_n);
}

@compute @workgroup_size(8, 8)
fn commit(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(frame.width, frame.height);
    if any(id.xy >= size) {
        return;
    }
    // The guide of the history after this frame's sample x.
    let pixel = vec2<i32>(id.xy);
    let x = hit_point(pixel);
    var guide_p = textureLoad(carried_position_in, pixel);
    var guide_n = textureLoad(carried_normal_in, pixel);
    if guide_n.w == 0.0 {
        guide_p = vec4<f32>(x.p, 0.0);
        guide_n = vec4<f32>(x.n, x.material);
    } else if guide_n.w > 0.0 && !same_surface(x, guide_p.xyz, guide_n) {
        guide_n.w = -1.0;
    }
    textureStore(guide_position_out, pixel, guide_p);
    textureStore(guide_normal_out, pixel, guide_n);
}
