//! The Rust GPU structs against `shaders/lib/scene.wgsl` as naga lays it out: a field added,
//! reordered or resized on one side only would corrupt every buffer silently. (The sizes
//! alone are compile-time assertions in src/scene/gpu_layout.rs.)

mod common;

use common::root;
use passgraph::graph::shader_source::ShaderSource;
use passgraph::scene::{
    Frame, GpuBvhGrid, GpuCamera, Material, PackedBvhNode, Triangle, TriangleShading,
};
use std::mem::{offset_of, size_of, size_of_val};

/// (field name, byte offset, byte size) of each Rust field, in declaration order.
macro_rules! fields {
    ($ty:ty { $($field:ident),* $(,)? }) => {{
        let value = <$ty as Default>::default();
        vec![$((
            stringify!($field),
            offset_of!($ty, $field) as u32,
            std::mem::size_of_val(&value.$field) as u32,
        )),*]
    }};
}

#[test]
fn gpu_structs_match_scene_wgsl_byte_for_byte() {
    // With its include (the material kinds, generated from the registry) resolved.
    let path = root().join("shaders/lib/scene.wgsl");
    let source = ShaderSource::load(&path, &root().join("shaders")).expect("includes resolve");
    let module = naga::front::wgsl::parse_str(&source.code).expect("scene.wgsl parses");

    let rust = [
        (
            "Triangle",
            size_of::<Triangle>(),
            fields!(Triangle {
                p0,
                material,
                p1,
                light,
                p2,
                opacity
            }),
        ),
        (
            "Material",
            size_of::<Material>(),
            fields!(Material {
                kd,
                ns,
                ks,
                kind,
                ke,
                alpha,
                tf,
                ior,
                map_kd,
                map_ks,
                map_pr,
                map_d,
                opacity,
                table,
                surface_map,
                bump_scale,
                eta,
                distribution,
                k,
                fresnel
            }),
        ),
        (
            "TriangleShading",
            size_of::<TriangleShading>(),
            fields!(TriangleShading {
                n0,
                u0,
                n1,
                v0,
                n2,
                flags,
                uv1,
                uv2
            }),
        ),
        (
            "BvhGrid",
            size_of::<GpuBvhGrid>(),
            fields!(GpuBvhGrid {
                origin,
                pad0,
                step,
                pad1
            }),
        ),
        (
            "PackedBvhNode",
            size_of::<PackedBvhNode>(),
            fields!(PackedBvhNode { bounds, link }),
        ),
        (
            "Camera",
            size_of::<GpuCamera>(),
            fields!(GpuCamera {
                eye,
                aperture_radius,
                forward,
                focus_distance,
                right,
                pad2,
                up,
                pad3
            }),
        ),
        (
            "Frame",
            size_of::<Frame>(),
            fields!(Frame {
                index,
                accumulated,
                width,
                height,
                seed,
                tile_row_stride,
                first_sample,
                pad2,
                image_origin,
                image_size
            }),
        ),
    ];
    for (name, size, fields) in rust {
        let ty = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("scene.wgsl has no struct {name}"))
            .1;
        let naga::TypeInner::Struct { members, span } = &ty.inner else {
            panic!("{name} is not a struct");
        };
        assert_eq!(*span as usize, size, "{name}: size");
        let wgsl: Vec<(&str, u32, u32)> = members
            .iter()
            .map(|m| {
                (
                    m.name.as_deref().unwrap_or(""),
                    m.offset,
                    module.types[m.ty].inner.size(module.to_ctx()),
                )
            })
            .collect();
        assert_eq!(wgsl, fields, "{name}: fields (name, offset, size)");
    }
}

/// `render` reports the scene's GPU bytes from `byte_len`, which counts without building the
/// buffers: it must be their lengths, on scenes with and without textures and shading data.
#[test]
fn scene_byte_len_is_the_sum_of_its_buffers() {
    let mut seen_textures = false;
    let mut seen_shading = false;
    for scene in ["cornell", "materials", "outdoor"] {
        let path = root().join("scenes").join(scene).join("scene.ron");
        let gpu = passgraph::scene::load_scene(&path)
            .unwrap_or_else(|e| panic!("{e}"))
            .to_gpu();
        seen_textures |= !gpu.textures.is_empty();
        seen_shading |= !gpu.shading.is_empty();
        let built = size_of_val(gpu.triangles.as_slice())
            + size_of_val(gpu.materials.as_slice())
            + size_of_val(gpu.lights.as_slice())
            + gpu.bvh_bytes().len()
            + gpu.shading_bytes().len()
            + gpu.textures_bytes().len();
        assert_eq!(gpu.byte_len(), built, "{scene}");
    }
    assert!(seen_textures && seen_shading);
}
