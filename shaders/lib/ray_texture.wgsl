// Reading the primary ray that intersect stored (ray_texture_store.wgsl). The including
// shader declares `rays` (texture_storage_2d_array<rgba32float, read>) and includes primary.wgsl.

fn load_primary(pixel: vec2<i32>) -> Primary {
    let o = textureLoad(rays, pixel, 0);
    let d = textureLoad(rays, pixel, 1);
    let h = textureLoad(rays, pixel, 2);
    return Primary(o.xyz, d.xyz, h.x, h.y, h.z, bitcast<u32>(h.w));
}
