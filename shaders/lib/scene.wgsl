// Scene data as the framework provides it. src/scene/gpu_layout.rs and src/material/record.rs
// mirror these layouts byte for byte.

// Set by the framework from the scene (pipeline-overridable constants).
override scene_light_count: u32 = 0u;
override scene_triangle_count: u32 = 0u;
override scene_node_count: u32 = 0u;
// The first BVH node of the triangles that can block a shadow ray (src/scene/hull.rs).
override scene_occluder_root: u32 = 0u;
// Whether a material has a lobe other than Lambert's.
override scene_has_specular: bool = true;
// Bit 1 << kind for each material kind (MATERIAL_*) a triangle uses: code for absent kinds is
// specialised away.
override scene_material_kinds: u32 = 0xffffffffu;
// The longest path in segments, as Mitsuba's max_depth: 1 emitters seen, 2 direct light,
// 3 one bounce (the seed's model), ...
override scene_max_depth: u32 = 3u;
// Russian roulette from the scene_rr_depth-th BSDF sample of a path on (Mitsuba's rr_depth);
// 0xffffffff: none (src/render/provided.rs).
override scene_rr_depth: u32 = 0xffffffffu;
// Whether a triangle has shading normals / texture coordinates in scene.shading
// (lib/shading.wgsl), whether a used material has a texture map (lib/texture.wgsl), and
// whether one can be cut out (opacity < 1 or map_d).
override scene_has_shading_normals: bool = true;
override scene_has_uvs: bool = true;
override scene_has_textures: bool = true;
override scene_has_cutouts: bool = false;
// The camera's projection (CAMERA_* in lib/camera_ray.wgsl) and the pixel filter (FILTER_* in
// lib/pixel_filter.wgsl) with its stddev or radius: a pinhole with a box filter specialises to
// the plain pinhole ray.
override scene_camera_kind: u32 = 0u;
override scene_filter: u32 = 0u;
override scene_filter_size: f32 = 0.0;

// Bit 1 << kind for each kind of light in scene.lights (LIGHT_AREA, ...): code for absent
// kinds is specialised away, so a scene of emissive triangles traces as it always did.
override scene_light_kinds: u32 = 0xffffffffu;
// The environment's index in scene.lights (lib/emitters.wgsl), or NO_LIGHT: rays that miss
// see black.
override scene_environment: u32 = 0xffffffffu;
// Whether a used material has a normal or bump map (lib/surface_map.wgsl).
override scene_has_surface_maps: bool = true;
// Whether a used material's rough lobe has Beckmann microfacets (lib/microfacet.wgsl), and
// whether a used conductor has a complex-index Fresnel term (lib/material/conductor.wgsl): without
// them a material's last two texels are not read and their code is specialised away.
override scene_has_beckmann: bool = true;
override scene_has_conductor_fresnel: bool = true;
// Whether a used material shades its back face as another material (Mitsuba's one-sided
// models: a black one; twosided with two BSDFs): scene_face_material.
override scene_has_back_materials: bool = true;
// Whether a used material is a null mask (Mitsuba's mask: src/scene/mesh.rs, Mesh::null_masks):
// its record's opacity (or map_d at the hit) is the probability the surface is there
// (lib/shading_point.wgsl).
override scene_has_null_masks: bool = true;

fn scene_has_kind(kind: u32) -> bool {
    return (scene_material_kinds & (1u << kind)) != 0u;
}

fn scene_has_light_kind(kind: u32) -> bool {
    return (scene_light_kinds & (1u << kind)) != 0u;
}

// Whether every light is an emissive triangle or parallelogram.
fn scene_area_lights_only() -> bool {
    return (scene_light_kinds & ~(1u << LIGHT_AREA)) == 0u;
}

// One triangle, in BVH order; `material` indexes `scene.materials`, `light` `scene.lights` (the
// light the triangle is part of, or NO_LIGHT).
struct Triangle {
    p0: vec3<f32>,
    material: u32,
    p1: vec3<f32>,
    light: u32,
    p2: vec3<f32>,
    // The fraction of rays the triangle stops (MTL d); bvh.wgsl lets the rest pass. Negative:
    // that of texture -1 - opacity (map_d) at the hit.
    opacity: f32,
}

#include "material_kinds.wgsl"

