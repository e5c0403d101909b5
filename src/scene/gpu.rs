//! [`SceneGpu`]: the buffers built from a scene (triangles in BVH order, materials, emissive
//! triangles, BVH nodes) with the facts the shaders are specialised on. The records themselves
//! are in src/scene/gpu_layout.rs.

use super::bvh::{Bvh, BvhStats};
use super::bvh_grid::BvhGrid;
use super::bvh_octants::{copy_of, octant_copies};
use super::description::Scene;
use super::gpu_layout::*;
use super::hull::hull_faces_with;
use super::intersect::{self, Hit, Ray};
use super::lights::LIGHT_AREA;
use super::lights::{Light, light_power, scene_lights};
use super::mesh::{Mesh, MeshTriangle};
use super::texture::{Texture, textures_byte_len, textures_bytes};
use crate::material::{Material, NO_TEXTURE};
use glam::Vec3;
use rayon::prelude::*;
use std::collections::BTreeMap;

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
    pub fn new(t: &MeshTriangle) -> TriangleShading {
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

    /// The `scene.bvh` buffer: the grid, then each node of each octant's copy as one texel,
    /// encoded in parallel (47 MB for a 1M-triangle mesh: 0.2 s on one thread).
    pub fn bvh_bytes(&self) -> Vec<u8> {
        let grid = self.grid.to_gpu();
        let head = bytemuck::bytes_of(&grid);
        let mut bytes = vec![0u8; self.bvh_byte_len()];
        let (to_head, to_nodes) = bytes.split_at_mut(head.len());
        to_head.copy_from_slice(head);
        to_nodes
            .par_chunks_mut(size_of::<PackedBvhNode>())
            .with_min_len(4096)
            .zip(&self.octant_nodes)
            .for_each(|(to, node)| to.copy_from_slice(bytemuck::bytes_of(&self.grid.encode(node))));
        bytes
    }

    fn bvh_byte_len(&self) -> usize {
        size_of::<GpuBvhGrid>() + size_of::<PackedBvhNode>() * self.octant_nodes.len()
    }

    /// The bytes of the scene's buffers (triangles, materials, lights, BVH, shading and
    /// textures), counted without building them.
    pub fn byte_len(&self) -> usize {
        size_of_val(self.triangles.as_slice())
            + size_of_val(self.materials.as_slice())
            + size_of_val(self.lights.as_slice())
            + self.bvh_byte_len()
            + self.shading_byte_len()
            + textures_byte_len(&self.textures)
    }

    fn shading_byte_len(&self) -> usize {
        size_of_val(self.shading.as_slice()).max(16)
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
