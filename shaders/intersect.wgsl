// Intersect: one jittered primary ray per pixel, stored for the lighting passes
// (layer 0: origin, layer 1: direction, layer 2: hit t, u, v, triangle as bits).
#include "lib/scene.wgsl"
#include "lib/rng.wgsl"
#include "lib/bvh.wgsl"
#include "lib/ray_count.wgsl"

// A pass param (see passes/intersect.ron).
override reseed_on_restart: bool = true;

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> frame: Frame;
@group(0) @binding(2) var triangles: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(3) var bvh: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(4) var rays: texture_storage_2d_array<rgba32float, write>;
@group(0) @binding(5) var seeds: texture_storage_2d<r32uint, read_write>;
@group(0) @binding(6) var<storage, read_write> ray_count: array<atomic<u32>, 2>;

fn shade(id: vec3<u32>) {
    if id.x >= frame.width || id.y >= frame.height {
        return;
    }
    let pixel = vec2<i32>(id.xy);
    // A restart re-seeds from the user seed, so the same seed gives the same image; a graph
    // that keeps history across restarts (reprojection) re-seeds only on the first frame, or
    // new samples would repeat the ones already in that history.
    var seed = textureLoad(seeds, pixel).x;
    if select(frame.index, frame.accumulated, reseed_on_restart) == 0u {
        seed = pcg_hash(id.y * frame.width + id.x ^ pcg_hash(frame.seed));
    }
    seed = pcg_hash(seed);
    textureStore(seeds, pixel, vec4<u32>(seed, 0u, 0u, 0u));

    var rng = rng_stream(seed, 0u);
    let jitter = vec2<f32>(rng_next(&rng), rng_next(&rng));
    let size = vec2<f32>(f32(frame.width), f32(frame.height));
    let s = (vec2<f32>(id.xy) + jitter) / size;
    let sx = 2.0 * s.x - 1.0;
    let sy = 1.0 - 2.0 * s.y;
    let dir = normalize(camera.forward + sx * camera.right + sy * camera.up);
    let hit = closest_hit(camera.eye, dir, 0.0, 3.0e38);

    textureStore(rays, pixel, 0, vec4<f32>(camera.eye, 0.0));
    textureStore(rays, pixel, 1, vec4<f32>(dir, 0.0));
    textureStore(rays, pixel, 2, vec4<f32>(hit.t, hit.u, hit.v, bitcast<f32>(hit.triangle)));
}

@compute @workgroup_size(8, 8)
fn main(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(local_invocation_index) local_index: u32,
) {
    shade(id);
    count_rays(local_index);
}
