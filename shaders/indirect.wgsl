// Indirect: one cosine-weighted bounce from the primary hit, then next-event estimation at the
// second hit with that point's BRDF. Emission met by the bounce is not added: L1 counts it.
#include "lib/scene.wgsl"
#include "lib/rng.wgsl"
#include "lib/sampling.wgsl"
#include "lib/brdf.wgsl"
#include "lib/bvh.wgsl"
#include "lib/ray_count.wgsl"
#include "lib/primary.wgsl"
#include "lib/surface.wgsl"
#include "lib/light_sample.wgsl"
#include "lib/light_select.wgsl"
#include "lib/nee.wgsl"

@group(0) @binding(0) var triangles: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(1) var materials: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(2) var lights: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(3) var bvh: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(4) var rays: texture_storage_2d_array<rgba32float, read>;
@group(0) @binding(5) var seeds: texture_storage_2d<r32uint, read>;
@group(0) @binding(6) var out: texture_storage_2d<rgba32float, write>;
@group(0) @binding(7) var<storage, read_write> ray_count: array<atomic<u32>, 2>;
@group(0) @binding(8) var light_power: texture_storage_2d<rgba32uint, read>;

fn shade(id: vec3<u32>) {
    let pixel = vec2<i32>(id.xy);
    if any(id.xy >= textureDimensions(out)) {
        return;
    }
    let ray = load_primary(pixel);
    // Without lights there is nothing to find at the second hit: no bounce ray at all.
    if ray.triangle == NO_HIT || scene_light_count == 0u {
        textureStore(out, pixel, vec4<f32>(0.0));
        return;
    }
    let s = surface_at(scene_triangle(triangles, ray.triangle), ray.u, ray.v, ray.dir);
    var rng = rng_stream(textureLoad(seeds, pixel).x, 3u);
    let d = sample_cosine(s.n, rng_next(&rng), rng_next(&rng));
    let second = closest_hit(offset_ray(s.p, s.n), d, 0.0, 3.0e38);
    var value = vec3<f32>(0.0);
    if second.triangle != NO_HIT {
        let s2 = surface_at(scene_triangle(triangles, second.triangle), second.u, second.v, d);
        // f * cos / pdf with pdf = cos / pi.
        let weight = brdf(scene_material(materials, s.material), s.n, -ray.dir, d) * PI;
        value = weight * direct_light(s2, -d, &rng);
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
