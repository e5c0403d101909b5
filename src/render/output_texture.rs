//! Images from a graph's textures by name (e.g. a denoiser's `denoised`, or layer 1 of the
//! ray texture, `rays[1]`): for graphs whose displayed image is not a plane of the
//! accumulation buffer, and to look at any texture a graph computes.

use super::image::RgbImage;
use crate::graph::format::TextureFormat;
use crate::graph::plan::{Plan, ResourceKind};

/// A texture channel's name split into the graph texture and its layer: `rays[1]` is layer 1
/// of `rays`; a plain name is layer 0.
pub fn texture_channel(name: &str) -> Result<(&str, u32), String> {
    let Some(open) = name
        .strip_suffix(']')
        .and_then(|n| n.rfind('[').map(|i| (i, n)))
    else {
        return Ok((name, 0));
    };
    let (i, inner) = open;
    let layer = inner[i + 1..].trim().parse::<u32>().map_err(|_| {
        format!("'{name}': a layer is written as a number in brackets, e.g. rays[1]")
    })?;
    Ok((&name[..i], layer))
}

/// How to decode a texture channel: the texture's format and which layer, or why it cannot be
/// shown: it must be a graph texture of the output size that the graph lists among its outputs
/// (only outputs keep their content after a frame; other transient textures may be reused;
/// sessions keep the texture they are asked to show, see `RenderSettings::keep`).
pub fn output_texture_format(plan: &Plan, name: &str) -> Result<(TextureFormat, u32), String> {
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
    let (texture, layer) = texture_channel(name).map_err(|e| format!("{graph}: {e}"))?;
    let Some(resource) = plan.resources.iter().find(|r| r.name == texture) else {
        return Err(format!(
            "{graph}: no resource '{texture}' to show (channels of 'result': sum, l0, direct, indirect, ambient; {})",
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
            "{graph}: '{texture}' is not a texture, so it cannot be shown as an image ({})",
            outputs()
        ));
    };
    if format == TextureFormat::Depth32Float {
        return Err(format!(
            "{graph}: '{texture}' is a depth attachment, which is not read back; show a colour texture ({})",
            outputs()
        ));
    }
    if [width, height] != plan.output_size {
        return Err(format!(
            "{graph}: '{texture}' is {width}x{height}; an image is shown at the output size {}x{}",
            plan.output_size[0], plan.output_size[1]
        ));
    }
    if layer >= layers {
        return Err(format!(
            "{graph}: '{texture}' has {layers} layer(s): show one of {texture}[0] to {texture}[{}]",
            layers - 1
        ));
    }
    if !resource.output {
        return Err(format!(
            "{graph}: '{texture}' is not among the graph's outputs, so its content is not kept ({}); a session keeps it when asked to (`render --channel` and the viewer do)",
            outputs()
        ));
    }
    Ok((format, layer))
}

/// The RGB of one layer of a texture's bytes (layer-major, then row-major, no padding), as
/// numbers: normalised formats in [0, 1] or [-1, 1], integers as their values, one component
/// shown as grey, two as red and green, BGRA reordered.
pub fn texture_image(
    bytes: &[u8],
    format: TextureFormat,
    layer: u32,
    width: u32,
    height: u32,
) -> RgbImage {
    use TextureFormat::*;
    let texels = width as usize * height as usize;
    let size = format.bytes_per_texel() as usize;
    let start = layer as usize * texels * size;
    let bytes = &bytes[start..start + texels * size];
    let values: Vec<f32> = match format {
        Rgba8Unorm | Bgra8Unorm => bytes.iter().map(|&b| f32::from(b) / 255.0).collect(),
        Rgba8Snorm => bytes
            .iter()
            .map(|&b| (f32::from(b as i8) / 127.0).max(-1.0))
            .collect(),
        Rgba8Uint => bytes.iter().map(|&b| f32::from(b)).collect(),
        Rgba8Sint => bytes.iter().map(|&b| f32::from(b as i8)).collect(),
        Rgba16Float => bytes
            .chunks_exact(2)
            .map(|b| half::f16::from_le_bytes([b[0], b[1]]).to_f32())
            .collect(),
        Rgba16Uint => bytes
            .chunks_exact(2)
            .map(|b| f32::from(u16::from_le_bytes([b[0], b[1]])))
            .collect(),
        Rgba16Sint => bytes
            .chunks_exact(2)
            .map(|b| f32::from(i16::from_le_bytes([b[0], b[1]])))
            .collect(),
        R32Float | Rg32Float | Rgba32Float | Depth32Float => bytemuck::pod_collect_to_vec(bytes),
        R32Uint | Rg32Uint | Rgba32Uint => bytes
            .chunks_exact(4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32)
            .collect(),
        R32Sint | Rg32Sint | Rgba32Sint => bytes
            .chunks_exact(4)
            .map(|b| i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32)
            .collect(),
    };
    let components = values.len() / texels.max(1);
    let pixels = values
        .chunks_exact(components.max(1))
        .map(|p| match (components, format) {
            (1, _) => [p[0]; 3],
            (2, _) => [p[0], p[1], 0.0],
            (_, Bgra8Unorm) => [p[2], p[1], p[0]],
            _ => [p[0], p[1], p[2]],
        })
        .collect();
    RgbImage {
        width,
        height,
        pixels,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rgba16_texels_decode_exactly_little_endian() {
        let bits: [u16; 8] = [0x3c00, 0xc000, 0x3555, 0x0001, 0x7c00, 0x7e00, 0x0001, 0];
        let bytes: Vec<u8> = bits.iter().flat_map(|b| b.to_le_bytes()).collect();
        let img = texture_image(&bytes, TextureFormat::Rgba16Float, 0, 2, 1);
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
            0,
            2,
            1,
        );
        assert_eq!(img.pixels, vec![[0.5, 1.5, 2.5], [-1.0, 0.0, 3.0]]);
    }

    #[test]
    fn a_layer_one_component_and_bgra_decode_to_rgb() {
        // Two layers of 1x1 R32Uint: layer 1 is 7, shown grey.
        let bytes: Vec<u8> = [3u32, 7].iter().flat_map(|v| v.to_le_bytes()).collect();
        let img = texture_image(&bytes, TextureFormat::R32Uint, 1, 1, 1);
        assert_eq!(img.pixels, vec![[7.0; 3]]);
        let img = texture_image(&[255, 0, 51, 255], TextureFormat::Bgra8Unorm, 0, 1, 1);
        assert_eq!(img.pixels, vec![[0.2, 0.0, 1.0]]);
        let bytes: Vec<u8> = [1.5f32, -2.0]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        let img = texture_image(&bytes, TextureFormat::Rg32Float, 0, 1, 1);
        assert_eq!(img.pixels, vec![[1.5, -2.0, 0.0]]);
    }

    #[test]
    fn a_channel_names_a_texture_and_optionally_its_layer() {
        assert_eq!(texture_channel("denoised"), Ok(("denoised", 0)));
        assert_eq!(texture_channel("rays[2]"), Ok(("rays", 2)));
        assert_eq!(
            texture_channel("denoise/atrous_a"),
            Ok(("denoise/atrous_a", 0))
        );
        assert!(texture_channel("rays[x]").unwrap_err().contains("rays[1]"));
    }
}
