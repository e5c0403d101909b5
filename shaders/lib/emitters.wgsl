// Point, spot and directional lights (src/scene/emitters.rs), as Mitsuba 3's `point`, `spot`
// and `directional`: delta lights, which only next-event estimation reaches. Their records in
// scene.lights (tagged LIGHT_TAG + kind in `material`, lib/scene.wgsl):
//   point:       p0 position, e1 intensity
//   spot:        p0 position, e1 intensity, e2 unit axis, second / first the cutoff angle / the
//                beam width in radians (bit patterns)
//   textured spot: as a spot, but e1 = (the texture's index as bits, (cos, sin) / tan(cutoff)):
//                the lookat frame's x axis in spot_basis(e2); the texture holds intensity x image
//   directional: e1 irradiance, e2 the unit direction the light travels
// The includer includes scene.wgsl.
#include "sampling.wgsl"

// A light sample of any kind but an area light (lib/light_sample.wgsl has those).
struct EmitterSample {
    // Unit direction from the shading point toward the light.
    wi: vec3<f32>,
    // What multiplies f cos: radiance over the solid-angle density, or for a delta light
    // I / d^2 (point, spot) or E (directional).
    value: vec3<f32>,
    // The solid-angle density of wi; 0 for a delta light (MIS leaves it alone).
    pdf: f32,
    // The shadow ray: to the point `end` (t < 1) or, for an infinite light, along wi forever.
    end: vec3<f32>,
    infinite: bool,
}

// Mitsuba's spot profile along the unit direction d leaving the light: 1 within the beam
// width, falling linearly in angle to 0 at the cutoff.
fn spot_falloff(light: Light, d: vec3<f32>) -> f32 {
    let cos_theta = dot(light.e2, d);
    let cutoff = bitcast<f32>(light.second);
    let beam = bitcast<f32>(light.first);
    if cos_theta <= cos(cutoff) {
        return 0.0;
    }
    if cos_theta >= cos(beam) {
        return 1.0;
    }
    // The angle from atan2, not acos(cos_theta): lavapipe's acos is off by ~1e-3 rad here,
    // which the linear ramp turns into errors of 0.5 %.
    let angle = atan2(length(cross(light.e2, d)), cos_theta);
    return (cutoff - angle) / (cutoff - beam);
}

// Whether a light of this kind has a spot's falloff.
fn is_spot(kind: u32) -> bool {
    return (scene_has_light_kind(LIGHT_SPOT) && kind == LIGHT_SPOT)
        || (scene_has_light_kind(LIGHT_SPOT_TEXTURED) && kind == LIGHT_SPOT_TEXTURED);
}

// The orthonormal pair perpendicular to the unit n (Duff et al. 2017), as spot_basis in
// src/scene/emitters.rs.
fn spot_basis(n: vec3<f32>) -> array<vec3<f32>, 2> {
    let sign = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    return array<vec3<f32>, 2>(
        vec3<f32>(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        vec3<f32>(b, sign + n.y * n.y * a, -n.y),
    );
}

// Where the unit direction d leaving a textured spot meets its image, as Mitsuba's spot
// direction_to_uv (v = 0 at the top row), in texture_bilinear's convention (v = 0 at the
// bottom row): hence 1 - v. The record's x axis comes divided by tan(cutoff) (lavapipe's tan
// is off by ~1e-4, which moved the edge of the image by a quarter of a texel per thousand).
fn spot_texture_uv(light: Light, d: vec3<f32>) -> vec2<f32> {
    let basis = spot_basis(light.e2);
    let x = light.e1.y * basis[0] + light.e1.z * basis[1];
    let y = cross(light.e2, x);
    let scale = 0.5 / dot(d, light.e2);
    return vec2<f32>(0.5 + dot(d, x) * scale, 0.5 - dot(d, y) * scale);
}

// The sample of a point, spot or directional light from `origin`; a textured spot's value
// still lacks its texture (nee.wgsl multiplies it in, where scene.textures is bound).
fn sample_delta_light(light: Light, kind: u32, origin: vec3<f32>) -> EmitterSample {
    if scene_has_light_kind(LIGHT_DIRECTIONAL) && kind == LIGHT_DIRECTIONAL {
        return EmitterSample(-light.e2, light.e1, 0.0, vec3<f32>(0.0), true);
    }
    let to = light.p0 - origin;
    let d2 = dot(to, to);
    let wi = to * inverseSqrt(d2);
    var value = light.e1 / d2;
    if scene_has_light_kind(LIGHT_SPOT_TEXTURED) && kind == LIGHT_SPOT_TEXTURED {
        value = vec3<f32>(1.0 / d2);
    }
    if is_spot(kind) {
        value *= spot_falloff(light, -wi);
    }
    return EmitterSample(wi, value, 0.0, light.p0, false);
}

// Light selection's weight (lib/light_select.wgsl) of a point, spot or directional light
// whose table weight is w (its intensity's or irradiance's luminance): the irradiance it could
// give, 0 exactly where it gives none (behind the tangent plane, outside a spot's cone).
fn delta_light_weight(light: Light, kind: u32, origin: vec3<f32>, n: vec3<f32>, w: f32) -> f32 {
    if scene_has_light_kind(LIGHT_DIRECTIONAL) && kind == LIGHT_DIRECTIONAL {
        return select(0.0, w, dot(n, light.e2) < 0.0);
    }
    let to = light.p0 - origin;
    let d2 = dot(to, to);
    if dot(n, to) <= 0.0 || d2 <= 0.0 {
        return 0.0;
    }
    if is_spot(kind) && spot_falloff(light, -to * inverseSqrt(d2)) <= 0.0 {
        return 0.0;
    }
    return w / d2;
}
