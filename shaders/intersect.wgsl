// Intersect: one jittered primary ray per pixel, stored for the lighting passes
// (layer 0: origin, layer 1: direction, layer 2: hit t, u, v, triangle as bits).
#include "lib/provided_scene.wgsl"
#include "lib/rng.wgsl"
#include "lib/sampler.wgsl"
#include "lib/camera_ray.wgsl"
#include "lib/bvh.wgsl"
#include "lib/cutout_map.wgsl"
#include "lib/ray_count.wgsl"
#include "lib/ray_texture_store.wgsl"

// A pass param: jitter within the pixel (true) or trace its centre (tests comparing with a
// rasteriser, tests/raster.rs).
override pixel_jitter: bool = true;

@group(0) @binding(0) var rays: texture_storage_2d_array<rgba32float, write>;
@group(0) @binding(1) var<storage, read_write> ray_count: array<atomic<u32>, 2>;

fn shade(id: vec3<u32>) {
    if id.x >= frame.width || id.y >= frame.height {
        return;
    }
    let pixel = vec2<i32>(id.xy);
    let source = sample_source(id.xy, 1u, 0u);
    let ray = camera_sample_ray(id.xy, source, pixel_jitter);
    let hit = closest_hit(ray.origin, ray.dir, 0.0, 3.0e38);
    store_primary(pixel, ray.origin, ray.dir, hit);
}

@compute @workgroup_size(8, 8)
fn main(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(local_invocation_index) local_index: u32,
) {
    shade(id);
    count_rays(local_index);
}
