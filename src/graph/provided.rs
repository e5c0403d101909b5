//! Resources the framework provides by well-known names, which passes bind like any other.

use super::param::ParamType;

/// How a provided resource is bound.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProvidedKind {
    /// A read-only storage buffer whose size comes from the scene.
    StorageBuffer,
    /// A uniform block the framework fills every frame.
    Uniform,
}

/// A well-known resource: the scene's geometry, the camera, the frame counter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Provided {
    pub name: &'static str,
    pub kind: ProvidedKind,
    pub what: &'static str,
}

pub const PROVIDED: &[Provided] = &[
    Provided {
        name: "scene.triangles",
        kind: ProvidedKind::StorageBuffer,
        what: "triangles: three vertices and a material index each",
    },
    Provided {
        name: "scene.materials",
        kind: ProvidedKind::StorageBuffer,
        what: "materials from the MTL file",
    },
    Provided {
        name: "scene.lights",
        kind: ProvidedKind::StorageBuffer,
        what: "the lights: emissive triangles, and parallelograms of two (p0, e1, e2, material, triangles; 48 bytes each)",
    },
    Provided {
        name: "scene.light_power",
        kind: ProvidedKind::StorageBuffer,
        what: "f32 power of each light (area x luminance of Ke), in scene.lights order",
    },
    Provided {
        name: "scene.bvh",
        kind: ProvidedKind::StorageBuffer,
        what: "threaded BVH nodes",
    },
    Provided {
        name: "camera",
        kind: ProvidedKind::Uniform,
        what: "the pinhole camera",
    },
    Provided {
        name: "camera_previous",
        kind: ProvidedKind::Uniform,
        what: "the camera of the previous frame; all zeros after a reset (no history to reuse)",
    },
    Provided {
        name: "frame",
        kind: ProvidedKind::Uniform,
        what: "frame index, accumulated frame count, output size, user seed",
    },
];

pub fn provided(name: &str) -> Option<&'static Provided> {
    PROVIDED.iter().find(|p| p.name == name)
}

/// A pipeline-overridable constant the framework sets from the scene, so shaders are
/// specialised to what the scene uses (no light loop without lights, no specular lobe
/// without `Ks`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ProvidedOverride {
    pub name: &'static str,
    pub ty: ParamType,
    pub what: &'static str,
}

pub const PROVIDED_OVERRIDES: &[ProvidedOverride] = &[
    ProvidedOverride {
        name: "scene_light_count",
        ty: ParamType::U32,
        what: "number of emissive triangles (0: no shadow rays)",
    },
    ProvidedOverride {
        name: "scene_triangle_count",
        ty: ParamType::U32,
        what: "number of triangles (texel views have no arrayLength)",
    },
    ProvidedOverride {
        name: "scene_node_count",
        ty: ParamType::U32,
        what: "number of BVH nodes (texel views have no arrayLength)",
    },
    ProvidedOverride {
        name: "scene_occluder_root",
        ty: ParamType::U32,
        what: "first BVH node of the triangles that can block a shadow ray",
    },
    ProvidedOverride {
        name: "scene_has_specular",
        ty: ParamType::Bool,
        what: "whether any material has a specular lobe (Ks > 0)",
    },
];

pub fn provided_override(name: &str) -> Option<&'static ProvidedOverride> {
    PROVIDED_OVERRIDES.iter().find(|o| o.name == name)
}
