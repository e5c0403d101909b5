//! The scene as the GPU sees it: `#[repr(C)]` mirrors of `shaders/lib/scene.wgsl`, byte for byte,
//! and [`SceneGpu`], the buffers built from a mesh (triangles in BVH order, materials, emissive
//! triangles, BVH nodes) with the facts the shaders are specialised on.

use super::bvh::{Bvh, BvhStats};
use super::bvh_grid::BvhGrid;
use super::bvh_octants::{copy_of, octant_copies};
use super::file::Scene;
use super::hull::hull_faces_with;
use super::intersect::{self, Hit, Ray};
use super::lights::LIGHT_AREA;
use super::lights::{Light, light_power, scene_lights};
use super::mesh::Mesh;
use super::texture::{Texture, textures_bytes};
use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use std::collections::BTreeMap;
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
    /// `NO_TABLE`: src/scene/material_tables.rs sets it.
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
/// width (see [`CameraDesc::to_gpu`](super::camera::CameraDesc::to_gpu)); the projection itself
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
            table: super::material_tables::NO_TABLE,
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

/// The materials some triangle uses (each once).
fn used_materials(
    triangles: &[Triangle],
    materials: &[Material],
    back_materials: &BTreeMap<u32, u32>,
) -> Vec<Material> {
    let mut used = vec![false; materials.len()];
    for t in triangles {
        if let Some(u) = used.get_mut(t.material as usize) {
            *u = true;
        }
    }
    for &back in back_materials.values() {
        if let Some(u) = used.get_mut(back as usize) {
            *u = true;
        }
    }
    materials
        .iter()
        .zip(used)
        .filter_map(|(m, u)| u.then_some(*m))
        .collect()
}

