// Light selection (docs/design.md §8 A): one light per shading point instead of all of
// them, chosen with probability proportional to its power (scene.light_power: area x luminance
// of Ke) over its squared distance. Next-event estimation divides by that probability, so the
// estimate stays unbiased. The including shader declares `triangles`, `lights` and
// `light_power` (texel views) and includes scene and surface. Lights that are not area lights
// weigh by lib/emitters.wgsl's delta_light_weight, the environment by its table weight alone
// (pi times its mean luminance: the irradiance it would give a surface open to all of it).
#include "emitters.wgsl"

// No light can contribute: every weight is 0.
const LIGHT_NONE: u32 = 0xffffffffu;

struct LightChoice {
    index: u32,
    pmf: f32,
}

// The unnormalised probability of light i from `origin` (the shading point, from which
// nee.wgsl samples the light) with normal n. Exactly 0 only where the light cannot contribute at all: the point lies on or
// behind the light's plane (emission is one-sided), or the whole light lies on or below the
// point's tangent plane. The squared distance to the centroid is clamped below by the area so
// that a point next to a light does not give it an unbounded weight.
fn light_weight(origin: vec3<f32>, n: vec3<f32>, i: u32) -> f32 {
    let light = scene_light(lights, i);
    let kind = light_kind(light);
    if kind == LIGHT_ENVIRONMENT_MAP || kind == LIGHT_ENVIRONMENT_CONSTANT {
        return scene_light_power(light_power, i);
    }
    if kind != LIGHT_AREA {
        return delta_light_weight(light, kind, origin, n, scene_light_power(light_power, i));
    }
    let normal = cross(light.e1, light.e2);
    if dot(normal, origin - light.p0) <= 0.0 {
        return 0.0;
    }
    let parallelogram = light.second != LIGHT_NO_TRIANGLE;
    // The corners' heights above the tangent plane: p0, p0 + e1, p0 + e2 and, for a
    // parallelogram, p0 + e1 + e2.
    let h0 = dot(n, light.p0 - origin);
    let h1 = h0 + dot(n, light.e1);
    let h2 = h0 + dot(n, light.e2);
    let h3 = select(h0, h1 + dot(n, light.e2), parallelogram);
    if max(max(h0, h1), max(h2, h3)) <= 0.0 {
        return 0.0;
    }
    let to_centroid = light.p0 + (light.e1 + light.e2) * select(1.0 / 3.0, 0.5, parallelogram) - origin;
    let area = select(0.5, 1.0, parallelogram) * length(normal);
    return scene_light_power(light_power, i) / max(dot(to_centroid, to_centroid), area);
}

// Draws one light with probability weight / total from the uniform number u.
// The running sum that picks the light adds the same weights as the total, so the chosen light
// is the first whose running sum exceeds u * total; if rounding leaves u * total at or above the
// final sum, the last light of positive weight is chosen. A light of weight 0 is never chosen.
fn select_light(origin: vec3<f32>, n: vec3<f32>, u: f32) -> LightChoice {
    var total = 0.0;
    for (var i = 0u; i < scene_light_count; i++) {
        total += light_weight(origin, n, i);
    }
    let goal = u * total;
    var choice = LightChoice(LIGHT_NONE, 0.0);
    var found = false;
    var sum = 0.0;
    for (var i = 0u; i < scene_light_count; i++) {
        let w = light_weight(origin, n, i);
        sum += w;
        if w > 0.0 && !found {
            choice = LightChoice(i, w / total);
            found = goal < sum;
        }
    }
    return choice;
}

// The probability with which select_light draws light i (for multiple importance sampling).
fn light_pmf(origin: vec3<f32>, n: vec3<f32>, i: u32) -> f32 {
    var total = 0.0;
    for (var j = 0u; j < scene_light_count; j++) {
        total += light_weight(origin, n, j);
    }
    return select(0.0, light_weight(origin, n, i) / total, total > 0.0);
}
