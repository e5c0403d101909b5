//! Normal and bump maps on the GPU (lavapipe in CI): `shading_point`'s shading normal at given
//! hits of random triangles, front and back, with normal maps, bump maps and none, and the
//! maps' shadowing of random directions, through
//! `tests/data/scenes/surface_map_check.wgsl`, against the CPU twin
//! (`passgraph::scene::surface_map`).

mod common;

use common::bvh_gpu::{dispatch_and_read, gpu, output_buffer, test_pipeline};
use glam::{Vec2, Vec3};
use passgraph::gpu::texels::create_texel_view;
use passgraph::scene::surface_map::{self, mapped_normal};
use passgraph::scene::texture::Texture;
use passgraph::scene::{
    MATERIAL_DIELECTRIC, MATERIAL_PLASTIC, Material, Mesh, MeshTriangle, SURFACE_MAP_BUMP,
    SceneGpu, materials_bytes,
};
use wgpu::util::DeviceExt;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Query {
    dir: [f32; 3],
    triangle: u32,
    bary: [f32; 2],
    pad: [u32; 2],
    w: [f32; 3],
    pad1: u32,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct Answer {
    ns: [f32; 3],
    front: u32,
    n_smooth: [f32; 3],
    shadowing: f32,
}

/// A small deterministic generator (xorshift), so failures reproduce.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }

    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.next()
    }

    fn vec3(&mut self) -> Vec3 {
        Vec3::new(
            self.range(-1.0, 1.0),
            self.range(-1.0, 1.0),
            self.range(-1.0, 1.0),
        )
    }
}

/// A normal map's texels: directions around +z (z >= 0.3), encoded as (n + 1) / 2.
fn normal_texture(rng: &mut Rng, width: u32, height: u32) -> Texture {
    let texels = (0..width * height)
        .map(|_| {
            let mut n = rng.vec3();
            n.z = n.z.abs().max(0.3);
            let c = (n.normalize() + Vec3::ONE) * 0.5;
            [c.x, c.y, c.z, 1.0]
        })
        .collect();
    Texture::from_texels(width, height, texels)
}

fn height_texture(rng: &mut Rng, width: u32, height: u32) -> Texture {
    let texels = (0..width * height)
        .map(|_| {
            let h = rng.next();
            [h, h * 0.5, 1.0 - h, 1.0]
        })
        .collect();
    Texture::from_texels(width, height, texels)
}

/// Random triangles with uvs, most with vertex normals; a Lambertian normal-mapped material,
/// a bump-mapped plastic, a normal-mapped dielectric and an unmapped one.
fn scene(rng: &mut Rng) -> SceneGpu {
    let mut triangles = Vec::new();
    for i in 0..48 {
        let base = Vec3::new(i as f32 * 3.0, 0.0, 0.0);
        let vertices = [base, base + rng.vec3() * 2.0, base + rng.vec3() * 2.0];
        let mut t = MeshTriangle::flat(vertices, (i % 4) as u32);
        if i % 3 != 0 {
            t.normals = Some([0, 1, 2].map(|_| rng.vec3().normalize()));
        }
        t.uvs = Some([0, 1, 2].map(|_| Vec2::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0))));
        triangles.push(t);
    }
    let normal = Material {
        surface_map: 0,
        ..Material::diffuse([0.5; 3])
    };
    let bump = Material {
        kind: MATERIAL_PLASTIC,
        alpha: 0.1,
        surface_map: 1 | SURFACE_MAP_BUMP,
        bump_scale: 0.3,
        ..Material::diffuse([0.5; 3])
    };
    let glass = Material {
        kind: MATERIAL_DIELECTRIC,
        surface_map: 0,
        ..Material::default()
    };
    let mesh = Mesh {
        path: "generated".into(),
        triangles,
        materials: vec![normal, bump, glass, Material::default()],
        material_names: ["normal", "bump", "glass", "plain"]
            .map(String::from)
            .to_vec(),
        textures: vec![normal_texture(rng, 5, 7), height_texture(rng, 9, 4)],
        back_materials: Default::default(),
        null_masks: Default::default(),
        warnings: Vec::new(),
    };
    SceneGpu::build(&mesh)
}

