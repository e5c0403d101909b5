//! What the path tracer provides to its graphs: the scene's buffers, the cameras, the frame
//! uniform and the scene overrides. One table registers each with the compiler (a
//! [`ProvidedSet`]) and fills its data (a [`ProvidedData`]), so neither can name something the
//! other lacks.

use crate::gpu::ProvidedData;
use crate::graph::param::ParamType;
use crate::graph::provided::{ProvidedKind, ProvidedSet};
use crate::render::tile_order::tile_row_stride;
use crate::render::tiling::Tile;
use crate::scene::gpu_layout::{Frame, GpuCamera};
use crate::scene::{Scene, SceneGpu};
use bytemuck::Zeroable;
use std::sync::OnceLock;

/// The uniform holding the frame index, accumulated count, output size and seed.
pub const FRAME: &str = "frame";
/// The uniform holding the camera.
pub const CAMERA: &str = "camera";
/// The uniform holding the previous frame's camera, all zeros when there is none.
pub const CAMERA_PREVIOUS: &str = "camera_previous";
/// The shader file whose readers take a scene buffer as texels.
const TEXEL_READERS: &str = "shaders/lib/scene.wgsl";

/// What the provided data is made from when a session starts.
pub struct ProvidedInputs<'a> {
    pub scene: &'a Scene,
    pub gpu: &'a SceneGpu,
    /// What of the image the session renders (all of it unless tiled).
    pub tile: Tile,
    pub seed: u32,
}

struct Resource {
    name: &'static str,
    /// The variable shaders/lib/provided.wgsl declares for it, bound without a graph naming it.
    variable: &'static str,
    kind: ProvidedKind,
    what: &'static str,
    bytes: fn(&ProvidedInputs) -> Vec<u8>,
}

struct Override {
    name: &'static str,
    ty: ParamType,
    what: &'static str,
    value: fn(&SceneGpu) -> f64,
}

const RESOURCES: &[Resource] = &[
    Resource {
        name: "scene.triangles",
        variable: "triangles",
        kind: ProvidedKind::StorageBuffer,
        what: "triangles: three vertices and a material index each",
        bytes: |i| bytemuck::cast_slice(&i.gpu.triangles).to_vec(),
    },
    Resource {
        name: "scene.materials",
        variable: "materials",
        kind: ProvidedKind::StorageBuffer,
        what: "materials from the MTL file (128 bytes each: src/material/record.rs), then their tables (src/material/tables.rs)",
        bytes: |i| {
            crate::scene::materials_bytes_with_backs(&i.gpu.materials, &i.gpu.back_materials)
        },
    },
    Resource {
        name: "scene.lights",
        variable: "lights",
        kind: ProvidedKind::StorageBuffer,
        what: "the lights: emissive triangles and parallelograms of two (p0, e1, e2, material, triangles), then point, spot and directional lights and the environment (tagged by material: src/scene/lights.rs); 48 bytes each",
        bytes: |i| bytemuck::cast_slice(&i.gpu.lights).to_vec(),
    },
    Resource {
        name: "scene.light_power",
        variable: "light_power",
        kind: ProvidedKind::StorageBuffer,
        what: "f32 selection weight of each light (area x luminance of Ke; src/scene/emitters.rs for the others), in scene.lights order, then an environment map's sampling tables (src/scene/environment.rs)",
        bytes: |i| i.gpu.light_power_bytes(),
    },
    Resource {
        name: "scene.shading",
        variable: "shading",
        kind: ProvidedKind::StorageBuffer,
        what: "per triangle in BVH order: corner normals and uvs (64 bytes each: TriangleShading in src/scene/gpu_layout.rs); one zero texel when no triangle has either",
        bytes: |i| i.gpu.shading_bytes(),
    },
    Resource {
        name: "scene.textures",
        variable: "textures",
        kind: ProvidedKind::StorageBuffer,
        what: "every texture as linear RGBA f32 texels after one header texel each (first texel, width, height: src/scene/texture.rs); one zero texel when there are none",
        bytes: |i| i.gpu.textures_bytes(),
    },
    Resource {
        name: "scene.bvh",
        variable: "bvh",
        kind: ProvidedKind::StorageBuffer,
        what: "threaded BVH: the box grid, then one 16-byte node each",
        bytes: |i| i.gpu.bvh_bytes(),
    },
    Resource {
        name: CAMERA,
        variable: "camera",
        kind: ProvidedKind::Uniform,
        what: "the camera: eye, forward and the scaled right and up (perspective or orthographic), the lens's aperture radius and focus distance",
        bytes: |i| {
            bytemuck::bytes_of(&i.scene.camera.to_gpu(i.tile.image[0], i.tile.image[1])).to_vec()
        },
    },
    Resource {
        name: CAMERA_PREVIOUS,
        variable: "camera_previous",
        kind: ProvidedKind::Uniform,
        what: "the camera of the previous frame; all zeros after a reset (no history to reuse)",
        bytes: |_| bytemuck::bytes_of(&GpuCamera::zeroed()).to_vec(),
    },
    Resource {
        name: FRAME,
        variable: "frame",
        kind: ProvidedKind::Uniform,
        what: "frame index, accumulated frame count, output size, user seed, the tile's place in the image",
        bytes: |i| bytemuck::bytes_of(&tile_frame(i.tile, i.seed, 0, 0)).to_vec(),
    },
];