// A material: its model (`kind`, a MATERIAL_* constant) and the model's parameters
// (src/material/record.rs documents each). ke is emitted radiance, front faces only.
struct Material {
    kd: vec3<f32>,
    ns: f32,
    ks: vec3<f32>,
    kind: u32,
    ke: vec3<f32>,
    // Microfacet alpha = r^2; 0: smooth (delta).
    alpha: f32,
    tf: vec3<f32>,
    ior: f32,
    map_kd: u32,
    map_ks: u32,
    map_pr: u32,
    map_d: u32,
    opacity: f32,
    // The texel index in this view of the model's table (Model::table, src/material/tables.rs),
    // or NO_TABLE.
    table: u32,
    // A normal map's texture index, a bump map's with SURFACE_MAP_BUMP set, or NO_TEXTURE
    // (lib/surface_map.wgsl); the bump map's height scale.
    surface_map: u32,
    bump_scale: f32,
    // A conductor's complex index eta + i k, read when fresnel is FRESNEL_CONDUCTOR (else
    // FRESNEL_NONE: Fresnel 1, the tint kd alone); the rough models' microfacet distribution
    // (DISTRIBUTION_GGX, DISTRIBUTION_BECKMANN: lib/microfacet.wgsl).
    eta: vec3<f32>,
    distribution: u32,
    k: vec3<f32>,
    fresnel: u32,
}

const FRESNEL_NONE: u32 = 0u;
const FRESNEL_CONDUCTOR: u32 = 1u;

// A triangle's shading data in scene.shading (BVH order, 4 texels): corner normals n0..n2 and
// texture coordinates (u0, v0), uv1, uv2; flags: SHADING_HAS_NORMALS | SHADING_HAS_UVS.
struct TriangleShading {
    n0: vec3<f32>,
    u0: f32,
    n1: vec3<f32>,
    v0: f32,
    n2: vec3<f32>,
    flags: u32,
    uv1: vec2<f32>,
    uv2: vec2<f32>,
}

const SHADING_HAS_NORMALS: u32 = 1u;
const SHADING_HAS_UVS: u32 = 2u;

const NO_TEXTURE: u32 = 0xffffffffu;
const SURFACE_MAP_BUMP: u32 = 0x80000000u;
const NO_TABLE: u32 = 0xffffffffu;
const NO_LIGHT: u32 = 0xffffffffu;

// A light (src/scene/lights.rs): the points p0 + a e1 + b e2 with a, b >= 0 and a + b <= 1 (a
// triangle, second == LIGHT_NO_TRIANGLE) or a, b in [0, 1] (a parallelogram of two triangles).
// Only the front face, the side cross(e1, e2) points to, emits.
struct Light {
    p0: vec3<f32>,
    material: u32,
    e1: vec3<f32>,
    second: u32,
    e2: vec3<f32>,
    first: u32,
}

const LIGHT_NO_TRIANGLE: u32 = 0xffffffffu;

// A light whose `material` is LIGHT_TAG + kind is not an area light (src/scene/lights.rs);
// lib/emitters.wgsl reads its fields by kind.
const LIGHT_TAG: u32 = 0xfffffff0u;
const LIGHT_AREA: u32 = 0u;
const LIGHT_POINT: u32 = 1u;
const LIGHT_SPOT: u32 = 2u;
const LIGHT_DIRECTIONAL: u32 = 3u;
const LIGHT_ENVIRONMENT_MAP: u32 = 4u;
const LIGHT_ENVIRONMENT_CONSTANT: u32 = 5u;
const LIGHT_SPOT_TEXTURED: u32 = 6u;

fn light_kind(light: Light) -> u32 {
    if scene_area_lights_only() {
        return LIGHT_AREA;
    }
    return select(LIGHT_AREA, light.material - LIGHT_TAG, light.material >= LIGHT_TAG);
}

// A threaded BVH node, decoded (scene.bvh stores it packed: PackedBvhNode). Interior: count == 0, `a` is the miss link (skip); the hit
// link is implicit (this index + 1). Leaf: count > 0 triangles from index `a`; a leaf's next
// node is always this index + 1. Traversal ends at index == scene_node_count.
struct BvhNode {
    lo: vec3<f32>,
    a: u32,
    hi: vec3<f32>,
    count: u32,
}

// The grid node boxes lie on (src/scene/bvh_grid.rs), the first two texels of scene.bvh: a box
// coordinate is origin + q * step, q a 16-bit integer, step a power of two; exact in f32.
struct BvhGrid {
    origin: vec3<f32>,
    pad0: u32,
    step: vec3<f32>,
    pad1: u32,
}

