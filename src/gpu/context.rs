//! The headless wgpu device every executor runs on.

use super::error::GpuError;

/// Environment variable naming the adapter to use when the caller names none.
pub const ADAPTER_ENV: &str = "PASSGRAPH_ADAPTER";

/// Optional features used when the adapter has them: per-stage timing, and storage textures
/// beyond WebGPU's guaranteed formats and accesses (e.g. `read_write` rgba32float).
const WANTED_FEATURES: wgpu::Features = wgpu::Features::TIMESTAMP_QUERY
    .union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS)
    .union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES)
    .union(wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES)
    .union(wgpu::Features::BGRA8UNORM_STORAGE);

/// Cheap to clone: wgpu's handles are shared, so a viewer can rebuild sessions on one device.
#[derive(Clone)]
pub struct GpuContext {
    adapter: wgpu::Adapter,
    device: wgpu::Device,
    queue: wgpu::Queue,
    info: wgpu::AdapterInfo,
}

impl GpuContext {
    /// Opens a device without a window. Backends come from `WGPU_BACKEND` (all if unset). With
    /// `adapter` (or else `PASSGRAPH_ADAPTER`) the first adapter whose name contains it,
    /// ignoring case, is used; otherwise wgpu's high-performance choice.
    pub fn new(adapter: Option<&str>) -> Result<GpuContext, GpuError> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle().with_env());
        GpuContext::with_instance(&instance, None, adapter)
    }

    /// As [`GpuContext::new`], on a caller's instance; with `surface`, only an adapter that can
    /// present to it is taken (a window's instance must be the one its surface came from).
    pub fn with_instance(
        instance: &wgpu::Instance,
        surface: Option<&wgpu::Surface<'_>>,
        adapter: Option<&str>,
    ) -> Result<GpuContext, GpuError> {
        let filter = adapter
            .map(str::to_string)
            .or_else(|| std::env::var(ADAPTER_ENV).ok())
            .filter(|f| !f.trim().is_empty());
        let adapter = match filter {
            Some(filter) => adapter_by_name(instance, &filter, surface)?,
            None => {
                let options = wgpu::RequestAdapterOptions {
                    power_preference: wgpu::PowerPreference::from_env()
                        .unwrap_or(wgpu::PowerPreference::HighPerformance),
                    compatible_surface: surface,
                    ..Default::default()
                };
                pollster::block_on(instance.request_adapter(&options))
                    .map_err(|_| GpuError::NoAdapter)?
            }
        };
        let info = adapter.get_info();
        let mut features = adapter.features().intersection(WANTED_FEATURES);
        if !features.contains(wgpu::Features::TIMESTAMP_QUERY) {
            // The "inside" variants extend TIMESTAMP_QUERY and are invalid without it.
            features.remove(
                wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS
                    .union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES),
            );
        }
        let descriptor = wgpu::DeviceDescriptor {
            label: Some("passgraph"),
            required_features: features,
            // The adapter's own limits, not WebGPU's defaults: scene and accumulation buffers
            // easily exceed the default 128 MiB storage binding.
            required_limits: adapter.limits(),
            ..Default::default()
        };
        let (device, queue) =
            pollster::block_on(adapter.request_device(&descriptor)).map_err(|source| {
                GpuError::RequestDevice {
                    adapter: info.name.clone(),
                    source,
                }
            })?;
        Ok(GpuContext {
            adapter,
            device,
            queue,
            info,
        })
    }

    /// Name, backend, driver: what the CLI prints.
    pub fn adapter_info(&self) -> &wgpu::AdapterInfo {
        &self.info
    }

    pub fn adapter(&self) -> &wgpu::Adapter {
        &self.adapter
    }

    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    pub fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }

    /// Whether executors can time their stages on this device.
    pub fn timestamps_supported(&self) -> bool {
        self.device
            .features()
            .contains(wgpu::Features::TIMESTAMP_QUERY)
    }

    /// What the device allows for `format`: the adapter's own capabilities when the
    /// adapter-specific feature is on, otherwise WebGPU's guarantees.
    pub fn format_features(&self, format: wgpu::TextureFormat) -> wgpu::TextureFormatFeatures {
        let features = self.device.features();
        if features.contains(wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES) {
            self.adapter.get_texture_format_features(format)
        } else {
            format.guaranteed_format_features(features)
        }
    }
}

fn adapter_by_name(
    instance: &wgpu::Instance,
    filter: &str,
    surface: Option<&wgpu::Surface<'_>>,
) -> Result<wgpu::Adapter, GpuError> {
    let mut adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()));
    if let Some(surface) = surface {
        adapters.retain(|a| a.is_surface_supported(surface));
    }
    if adapters.is_empty() {
        return Err(GpuError::NoAdapter);
    }
    let wanted = filter.to_lowercase();
    let names: Vec<String> = adapters
        .iter()
        .map(|a| {
            let info = a.get_info();
            format!("{} ({:?})", info.name, info.backend)
        })
        .collect();
    adapters
        .into_iter()
        .find(|a| a.get_info().name.to_lowercase().contains(&wanted))
        .ok_or(GpuError::NoMatchingAdapter {
            filter: filter.to_string(),
            available: names,
        })
}
