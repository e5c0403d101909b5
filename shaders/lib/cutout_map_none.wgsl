// For includers of lib/bvh.wgsl that bind no textures (tests of the traversal alone): a
// triangle cut out by a map_d texture counts as opaque. Shaders that render scenes include
// lib/cutout_map.wgsl instead.
fn cutout_map_opacity(map: u32, k: u32, u: f32, v: f32) -> f32 {
    return 1.0;
}