const OVERRIDES: &[Override] = &[
    Override {
        name: "scene_light_count",
        ty: ParamType::U32,
        what: "number of emissive triangles (0: no shadow rays)",
        value: |gpu| f64::from(gpu.light_count),
    },
    Override {
        name: "scene_light_kinds",
        ty: ParamType::U32,
        what: "bit 1 << kind for each kind of light in scene.lights (area, point, spot, directional, environment map, uniform environment: src/scene/lights.rs)",
        value: |gpu| f64::from(gpu.light_kinds),
    },
    Override {
        name: "scene_environment",
        ty: ParamType::U32,
        what: "the environment's index in scene.lights, or 0xffffffff without one (rays that miss see black)",
        value: |gpu| f64::from(gpu.environment_light.unwrap_or(u32::MAX)),
    },
    Override {
        name: "scene_triangle_count",
        ty: ParamType::U32,
        what: "number of triangles (texel views have no arrayLength)",
        value: |gpu| gpu.triangles.len() as f64,
    },
    Override {
        name: "scene_node_count",
        ty: ParamType::U32,
        what: "number of BVH nodes (texel views have no arrayLength)",
        value: |gpu| gpu.nodes.len() as f64,
    },
    Override {
        name: "scene_occluder_root",
        ty: ParamType::U32,
        what: "first BVH node of the triangles that can block a shadow ray",
        value: |gpu| f64::from(gpu.occluder_root),
    },
    Override {
        name: "scene_has_specular",
        ty: ParamType::Bool,
        what: "whether any material has a lobe other than Lambert's (Phong Ks > 0, GGX, smooth)",
        value: |gpu| if gpu.has_specular { 1.0 } else { 0.0 },
    },
    Override {
        name: "scene_material_kinds",
        ty: ParamType::U32,
        what: "bit 1 << kind for each material kind a triangle uses (src/scene/gpu_layout.rs)",
        value: |gpu| f64::from(gpu.material_kinds),
    },
    Override {
        name: "scene_max_depth",
        ty: ParamType::U32,
        what: "longest path in segments, as Mitsuba's max_depth (3: direct light and one bounce)",
        value: |gpu| f64::from(gpu.max_depth),
    },
    Override {
        name: "scene_rr_depth",
        ty: ParamType::U32,
        what: "Russian roulette from this BSDF sample on, as Mitsuba's rr_depth (0xffffffff: none)",
        value: |gpu| f64::from(gpu.rr_depth),
    },
    Override {
        name: "scene_has_shading_normals",
        ty: ParamType::Bool,
        what: "whether a triangle has shading normals (OBJ vn) in scene.shading",
        value: |gpu| if gpu.has_shading_normals { 1.0 } else { 0.0 },
    },
    Override {
        name: "scene_has_uvs",
        ty: ParamType::Bool,
        what: "whether a triangle has texture coordinates (OBJ vt) in scene.shading",
        value: |gpu| if gpu.has_uvs { 1.0 } else { 0.0 },
    },
    Override {
        name: "scene_has_textures",
        ty: ParamType::Bool,
        what: "whether a used material has a texture map (map_Kd, map_Ks, map_Pr, map_d)",
        value: |gpu| if gpu.has_textures { 1.0 } else { 0.0 },
    },
    Override {
        name: "scene_has_cutouts",
        ty: ParamType::Bool,
        what: "whether a triangle is cut out (MTL opacity d < 1 or map_d; not a null mask)",
        value: |gpu| if gpu.has_cutouts { 1.0 } else { 0.0 },
    },
    Override {
        name: "scene_camera_kind",
        ty: ParamType::U32,
        what: "the camera's projection: 0 pinhole, 1 thin lens, 2 orthographic (lib/camera_ray.wgsl)",
        value: |gpu| f64::from(gpu.camera_kind),
    },
    Override {
        name: "scene_filter",
        ty: ParamType::U32,
        what: "the pixel filter: 0 box, 1 Gaussian, 2 tent (lib/pixel_filter.wgsl)",
        value: |gpu| f64::from(gpu.filter),
    },
    Override {
        name: "scene_filter_size",
        ty: ParamType::F32,
        what: "the Gaussian filter's stddev or the tent's radius, in pixels (0 for the box)",
        value: |gpu| f64::from(gpu.filter_size),
    },
    Override {
        name: "scene_has_surface_maps",
        ty: ParamType::Bool,
        what: "whether a used material has a normal map (MTL norm) or bump map (map_Bump, bump)",
        value: |gpu| if gpu.has_surface_maps { 1.0 } else { 0.0 },
    },
    Override {
        name: "scene_has_beckmann",
        ty: ParamType::Bool,
        what: "whether a used material's rough lobe has Beckmann microfacets (MTL distribution beckmann)",
        value: |gpu| if gpu.has_beckmann { 1.0 } else { 0.0 },
    },
    Override {
        name: "scene_has_back_materials",
        ty: ParamType::Bool,
        what: "whether a used material shades its back face as another (Mitsuba's one-sided models; twosided with two BSDFs)",
        value: |gpu| if gpu.has_back_materials { 1.0 } else { 0.0 },
    },
    Override {
        name: "scene_has_null_masks",
        ty: ParamType::Bool,
        what: "whether a used material is a null mask (Mitsuba's mask: shades with probability opacity, else the path goes straight on)",
        value: |gpu| if gpu.has_null_masks { 1.0 } else { 0.0 },
    },
    Override {
        name: "scene_has_conductor_fresnel",
        ty: ParamType::Bool,
        what: "whether a used conductor has a complex-index Fresnel term (MTL eta/k or conductor NAME)",
        value: |gpu| if gpu.has_conductor_fresnel { 1.0 } else { 0.0 },
    },
];