#[test]
fn the_mapped_shading_normal_matches_the_cpu_twin() {
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    let scene = scene(&mut rng);
    assert!(scene.has_surface_maps);
    let mut queries = Vec::new();
    for i in 0..1024u32 {
        let (u, v) = (rng.next(), rng.next());
        let (u, v) = if u + v > 1.0 {
            (1.0 - u, 1.0 - v)
        } else {
            (u, v)
        };
        queries.push(Query {
            dir: rng.vec3().normalize().into(),
            triangle: i % scene.triangles.len() as u32,
            bary: [u, v],
            pad: [0; 2],
            w: rng.vec3().normalize().into(),
            pad1: 0,
        });
    }

    let gpu = gpu();
    let view = |label: &str, bytes: &[u8]| {
        create_texel_view(&gpu.device, &gpu.queue, label, bytes)
            .expect("fits a texture")
            .create_view(&Default::default())
    };
    let triangles = view("triangles", bytemuck::cast_slice(&scene.triangles));
    let shading = view("shading", &scene.shading_bytes());
    let textures = view("textures", &scene.textures_bytes());
    let materials = view("materials", &materials_bytes(&scene.materials));
    let query_buffer = gpu
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("queries"),
            contents: bytemuck::cast_slice(&queries),
            usage: wgpu::BufferUsages::STORAGE,
        });
    let answers = output_buffer(&gpu, (queries.len() * size_of::<Answer>()) as u64);
    let pipeline = test_pipeline(&gpu, "surface_map_check");
    let texture_entry = |binding, view| wgpu::BindGroupEntry {
        binding,
        resource: wgpu::BindingResource::TextureView(view),
    };
    let bind_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            texture_entry(0, &triangles),
            texture_entry(1, &shading),
            texture_entry(2, &textures),
            texture_entry(3, &materials),
            wgpu::BindGroupEntry {
                binding: 4,
                resource: query_buffer.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 5,
                resource: answers.as_entire_binding(),
            },
        ],
    });
    let answers: Vec<Answer> =
        dispatch_and_read(&gpu, &pipeline, &bind_group, queries.len(), &answers);

    let mut perturbed = 0;
    for (q, a) in queries.iter().zip(&answers) {
        let t = scene.triangles[q.triangle as usize];
        let s = scene.shading[q.triangle as usize];
        let p = t.vertices();
        let ng = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
        let front = ng.dot(Vec3::from(q.dir)) < 0.0;
        assert_eq!(a.front == 1, front);
        let (u, v) = (q.bary[0], q.bary[1]);
        let uvs = [Vec2::new(s.u0, s.v0), s.uv1.into(), s.uv2.into()];
        let uv = (1.0 - u - v) * uvs[0] + u * uvs[1] + v * uvs[2];
        // The unperturbed shading normal as the GPU found it (tests/shading_gpu.rs checks it).
        let n = Vec3::from(a.n_smooth);
        let expected = mapped_normal(
            &scene.materials[t.material as usize],
            &scene.textures,
            p,
            uvs,
            uv,
            n,
            front,
            -Vec3::from(q.dir),
        );
        let got = Vec3::from(a.ns);
        assert!(
            (expected - got).abs().max_element() < 2e-4,
            "triangle {} (material {}) at {uv}, front {front}: CPU {expected} vs GPU {got}",
            q.triangle,
            t.material
        );
        let shadowing = surface_map::shadowing(n, got, q.w.into());
        assert!(
            (shadowing - a.shadowing).abs() < 1e-4,
            "shadowing: CPU {shadowing} vs GPU {}",
            a.shadowing
        );
        if (got - n).length() > 1e-3 {
            perturbed += 1;
        }
    }
    // The maps did perturb most normals (3 materials in 4 have one).
    assert!(perturbed > queries.len() / 2, "{perturbed} perturbed");
    eprintln!("{} queries agree, {perturbed} perturbed", queries.len());
}
