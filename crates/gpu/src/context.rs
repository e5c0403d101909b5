//! The headless wgpu device every executor runs on.

use super::error::GpuError;

/// Environment variable naming the adapter to use when the caller names none.
pub const ADAPTER_ENV: &str = "PASSGRAPH_ADAPTER";

/// Optional features used when the adapter has them: per-stage timing, storage textures
/// beyond WebGPU's guaranteed formats and accesses (e.g. `read_write` rgba32float), and
/// subgroup operations (shaders/path_reuse.wgsl).
const WANTED_FEATURES: wgpu::Features = wgpu::Features::TIMESTAMP_QUERY
    .union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS)
    .union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES)
    .union(wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES)
    .union(wgpu::Features::BGRA8UNORM_STORAGE)
    .union(wgpu::Features::SUBGROUP);

/// Cheap to clone: wgpu's handles are shared, so a viewer can rebuild sessions on one device.
#[derive(Clone)]
pub struct GpuContext {
    adapter: wgpu::Adapter,
    device: wgpu::Device,
    queue: wgpu::Queue,
    info: wgpu::AdapterInfo,
}

impl GpuContext {
    /// Opens a device without a window, on the [`backends`]. With `adapter` (or else
    /// `PASSGRAPH_ADAPTER`) the first adapter whose [`describe`] line contains it, ignoring case,
    /// is used; otherwise the fastest kind (discrete, integrated, virtual, CPU; `WGPU_POWER_PREF`
    /// `low` puts integrated first).
    pub fn new(adapter: Option<&str>) -> Result<GpuContext, GpuError> {
        let mut descriptor = wgpu::InstanceDescriptor::new_without_display_handle().with_env();
        descriptor.backends = backends()?;
        GpuContext::with_instance(&wgpu::Instance::new(descriptor), None, adapter)
    }