// A node as scene.bvh stores it after the grid, one texel: per axis the box's low grid cell in
// the low 16 bits and its high cell in the high 16; `link` is BvhNode's `a` with its count in
// the top 4 bits.
struct PackedBvhNode {
    bounds: vec3<u32>,
    link: u32,
}

// The camera. `right` and `up` are scaled so that a pixel's direction is
// normalize(forward + sx * right + sy * up) with sx, sy in [-1, 1] (sy = +1 at the top row);
// an orthographic camera's rays start at eye + sx * right + sy * up instead, along forward.
// A thin lens's aperture_radius and focus_distance are 0 otherwise (lib/camera_ray.wgsl).
struct Camera {
    eye: vec3<f32>,
    aperture_radius: f32,
    forward: vec3<f32>,
    focus_distance: f32,
    right: vec3<f32>,
    pad2: f32,
    up: vec3<f32>,
    pad3: f32,
}

// Per-frame values. `accumulated` is how many frames the result already holds (0: restart).
struct Frame {
    index: u32,
    accumulated: u32,
    width: u32,
    height: u32,
    seed: u32,
    // How image passes order their rows of tiles: lib/tile_order.wgsl.
    tile_row_stride: u32,
    // The sample index of the accumulation's first frame (a sample range A..B starts at A):
    // lib/sampler.wgsl adds it to the frame's index.
    first_sample: u32,
    pad2: u32,
    // Where this frame's pixel (0, 0) lies in the whole image, and the whole image's size:
    // (0, 0) and (width, height) unless the image is rendered in tiles (src/render/tiles.rs).
    // width and height above are the tile's: bounds and buffer indices are the tile's, while
    // camera rays (lib/camera_ray.wgsl) and sampler seeds (lib/sampler.wgsl) take the pixel's
    // place in the image, so a tiled render equals the untiled one bit for bit.
    image_origin: vec2<u32>,
    image_size: vec2<u32>,
}

// Texel views: a pass may bind scene.triangles, scene.materials, scene.lights and scene.bvh as
// texture_storage_2d<rgba32uint, read> instead of storage buffers, and read them with the functions below. The
// framework stores the same bytes as 16-byte texels, row-major, in rows of a power-of-two
// width (crates/gpu/src/texels.rs). Texel fetches are several times cheaper than storage-buffer loads
// on lavapipe, which gathers the latter lane by lane.

// Texel i of a texel view.
fn scene_texel(view: texture_storage_2d<rgba32uint, read>, i: u32) -> vec4<u32> {
    let width = textureDimensions(view).x;
    return textureLoad(view, vec2<u32>(i & (width - 1u), i >> countTrailingZeros(width)));
}

// Triangle i of a scene.triangles view (3 texels each).
fn scene_triangle(view: texture_storage_2d<rgba32uint, read>, i: u32) -> Triangle {
    let a = scene_texel(view, 3u * i);
    let b = scene_texel(view, 3u * i + 1u);
    let c = scene_texel(view, 3u * i + 2u);
    return Triangle(bitcast<vec3<f32>>(a.xyz), a.w, bitcast<vec3<f32>>(b.xyz), b.w,
                    bitcast<vec3<f32>>(c.xyz), bitcast<f32>(c.w));
}

// The three vertices of triangle i only (what ray tests need).
fn scene_triangle_vertices(view: texture_storage_2d<rgba32uint, read>, i: u32) -> array<vec3<f32>, 3> {
    return array<vec3<f32>, 3>(
        bitcast<vec3<f32>>(scene_texel(view, 3u * i).xyz),
        bitcast<vec3<f32>>(scene_texel(view, 3u * i + 1u).xyz),
        bitcast<vec3<f32>>(scene_texel(view, 3u * i + 2u).xyz),
    );
}

