// Shading normals and texture coordinates from scene.shading (a texel view:
// src/scene/gpu_layout.rs's TriangleShading, 4 texels per triangle in BVH order).
//
// The includer includes lib/scene.wgsl first (scene_texel, the scene_has_* overrides) and binds
// scene.shading as texture_storage_2d<rgba32uint, read>. `triangle` is the BVH-order index a
// hit reports; u, v its barycentrics (the point is (1 - u - v) p0 + u p1 + v p2).

// The interpolated corner normal, normalised and turned to n_geometric's side (n_geometric as
// Surface.n: the geometric normal flipped toward the ray). n_geometric itself when the scene has
// no shading normals (specialised away), the triangle has none, or they cancel out.
fn shading_normal(view: texture_storage_2d<rgba32uint, read>, triangle: u32, u: f32, v: f32,
                  n_geometric: vec3<f32>) -> vec3<f32> {
    if (!scene_has_shading_normals) {
        return n_geometric;
    }
    let a = scene_texel(view, 4u * triangle);
    let b = scene_texel(view, 4u * triangle + 1u);
    let c = scene_texel(view, 4u * triangle + 2u);
    if ((c.w & SHADING_HAS_NORMALS) == 0u) {
        return n_geometric;
    }
    let n = (1.0 - u - v) * bitcast<vec3<f32>>(a.xyz) + u * bitcast<vec3<f32>>(b.xyz)
        + v * bitcast<vec3<f32>>(c.xyz);
    let length2 = dot(n, n);
    if (!(length2 > 1e-12)) {
        return n_geometric;
    }
    let unit = n * inverseSqrt(length2);
    return select(-unit, unit, dot(unit, n_geometric) >= 0.0);
}

// The interpolated texture coordinates; (0, 0) when the scene has none (specialised away) or
// the triangle has none.
fn shading_uv(view: texture_storage_2d<rgba32uint, read>, triangle: u32, u: f32, v: f32) -> vec2<f32> {
    if (!scene_has_uvs) {
        return vec2<f32>(0.0);
    }
    let a = scene_texel(view, 4u * triangle);
    let b = scene_texel(view, 4u * triangle + 1u);
    let c = scene_texel(view, 4u * triangle + 2u);
    if ((c.w & SHADING_HAS_UVS) == 0u) {
        return vec2<f32>(0.0);
    }
    let d = bitcast<vec4<f32>>(scene_texel(view, 4u * triangle + 3u));
    let uv0 = bitcast<vec2<f32>>(vec2<u32>(a.w, b.w));
    return (1.0 - u - v) * uv0 + u * d.xy + v * d.zw;
}

// The corners' texture coordinates (uv0, uv1, uv2) of a triangle that has them.
fn shading_corner_uvs(view: texture_storage_2d<rgba32uint, read>, triangle: u32) -> array<vec2<f32>, 3> {
    let a = scene_texel(view, 4u * triangle);
    let b = scene_texel(view, 4u * triangle + 1u);
    let d = bitcast<vec4<f32>>(scene_texel(view, 4u * triangle + 3u));
    return array<vec2<f32>, 3>(bitcast<vec2<f32>>(vec2<u32>(a.w, b.w)), d.xy, d.zw);
}
