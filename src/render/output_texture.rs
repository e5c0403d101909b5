//! Images from a graph's output textures by name (e.g. a denoiser's `denoised`), for graphs
//! whose displayed image is not a plane of the accumulation buffer.

use super::image::RgbImage;
use crate::graph::format::TextureFormat;
use crate::graph::plan::{Plan, ResourceKind};

/// Where `name`'s texels are and how to decode them, or why it cannot be shown: it must be a
/// single-layer float texture of the output size that the graph lists among its outputs (only
/// outputs keep their content after a frame; other transient textures may be reused).
pub fn output_texture_format(plan: &Plan, name: &str) -> Result<TextureFormat, String> {
    let outputs = || {
        let names: Vec<&str> = plan
            .resources
            .iter()
            .filter(|r| r.output && matches!(r.kind, ResourceKind::Texture { .. }))
            .map(|r| r.name.as_str())
            .collect();
        if names.is_empty() {
            "it has no output textures".to_string()
        } else {
            format!("its output textures: {}", names.join(", "))
        }
    };
    let graph = plan.graph.display();
    let Some(resource) = plan.resources.iter().find(|r| r.name == name) else {
        return Err(format!(
            "{graph}: no resource '{name}' to show (channels of 'result': sum, l0, direct, indirect, ambient; {})",
            outputs()
        ));
    };
    let ResourceKind::Texture {
        format,
        width,
        height,
        layers,
    } = resource.kind
    else {
        return Err(format!(
            "{graph}: '{name}' is not a texture, so it cannot be shown as an image ({})",
            outputs()
        ));
    };
    if !matches!(
        format,
        TextureFormat::Rgba32Float | TextureFormat::Rgba16Float
    ) || layers != 1
        || [width, height] != plan.output_size
    {
        return Err(format!(
            "{graph}: '{name}' is {} with {layers} layer(s) at {width}x{height}; an image needs rgba32float or rgba16float, 1 layer, at the output size {}x{}",
            format.wgsl_name(),
            plan.output_size[0],
            plan.output_size[1]
        ));
    }
    if !resource.output {
        return Err(format!(
            "{graph}: '{name}' is not among the graph's outputs, so its content is not kept ({})",
            outputs()
        ));
    }
    Ok(format)
}

/// The RGB of an Rgba32Float or Rgba16Float texture's bytes (row-major, no padding).
pub fn texture_image(bytes: &[u8], format: TextureFormat, width: u32, height: u32) -> RgbImage {
    let channels: Vec<f32> = match format {
        TextureFormat::Rgba16Float => bytes
            .chunks_exact(2)
            .map(|b| half::f16::from_le_bytes([b[0], b[1]]).to_f32())
            .collect(),
        _ => bytemuck::pod_collect_to_vec(bytes),
    };
    RgbImage {
        width,
        height,
        pixels: channels
            .chunks_exact(4)
            .map(|p| [p[0], p[1], p[2]])
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rgba16_texels_decode_exactly_little_endian() {
        let bits: [u16; 8] = [0x3c00, 0xc000, 0x3555, 0x0001, 0x7c00, 0x7e00, 0x0001, 0];
        let bytes: Vec<u8> = bits.iter().flat_map(|b| b.to_le_bytes()).collect();
        let img = texture_image(&bytes, TextureFormat::Rgba16Float, 2, 1);
        assert_eq!(img.pixels[0], [1.0, -2.0, 0.333_251_95]);
        assert_eq!(img.pixels[1][0], f32::INFINITY);
        assert!(img.pixels[1][1].is_nan());
        assert_eq!(img.pixels[1][2], 2f32.powi(-24));
    }

    #[test]
    fn rgba32_texels_become_rgb_pixels() {
        let texels: [f32; 8] = [0.5, 1.5, 2.5, 7.0, -1.0, 0.0, 3.0, 9.0];
        let img = texture_image(
            bytemuck::cast_slice(&texels),
            TextureFormat::Rgba32Float,
            2,
            1,
        );
        assert_eq!(img.pixels, vec![[0.5, 1.5, 2.5], [-1.0, 0.0, 3.0]]);
    }
}