    /// As [`GpuContext::new`], on a caller's instance (made with [`backends`]); with `surface`,
    /// only an adapter that can present to it is taken (a window's instance must be the one its
    /// surface came from).
    pub fn with_instance(
        instance: &wgpu::Instance,
        surface: Option<&wgpu::Surface<'_>>,
        adapter: Option<&str>,
    ) -> Result<GpuContext, GpuError> {
        let filter = adapter
            .map(str::to_string)
            .or_else(|| std::env::var(ADAPTER_ENV).ok())
            .filter(|f| !f.trim().is_empty());
        let mut adapters = pollster::block_on(instance.enumerate_adapters(SUPPORTED_BACKENDS));
        if let Some(surface) = surface {
            let all: Vec<String> = adapters.iter().map(|a| describe(&a.get_info())).collect();
            adapters.retain(|a| a.is_surface_supported(surface));
            if adapters.is_empty() && !all.is_empty() {
                return Err(GpuError::NoPresentingAdapter { available: all });
            }
        }
        let candidates: Vec<Candidate> = adapters
            .iter()
            .map(|a| Candidate::new(&a.get_info()))
            .collect();
        let power = wgpu::PowerPreference::from_env().unwrap_or_default();
        let chosen = choose_adapter(&candidates, filter.as_deref(), power)?;
        let adapter = adapters.swap_remove(chosen);
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

/// The backends passgraph runs on: not wgpu's GL backend, whose GLSL translation of the path
/// tracer's shaders Mesa's GL rejects (`is not allowed on function parameter`); falling back
/// to it silently would trade "install a Vulkan driver" for a shader compiler error.
pub const SUPPORTED_BACKENDS: wgpu::Backends = wgpu::Backends::VULKAN
    .union(wgpu::Backends::METAL)
    .union(wgpu::Backends::DX12);

/// The backends to open an instance on: [`SUPPORTED_BACKENDS`], narrowed by `WGPU_BACKEND`.
pub fn backends() -> Result<wgpu::Backends, GpuError> {
    backends_from_env(std::env::var("WGPU_BACKEND").ok().as_deref())
}

fn backends_from_env(value: Option<&str>) -> Result<wgpu::Backends, GpuError> {
    let Some(value) = value else {
        return Ok(SUPPORTED_BACKENDS);
    };
    let backends = wgpu::Backends::from_comma_list(value) & SUPPORTED_BACKENDS;
    if backends.is_empty() {
        return Err(GpuError::UnsupportedBackend {
            value: value.to_string(),
        });
    }
    Ok(backends)
}

/// One line naming an adapter, its backend and its driver with the driver's version, e.g.
/// `llvmpipe (LLVM 19.1.7, 256 bits) (Vulkan) · llvmpipe, Mesa 25.0.7 (LLVM 19.1.7)`: what the
/// CLI prints, what the bench report records and what `--adapter` matches.
pub fn describe(info: &wgpu::AdapterInfo) -> String {
    describe_parts(&info.name, info.backend, &info.driver, &info.driver_info)
}

fn describe_parts(name: &str, backend: wgpu::Backend, driver: &str, driver_info: &str) -> String {
    let mut line = format!("{name} ({backend:?})");
    let driver: Vec<&str> = [driver.trim(), driver_info.trim()]
        .into_iter()
        .filter(|s| !s.is_empty())
        .collect();
    if !driver.is_empty() {
        line += " · ";
        line += &driver.join(", ");
    }
    line
}

/// What adapter choice needs to know of an adapter (no device needed).
#[derive(Clone, Debug)]
struct Candidate {
    description: String,
    device_type: wgpu::DeviceType,
}

impl Candidate {
    fn new(info: &wgpu::AdapterInfo) -> Candidate {
        Candidate {
            description: describe(info),
            device_type: info.device_type,
        }
    }
}

/// The index of the adapter to use: with `filter`, the first whose description contains it
/// (ignoring case); otherwise the first of the preferred kind.
fn choose_adapter(
    candidates: &[Candidate],
    filter: Option<&str>,
    power: wgpu::PowerPreference,
) -> Result<usize, GpuError> {
    if candidates.is_empty() {
        return Err(GpuError::NoAdapter);
    }
    if let Some(filter) = filter {
        let wanted = filter.trim().to_lowercase();
        return candidates
            .iter()
            .position(|c| c.description.to_lowercase().contains(&wanted))
            .ok_or_else(|| GpuError::NoMatchingAdapter {
                filter: filter.to_string(),
                available: candidates.iter().map(|c| c.description.clone()).collect(),
            });
    }
    let rank = |t: wgpu::DeviceType| match (t, power) {
        (wgpu::DeviceType::IntegratedGpu, wgpu::PowerPreference::LowPower) => 0,
        (wgpu::DeviceType::DiscreteGpu, _) => 1,
        (wgpu::DeviceType::IntegratedGpu, _) => 2,
        (wgpu::DeviceType::VirtualGpu, _) => 3,
        (wgpu::DeviceType::Cpu, _) => 4,
        (wgpu::DeviceType::Other, _) => 5,
    };
    Ok(candidates
        .iter()
        .enumerate()
        .min_by_key(|(i, c)| (rank(c.device_type), *i))
        .map(|(i, _)| i)
        .expect("candidates is not empty"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use wgpu::{Backend, DeviceType, PowerPreference};

    fn candidate(name: &str, backend: Backend, device_type: DeviceType) -> Candidate {
        Candidate {
            description: describe_parts(name, backend, "llvmpipe", "Mesa 25.0.7"),
            device_type,
        }
    }

    #[test]
    fn the_description_carries_backend_driver_and_version() {
        assert_eq!(
            describe_parts(
                "llvmpipe (LLVM 19.1.7, 256 bits)",
                Backend::Vulkan,
                "llvmpipe",
                "Mesa 25.0.7-2~bpo12+1 (LLVM 19.1.7)"
            ),
            "llvmpipe (LLVM 19.1.7, 256 bits) (Vulkan) · llvmpipe, Mesa 25.0.7-2~bpo12+1 (LLVM 19.1.7)"
        );
        assert_eq!(
            describe_parts("Apple M2", Backend::Metal, "", " "),
            "Apple M2 (Metal)"
        );
    }

    #[test]
    fn gl_is_never_opened_and_asking_for_it_alone_says_why() {
        assert!(!SUPPORTED_BACKENDS.contains(wgpu::Backends::GL));
        assert_eq!(backends_from_env(None).unwrap(), SUPPORTED_BACKENDS);
        assert_eq!(
            backends_from_env(Some("gl,vulkan")).unwrap(),
            wgpu::Backends::VULKAN
        );
        let message = backends_from_env(Some("gl")).unwrap_err().to_string();
        assert!(
            message.contains("WGPU_BACKEND='gl'") && message.contains("GL backend"),
            "{message}"
        );
    }

    #[test]
    fn no_adapter_says_what_to_install() {
        let message = choose_adapter(&[], None, PowerPreference::HighPerformance)
            .unwrap_err()
            .to_string();
        for part in [
            "no Vulkan adapter",
            "scripts/setup",
            "apt-get install -t bookworm-backports mesa-vulkan-drivers",
        ] {
            assert!(message.contains(part), "{part:?} missing from: {message}");
        }
    }

    #[test]
    fn a_filter_matches_what_the_adapter_list_prints() {
        let list = [
            candidate(
                "llvmpipe (LLVM 19.1.7, 256 bits)",
                Backend::Vulkan,
                DeviceType::Cpu,
            ),
            candidate("Apple M2", Backend::Metal, DeviceType::IntegratedGpu),
        ];
        let pick = |f| choose_adapter(&list, Some(f), PowerPreference::HighPerformance);
        assert_eq!(pick("LLVMPIPE").unwrap(), 0);
        assert_eq!(pick("(metal)").unwrap(), 1, "backends as printed");
        assert_eq!(pick("vulkan").unwrap(), 0);
        assert_eq!(pick("mesa 25").unwrap(), 0, "driver versions match too");
        let message = pick("(Gl)").unwrap_err().to_string();
        assert!(
            message.contains("'(Gl)'")
                && message.contains("'Apple M2 (Metal) · llvmpipe, Mesa 25.0.7'"),
            "{message}"
        );
    }

    #[test]
    fn without_a_filter_the_fastest_kind_wins() {
        let list = [
            candidate("cpu", Backend::Vulkan, DeviceType::Cpu),
            candidate("integrated", Backend::Vulkan, DeviceType::IntegratedGpu),
            candidate("discrete", Backend::Vulkan, DeviceType::DiscreteGpu),
        ];
        assert_eq!(
            choose_adapter(&list, None, PowerPreference::HighPerformance).unwrap(),
            2
        );
        assert_eq!(
            choose_adapter(&list, None, PowerPreference::LowPower).unwrap(),
            1
        );
        assert_eq!(
            choose_adapter(&list[..1], None, PowerPreference::None).unwrap(),
            0
        );
    }
}
