//! The harness that runs `shaders/lib/bvh.wgsl` on a GPU (lavapipe in CI) through
//! `tests/data/scenes/bvh_check.wgsl`, and the comparison of its answers with the CPU traversal.
//! Shared by tests/bvh_wgsl.rs and the tests/robust_*.rs suites.

use super::root;
use glam::Vec3;
use passgraph::gpu::GpuContext;
use passgraph::gpu::texels::create_texel_view;
use passgraph::graph::shader_source::ShaderSource;
use passgraph::scene::intersect::{PreparedRay, intersect_triangle};
use passgraph::scene::{Ray, SceneGpu};

/// bvh_check.wgsl with its includes resolved.
pub fn check_shader() -> ShaderSource {
    let path = root().join("tests/data/scenes/bvh_check.wgsl");
    ShaderSource::load(&path, &root().join("shaders")).expect("includes resolve")
}

/// Matches `Query` in bvh_check.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Query {
    pub origin: [f32; 3],
    pub tmin: f32,
    pub dir: [f32; 3],
    pub tmax: f32,
}

impl Query {
    /// A ray from `origin` along `dir` (not normalised) with t in (tmin, tmax).
    pub fn new(origin: Vec3, dir: Vec3, tmin: f32, tmax: f32) -> Query {
        Query {
            origin: origin.into(),
            tmin,
            dir: dir.into(),
            tmax,
        }
    }

    pub fn ray(&self) -> Ray {
        Ray {
            origin: self.origin.into(),
            dir: self.dir.into(),
        }
    }
}

/// Matches `Answer` in bvh_check.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Answer {
    pub t: f32,
    pub u: f32,
    pub v: f32,
    pub triangle: u32,
    pub any: u32,
    /// shadow_hit: any_hit over the occluders' subtree.
    pub shadow: u32,
    pub pad: [u32; 2],
}

pub struct Gpu {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
}

/// The GPU these tests need, chosen as the binary chooses it; without one they fail with the
/// binary's message saying what to install, rather than skip.
pub fn gpu() -> Gpu {
    let ctx = GpuContext::new(None).unwrap_or_else(|e| panic!("{e}"));
    Gpu {
        device: ctx.device().clone(),
        queue: ctx.queue().clone(),
    }
}

/// Runs bvh_check.wgsl over `queries` against `scene`.
pub fn run_on_gpu(gpu: &Gpu, scene: &SceneGpu, queries: &[Query]) -> Vec<Answer> {
    use wgpu::util::DeviceExt;
    let device = &gpu.device;
    let storage = |label: &str, bytes: &[u8]| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytes,
            usage: wgpu::BufferUsages::STORAGE,
        })
    };
    // The scene as texel views, as the executor binds it to passes.
    let view = |label: &str, bytes: &[u8]| {
        create_texel_view(device, &gpu.queue, label, bytes)
            .expect("scene fits a texture")
            .create_view(&Default::default())
    };
    let triangles = view("triangles", bytemuck::cast_slice(&scene.triangles));
    let nodes = view("bvh", &scene.bvh_bytes());
    let query_buffer = storage("queries", bytemuck::cast_slice(queries));
    let size = (queries.len() * size_of::<Answer>()) as u64;
    let answers = output_buffer(gpu, size);
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("bvh_check"),
        source: wgpu::ShaderSource::Wgsl(check_shader().code.into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("bvh_check"),
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: wgpu::PipelineCompilationOptions {
            constants: &[
                ("scene_triangle_count", scene.triangles.len() as f64),
                ("scene_node_count", scene.nodes.len() as f64),
                ("scene_occluder_root", f64::from(scene.occluder_root)),
            ],
            ..Default::default()
        },
        cache: None,
    });
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&triangles),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(&nodes),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: query_buffer.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: answers.as_entire_binding(),
            },
        ],
    });
    dispatch_and_read(gpu, &pipeline, &bind_group, queries.len(), &answers)
}

/// The compute pipeline of test shader `tests/data/scenes/NAME.wgsl` (entry point `main`, its
/// includes resolved against `shaders/`).
pub fn test_pipeline(gpu: &Gpu, name: &str) -> wgpu::ComputePipeline {
    let path = root().join(format!("tests/data/scenes/{name}.wgsl"));
    let source = ShaderSource::load(&path, &root().join("shaders")).expect("includes resolve");
    let module = gpu
        .device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(name),
            source: wgpu::ShaderSource::Wgsl(source.code.into()),
        });
    gpu.device
        .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(name),
            layout: None,
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        })
}

/// A bind group for group 0 of `pipeline` with `buffers` at bindings 0, 1, 2...
pub fn bind_buffers(
    gpu: &Gpu,
    pipeline: &wgpu::ComputePipeline,
    buffers: &[&wgpu::Buffer],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = buffers
        .iter()
        .enumerate()
        .map(|(i, buffer)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: buffer.as_entire_binding(),
        })
        .collect();
    gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &entries,
    })
}

