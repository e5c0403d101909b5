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
            .map(|b| f16_to_f32(u16::from_le_bytes([b[0], b[1]])))
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

/// IEEE 754 half to single precision (exact: every half is a single). By hand rather than a
/// new dependency for eight lines.
fn f16_to_f32(bits: u16) -> f32 {
    let sign = if bits & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exponent = i32::from((bits >> 10) & 0x1f);
    let mantissa = f32::from(bits & 0x3ff);
    sign * match exponent {
        0 => mantissa * 2f32.powi(-24),
        31 if mantissa == 0.0 => f32::INFINITY,
        31 => f32::NAN,
        e => (1.0 + mantissa / 1024.0) * 2f32.powi(e - 15),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halves_decode_exactly() {
        assert_eq!(f16_to_f32(0x3c00), 1.0);
        assert_eq!(f16_to_f32(0xc000), -2.0);
        assert_eq!(f16_to_f32(0x3555), 0.333_251_95);
        assert_eq!(f16_to_f32(0x0001), 2f32.powi(-24));
        assert_eq!(f16_to_f32(0x7c00), f32::INFINITY);
        assert!(f16_to_f32(0x7e00).is_nan());
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
