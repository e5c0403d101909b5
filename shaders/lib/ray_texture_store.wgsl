// Writing a pixel's primary ray and its closest hit into the ray texture, in the layout
// ray_texture.wgsl reads: origin, direction, then (t, u, v, triangle). The including shader
// declares `rays` (texture_storage_2d_array<rgba32float, write>) and includes bvh.wgsl (Hit).

fn store_primary(pixel: vec2<i32>, origin: vec3<f32>, dir: vec3<f32>, hit: Hit) {
    textureStore(rays, pixel, 0, vec4<f32>(origin, 0.0));
    textureStore(rays, pixel, 1, vec4<f32>(dir, 0.0));
    textureStore(rays, pixel, 2, vec4<f32>(hit.t, hit.u, hit.v, bitcast<f32>(hit.triangle)));
}