// Material i of a scene.materials view (8 texels each). The last two are read only in scenes
// that use them (scene_has_beckmann, scene_has_conductor_fresnel); elsewhere they hold the
// defaults (GGX, Fresnel none), which the zeros here are.
fn scene_material(view: texture_storage_2d<rgba32uint, read>, i: u32) -> Material {
    let a = scene_texel(view, 8u * i);
    let b = scene_texel(view, 8u * i + 1u);
    let c = scene_texel(view, 8u * i + 2u);
    let d = scene_texel(view, 8u * i + 3u);
    let e = scene_texel(view, 8u * i + 4u);
    let f = scene_texel(view, 8u * i + 5u);
    var g = vec4<u32>(0u);
    if scene_has_beckmann || scene_has_conductor_fresnel {
        g = scene_texel(view, 8u * i + 6u);
    }
    var h = vec4<u32>(0u);
    if scene_has_conductor_fresnel {
        h = scene_texel(view, 8u * i + 7u);
    }
    let kind = b.w & ((1u << MATERIAL_KIND_BITS) - 1u);
    return Material(bitcast<vec3<f32>>(a.xyz), bitcast<f32>(a.w), bitcast<vec3<f32>>(b.xyz), kind,
                    bitcast<vec3<f32>>(c.xyz), bitcast<f32>(c.w), bitcast<vec3<f32>>(d.xyz),
                    bitcast<f32>(d.w), e.x, e.y, e.z, e.w, bitcast<f32>(f.x), f.y, f.z,
                    bitcast<f32>(f.w), bitcast<vec3<f32>>(g.xyz), g.w, bitcast<vec3<f32>>(h.xyz),
                    h.w);
}

// The material that shades material i's face hit from the front (true) or from behind.
fn scene_face_material(view: texture_storage_2d<rgba32uint, read>, i: u32, front: bool) -> Material {
    if scene_has_back_materials && !front {
        let back = scene_texel(view, 8u * i + 1u).w >> MATERIAL_KIND_BITS;
        if back != 0u {
            return scene_material(view, back - 1u);
        }
    }
    return scene_material(view, i);
}

// Only the emitted radiance of material i (what light sampling needs).
fn scene_material_ke(view: texture_storage_2d<rgba32uint, read>, i: u32) -> vec3<f32> {
    return bitcast<vec3<f32>>(scene_texel(view, 8u * i + 2u).xyz);
}

// Light i of a scene.lights view (3 texels each).
fn scene_light(view: texture_storage_2d<rgba32uint, read>, i: u32) -> Light {
    let a = scene_texel(view, 3u * i);
    let b = scene_texel(view, 3u * i + 1u);
    let c = scene_texel(view, 3u * i + 2u);
    return Light(bitcast<vec3<f32>>(a.xyz), a.w, bitcast<vec3<f32>>(b.xyz), b.w,
                 bitcast<vec3<f32>>(c.xyz), c.w);
}

// The grid of a scene.bvh view (its first two texels).
fn scene_bvh_grid(view: texture_storage_2d<rgba32uint, read>) -> BvhGrid {
    let a = scene_texel(view, 0u);
    let b = scene_texel(view, 1u);
    return BvhGrid(bitcast<vec3<f32>>(a.xyz), a.w, bitcast<vec3<f32>>(b.xyz), b.w);
}

// Node i of a scene.bvh view as stored (one texel after the grid).
fn scene_packed_node(view: texture_storage_2d<rgba32uint, read>, i: u32) -> PackedBvhNode {
    let texel = scene_texel(view, i + 2u);
    return PackedBvhNode(texel.xyz, texel.w);
}

// A packed node's grid cells at bit `shift` of each axis (0: the low ones, 16: the high), as
// f32 (exact).
fn scene_node_cells(node: PackedBvhNode, shift: vec3<u32>) -> vec3<f32> {
    return vec3<f32>((node.bounds >> shift) & vec3<u32>(0xffffu));
}

// A packed node's link and count, its box left at 0 (for a traversal that reads the box from
// the cells).
fn scene_node_links(node: PackedBvhNode) -> BvhNode {
    return BvhNode(vec3<f32>(0.0), node.link & 0x0fffffffu, vec3<f32>(0.0), node.link >> 28u);
}

// Node i of a scene.bvh view, its box decoded on `grid` (scene_bvh_grid).
fn scene_node(view: texture_storage_2d<rgba32uint, read>, grid: BvhGrid, i: u32) -> BvhNode {
    let packed = scene_packed_node(view, i);
    var node = scene_node_links(packed);
    node.lo = scene_node_cells(packed, vec3<u32>(0u)) * grid.step + grid.origin;
    node.hi = scene_node_cells(packed, vec3<u32>(16u)) * grid.step + grid.origin;
    return node;
}

// Entry i of a scene.light_power view (four f32 per texel).
fn scene_light_power(view: texture_storage_2d<rgba32uint, read>, i: u32) -> f32 {
    return bitcast<f32>(scene_texel(view, i >> 2u)[i & 3u]);
}
