// The pixel an invocation of an image pass in 8x8 workgroups shades, the dispatch's tiles
// taken in a scattered order: workgroup (x, y) shades the tile in column x and row
// ((x + y) * frame.tile_row_stride) mod rows. Why (lavapipe gives each CPU thread one
// contiguous run of workgroups, so in row order one thread would shade the top of the image and
// another the bottom) and how the stride is chosen: src/render/tile_order.rs. A dispatch whose
// rows are not the frame's keeps row order: the stride permutes the frame's rows only.
fn scattered_pixel(group: vec3<u32>, groups: vec3<u32>, local: vec3<u32>, frame: Frame) -> vec3<u32> {
    let scattered = ((group.x + group.y) * frame.tile_row_stride) % groups.y;
    let row = select(group.y, scattered, groups.y == (frame.height + 7u) / 8u);
    return vec3<u32>(group.x * 8u + local.x, row * 8u + local.y, group.z);
}
