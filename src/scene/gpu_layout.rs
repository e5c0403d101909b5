//! The scene as the GPU sees it: `#[repr(C)]` mirrors of `shaders/lib/scene.wgsl`, byte for byte,
//! and the constants both sides share; the material record is the material module's
//! (src/material/record.rs). Nothing here knows how a scene is built (src/scene/gpu.rs builds
//! `SceneGpu` from these), so the loaders and the BVH can use the records without importing
//! the builder.

use crate::material::{Material, NO_TEXTURE};
use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use std::mem::size_of;

/// One triangle, in BVH order; `material` indexes the materials buffer, `light` the lights
/// buffer (the light this triangle is part of, or [`NO_LIGHT`]): what multiple importance
/// sampling needs to weigh a ray that hits an emitter.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Triangle {
    pub p0: [f32; 3],
    pub material: u32,
    pub p1: [f32; 3],
    pub light: u32,
    pub p2: [f32; 3],
    /// The fraction of rays the triangle stops: its material's `opacity` (MTL `d`); below 1 a
    /// ray passes through with probability 1 - opacity (shaders/lib/bvh.wgsl). Negative: the
    /// opacity is texture `-1 - opacity`'s (`map_d`) at the hit ([`Triangle::opacity_of`]).
    pub opacity: f32,
}

/// A triangle's shading data (`scene.shading`, in BVH order, 4 texels): corner normals
/// `n0..n2` (unit length) and texture coordinates `(u0, v0)`, `uv1`, `uv2`; `flags` says which
/// the triangle has ([`SHADING_HAS_NORMALS`], [`SHADING_HAS_UVS`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct TriangleShading {
    pub n0: [f32; 3],
    pub u0: f32,
    pub n1: [f32; 3],
    pub v0: f32,
    pub n2: [f32; 3],
    pub flags: u32,
    pub uv1: [f32; 2],
    pub uv2: [f32; 2],
}

pub const SHADING_HAS_NORMALS: u32 = 1;
pub const SHADING_HAS_UVS: u32 = 2;

/// Mitsuba's `max_depth` of the seed's model: direct light and one bounce.
pub const DEFAULT_MAX_DEPTH: u32 = 3;

/// The `scene_rr_depth` of a scene without Russian roulette.
pub const NO_RUSSIAN_ROULETTE: u32 = u32::MAX;

/// A triangle's `light` when it is not part of one.
pub const NO_LIGHT: u32 = u32::MAX;

/// A threaded BVH node as the build and the CPU twin see it, its box on the BVH's grid
/// ([`BvhGrid`]); the GPU reads it as a [`PackedBvhNode`]. Interior: `count == 0` and `a` is the
/// miss link (skip); the hit link is implicit (this index + 1). Leaf: `count > 0` triangles
/// starting at index `a`; its next node is always this index + 1.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BvhNode {
    pub lo: [f32; 3],
    pub a: u32,
    pub hi: [f32; 3],
    pub count: u32,
}

/// The head of the `scene.bvh` buffer (two texels): the grid node boxes are stored on
/// ([`BvhGrid`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuBvhGrid {
    pub origin: [f32; 3],
    pub pad0: u32,
    pub step: [f32; 3],
    pub pad1: u32,
}

/// A BVH node as `scene.bvh` holds it after the grid, one texel: per axis the box's low grid
/// cell in the low 16 bits and its high cell in the high 16; `link` is [`BvhNode::a`] with
/// [`BvhNode::count`] in the top 4 bits (see [`BvhGrid::encode`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PackedBvhNode {
    pub bounds: [u32; 3],
    pub link: u32,
}

/// The camera, `right` and `up` scaled by the field of view and aspect, or by the orthographic
/// width (see `CameraDesc::to_gpu` in src/scene/camera.rs); the projection itself
/// is the `scene_camera_kind` override. The lens fields are 0 without a lens, so a pinhole's
/// uniform is what it always was.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuCamera {
    pub eye: [f32; 3],
    pub aperture_radius: f32,
    pub forward: [f32; 3],
    pub focus_distance: f32,
    pub right: [f32; 3],
    pub pad2: f32,
    pub up: [f32; 3],
    pub pad3: f32,
}

/// Per-frame values. `accumulated` is how many frames the result already holds (0: restart).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct Frame {
    pub index: u32,
    pub accumulated: u32,
    pub width: u32,
    pub height: u32,
    pub seed: u32,
    /// How image passes order their rows of tiles: `render::tile_order`.
    pub tile_row_stride: u32,
    /// The sample index of the accumulation's first frame: a render of samples A..B
    /// (`--samples`) starts at A, so its frames draw what frames A.. of a whole render draw.
    pub first_sample: u32,
    pub pad2: u32,
    /// Where this frame's pixel (0, 0) lies in the whole image, and the whole image's size:
    /// (0, 0) and (width, height) unless the image is rendered in tiles (`render::tiles`), so
    /// that rays and samples follow the pixel's place in the image, not in the tile.
    pub image_origin: [u32; 2],
    pub image_size: [u32; 2],
}

// WGSL aligns vec3<f32> to 16 bytes; these sizes are what scene.wgsl's structs occupy.
const _: () = assert!(size_of::<Triangle>() == 48);
const _: () = assert!(size_of::<TriangleShading>() == 64);
const _: () = assert!(size_of::<GpuBvhGrid>() == 32);
const _: () = assert!(size_of::<PackedBvhNode>() == 16);
const _: () = assert!(size_of::<GpuCamera>() == 64);
const _: () = assert!(size_of::<Frame>() == 48);

impl Triangle {
    pub fn new(vertices: [Vec3; 3], material: u32) -> Triangle {
        Triangle {
            p0: vertices[0].into(),
            material,
            p1: vertices[1].into(),
            light: NO_LIGHT,
            p2: vertices[2].into(),
            opacity: 1.0,
        }
    }

    /// The `opacity` of a triangle of material `m`: `m.opacity`, or the encoded `map_d`, which
    /// replaces it (as `material_at` does), so that the traversal needs no material lookup.
    pub fn opacity_of(m: &Material) -> f32 {
        if m.map_d == NO_TEXTURE {
            m.opacity
        } else {
            // Exact below 2^24 textures, far more than a texel view holds.
            -1.0 - m.map_d as f32
        }
    }

    pub fn vertices(&self) -> [Vec3; 3] {
        [self.p0.into(), self.p1.into(), self.p2.into()]
    }
}

impl BvhNode {
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }
}

impl GpuCamera {
    pub fn new(eye: Vec3, forward: Vec3, right: Vec3, up: Vec3) -> GpuCamera {
        GpuCamera {
            eye: eye.into(),
            forward: forward.into(),
            right: right.into(),
            up: up.into(),
            ..GpuCamera::default()
        }
    }
}
