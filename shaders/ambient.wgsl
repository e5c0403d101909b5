// Ambient: one cosine-weighted ray from the primary hit; unoccluded within `radius`, the point
// receives kd * ambient_color. A black ambient colour (the physical default) casts no ray.
#include "lib/scene.wgsl"
#include "lib/rng.wgsl"
#include "lib/sampling.wgsl"
#include "lib/bvh.wgsl"
#include "lib/ray_count.wgsl"
#include "lib/primary.wgsl"
#include "lib/surface.wgsl"

struct Params {
    ambient_color: vec3<f32>,
    radius: f32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var triangles: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(2) var materials: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(3) var bvh: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(4) var rays: texture_storage_2d_array<rgba32float, read>;
@group(0) @binding(5) var seeds: texture_storage_2d<r32uint, read>;
@group(0) @binding(6) var out: texture_storage_2d<rgba32float, write>;
@group(0) @binding(7) var<storage, read_write> ray_count: array<atomic<u32>, 2>;

fn shade(id: vec3<u32>) {
    let pixel = vec2<i32>(id.xy);
    if any(id.xy >= textureDimensions(out)) {
        return;
    }
    let ray = load_primary(pixel);
    if ray.triangle == NO_HIT || all(params.ambient_color == vec3<f32>(0.0)) {
        textureStore(out, pixel, vec4<f32>(0.0));
        return;
    }
    let s = surface_at(scene_triangle(triangles, ray.triangle), ray.u, ray.v, ray.dir);
    var rng = rng_stream(textureLoad(seeds, pixel).x, 1u);
    let d = sample_cosine(s.n, rng_next(&rng), rng_next(&rng));
    var value = vec3<f32>(0.0);
    if !any_hit(offset_ray(s.p, s.n), d, 0.0, params.radius) {
        value = scene_material(materials, s.material).kd * params.ambient_color;
    }
    textureStore(out, pixel, vec4<f32>(value, 1.0));
}

@compute @workgroup_size(8, 8)
fn main(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(local_invocation_index) local_index: u32,
) {
    shade(id);
    count_rays(local_index);
}