impl TriangleShading {
    pub fn new(t: &super::mesh::MeshTriangle) -> TriangleShading {
        let mut s = TriangleShading::default();
        if let Some([n0, n1, n2]) = t.normals {
            s.n0 = n0.into();
            s.n1 = n1.into();
            s.n2 = n2.into();
            s.flags |= SHADING_HAS_NORMALS;
        }
        if let Some([uv0, uv1, uv2]) = t.uvs {
            s.u0 = uv0.x;
            s.v0 = uv0.y;
            s.uv1 = uv1.into();
            s.uv2 = uv2.into();
            s.flags |= SHADING_HAS_UVS;
        }
        s
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

/// The scene's GPU buffers and the values of the scene's pipeline-overridable constants.
#[derive(Clone, Debug)]
pub struct SceneGpu {
    /// In BVH order: leaves reference contiguous ranges; degenerate (zero-area) triangles come
    /// last and no leaf references them.
    pub triangles: Vec<Triangle>,
    pub materials: Vec<Material>,
    /// Material `front` seen from behind is material `back` (`Mesh::back_materials`, for the
    /// used materials only).
    pub back_materials: BTreeMap<u32, u32>,
    /// The lights: emissive triangles with nonzero area, pairs of them forming a
    /// parallelogram joined into one (see `lights.rs`), ordered by first triangle. Empty when
    /// the scene has no emitters.
    pub lights: Vec<Light>,
    /// Each light's area times the luminance of its `Ke`, in `lights` order: the
    /// `scene.light_power` table that light selection samples from.
    pub light_power: Vec<f32>,
    /// Depth-first threaded BVH; node 0 is the root. Empty only if no triangle has area.
    pub nodes: Vec<BvhNode>,
    /// `nodes` re-threaded for four octants of ray directions (`bvh_octants.rs`): what the GPU
    /// and the CPU twin traverse, the copy for ray direction d at `copy_of(d) * nodes.len()`.
    pub octant_nodes: Vec<BvhNode>,
    /// Where shadow rays start their traversal: the subtree without the scene's hull faces,
    /// which no shadow ray can meet (`hull.rs`). The `scene_occluder_root` override.
    pub occluder_root: u32,
    /// The grid the node boxes lie on.
    pub grid: BvhGrid,
    /// `lights.len()`: the `scene_light_count` override.
    pub light_count: u32,
    /// Bit `1 << kind` for each kind of light in `lights` (`lights.rs`): the
    /// `scene_light_kinds` override, which specialises the shaders to those kinds.
    pub light_kinds: u32,
    /// The environment's index in `lights`, if the scene has one: the `scene_environment`
    /// override (`NO_LIGHT` without).
    pub environment_light: Option<u32>,
    /// An environment map's sampling tables (`environment.rs`), after the weights in
    /// `scene.light_power`; empty without a map.
    pub environment_table: Vec<f32>,
    /// Whether a triangle uses a material with Ks > 0 or a null mask (a delta pass-through):
    /// the `scene_has_specular` override.
    pub has_specular: bool,
    /// Bit `1 << kind` for each material kind a triangle uses: the `scene_material_kinds`
    /// override, which specialises the shaders to those models.
    pub material_kinds: u32,
    /// The longest path in segments (Mitsuba's `max_depth`): the `scene_max_depth` override.
    pub max_depth: u32,
    /// Russian roulette from this BSDF sample on (Mitsuba's `rr_depth`), [`NO_RUSSIAN_ROULETTE`]
    /// for none: the `scene_rr_depth` override.
    pub rr_depth: u32,
    /// The camera's projection (`CameraKind` as u32): the `scene_camera_kind` override.
    pub camera_kind: u32,
    /// The pixel filter (`filter::FILTER_*`) and its stddev or radius: the `scene_filter` and
    /// `scene_filter_size` overrides.
    pub filter: u32,
    pub filter_size: f32,
    /// Per triangle in `triangles` order: normals and uvs. Empty when no triangle has either
    /// (`shading_bytes` then gives one dummy texel).
    pub shading: Vec<TriangleShading>,
    /// The images materials index (`scene.textures`).
    pub textures: Vec<Texture>,
    /// Whether a triangle has shading normals: the `scene_has_shading_normals` override.
    pub has_shading_normals: bool,
    /// Whether a triangle has texture coordinates: the `scene_has_uvs` override.
    pub has_uvs: bool,
    /// Whether a used material has a texture map: the `scene_has_textures` override.
    pub has_textures: bool,
    /// Whether a used material can be cut out (opacity < 1 or `map_d`): `scene_has_cutouts`.
    pub has_cutouts: bool,
    /// Whether a used material has a normal or bump map: `scene_has_surface_maps`.
    pub has_surface_maps: bool,
    /// Whether a used material's rough lobe is Beckmann: `scene_has_beckmann`.
    pub has_beckmann: bool,
    /// Whether a used conductor has a complex-index Fresnel term: `scene_has_conductor_fresnel`.
    pub has_conductor_fresnel: bool,
    /// Whether a used material has a back-face material: `scene_has_back_materials`.
    pub has_back_materials: bool,
    /// Whether a used material is a null mask (`Mesh::null_masks`): `scene_has_null_masks`.
    pub has_null_masks: bool,
    pub bvh: BvhStats,
}

impl SceneGpu {
    /// Builds the BVH over `mesh` and lays its data out for the GPU.
    pub fn build(mesh: &Mesh) -> SceneGpu {
        SceneGpu::build_with_points(mesh, &[])
    }

    /// As [`SceneGpu::build`], for a scene that also has lights at `light_points`: a hull face
    /// must have them on its side too, since shadow rays end there.
    pub fn build_with_points(mesh: &Mesh, light_points: &[Vec3]) -> SceneGpu {
        let vertices: Vec<[Vec3; 3]> = mesh.triangles.iter().map(|t| t.vertices).collect();
        let occluder: Vec<bool> = hull_faces_with(&vertices, light_points)
            .iter()
            .map(|&h| !h)
            .collect();
        let bvh = Bvh::build_with_occluders(&vertices, &occluder);
        let mut triangles: Vec<Triangle> = bvh
            .order
            .iter()
            .map(|&i| {
                let source = &mesh.triangles[i as usize];
                Triangle::new(source.vertices, source.material)
            })
            .collect();
        let mut materials = mesh.materials.clone();
        let lights = scene_lights(&triangles, &materials);
        for t in &mut triangles {
            // A null mask stops every ray (Mitsuba's shadow rays stop at a mask): shading
            // draws its pass-through.
            if !mesh.null_masks.contains(&t.material) {
                t.opacity = materials
                    .get(t.material as usize)
                    .map_or(1.0, Triangle::opacity_of);
            }
        }
        // A cut-out lives in its triangles; the record keeps the opacity of null masks only,
        // so that shading reads any opacity below 1 as a null mask's.
        for (i, m) in materials.iter_mut().enumerate() {
            if !mesh.null_masks.contains(&(i as u32)) && m.has_opacity() {
                m.opacity = 1.0;
                m.map_d = NO_TEXTURE;
            }
        }
        for (index, light) in lights.iter().enumerate() {
            for t in light.triangles() {
                triangles[t as usize].light = index as u32;
            }
        }
        let light_power = light_power(&lights, &materials);
        // Shadow rays start at occluder_root, which must stay the occluders' subtree.
        let keep_root = bvh.occluder_root > 0 && (bvh.occluder_root as usize) < bvh.nodes.len();
        let has_specular = triangles.iter().any(|t| {
            materials
                .get(t.material as usize)
                .is_some_and(Material::is_specular)
        });
        // The back-face materials of the used ones are used too.
        let back_materials: BTreeMap<u32, u32> = mesh
            .back_materials
            .iter()
            .filter(|(front, _)| triangles.iter().any(|t| t.material == **front))
            .map(|(&f, &b)| (f, b))
            .collect();
        let used = used_materials(&triangles, &materials, &back_materials);
        let material_kinds = used.iter().fold(0, |kinds, m| kinds | 1 << m.kind);
        let has_textures = used.iter().any(|m| {
            [m.map_kd, m.map_ks, m.map_pr, m.map_d]
                .iter()
                .any(|&t| t != NO_TEXTURE)
        });
        // Only cut-outs' triangles have an opacity; only null masks' records do.
        let has_cutouts = triangles.iter().any(|t| t.opacity < 1.0);
        let has_null_masks = used.iter().any(Material::has_opacity);
        // A null mask's pass-through is a delta lobe.
        let has_specular = has_specular || has_null_masks;
        let has_surface_maps = used.iter().any(|m| m.surface_map != NO_TEXTURE);
        let has_beckmann = used.iter().any(Material::uses_beckmann);
        let has_conductor_fresnel = used.iter().any(Material::uses_conductor_fresnel);
        let has_shading_normals = mesh.triangles.iter().any(|t| t.normals.is_some());
        let has_uvs = mesh.triangles.iter().any(|t| t.uvs.is_some());
        let shading = if has_shading_normals || has_uvs {
            bvh.order
                .iter()
                .map(|&i| TriangleShading::new(&mesh.triangles[i as usize]))
                .collect()
        } else {
            Vec::new()
        };
        SceneGpu {
            light_count: lights.len() as u32,
            light_kinds: if lights.is_empty() {
                0
            } else {
                1 << LIGHT_AREA
            },
            environment_light: None,
            environment_table: Vec::new(),
            material_kinds,
            max_depth: DEFAULT_MAX_DEPTH,
            rr_depth: NO_RUSSIAN_ROULETTE,
            camera_kind: 0,
            filter: 0,
            filter_size: 0.0,
            shading,
            textures: mesh.textures.clone(),
            has_shading_normals,
            has_uvs,
            has_textures,
            has_cutouts,
            has_surface_maps,
            has_beckmann,
            has_conductor_fresnel,
            has_back_materials: !back_materials.is_empty(),
            has_null_masks,
            triangles,
            materials,
            back_materials,
            lights,
            light_power,
            octant_nodes: octant_copies(&bvh.nodes, keep_root),
            nodes: bvh.nodes,
            occluder_root: bvh.occluder_root,
            grid: bvh.grid,
            has_specular,
            bvh: bvh.stats,
        }
    }

    /// The `scene.shading` buffer (one zero texel when no triangle has normals or uvs).
    pub fn shading_bytes(&self) -> Vec<u8> {
        if self.shading.is_empty() {
            vec![0; 16]
        } else {
            bytemuck::cast_slice(&self.shading).to_vec()
        }
    }

    /// The `scene.textures` buffer (`texture.rs`).
    pub fn textures_bytes(&self) -> Vec<u8> {
        textures_bytes(&self.textures)
    }

    /// The `scene.bvh` buffer: the grid, then each node of each octant's copy as one texel.
    pub fn bvh_bytes(&self) -> Vec<u8> {
        let mut bytes = bytemuck::bytes_of(&self.grid.to_gpu()).to_vec();
        for node in &self.octant_nodes {
            bytes.extend_from_slice(bytemuck::bytes_of(&self.grid.encode(node)));
        }
        bytes
    }

    /// The nearest hit with t in (tmin, tmax), by the same traversal as `bvh.wgsl`.
    pub fn closest_hit(&self, ray: &Ray, tmin: f32, tmax: f32) -> Option<Hit> {
        intersect::closest_hit(self.nodes_for(ray), &self.triangles, ray, tmin, tmax)
    }

    /// The copy of the BVH a ray traverses (`bvh_octants::copy_of`).
    pub fn nodes_for(&self, ray: &Ray) -> &[BvhNode] {
        let n = self.nodes.len();
        let start = copy_of(ray.dir) * n;
        &self.octant_nodes[start..start + n]
    }

    /// Whether anything is hit with t in (tmin, tmax), by the same traversal as `bvh.wgsl`.
    pub fn any_hit(&self, ray: &Ray, tmin: f32, tmax: f32) -> bool {
        intersect::any_hit(self.nodes_for(ray), &self.triangles, ray, tmin, tmax)
    }

    /// Whether a shadow ray, a segment between two points of the scene, is blocked: any_hit
    /// over the occluders only, as `bvh.wgsl`'s shadow_hit.
    pub fn shadow_hit(&self, ray: &Ray, tmin: f32, tmax: f32) -> bool {
        let root = self.occluder_root as usize;
        intersect::any_hit_from(self.nodes_for(ray), root, &self.triangles, ray, tmin, tmax)
    }
}

impl Scene {
    /// The scene's GPU buffers (builds the BVH).
    pub fn to_gpu(&self) -> SceneGpu {
        let points: Vec<Vec3> = self
            .emitters
            .lights
            .iter()
            .filter_map(|l| l.position())
            .collect();
        let mut gpu = SceneGpu {
            max_depth: self.max_depth,
            rr_depth: self.rr_depth.unwrap_or(NO_RUSSIAN_ROULETTE),
            camera_kind: self.camera.kind() as u32,
            filter: self.filter.kind(),
            filter_size: self.filter.size(),
            ..SceneGpu::build_with_points(&self.mesh, &points)
        };
        gpu.add_emitters(&self.emitters);
        gpu
    }
}
