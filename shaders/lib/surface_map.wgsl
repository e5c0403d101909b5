// Normal and bump maps, as Mitsuba 3's normalmap and bumpmap BSDF adapters (the CPU twin and
// the derivation: src/scene/surface_map.rs). They perturb the shading normal only; the
// geometric normal keeps deciding sides and ray offsets. The frame is Mitsuba's at a mesh hit:
// dp/du of the triangle from its positions and texture coordinates, Gram-Schmidt against the
// shading normal n (s), t = n x s.
//
// The includer includes lib/scene.wgsl, lib/sampling.wgsl (basis), lib/shading.wgsl and
// lib/texture.wgsl first and binds scene.shading and scene.textures.

// The shading normal of material m at a hit of triangle `index` (t its data) at texture
// coordinates uv: n (the unperturbed shading normal, on the ray's side) perturbed by m's map, on
// the ray's side; `front`: the ray hit the front face; wo toward the viewer. Two-sided models see the front's normal
// mirrored in the tangent plane from the back (Mitsuba's twosided flips the local z only), the
// one-sided dielectric its negation. n itself when m has no map (or no scene has one:
// specialised away).
fn surface_mapped_normal(shading_view: texture_storage_2d<rgba32uint, read>,
                         texture_view: texture_storage_2d<rgba32uint, read>, t: Triangle,
                         index: u32, m: Material, uv: vec2<f32>, n: vec3<f32>, front: bool,
                         wo: vec3<f32>) -> vec3<f32> {
    if !scene_has_surface_maps || m.surface_map == NO_TEXTURE {
        return n;
    }
    let texture = m.surface_map & ~SURFACE_MAP_BUMP;
    // The front-face frame, as Mitsuba's mesh sees it (its shading normal is not flipped).
    let n0 = select(-n, n, front);
    let dp0 = t.p1 - t.p0;
    let dp1 = t.p2 - t.p0;
    let ng = normalize(cross(dp0, dp1));
    let uvs = shading_corner_uvs(shading_view, index);
    let duv0 = uvs[1] - uvs[0];
    let duv1 = uvs[2] - uvs[0];
    let det = duv0.x * duv1.y - duv0.y * duv1.x;
    var dp_du: vec3<f32>;
    var dp_dv: vec3<f32>;
    if det != 0.0 && abs(det) < 3.0e38 {
        let inv = 1.0 / det;
        dp_du = (dp0 * duv1.y - dp1 * duv0.y) * inv;
        dp_dv = (dp1 * duv0.x - dp0 * duv1.x) * inv;
    } else {
        // Degenerate texture coordinates: any frame around the face.
        let frame = basis(ng);
        dp_du = frame[0];
        dp_dv = frame[1];
    }
    var perturbed: vec3<f32>;
    if (m.surface_map & SURFACE_MAP_BUMP) == 0u {
        let local = normalize(texture_bilinear(texture_view, texture, uv).rgb * 2.0 - 1.0);
        let s = normalize(dp_du - n0 * dot(n0, dp_du));
        let tb = cross(n0, s);
        perturbed = s * local.x + tb * local.y + n0 * local.z;
    } else {
        let g = texture_gradient(texture_view, texture, uv) * m.bump_scale;
        let du = dp_du + n0 * (g.x - dot(n0, dp_du));
        let dv = dp_dv + n0 * (g.y - dot(n0, dp_dv));
        let nb = normalize(cross(du, dv));
        perturbed = select(-nb, nb, dot(nb, ng) >= 0.0);
    }
    var r = perturbed;
    if !front {
        if m.kind == MATERIAL_DIELECTRIC {
            r = -perturbed;
        } else {
            r = perturbed - 2.0 * dot(perturbed, n0) * n0;
        }
    }
    // Facing away from the viewer: the tangent part negated, the part along n kept.
    if dot(n, wo) * dot(r, wo) <= 0.0 {
        r = 2.0 * dot(r, n) * n - r;
    }
    return r;
}

// Conty Estevez et al.'s shadowing of a direction w by the map's tilt (Mitsuba's
// eval_shadow_terminator), what the BSDF's value and sample weight are multiplied by: with
// alpha^2 = min(tan^2(n, ns) / 8, 1), 2 / (1 + sqrt(1 + alpha^2 tan^2(n, w))). n the unperturbed
// shading normal, ns the perturbed one; 1 where they are equal (no map).
fn surface_map_shadowing(n: vec3<f32>, ns: vec3<f32>, w: vec3<f32>) -> f32 {
    if all(n == ns) {
        return 1.0;
    }
    let c = dot(n, ns);
    let alpha2 = min(0.125 * max(0.0, 1.0 - c * c) / (c * c), 1.0);
    let cw = dot(n, w);
    let tan2 = max(0.0, 1.0 - cw * cw) / (cw * cw);
    return 2.0 / (1.0 + sqrt(1.0 + alpha2 * tan2));
}

// Whether a direction wi survives the map (Mitsuba's adapters' check): on the same side of the
// unperturbed shading normal n and of the perturbed one ns.
fn surface_map_keeps(n: vec3<f32>, ns: vec3<f32>, wi: vec3<f32>) -> bool {
    return dot(n, wi) * dot(ns, wi) > 0.0;
}
