// Path: the whole sample in one pass — the primary ray (as intersect), then the ambient, L0,
// direct and indirect channels (as ambient, direct and indirect) from the same per-channel
// functions and sampler dimensions, so its image has the same expectation as the seed's
// separate passes, and with one sample per frame the same samples. What it saves: the ray
// texture's writes and reads, three dispatches and their barriers. `samples_per_frame` traces
// that many samples per pixel per frame and writes their mean, amortising per-dispatch costs.
#include "lib/scene.wgsl"
#include "lib/rng.wgsl"
#include "lib/sampler.wgsl"
#include "lib/camera_ray.wgsl"
#include "lib/sampling.wgsl"
#include "lib/brdf.wgsl"
#include "lib/bvh.wgsl"
#include "lib/ray_count.wgsl"
#include "lib/tile_order.wgsl"
#include "lib/primary.wgsl"
#include "lib/surface.wgsl"
#include "lib/light_sample.wgsl"
#include "lib/light_select.wgsl"
#include "lib/nee.wgsl"
#include "lib/shade_ambient.wgsl"
#include "lib/shade_direct.wgsl"
#include "lib/shade_indirect.wgsl"

struct Params {
    ambient_color: vec3<f32>,
    radius: f32,
}

// A pass param: samples per pixel per frame.
override samples_per_frame: u32 = 1u;

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> camera: Camera;
@group(0) @binding(2) var<uniform> frame: Frame;
@group(0) @binding(3) var triangles: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(4) var materials: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(5) var lights: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(6) var light_power: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(7) var bvh: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(8) var l0: texture_storage_2d<rgba32float, write>;
@group(0) @binding(9) var direct: texture_storage_2d<rgba32float, write>;
@group(0) @binding(10) var indirect: texture_storage_2d<rgba32float, write>;
@group(0) @binding(11) var ambient: texture_storage_2d<rgba32float, write>;
@group(0) @binding(12) var<storage, read_write> ray_count: array<atomic<u32>, 2>;

fn shade(id: vec3<u32>) {
    if id.x >= frame.width || id.y >= frame.height {
        return;
    }
    var sum_l0 = vec3<f32>(0.0);
    var sum_direct = vec3<f32>(0.0);
    var sum_indirect = vec3<f32>(0.0);
    var sum_ambient = vec3<f32>(0.0);
    for (var k = 0u; k < samples_per_frame; k++) {
        let source = sample_source(id.xy, samples_per_frame, k);
        let dir = camera_ray_dir(id.xy, sample_2d(source, DIM_PIXEL));
        let hit = closest_hit(camera.eye, dir, 0.0, 3.0e38);
        let ray = Primary(camera.eye, dir, hit.t, hit.u, hit.v, hit.triangle);
        let lit = shade_direct(ray, source);
        sum_l0 += lit.l0;
        sum_direct += lit.direct;
        sum_indirect += shade_indirect(ray, source);
        sum_ambient += shade_ambient(ray, source, params.ambient_color, params.radius);
    }
    let pixel = vec2<i32>(id.xy);
    let scale = 1.0 / f32(samples_per_frame);
    textureStore(l0, pixel, vec4<f32>(sum_l0 * scale, 1.0));
    textureStore(direct, pixel, vec4<f32>(sum_direct * scale, 1.0));
    textureStore(indirect, pixel, vec4<f32>(sum_indirect * scale, 1.0));
    textureStore(ambient, pixel, vec4<f32>(sum_ambient * scale, 1.0));
}

@compute @workgroup_size(8, 8)
fn main(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_id) local: vec3<u32>,
    @builtin(local_invocation_index) local_index: u32,
) {
    shade(scattered_pixel(group, groups, local, frame));
    count_rays(local_index);
}
