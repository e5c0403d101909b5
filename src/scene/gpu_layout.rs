//! The scene as the GPU sees it: `#[repr(C)]` mirrors of `shaders/lib/scene.wgsl`, byte for byte,
//! and the constants both sides share. Nothing here knows how a scene is built
//! (src/scene/gpu.rs builds `SceneGpu` from these), so the loaders, the
//! BVH and the BSDF twins can use the records without importing the builder.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use std::mem::size_of;

/// A material's `table` when it has none (src/scene/material_tables.rs gives plastic and
/// metallic-roughness materials their albedo tables).
pub const NO_TABLE: u32 = u32::MAX;

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

/// A material: its model (`kind`, one of the `MATERIAL_*` constants) and the model's
/// parameters, as `shaders/lib/scene.wgsl`'s `Material` (8 texels). Which MTL keys give which
/// kind: `obj.rs`. `ke` is emitted radiance (front face only) whatever the kind.
///
/// - Lambert: f = kd / pi.
/// - Phong (the seed's normalised Blinn-Phong): f = kd/pi + ks (ns + 8)/(8 pi) max(0, n.h)^ns.
/// - Conductor: microfacets of roughness `alpha` (0: a perfect mirror), Fresnel = kd, or with
///   `fresnel` [`FRESNEL_CONDUCTOR`] kd times the complex-index Fresnel of `eta` + i `k`.
/// - Plastic: diffuse kd under a dielectric microfacet coat of index `ior`, specular tint ks.
/// - Dielectric: one-sided glass of index `ior` (the front face is outside), transmittance tf.
/// - Thin dielectric: a two-sided sheet of index `ior`, reflecting 2R / (1 + R) and passing the
///   rest straight through tinted tf (always smooth).
///
/// The rough models' microfacets follow `distribution` ([`Distribution`]: GGX by default).
///
/// `map_*` index `scene.textures` (or [`NO_TEXTURE`]): a texture replaces kd, ks or the
/// roughness r (alpha = r²); `map_d` and `opacity` < 1 cut the surface out. `surface_map`
/// perturbs the shading normal (MTL `norm`, `map_Bump`: src/scene/surface_map.rs).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Material {
    pub kd: [f32; 3],
    pub ns: f32,
    pub ks: [f32; 3],
    pub kind: u32,
    pub ke: [f32; 3],
    /// GGX alpha = r²; 0 is the smooth (delta) case.
    pub alpha: f32,
    pub tf: [f32; 3],
    pub ior: f32,
    pub map_kd: u32,
    pub map_ks: u32,
    pub map_pr: u32,
    pub map_d: u32,
    /// MTL `d`: 1 opaque; below 1 the fraction of light the surface stops.
    pub opacity: f32,
    /// The texel index in `scene.materials` of the model's table (rough plastic's), or
    /// [`NO_TABLE`]: src/scene/material_tables.rs sets it.
    pub table: u32,
    /// A normal map's texture index, or a bump map's with [`SURFACE_MAP_BUMP`] set, or
    /// [`NO_TEXTURE`]: the two free words of the last texel, so the struct keeps its size.
    pub surface_map: u32,
    /// The bump map's height scale (MTL `-bm`, Mitsuba's `bumpmap` `scale`).
    pub bump_scale: f32,
    /// A conductor's complex index of refraction eta + i k (per RGB channel), read when
    /// `fresnel` is [`FRESNEL_CONDUCTOR`].
    pub eta: [f32; 3],
    /// The rough models' microfacet distribution: a [`Distribution`] as u32.
    pub distribution: u32,
    pub k: [f32; 3],
    /// A conductor's Fresnel term: [`FRESNEL_NONE`] (1: the tint kd alone, Mitsuba's material
    /// none) or [`FRESNEL_CONDUCTOR`].
    pub fresnel: u32,
}

/// The microfacet normal distribution of a rough model (`Material::distribution`), as Mitsuba
/// 3's `distribution` parameter; alpha means the same for both (Mitsuba uses it unmapped: the
/// RMS slope for Beckmann).
#[repr(u32)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Distribution {
    /// GGX (Trowbridge-Reitz): passgraph's default.
    #[default]
    Ggx = 0,
    /// Beckmann: Mitsuba's default.
    Beckmann = 1,
}

impl Distribution {
    /// The distribution of a `Material::distribution` value; unknown values read as GGX, as
    /// the shaders treat them.
    pub fn from_u32(value: u32) -> Distribution {
        if value == Distribution::Beckmann as u32 {
            Distribution::Beckmann
        } else {
            Distribution::Ggx
        }
    }

    /// Mitsuba's name for it (`<string name="distribution" value="...">`).
    pub fn mitsuba_name(self) -> &'static str {
        match self {
            Distribution::Ggx => "ggx",
            Distribution::Beckmann => "beckmann",
        }
    }

    /// The distribution Mitsuba names `name` (case-insensitive, as Mitsuba reads it).
    pub fn from_mitsuba_name(name: &str) -> Option<Distribution> {
        match name.to_ascii_lowercase().as_str() {
            "ggx" => Some(Distribution::Ggx),
            "beckmann" => Some(Distribution::Beckmann),
            _ => None,
        }
    }
}

/// `Material::fresnel`: the conductor's Fresnel term is 1 (kd alone).
pub const FRESNEL_NONE: u32 = 0;
/// `Material::fresnel`: the conductor's Fresnel term is that of the complex index eta + i k.
pub const FRESNEL_CONDUCTOR: u32 = 1;

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

