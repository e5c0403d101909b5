//! The graph's wgpu-free descriptions translated to wgpu's types.

use passgraph_graph::format::{SampleKind, TextureDim, TextureFormat};
use passgraph_graph::interface::{Access, BindingKind};

pub fn texture_format(format: TextureFormat) -> wgpu::TextureFormat {
    use wgpu::TextureFormat as W;
    match format {
        TextureFormat::Rgba8Unorm => W::Rgba8Unorm,
        TextureFormat::Rgba8Snorm => W::Rgba8Snorm,
        TextureFormat::Rgba8Uint => W::Rgba8Uint,
        TextureFormat::Rgba8Sint => W::Rgba8Sint,
        TextureFormat::Bgra8Unorm => W::Bgra8Unorm,
        TextureFormat::Rgba16Uint => W::Rgba16Uint,
        TextureFormat::Rgba16Sint => W::Rgba16Sint,
        TextureFormat::Rgba16Float => W::Rgba16Float,
        TextureFormat::R32Uint => W::R32Uint,
        TextureFormat::R32Sint => W::R32Sint,
        TextureFormat::R32Float => W::R32Float,
        TextureFormat::Rg32Uint => W::Rg32Uint,
        TextureFormat::Rg32Sint => W::Rg32Sint,
        TextureFormat::Rg32Float => W::Rg32Float,
        TextureFormat::Rgba32Uint => W::Rgba32Uint,
        TextureFormat::Rgba32Sint => W::Rgba32Sint,
        TextureFormat::Rgba32Float => W::Rgba32Float,
        TextureFormat::Depth32Float => W::Depth32Float,
    }
}

pub fn view_dimension(dim: TextureDim) -> wgpu::TextureViewDimension {
    match dim {
        TextureDim::D2 => wgpu::TextureViewDimension::D2,
        TextureDim::D2Array => wgpu::TextureViewDimension::D2Array,
    }
}

pub fn storage_access(access: Access) -> wgpu::StorageTextureAccess {
    match access {
        Access::Read => wgpu::StorageTextureAccess::ReadOnly,
        Access::Write => wgpu::StorageTextureAccess::WriteOnly,
        Access::ReadWrite => wgpu::StorageTextureAccess::ReadWrite,
    }
}

/// The format feature a storage texture binding with this access needs.
pub fn storage_feature(access: Access) -> wgpu::TextureFormatFeatureFlags {
    match access {
        Access::Read => wgpu::TextureFormatFeatureFlags::STORAGE_READ_ONLY,
        Access::Write => wgpu::TextureFormatFeatureFlags::STORAGE_WRITE_ONLY,
        Access::ReadWrite => wgpu::TextureFormatFeatureFlags::STORAGE_READ_WRITE,
    }
}

/// Sampled textures are only read with `textureLoad`, so they never need to be filterable
/// (which 32-bit float formats are not without an extra feature).
pub fn sample_type(sample: SampleKind) -> wgpu::TextureSampleType {
    match sample {
        SampleKind::Float => wgpu::TextureSampleType::Float { filterable: false },
        SampleKind::Uint => wgpu::TextureSampleType::Uint,
        SampleKind::Sint => wgpu::TextureSampleType::Sint,
    }
}

/// The layout entry type of a shader binding. Minimum buffer sizes are stated so that a
/// too-small buffer fails when the bind group is built, naming the pass, not mid-frame.
pub fn binding_type(kind: &BindingKind) -> wgpu::BindingType {
    match kind {
        BindingKind::Uniform { size } => wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: wgpu::BufferSize::new(*size),
        },
        BindingKind::Storage { access, min_size } => wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage {
                read_only: *access == Access::Read,
            },
            has_dynamic_offset: false,
            min_binding_size: wgpu::BufferSize::new(*min_size),
        },
        BindingKind::StorageTexture {
            access,
            format,
            dim,
        } => wgpu::BindingType::StorageTexture {
            access: storage_access(*access),
            format: texture_format(*format),
            view_dimension: view_dimension(*dim),
        },
        BindingKind::SampledTexture { sample, dim } => wgpu::BindingType::Texture {
            sample_type: sample_type(*sample),
            view_dimension: view_dimension(*dim),
            multisampled: false,
        },
    }
}
