//! `shaders/lib/shading.wgsl` and `shaders/lib/texture.wgsl` on the GPU (lavapipe in CI)
//! through `tests/data/scenes/shading_check.wgsl`, against their CPU twins: interpolated
//! normals and uvs per BVH-order triangle, Mitsuba's bilinear lookup, and `material_at`.

mod common;

use common::bvh_gpu::{dispatch_and_read, gpu, output_buffer, test_pipeline};
use glam::{Vec2, Vec3, Vec4};
use passgraph::gpu::texels::create_texel_view;
use passgraph::scene::texture::{LUMINANCE, Texture};
use passgraph::scene::{
    MATERIAL_PLASTIC, Material, Mesh, MeshTriangle, NO_TEXTURE, SHADING_HAS_NORMALS,
    SHADING_HAS_UVS, SceneGpu,
};
use wgpu::util::DeviceExt;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Query {
    n_geometric: [f32; 3],
    triangle: u32,
    bary: [f32; 2],
    uv: [f32; 2],
    texture: u32,
    material: u32,
    pad: [u32; 2],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct Answer {
    normal: [f32; 3],
    pad0: f32,
    uv: [f32; 2],
    pad1: [f32; 2],
    texel: [f32; 4],
    kd: [f32; 3],
    alpha: f32,
    ks: [f32; 3],
    opacity: f32,
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

fn random_texture(rng: &mut Rng, width: u32, height: u32) -> Texture {
    let texels = (0..width * height)
        .map(|_| [rng.next(), rng.next(), rng.next(), rng.next()])
        .collect();
    Texture::from_texels(width, height, texels)
}

/// Triangles with normals and uvs, some with neither; materials with and without maps.
fn scene(rng: &mut Rng) -> SceneGpu {
    let mut triangles = Vec::new();
    for i in 0..40 {
        let base = Vec3::new(i as f32 * 2.0, 0.0, 0.0);
        let vertices = [base, base + Vec3::X, base + Vec3::Y + rng.vec3() * 0.1];
        let mut t = MeshTriangle::flat(vertices, (i % 3) as u32);
        if i % 4 != 0 {
            t.normals = Some([rng.vec3(), rng.vec3(), rng.vec3()].map(Vec3::normalize));
        }
        if i % 5 != 0 {
            t.uvs = Some([0, 1, 2].map(|_| Vec2::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0))));
        }
        triangles.push(t);
    }
    let mapped = Material {
        kind: MATERIAL_PLASTIC,
        map_kd: 0,
        map_ks: 1,
        map_pr: 2,
        map_d: 1,
        ..Material::diffuse([0.1, 0.2, 0.3])
    };
    let constant = Material {
        ks: [0.4; 3],
        alpha: 0.09,
        opacity: 0.5,
        ..Material::diffuse([0.7, 0.6, 0.5])
    };
    let partly = Material {
        map_kd: 2,
        ..constant
    };
    let mesh = Mesh {
        path: "generated".into(),
        triangles,
        materials: vec![mapped, constant, partly],
        material_names: vec!["mapped".into(), "constant".into(), "partly".into()],
        textures: vec![
            random_texture(rng, 5, 3),
            random_texture(rng, 1, 1),
            random_texture(rng, 8, 16),
        ],
        back_materials: Default::default(),
        // Null masks keep their opacity in the record (a cut-out's lives in its triangles),
        // where shading reads it through material_at.
        null_masks: (0..3).collect(),
        warnings: Vec::new(),
    };
    SceneGpu::build(&mesh)
}

/// The CPU twin of shading_normal.
fn cpu_normal(scene: &SceneGpu, triangle: u32, bary: Vec2, ng: Vec3) -> Vec3 {
    let s = scene.shading[triangle as usize];
    if s.flags & SHADING_HAS_NORMALS == 0 {
        return ng;
    }
    let n = (1.0 - bary.x - bary.y) * Vec3::from(s.n0)
        + bary.x * Vec3::from(s.n1)
        + bary.y * Vec3::from(s.n2);
    if n.length_squared() <= 1e-12 {
        return ng;
    }
    let n = n.normalize();
    if n.dot(ng) >= 0.0 { n } else { -n }
}

fn cpu_uv(scene: &SceneGpu, triangle: u32, bary: Vec2) -> Vec2 {
    let s = scene.shading[triangle as usize];
    if s.flags & SHADING_HAS_UVS == 0 {
        return Vec2::ZERO;
    }
    (1.0 - bary.x - bary.y) * Vec2::new(s.u0, s.v0)
        + bary.x * Vec2::from(s.uv1)
        + bary.y * Vec2::from(s.uv2)
}

