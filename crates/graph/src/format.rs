//! Texture formats and dimensions a graph can declare, independent of wgpu.

use serde::Deserialize;
use std::fmt;

/// The storage-capable texture formats of WebGPU (WGSL `texel_format`), which are the formats
/// a compute pass can write. Names follow wgpu's `TextureFormat` so RON files read naturally.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Deserialize, PartialOrd, Ord)]
pub enum TextureFormat {
    Rgba8Unorm,
    Rgba8Snorm,
    Rgba8Uint,
    Rgba8Sint,
    Bgra8Unorm,
    Rgba16Uint,
    Rgba16Sint,
    Rgba16Float,
    R32Uint,
    R32Sint,
    R32Float,
    Rg32Uint,
    Rg32Sint,
    Rg32Float,
    Rgba32Uint,
    Rgba32Sint,
    Rgba32Float,
    /// A depth buffer: only a raster pass's depth attachment, never a shader binding.
    Depth32Float,
}

/// What a sampled-texture binding returns, which the resource's format must agree with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SampleKind {
    Float,
    Uint,
    Sint,
}

impl TextureFormat {
    /// Every format a shader can bind as a storage texture (all but the depth format), the
    /// ones reflection finds by WGSL name.
    pub const STORAGE: [TextureFormat; 17] = {
        use TextureFormat::*;
        [
            Rgba8Unorm,
            Rgba8Snorm,
            Rgba8Uint,
            Rgba8Sint,
            Bgra8Unorm,
            Rgba16Uint,
            Rgba16Sint,
            Rgba16Float,
            R32Uint,
            R32Sint,
            R32Float,
            Rg32Uint,
            Rg32Sint,
            Rg32Float,
            Rgba32Uint,
            Rgba32Sint,
            Rgba32Float,
        ]
    };

    pub fn bytes_per_texel(self) -> u64 {
        use TextureFormat::*;
        match self {
            Rgba8Unorm | Rgba8Snorm | Rgba8Uint | Rgba8Sint | Bgra8Unorm | R32Uint | R32Sint
            | R32Float | Depth32Float => 4,
            Rgba16Uint | Rgba16Sint | Rgba16Float | Rg32Uint | Rg32Sint | Rg32Float => 8,
            Rgba32Uint | Rgba32Sint | Rgba32Float => 16,
        }
    }

    pub fn sample_kind(self) -> SampleKind {
        use TextureFormat::*;
        match self {
            Rgba8Uint | Rgba16Uint | R32Uint | Rg32Uint | Rgba32Uint => SampleKind::Uint,
            Rgba8Sint | Rgba16Sint | R32Sint | Rg32Sint | Rgba32Sint => SampleKind::Sint,
            _ => SampleKind::Float,
        }
    }

    /// Channels per texel, what a fragment output must at least have to fill it.
    pub fn components(self) -> u32 {
        use TextureFormat::*;
        match self {
            R32Uint | R32Sint | R32Float | Depth32Float => 1,
            Rg32Uint | Rg32Sint | Rg32Float => 2,
            _ => 4,
        }
    }

    pub fn is_depth(self) -> bool {
        self == TextureFormat::Depth32Float
    }

    /// The WGSL spelling, used in messages so users see what to write in the shader.
    pub fn wgsl_name(self) -> &'static str {
        use TextureFormat::*;
        match self {
            Rgba8Unorm => "rgba8unorm",
            Rgba8Snorm => "rgba8snorm",
            Rgba8Uint => "rgba8uint",
            Rgba8Sint => "rgba8sint",
            Bgra8Unorm => "bgra8unorm",
            Rgba16Uint => "rgba16uint",
            Rgba16Sint => "rgba16sint",
            Rgba16Float => "rgba16float",
            R32Uint => "r32uint",
            R32Sint => "r32sint",
            R32Float => "r32float",
            Rg32Uint => "rg32uint",
            Rg32Sint => "rg32sint",
            Rg32Float => "rg32float",
            Rgba32Uint => "rgba32uint",
            Rgba32Sint => "rgba32sint",
            Rgba32Float => "rgba32float",
            Depth32Float => "depth32float",
        }
    }
}

impl fmt::Display for TextureFormat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.wgsl_name())
    }
}

impl fmt::Display for SampleKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            SampleKind::Float => "f32",
            SampleKind::Uint => "u32",
            SampleKind::Sint => "i32",
        })
    }
}

/// The view dimensions a pass can bind. A one-layer texture may be bound as either.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TextureDim {
    D2,
    D2Array,
}

impl fmt::Display for TextureDim {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            TextureDim::D2 => "2d",
            TextureDim::D2Array => "2d_array",
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fails when a format is added to the enum but not to `STORAGE` (reflection would not
    /// find it by its WGSL name): the match below stops compiling until the new one is placed.
    #[test]
    fn storage_holds_every_format_but_depth_once() {
        use TextureFormat::*;
        let is_storage = |f: TextureFormat| match f {
            Depth32Float => false,
            Rgba8Unorm | Rgba8Snorm | Rgba8Uint | Rgba8Sint | Bgra8Unorm | Rgba16Uint
            | Rgba16Sint | Rgba16Float | R32Uint | R32Sint | R32Float | Rg32Uint | Rg32Sint
            | Rg32Float | Rgba32Uint | Rgba32Sint | Rgba32Float => true,
        };
        let mut listed = TextureFormat::STORAGE.to_vec();
        assert!(listed.iter().all(|&f| is_storage(f)));
        listed.sort();
        listed.dedup();
        assert_eq!(listed.len(), TextureFormat::STORAGE.len());
        // 17 storage formats in the match above, each listed once.
        assert_eq!(listed.len(), 17);
    }
}