/// A storage buffer of `size` bytes a test shader writes its answers to.
pub fn output_buffer(gpu: &Gpu, size: u64) -> wgpu::Buffer {
    gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("answers"),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

/// Runs `pipeline` with `bind_group` over `count` items (workgroups of 64) and reads `answers`
/// (an [`output_buffer`] the bind group holds) back.
pub fn dispatch_and_read<T: bytemuck::Pod>(
    gpu: &Gpu,
    pipeline: &wgpu::ComputePipeline,
    bind_group: &wgpu::BindGroup,
    count: usize,
    answers: &wgpu::Buffer,
) -> Vec<T> {
    let groups = [count.div_ceil(64) as u32, 1, 1];
    dispatch_groups_and_read(gpu, pipeline, bind_group, groups, answers)
}

/// As [`dispatch_and_read`], over a grid of `groups` workgroups.
pub fn dispatch_groups_and_read<T: bytemuck::Pod>(
    gpu: &Gpu,
    pipeline: &wgpu::ComputePipeline,
    bind_group: &wgpu::BindGroup,
    groups: [u32; 3],
    answers: &wgpu::Buffer,
) -> Vec<T> {
    let size = answers.size();
    let readback = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.dispatch_workgroups(groups[0], groups[1], groups[2]);
    }
    encoder.copy_buffer_to_buffer(answers, 0, &readback, 0, size);
    gpu.queue.submit([encoder.finish()]);
    readback.map_async(wgpu::MapMode::Read, .., |result| result.expect("map"));
    gpu.device
        .poll(wgpu::PollType::wait_indefinitely())
        .expect("poll");
    let answers = bytemuck::cast_slice(&readback.get_mapped_range(..).expect("mapped")).to_vec();
    readback.unmap();
    answers
}

/// Compares GPU answers with the CPU traversal. WGSL lets the GPU compiler fuse a multiply
/// and an add, and its division need not be correctly rounded, so t may differ in its last
/// bits; where several triangles are hit at (almost) the same t (a shared vertex or edge), that
/// can pick another of them. Anything else must agree exactly.
pub fn compare(
    name: &str,
    scene: &SceneGpu,
    queries: &[Query],
    answers: &[Answer],
    aimed_at_edges: bool,
) {
    let (mut t_differences, mut ties) = (0, 0);
    for (q, a) in queries.iter().zip(answers) {
        let ray = Ray {
            origin: q.origin.into(),
            dir: q.dir.into(),
        };
        let cpu = scene.closest_hit(&ray, q.tmin, q.tmax);
        let any = scene.any_hit(&ray, q.tmin, q.tmax);
        assert_eq!(a.any != 0, any, "{name}: any_hit differs for {ray:?}");
        let shadow = scene.shadow_hit(&ray, q.tmin, q.tmax);
        assert_eq!(
            a.shadow != 0,
            shadow,
            "{name}: shadow_hit differs for {ray:?}"
        );
        let Some(hit) = cpu else {
            assert_eq!(
                a.triangle,
                u32::MAX,
                "{name}: GPU hit, CPU missed: {ray:?} {a:?}"
            );
            continue;
        };
        // t is a weighted mean of the vertices' distances along the ray, so its rounding
        // error scales with the farthest vertex, not with t.
        let reach = scene.triangles[hit.triangle as usize]
            .vertices()
            .iter()
            .map(|p| (*p - ray.origin).length() / ray.dir.length())
            .fold(hit.t.abs(), f32::max);
        let tolerance = 64.0 * f32::EPSILON * reach;
        assert!(
            (a.t - hit.t).abs() <= tolerance,
            "{name}: t {} vs {} for {ray:?}",
            a.t,
            hit.t
        );
        t_differences += usize::from(a.t != hit.t);
        if a.triangle != hit.triangle {
            // Another triangle is acceptable only where the two meet: the CPU hits it at the
            // same t too, or (rays aimed at shared edges) the GPU's barycentrics put the hit on
            // that triangle's boundary, at the same point.
            let other = scene
                .triangles
                .get(a.triangle as usize)
                .map(|t| t.vertices());
            let other_t = other.and_then(|v| {
                intersect_triangle(&PreparedRay::new(&ray), &v, q.tmin, q.tmax).map(|h| h.t)
            });
            let on_boundary = other.is_some_and(|[p0, p1, p2]| {
                let point = (1.0 - a.u - a.v) * p0 + a.u * p1 + a.v * p2;
                let slack = 1e-6;
                aimed_at_edges
                    && a.u >= -slack
                    && a.v >= -slack
                    && a.u + a.v <= 1.0 + slack
                    && (point - (ray.origin + a.t * ray.dir)).length()
                        <= tolerance * ray.dir.length()
            });
            assert!(
                other_t.is_some_and(|t| (t - hit.t).abs() <= tolerance) || on_boundary,
                "{name}: GPU hit triangle {} ({a:?}), CPU hit {hit:?} for {ray:?}",
                a.triangle
            );
            ties += 1;
        }
    }
    eprintln!(
        "{name}: {} rays agree ({t_differences} with t a few ulps apart, {ties} ties at shared \
         edges resolved to the neighbour)",
        queries.len()
    );
}
