// What shading needs at a ray's hit: the surface (geometric side and offsets), the shading
// normal, the BSDF with textures applied, the emitted radiance toward the ray and the light the
// triangle belongs to. The including shader declares `triangles`, `materials`, `shading` and
// `textures` (scene.shading, scene.textures) and includes scene, surface, shading, texture
// and bsdf; this file brings surface_map.

#include "surface_map.wgsl"

struct ShadingPoint {
    s: Surface,
    // The shading normal (interpolated vertex normals, or the geometric one, perturbed by a
    // normal or bump map), on the ray's side.
    ns: vec3<f32>,
    // The shading normal before the map (ns itself without one): what point_eval,
    // point_pdf and point_sample check directions against, as Mitsuba's map adapters do.
    n_smooth: vec3<f32>,
    b: Bsdf,
    // Ke on the front face, 0 on the back (emission is one-sided).
    emitted: vec3<f32>,
    // The light the triangle is part of, or NO_LIGHT.
    light: u32,
    // The probability the surface is there: a null mask's opacity at the hit (1 elsewhere).
    // point_eval, point_pdf and point_sample mix the BSDF with a null interaction by it, as
    // Mitsuba's mask: the path goes straight on through the rest, one segment longer, and
    // shadow rays stop at the surface (its triangles are opaque to the traversal).
    opacity: f32,
}

// The hit at barycentrics (u, v) of `triangle` by a ray along dir.
fn shading_point(triangle: u32, u: f32, v: f32, dir: vec3<f32>) -> ShadingPoint {
    let t = scene_triangle(triangles, triangle);
    let s = surface_at(t, u, v, dir);
    let n_smooth = shading_normal(shading, triangle, u, v, s.n);
    var m = scene_face_material(materials, s.material, s.front);
    var ns = n_smooth;
    if scene_has_textures || scene_has_surface_maps {
        let uv = shading_uv(shading, triangle, u, v);
        m = material_at(m, textures, uv);
        ns = surface_mapped_normal(shading, textures, t, triangle, m, uv, n_smooth, s.front, -dir);
    }
    // A cut-out's record has opacity 1 (its triangles carry it): any opacity below is a mask's.
    let opacity = select(1.0, m.opacity, scene_has_null_masks);
    return ShadingPoint(s, ns, n_smooth, bsdf_from_material(m), select(vec3<f32>(0.0), m.ke, s.front), t.light, opacity);
}

// The BSDF at p (bsdf.wgsl's eval, pdf and sample with p's shading normal), with Mitsuba's
// map adapters' check (0 for a wi on opposite sides of the normal before and after the map)
// and shadowing (eval and the sample's weight, not the pdf: lib/surface_map.wgsl), and a null
// mask's mixture: eval and pdf scaled by the opacity, the sample the null interaction (a delta
// straight on, weight 1) with probability 1 - opacity.
fn point_eval(p: ShadingPoint, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if scene_has_null_masks {
        return point_eval_surface(p, wo, wi) * p.opacity;
    }
    return point_eval_surface(p, wo, wi);
}

fn point_eval_surface(p: ShadingPoint, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if scene_has_surface_maps {
        if !surface_map_keeps(p.n_smooth, p.ns, wi) {
            return vec3<f32>(0.0);
        }
        return bsdf_eval(p.b, p.ns, p.s.front, wo, wi) * surface_map_shadowing(p.n_smooth, p.ns, wi);
    }
    return bsdf_eval(p.b, p.ns, p.s.front, wo, wi);
}

fn point_pdf(p: ShadingPoint, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if scene_has_surface_maps && !surface_map_keeps(p.n_smooth, p.ns, wi) {
        return 0.0;
    }
    if scene_has_null_masks {
        return bsdf_pdf(p.b, p.ns, p.s.front, wo, wi) * p.opacity;
    }
    return bsdf_pdf(p.b, p.ns, p.s.front, wo, wi);
}

fn point_sample(p: ShadingPoint, wo: vec3<f32>, u: vec2<f32>, u_lobe: f32) -> BsdfSample {
    var lobe = u_lobe;
    if scene_has_null_masks && p.opacity < 1.0 {
        if u_lobe >= p.opacity {
            return BsdfSample(-wo, vec3<f32>(1.0), 1.0 - p.opacity, true, 1.0);
        }
        // The rest of u_lobe's interval picks the BSDF's lobe.
        lobe = u_lobe / p.opacity;
    }
    var bs = bsdf_sample(p.b, p.ns, p.s.front, wo, u, lobe);
    if scene_has_null_masks {
        bs.pdf *= p.opacity;
    }
    if scene_has_surface_maps {
        if surface_map_keeps(p.n_smooth, p.ns, bs.wi) {
            bs.weight *= surface_map_shadowing(p.n_smooth, p.ns, bs.wi);
        } else {
            bs.weight = vec3<f32>(0.0);
            bs.pdf = 0.0;
        }
    }
    return bs;
}

// The origin of a ray leaving s toward wi: moved off the surface to wi's side (transmitted
// rays leave from the other side).
fn leaving(s: Surface, wi: vec3<f32>) -> vec3<f32> {
    return ray_origin(s, select(-s.n, s.n, dot(s.n, wi) >= 0.0));
}
