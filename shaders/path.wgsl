// Path: the whole sample in one pass — the primary ray (as intersect), then the ambient, L0,
// direct and indirect channels (as ambient, direct and indirect) from the same per-channel
// functions and sampler dimensions, so its image has the same expectation as the seed's
// separate passes, and with one sample per frame the same samples. What it saves: the ray
// texture's writes and reads, three dispatches and their barriers; with one light sample and one
// bounce, also the primary hit's BSDF sample traced a second time (lib/shade_one_path.wgsl).
// `samples_per_frame` traces that many samples per pixel per frame and writes their mean,
// amortising per-dispatch costs.
#include "lib/provided_scene.wgsl"
#include "lib/rng.wgsl"
#include "lib/sampler.wgsl"
#include "lib/camera_ray.wgsl"
#include "lib/sampling.wgsl"
#include "lib/bsdf.wgsl"
#include "lib/mis.wgsl"
#include "lib/bvh.wgsl"
#include "lib/cutout_map.wgsl"
#include "lib/ray_count.wgsl"
#include "lib/tile_order.wgsl"
#include "lib/primary.wgsl"
#include "lib/surface.wgsl"
#include "lib/shading.wgsl"
#include "lib/texture.wgsl"
#include "lib/shading_point.wgsl"
#include "lib/light_sample.wgsl"
#include "lib/light_select.wgsl"
#include "lib/nee.wgsl"
#include "lib/shade_ambient.wgsl"
#include "lib/shade_direct.wgsl"
#include "lib/path_primary.wgsl"
#include "lib/path_pass.wgsl"
#include "lib/path_light.wgsl"
#include "lib/shade_indirect.wgsl"
#include "lib/shade_one_path.wgsl"

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
        let ray = path_primary(id.xy, source);
        if light_samples == 1u && bounces == 1u {
            let one = shade_one_path(ray, source);
            sum_l0 += one.l0;
            sum_direct += one.direct;
            sum_indirect += one.indirect;
        } else {
            let lit = shade_direct(ray, source);
            sum_l0 += lit.l0;
            sum_direct += lit.direct;
            sum_indirect += shade_indirect(ray, source);
        }
        sum_ambient += shade_ambient(ray, source, params.ambient_color, params.radius);
    }
    store_channel_means(id.xy, sum_l0, sum_direct, sum_indirect, sum_ambient);
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