/// The path tracer's provided resources and overrides, as the compiler checks graphs against.
pub fn path_tracer() -> &'static ProvidedSet {
    static SET: OnceLock<ProvidedSet> = OnceLock::new();
    SET.get_or_init(|| {
        let set = RESOURCES.iter().fold(ProvidedSet::new(), |set, r| {
            set.resource(r.name, r.kind, r.what)
                .bind_by_name(r.variable, r.name)
        });
        OVERRIDES
            .iter()
            .fold(set, |set, o| set.override_constant(o.name, o.ty, o.what))
            .texel_readers(TEXEL_READERS)
    })
}

/// The data of every entry of [`path_tracer`] for a session's first frame.
pub fn provided_data(inputs: &ProvidedInputs) -> ProvidedData {
    let mut data = ProvidedData::default();
    for r in RESOURCES {
        data.buffers.insert(r.name.into(), (r.bytes)(inputs));
    }
    for o in OVERRIDES {
        data.overrides.insert(o.name.into(), (o.value)(inputs.gpu));
    }
    data
}

/// The `frame` uniform's bytes for a whole image of `size`.
pub fn frame_bytes(size: [u32; 2], seed: u32, index: u32, accumulated: u32) -> Vec<u8> {
    bytemuck::bytes_of(&frame(size, seed, index, accumulated)).to_vec()
}

/// The `frame` uniform of a whole image (`first_sample` 0: a session starting at another
/// sample sets it).
pub fn frame(size: [u32; 2], seed: u32, index: u32, accumulated: u32) -> Frame {
    tile_frame(Tile::whole(size), seed, index, accumulated)
}

