// Visibility buffer to rays: turns visibility.wgsl's vbuffer into the ray texture exactly as
// intersect writes it (lib/ray_texture.wgsl), so the lighting passes run unchanged. The ray is
// the frame's jittered camera ray (lib/frame_jitter.wgsl, through the lens of a thin-lens camera,
// whose lens sample is the pixel's own); t, u, v come from the same watertight
// test intersect's traversal applies (bvh_intersect_triangle) against the drawn triangle alone,
// so they are intersect's wherever both see that triangle. Where the test disagrees with the
// rasteriser (a pixel whose ray grazes the drawn triangle's edge), the ray passes a cut-out
// drawn there, or nothing was drawn, the ray is traced through the BVH as intersect traces it.
#include "lib/provided_scene.wgsl"
#include "lib/rng.wgsl"
#include "lib/sampler.wgsl"
#include "lib/camera_ray.wgsl"
#include "lib/frame_jitter.wgsl"
#include "lib/bvh.wgsl"
#include "lib/cutout_map.wgsl"
#include "lib/ray_count.wgsl"
#include "lib/ray_texture_store.wgsl"

@group(0) @binding(0) var vbuffer: texture_2d<u32>;
@group(0) @binding(1) var rays: texture_storage_2d_array<rgba32float, write>;
@group(0) @binding(2) var<storage, read_write> ray_count: array<atomic<u32>, 2>;

fn convert(id: vec3<u32>) {
    if id.x >= frame.width || id.y >= frame.height {
        return;
    }
    let pixel = vec2<i32>(id.xy);
    let primary = camera_ray(id.xy, frame_jitter(), camera_lens_sample(sample_source(id.xy, 1u, 0u)));
    let origin = primary.origin;
    let dir = primary.dir;
    let drawn = textureLoad(vbuffer, pixel, 0).x;
    var hit = Hit(3.0e38, 0.0, 0.0, BVH_NO_HIT);
    var found = false;
    // visibility.wgsl rasterises through the pinhole only: other cameras trace every ray.
    if scene_camera_kind == CAMERA_PINHOLE && drawn != 0u && drawn <= scene_triangle_count {
        let k = drawn - 1u;
        let p = scene_triangle_vertices(triangles, k);
        let ray = bvh_prepare_ray(origin, dir);
        let h = bvh_intersect_triangle(ray, p[0], p[1], p[2], 0.0, 3.0e38);
        // A cut-out the ray passes (bvh_stops decides as the traversal would) was drawn but
        // is not what the ray sees: trace past it.
        if h.hit && bvh_stops(ray, k, h.u, h.v) {
            hit = Hit(h.t, h.u, h.v, k);
            found = true;
            bvh_rays_traced += 1u;
        }
    }
    if !found {
        hit = closest_hit(origin, dir, 0.0, 3.0e38);
    }
    store_primary(pixel, origin, dir, hit);
}

@compute @workgroup_size(8, 8)
fn main(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(local_invocation_index) local_index: u32,
) {
    convert(id);
    count_rays(local_index);
}
