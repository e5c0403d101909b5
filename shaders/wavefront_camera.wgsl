// The wavefront's first pass: per pixel, the primary ray and its channels that need no
// further segment (ambient, L0, the direct channel's next-event estimate), and the primary
// hit's BSDF sample, queued for level 0 when the direct channel's MIS half or the indirect
// channel needs its ray (lib/wavefront.wgsl).
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
#include "lib/path_primary.wgsl"
#include "lib/path_light.wgsl"
#include "lib/shade_one_path.wgsl"
#include "lib/wavefront.wgsl"
#include "lib/wavefront_vertex.wgsl"

struct Params {
    ambient_color: vec3<f32>,
    radius: f32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var l0: texture_storage_2d<rgba32float, write>;
@group(0) @binding(2) var ambient: texture_storage_2d<rgba32float, write>;
@group(0) @binding(3) var<storage, read_write> paths: array<WavefrontPath>;
@group(0) @binding(4) var<storage, read_write> queue_out: array<u32>;
@group(0) @binding(5) var<storage, read_write> levels_out: array<WavefrontLevelCounter>;
@group(0) @binding(6) var<storage, read_write> ray_count: array<atomic<u32>, 2>;

fn shade(id: vec3<u32>) {
    if id.x >= frame.width || id.y >= frame.height {
        return;
    }
    let source = sample_source(id.xy, 1u, 0u);
    let ray = path_primary(id.xy, source);
    var path = WavefrontPath();
    let pixel = vec2<i32>(id.xy);
    textureStore(ambient, pixel, vec4<f32>(shade_ambient(ray, source, params.ambient_color, params.radius), 1.0));
    if ray.triangle == NO_HIT {
        // A camera ray that leaves the scene sees the environment (L0), as in Mitsuba.
        textureStore(l0, pixel, vec4<f32>(environment_seen(ray.dir), 1.0));
        paths[wavefront_slot(id.xy)] = path;
        return;
    }
    let p = shading_point(ray.triangle, ray.u, ray.v, ray.dir);
    textureStore(l0, pixel, vec4<f32>(p.emitted, 1.0));
    // The fused pass's start of a sample (lib/shade_one_path.wgsl): one BSDF sample for the
    // direct channel's MIS half and the indirect channel's first bounce.
    let b = primary_bounce(p, -ray.dir, source);
    path.direct = b.direct;
    if b.traced {
        path.direct_weight = b.direct_weight;
        path.throughput = b.weight;
        path.eta2 = b.bs.eta * b.bs.eta;
        wavefront_continue(&path, p, b.bs, 2u);
    }
    paths[wavefront_slot(id.xy)] = path;
    if b.traced {
        wavefront_queue(0u, wavefront_slot(id.xy));
    }
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