/// The CPU twin of material_at.
fn cpu_material(scene: &SceneGpu, m: Material, uv: Vec2) -> Material {
    let lookup = |i: u32| scene.textures[i as usize].bilinear(uv);
    let scalar = |i: u32| lookup(i).truncate().dot(Vec3::from(LUMINANCE));
    let mut r = m;
    if m.map_kd != NO_TEXTURE {
        r.kd = lookup(m.map_kd).truncate().into();
    }
    if m.map_ks != NO_TEXTURE {
        r.ks = lookup(m.map_ks).truncate().into();
    }
    if m.map_pr != NO_TEXTURE {
        r.alpha = scalar(m.map_pr).powi(2);
    }
    if m.map_d != NO_TEXTURE {
        r.opacity = scalar(m.map_d);
    }
    r
}

fn close(a: impl Into<Vec4>, b: impl Into<Vec4>, tolerance: f32) -> bool {
    (a.into() - b.into()).abs().max_element() <= tolerance
}

#[test]
fn shading_and_texture_accessors_match_the_cpu() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let scene = scene(&mut rng);
    assert!(scene.has_shading_normals && scene.has_uvs && scene.has_textures);
    let mut queries = Vec::new();
    for i in 0..2000u32 {
        let u = rng.next();
        let v = rng.next() * (1.0 - u);
        // Near-integer uvs (texel edges, the wrap seam) as well as anywhere in [-3, 3].
        let uv = if i % 4 == 0 {
            Vec2::new(
                (rng.range(-3.0, 3.0) * 8.0).round() / 8.0,
                (rng.range(-3.0, 3.0) * 6.0).round() / 6.0,
            )
        } else {
            Vec2::new(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0))
        };
        queries.push(Query {
            n_geometric: rng.vec3().normalize().into(),
            triangle: i % scene.triangles.len() as u32,
            bary: [u, v],
            uv: uv.into(),
            texture: i % 3,
            material: i % 3,
            pad: [0; 2],
        });
    }

    let gpu = gpu();
    let view = |label: &str, bytes: &[u8]| {
        create_texel_view(&gpu.device, &gpu.queue, label, bytes)
            .expect("fits a texture")
            .create_view(&Default::default())
    };
    let shading = view("shading", &scene.shading_bytes());
    let textures = view("textures", &scene.textures_bytes());
    let materials = view("materials", bytemuck::cast_slice(&scene.materials));
    let query_buffer = gpu
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("queries"),
            contents: bytemuck::cast_slice(&queries),
            usage: wgpu::BufferUsages::STORAGE,
        });
    let answers = output_buffer(&gpu, (queries.len() * size_of::<Answer>()) as u64);
    let pipeline = test_pipeline(&gpu, "shading_check");
    let texture_entry = |binding, view| wgpu::BindGroupEntry {
        binding,
        resource: wgpu::BindingResource::TextureView(view),
    };
    let bind_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            texture_entry(0, &shading),
            texture_entry(1, &textures),
            texture_entry(2, &materials),
            wgpu::BindGroupEntry {
                binding: 3,
                resource: query_buffer.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 4,
                resource: answers.as_entire_binding(),
            },
        ],
    });
    let answers: Vec<Answer> =
        dispatch_and_read(&gpu, &pipeline, &bind_group, queries.len(), &answers);

    for (q, a) in queries.iter().zip(&answers) {
        let bary = Vec2::from(q.bary);
        let uv = Vec2::from(q.uv);
        let n = cpu_normal(&scene, q.triangle, bary, q.n_geometric.into());
        assert!(
            close(n.extend(0.0), Vec3::from(a.normal).extend(0.0), 1e-5),
            "normal {n} vs {:?} for triangle {}",
            a.normal,
            q.triangle
        );
        let s = cpu_uv(&scene, q.triangle, bary);
        assert!(
            close(
                s.extend(0.0).extend(0.0),
                Vec2::from(a.uv).extend(0.0).extend(0.0),
                1e-5
            ),
            "uv {s} vs {:?}",
            a.uv
        );
        // Texel indices are exact; the weights differ by the rounding of uv * size (fma).
        let texel = scene.textures[q.texture as usize].bilinear(uv);
        assert!(
            close(texel, Vec4::from(a.texel), 1e-4),
            "texture {} at {uv}: {texel} vs {:?}",
            q.texture,
            a.texel
        );
        let m = cpu_material(&scene, scene.materials[q.material as usize], uv);
        let got = Vec4::from((Vec3::from(a.kd), a.alpha));
        assert!(
            close(Vec4::from((Vec3::from(m.kd), m.alpha)), got, 1e-4),
            "{m:?} vs {a:?}"
        );
        let got = Vec4::from((Vec3::from(a.ks), a.opacity));
        assert!(
            close(Vec4::from((Vec3::from(m.ks), m.opacity)), got, 1e-4),
            "{m:?} vs {a:?}"
        );
    }
    eprintln!("{} queries agree", queries.len());
}
