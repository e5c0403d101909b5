//! Scenes: a RON scene file naming a mesh (OBJ/MTL through tobj, or PLY), a camera and a pixel filter;
//! the SAH BVH in its threaded, depth-first layout; the emissive triangles; and the `#[repr(C)]`
//! buffers that mirror `shaders/lib/scene.wgsl`. `intersect` is the CPU twin of
//! `shaders/lib/bvh.wgsl`, with the brute-force oracle the tests hold both to.

pub mod bvh;
pub mod bvh_grid;
pub mod bvh_octants;
pub mod camera;
pub mod description;
pub mod emitters;
pub mod environment;
pub mod environment_image;
pub mod error;
pub mod file;
pub mod filter;
pub mod gltf;
pub mod gpu;
pub mod gpu_emitters;
pub mod gpu_layout;
pub mod hull;
pub mod intersect;
pub mod lights;
pub mod mesh;
pub mod mesh_file;
pub mod mitsuba;
pub mod mitsuba_xml;
mod obj;
mod ply;
pub mod regions;
pub mod surface_map;
pub mod texture;

pub use bvh::{Bvh, BvhStats};
pub use bvh_grid::BvhGrid;
pub use camera::{CameraDesc, CameraError, CameraKind, FovAxis, Lens, Projection};
pub use error::{Location, SceneError};
pub use file::{
    DEFAULT_SCENE, LoadedScene, MAX_MAX_DEPTH, Scene, SceneOptions, check_max_depth,
    is_mitsuba_xml, load_scene, load_scene_with,
};
pub use filter::PixelFilter;
pub use gpu::SceneGpu;
pub use gpu_layout::{
    BvhNode, Frame, GpuBvhGrid, GpuCamera, NO_LIGHT, PackedBvhNode, SHADING_HAS_NORMALS,
    SHADING_HAS_UVS, Triangle, TriangleShading,
};
// The materials a scene holds (src/material), as the loaders and tests name them.
pub use crate::bsdf::microfacet::Distribution;
pub use crate::material::{
    FRESNEL_CONDUCTOR, FRESNEL_NONE, MATERIAL_CONDUCTOR, MATERIAL_DIELECTRIC, MATERIAL_LAMBERT,
    MATERIAL_METALLIC_ROUGHNESS, MATERIAL_PHONG, MATERIAL_PLASTIC, MATERIAL_THIN_DIELECTRIC,
    Material, NO_TABLE, NO_TEXTURE, SURFACE_MAP_BUMP, materials_bytes, materials_bytes_with_backs,
};
pub use intersect::{Hit, Ray};
pub use mesh::{Mesh, MeshTriangle};
pub use mesh_file::load_mesh;
