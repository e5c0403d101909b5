// The scene data the path tracer provides (src/render/provided.rs), declared once for every
// pass: group 1 after the per-frame uniforms, each bound by its variable's name, so no graph
// lists them. Each is a storage buffer read through a texel view (lib/scene.wgsl's readers).
// shaders/visibility.wgsl declares its own `triangles`: vertex shaders read no storage textures.
#include "provided_view.wgsl"

@group(1) @binding(3) var triangles: texture_storage_2d<rgba32uint, read>;
@group(1) @binding(4) var materials: texture_storage_2d<rgba32uint, read>;
@group(1) @binding(5) var lights: texture_storage_2d<rgba32uint, read>;
@group(1) @binding(6) var light_power: texture_storage_2d<rgba32uint, read>;
@group(1) @binding(7) var bvh: texture_storage_2d<rgba32uint, read>;
// Shading normals and texture coordinates (also for cut-outs: lib/cutout_map.wgsl).
@group(1) @binding(8) var shading: texture_storage_2d<rgba32uint, read>;
@group(1) @binding(9) var textures: texture_storage_2d<rgba32uint, read>;
