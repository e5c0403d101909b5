//! Putting the current image on a window: the linear RGB image is uploaded to a float texture
//! and drawn over the whole target by one triangle, scaled to the nearest texel; the same draw
//! into an offscreen texture gives the screenshot of exactly what is shown.

use crate::gpu::readback::read_mapped;
use crate::render::image::RgbImage;

pub struct Presenter {
    pipeline: wgpu::RenderPipeline,
    bind_group: wgpu::BindGroup,
    image: wgpu::Texture,
    format: wgpu::TextureFormat,
    /// The upload staging: RGBA rows, since there is no three-channel float texture format.
    rgba: Vec<[f32; 4]>,
}

impl Presenter {
    /// A presenter for images of `image_size` drawn into targets of `format`.
    pub fn new(
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        image_size: [u32; 2],
    ) -> Presenter {
        let image = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("view image"),
            size: extent(image_size),
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            // Float32 keeps the accumulation's values; textureLoad needs no filtering.
            format: wgpu::TextureFormat::Rgba32Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("present.wgsl"),
            source: wgpu::ShaderSource::Wgsl(include_str!("present.wgsl").into()),
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("view image"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            }],
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("view image"),
            layout: &layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(
                    &image.create_view(&wgpu::TextureViewDescriptor::default()),
                ),
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("present"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        // An *Srgb target encodes on store; any other gets the encoding from the shader.
        let constants = [("encode_srgb", if format.is_srgb() { 0.0 } else { 1.0 })];
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("present"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_main"),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants: &constants,
                    ..Default::default()
                },
                targets: &[Some(wgpu::ColorTargetState {
                    format,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        Presenter {
            pipeline,
            bind_group,
            image,
            format,
            rgba: Vec::new(),
        }
    }

    pub fn image_size(&self) -> [u32; 2] {
        let s = self.image.size();
        [s.width, s.height]
    }

    /// Replaces the shown image (same size as the presenter's).
    pub fn upload(&mut self, queue: &wgpu::Queue, image: &RgbImage) {
        let size = self.image_size();
        debug_assert_eq!([image.width, image.height], size);
        self.rgba.clear();
        self.rgba
            .extend(image.pixels.iter().map(|p| [p[0], p[1], p[2], 1.0]));
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &self.image,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            bytemuck::cast_slice(&self.rgba),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(size[0] * 16),
                rows_per_image: Some(size[1]),
            },
            extent(size),
        );
    }

    /// Records the draw of the current image over all of `target`.
    pub fn draw(&self, encoder: &mut wgpu::CommandEncoder, target: &wgpu::TextureView) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("present"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            ..Default::default()
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.draw(0..3, 0..1);
    }

    /// What a `size` target shows, as 8-bit sRGB: the same draw, into an offscreen texture of
    /// the window's format, read back. Blocks until the GPU is done.
    pub fn capture(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        size: [u32; 2],
    ) -> Result<image::RgbImage, String> {
        let target = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("screenshot"),
            size: extent(size),
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: self.format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        // Rows of a texture-to-buffer copy are aligned to 256 bytes.
        let row = (size[0] * 4).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("screenshot readback"),
            size: u64::from(row) * u64::from(size[1]),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("screenshot"),
        });
        self.draw(
            &mut encoder,
            &target.create_view(&wgpu::TextureViewDescriptor::default()),
        );
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &target,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(row),
                    rows_per_image: Some(size[1]),
                },
            },
            extent(size),
        );
        queue.submit([encoder.finish()]);
        let bytes = read_mapped(device, &buffer, buffer.size())?;
        let bgra = matches!(
            self.format,
            wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb
        );
        let mut rgb = Vec::with_capacity((size[0] * size[1] * 3) as usize);
        for y in 0..size[1] as usize {
            let start = y * row as usize;
            for px in bytes[start..start + size[0] as usize * 4].chunks_exact(4) {
                if bgra {
                    rgb.extend([px[2], px[1], px[0]]);
                } else {
                    rgb.extend([px[0], px[1], px[2]]);
                }
            }
        }
        image::RgbImage::from_raw(size[0], size[1], rgb)
            .ok_or_else(|| "screenshot: the readback has the wrong size".to_string())
    }
}

/// The target formats [`Presenter::capture`] can read back: 8-bit RGBA or BGRA.
pub fn capturable(format: wgpu::TextureFormat) -> bool {
    matches!(
        format,
        wgpu::TextureFormat::Bgra8Unorm
            | wgpu::TextureFormat::Bgra8UnormSrgb
            | wgpu::TextureFormat::Rgba8Unorm
            | wgpu::TextureFormat::Rgba8UnormSrgb
    )
}

fn extent(size: [u32; 2]) -> wgpu::Extent3d {
    wgpu::Extent3d {
        width: size[0],
        height: size[1],
        depth_or_array_layers: 1,
    }
}