/// Material kinds (`Material::kind`); bit `1 << kind` of the `scene_material_kinds` override.
pub const MATERIAL_LAMBERT: u32 = 0;
pub const MATERIAL_PHONG: u32 = 1;
pub const MATERIAL_CONDUCTOR: u32 = 2;
pub const MATERIAL_PLASTIC: u32 = 3;
pub const MATERIAL_DIELECTRIC: u32 = 4;
pub const MATERIAL_THIN_DIELECTRIC: u32 = 5;
/// glTF 2.0's metallic-roughness BRDF (src/bsdf/metallic_roughness.rs): kd the base colour,
/// ks.x the metallic factor, alpha roughness^2.
pub const MATERIAL_METALLIC_ROUGHNESS: u32 = 6;

/// Mitsuba's `max_depth` of the seed's model: direct light and one bounce.
pub const DEFAULT_MAX_DEPTH: u32 = 3;

/// The `scene_rr_depth` of a scene without Russian roulette.
pub const NO_RUSSIAN_ROULETTE: u32 = u32::MAX;

/// A triangle's `light` when it is not part of one.
pub const NO_LIGHT: u32 = u32::MAX;

/// A material's texture index when it has none.
pub const NO_TEXTURE: u32 = u32::MAX;

/// The bit of `Material::surface_map` that makes its texture a bump map (a height field)
/// rather than a tangent-space normal map; texture indices stay far below it.
pub const SURFACE_MAP_BUMP: u32 = 1 << 31;

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
const _: () = assert!(size_of::<Material>() == 128);
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

impl Material {
    /// What faces without a material get: white diffuse, Kd 0.8.
    pub const DEFAULT: Material = Material::diffuse([0.8; 3]);

    pub const fn diffuse(kd: [f32; 3]) -> Material {
        Material {
            kd,
            ns: 0.0,
            ks: [0.0; 3],
            kind: MATERIAL_LAMBERT,
            ke: [0.0; 3],
            alpha: 0.0,
            tf: [1.0; 3],
            ior: 1.5,
            map_kd: NO_TEXTURE,
            map_ks: NO_TEXTURE,
            map_pr: NO_TEXTURE,
            map_d: NO_TEXTURE,
            opacity: 1.0,
            table: NO_TABLE,
            surface_map: NO_TEXTURE,
            bump_scale: 1.0,
            eta: [0.0; 3],
            distribution: Distribution::Ggx as u32,
            k: [1.0; 3],
            fresnel: FRESNEL_NONE,
        }
    }

    /// A conductor (Mitsuba's `conductor` / `roughconductor`): roughness `alpha` (0: smooth),
    /// `specular_reflectance` the tint kd, and `ior` its complex index (eta, k) per RGB channel
    /// ([`crate::bsdf::conductor_presets::conductor_preset`] has Mitsuba's named ones), or
    /// `None` for Mitsuba's material none (Fresnel 1).
    pub fn conductor(
        specular_reflectance: [f32; 3],
        alpha: f32,
        distribution: Distribution,
        ior: Option<(Vec3, Vec3)>,
    ) -> Material {
        let mut m = Material {
            kind: MATERIAL_CONDUCTOR,
            kd: specular_reflectance,
            alpha,
            distribution: distribution as u32,
            ..Material::DEFAULT
        };
        if let Some((eta, k)) = ior {
            m.eta = eta.to_array();
            m.k = k.to_array();
            m.fresnel = FRESNEL_CONDUCTOR;
        }
        m
    }

    /// A thin dielectric sheet (Mitsuba's `thindielectric`) of index `ior` relative to outside
    /// (Mitsuba's int_ior / ext_ior), its transmission tinted `specular_transmittance`.
    pub fn thin_dielectric(ior: f32, specular_transmittance: [f32; 3]) -> Material {
        Material {
            kind: MATERIAL_THIN_DIELECTRIC,
            ior,
            tf: specular_transmittance,
            ..Material::DEFAULT
        }
    }

    /// The same material with its rough lobes' microfacets from `distribution`.
    pub fn with_distribution(self, distribution: Distribution) -> Material {
        Material {
            distribution: distribution as u32,
            ..self
        }
    }

    /// Whether a rough lobe of this material samples the Beckmann distribution (what the
    /// `scene_has_beckmann` override keeps in the shaders).
    pub fn uses_beckmann(&self) -> bool {
        let rough = self.alpha > 0.0 || self.map_pr != NO_TEXTURE;
        let microfacet = matches!(
            self.kind,
            MATERIAL_CONDUCTOR | MATERIAL_PLASTIC | MATERIAL_DIELECTRIC
        );
        rough && microfacet && self.distribution == Distribution::Beckmann as u32
    }

    /// Whether this is a conductor with a complex-index Fresnel term (the
    /// `scene_has_conductor_fresnel` override).
    pub fn uses_conductor_fresnel(&self) -> bool {
        self.kind == MATERIAL_CONDUCTOR && self.fresnel == FRESNEL_CONDUCTOR
    }

    pub fn is_emissive(&self) -> bool {
        self.ke.iter().any(|&c| c > 0.0)
    }

    /// Whether the surface is not all there: an opacity below 1 or an opacity map (`map_d`),
    /// a cut-out or a null mask (`Mesh::null_masks`).
    pub fn has_opacity(&self) -> bool {
        self.opacity < 1.0 || self.map_d != NO_TEXTURE
    }

    /// Whether the model has a lobe other than Lambert's (Phong with ks > 0 or any GGX or
    /// smooth model).
    pub fn is_specular(&self) -> bool {
        match self.kind {
            MATERIAL_LAMBERT => false,
            MATERIAL_PHONG => self.ks.iter().any(|&c| c > 0.0),
            _ => true,
        }
    }
}

impl Default for Material {
    fn default() -> Material {
        Material::DEFAULT
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
