//! shaders/lib/tile_order.wgsl on the GPU: every pixel of an image pass is shaded exactly once,
//! by the workgroup src/render/tile_order.rs names, at sizes with partial edge tiles.

mod common;

use common::bvh_gpu::{bind_buffers, dispatch_groups_and_read, gpu, output_buffer, test_pipeline};
use passgraph::render::provided::frame_bytes;
use passgraph::render::tile_order::{TILE, scattered_tile, tile_row_stride};
use wgpu::util::DeviceExt;

/// (count, linear workgroup index) per pixel, row-major.
fn shade(size: [u32; 2]) -> Vec<[u32; 2]> {
    let gpu = gpu();
    let pipeline = test_pipeline(&gpu, "tile_order_check");
    let frame = gpu
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("frame"),
            contents: &frame_bytes(size, 0, 0, 0),
            usage: wgpu::BufferUsages::UNIFORM,
        });
    let answers = output_buffer(&gpu, u64::from(size[0] * size[1]) * 8);
    let bind_group = bind_buffers(&gpu, &pipeline, &[&frame, &answers]);
    let groups = [size[0].div_ceil(TILE), size[1].div_ceil(TILE), 1];
    dispatch_groups_and_read(&gpu, &pipeline, &bind_group, groups, &answers)
}

#[test]
fn every_pixel_is_shaded_once_by_the_workgroup_the_cpu_model_names() {
    for size in [[1, 1], [8, 8], [9, 17], [100, 37], [256, 256], [13, 300]] {
        let answers = shade(size);
        let (columns, rows) = (size[0].div_ceil(TILE), size[1].div_ceil(TILE));
        let stride = tile_row_stride(size[1]);
        // Which tile each workgroup shades, by the model; then which workgroup each tile has.
        let mut owner = vec![u32::MAX; (columns * rows) as usize];
        for y in 0..rows {
            for x in 0..columns {
                let [tx, ty] = scattered_tile([x, y], rows, stride);
                owner[(ty * columns + tx) as usize] = y * columns + x;
            }
        }
        for (i, [count, group]) in answers.iter().enumerate() {
            let (px, py) = (i as u32 % size[0], i as u32 / size[0]);
            assert_eq!(
                *count, 1,
                "{size:?}: pixel ({px}, {py}) shaded {count} times"
            );
            let tile = (py / TILE) * columns + px / TILE;
            assert_eq!(*group, owner[tile as usize], "{size:?}: pixel ({px}, {py})");
        }
    }
}