/// The `frame` uniform of one tile of an image (or all of it).
pub fn tile_frame(tile: Tile, seed: u32, index: u32, accumulated: u32) -> Frame {
    let size = tile.size;
    Frame {
        index,
        accumulated,
        width: size[0],
        height: size[1],
        seed,
        tile_row_stride: tile_row_stride(size[1]),
        image_origin: tile.origin,
        image_size: tile.image,
        ..Default::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph::interface::BindingKind;
    use crate::graph::reflect::reflect;
    use crate::graph::shader_source::ShaderSource;
    use crate::scene::load_scene;
    use std::collections::BTreeSet;
    use std::path::Path;

    fn root() -> &'static Path {
        Path::new(env!("CARGO_MANIFEST_DIR"))
    }

    /// The shared declaration and the table must name the same variables: a resource added to
    /// one and not the other would leave a pass with an unbound or undeclared variable.
    #[test]
    fn the_shared_wgsl_declares_exactly_the_variables_the_set_binds_by_name() {
        let source = ShaderSource::load(
            &root().join("shaders/lib/provided_scene.wgsl"),
            &root().join("shaders"),
        )
        .unwrap_or_else(|e| panic!("{e}"));
        let declared: BTreeSet<String> = source
            .code
            .lines()
            .filter_map(|line| line.trim().strip_prefix("@group(1)"))
            .filter_map(|rest| {
                let name = rest.split(" var").nth(1)?.split(':').next()?;
                Some(name.trim_start_matches(|c| c != ' ').trim().to_string())
            })
            .collect();
        let bound: BTreeSet<String> = path_tracer()
            .resources()
            .iter()
            .map(|r| {
                r.variable
                    .clone()
                    .unwrap_or_else(|| panic!("{} has no variable", r.name))
            })
            .collect();
        assert_eq!(declared, bound);
    }

    /// Each resource's first-frame bytes against the size its one WGSL declaration has (a
    /// uniform's struct and the host struct must agree byte for byte; a scene buffer holds whole
    /// texels), and each override declared in WGSL with the registered type and given a value.
    #[test]
    fn every_registered_resource_gets_data_of_the_size_its_declaration_takes() {
        let path = root().join(crate::scene::DEFAULT_SCENE);
        let scene = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
        let gpu = scene.to_gpu();
        let data = provided_data(&ProvidedInputs {
            scene: &scene,
            gpu: &gpu,
            tile: Tile::whole([8, 8]),
            seed: 0,
        });
        let set = path_tracer();
        let variables = set.resources().iter().filter_map(|r| r.variable.as_deref());
        let overrides = set.overrides().iter().map(|o| o.name.as_str());
        let uses: String = variables
            .chain(overrides)
            .map(|name| format!("    _ = {name};\n"))
            .collect();
        let code = format!(
            "#include \"lib/provided_scene.wgsl\"\n@compute @workgroup_size(1)\nfn main() {{\n{uses}}}\n"
        );
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("uses_all.wgsl");
        std::fs::write(&file, code).unwrap();
        let source =
            ShaderSource::load(&file, &root().join("shaders")).unwrap_or_else(|e| panic!("{e}"));
        let interface = reflect(&source, "main").unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(interface.bindings.len(), set.resources().len());
        for r in set.resources() {
            let variable = r.variable.as_deref().unwrap();
            let binding = interface
                .bindings
                .iter()
                .find(|b| b.name == variable)
                .unwrap_or_else(|| panic!("{variable} is not declared"));
            assert_eq!(binding.group, 1, "{variable}: the application's group");
            let bytes = data.buffers[&r.name].len() as u64;
            match (r.kind, &binding.kind) {
                (ProvidedKind::Uniform, BindingKind::Uniform { size }) => {
                    assert_eq!(
                        bytes, *size,
                        "{}: host bytes against the WGSL struct",
                        r.name
                    )
                }
                (ProvidedKind::StorageBuffer, BindingKind::StorageTexture { .. }) => {
                    assert!(
                        bytes >= 16 && bytes.is_multiple_of(16),
                        "{}: {bytes} bytes",
                        r.name
                    )
                }
                (kind, declared) => panic!("{}: {kind:?} declared as {declared:?}", r.name),
            }
        }
        let filled: BTreeSet<&str> = data.buffers.keys().map(String::as_str).collect();
        let registered: BTreeSet<&str> = set.resources().iter().map(|r| r.name.as_str()).collect();
        assert_eq!(registered, filled);
        for o in set.overrides() {
            let declared = interface.overrides.iter().find(|d| d.name == o.name);
            assert_eq!(declared.map(|d| d.ty), Some(o.ty), "override {}", o.name);
            assert!(
                data.overrides.contains_key(&o.name),
                "{} has no value",
                o.name
            );
        }
    }
}
