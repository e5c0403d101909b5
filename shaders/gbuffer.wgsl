// G-buffer: the guides of the à-trous denoiser (shaders/atrous.wgsl) at each pixel's primary
// hit: shading normal, position and diffuse albedo (kd). Each is a running mean over the frames
// of the accumulation, like the image it guides: the jittered primary rays cover the pixel's
// footprint, so at a silhouette the guide mixes the two surfaces in the proportions the
// accumulated colour does, and the albedo divides that colour consistently.
#include "lib/provided_scene.wgsl"
#include "lib/primary.wgsl"
#include "lib/ray_texture.wgsl"
#include "lib/surface.wgsl"

@group(0) @binding(0) var rays: texture_storage_2d_array<rgba32float, read>;
@group(0) @binding(1) var normal: texture_storage_2d<rgba32float, read_write>;
@group(0) @binding(2) var position: texture_storage_2d<rgba32float, read_write>;
@group(0) @binding(3) var albedo: texture_storage_2d<rgba32float, read_write>;

// What a primary ray that leaves the scene contributes: no normal, a far position, albedo 1
// (nothing to demodulate), so misses group with misses only.
const MISS_POSITION: f32 = 1.0e9;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = vec2<i32>(id.xy);
    if any(id.xy >= textureDimensions(normal)) {
        return;
    }
    let ray = load_primary(pixel);
    var n = vec3<f32>(0.0);
    var p = vec3<f32>(MISS_POSITION);
    var kd = vec3<f32>(1.0);
    if ray.triangle != NO_HIT {
        let s = surface_at(scene_triangle(triangles, ray.triangle), ray.u, ray.v, ray.dir);
        n = s.n;
        p = s.p;
        kd = scene_face_material(materials, s.material, s.front).kd;
    }
    // Running mean over the accumulation; a restart (accumulated == 0) forgets the history.
    let count = f32(frame.accumulated);
    let keep = select(count / (count + 1.0), 0.0, frame.accumulated == 0u);
    let old_n = textureLoad(normal, pixel).xyz;
    let old_p = textureLoad(position, pixel).xyz;
    let old_a = textureLoad(albedo, pixel).xyz;
    textureStore(normal, pixel, vec4<f32>(mix(n, old_n, keep), 0.0));
    textureStore(position, pixel, vec4<f32>(mix(p, old_p, keep), 0.0));
    textureStore(albedo, pixel, vec4<f32>(mix(kd, old_a, keep), 0.0));
}
