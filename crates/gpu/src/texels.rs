//! Texel views: a provided buffer bound as `texture_storage_2d<rgba32uint, read>` (what the
//! readers in `shaders/lib/scene.wgsl` take) or `texture_2d<u32>`, its bytes in 16-byte
//! `Rgba32Uint` texels, row-major. Where storage-buffer loads are slow (lavapipe gathers them lane by lane
//! with a branch each; a texel fetch is one vector load per lane) scene data read this way
//! costs a fraction as much, and on other GPUs it goes through the texture cache.
//!
//! The width is a power of two so that shaders find texel `i` with a mask and a shift
//! (`shaders/lib/scene.wgsl`'s `scene_texel`), never an integer division.

use wgpu::util::DeviceExt;

/// Bytes per texel.
pub const TEXEL_BYTES: u64 = 16;

/// Width and height of the view of `bytes` bytes, or why no texture can hold it. At least one
/// texel, so that an empty buffer (a scene without lights) can still be bound.
pub fn texel_view_size(bytes: u64, max_dimension: u32) -> Result<(u32, u32), String> {
    let texels = bytes.div_ceil(TEXEL_BYTES).max(1);
    // The largest power of two the device allows as a width.
    let max_width = 1u64 << (u32::BITS - 1 - max_dimension.max(1).leading_zeros());
    let width = texels.next_power_of_two().min(max_width);
    let height = texels.div_ceil(width);
    if height > u64::from(max_dimension) {
        return Err(format!(
            "{bytes} bytes need {texels} texels, more than a {width} x {max_dimension} texture holds"
        ));
    }
    Ok((width as u32, height as u32))
}

/// Uploads `bytes` as a texel view, zero-padded to whole rows.
pub fn create_texel_view(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    name: &str,
    bytes: &[u8],
) -> Result<wgpu::Texture, String> {
    let max_dimension = device.limits().max_texture_dimension_2d;
    let (width, height) = texel_view_size(bytes.len() as u64, max_dimension)?;
    let mut contents = bytes.to_vec();
    contents.resize(
        (u64::from(width) * u64::from(height) * TEXEL_BYTES) as usize,
        0,
    );
    Ok(device.create_texture_with_data(
        queue,
        &wgpu::TextureDescriptor {
            label: Some(name),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba32Uint,
            usage: wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        &contents,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn widths_are_powers_of_two_within_the_limit() {
        assert_eq!(texel_view_size(0, 8192), Ok((1, 1)));
        assert_eq!(texel_view_size(16, 8192), Ok((1, 1)));
        assert_eq!(texel_view_size(17, 8192), Ok((2, 1)));
        // 32 triangles of 48 bytes: 96 texels in one row of 128.
        assert_eq!(texel_view_size(32 * 48, 8192), Ok((128, 1)));
        // 10^6 triangles: 3 * 10^6 texels in rows of 8192.
        assert_eq!(texel_view_size(48_000_000, 8192), Ok((8192, 367)));
        // A limit that is not a power of two: rows of the largest power below it.
        assert_eq!(texel_view_size(16 * 5000, 3000), Ok((2048, 3)));
    }

    #[test]
    fn too_many_texels_is_an_error_not_a_truncation() {
        let err = texel_view_size(16 * 5 * 4, 4).unwrap_err();
        assert!(err.contains("20 texels"), "{err}");
    }
}
