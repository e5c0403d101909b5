// Next-event estimation and its counterpart, BSDF-sampled rays that hit an emitter, weighted
// against each other (mis.wgsl); shared by the direct and indirect channels. The including
// shader declares `triangles`, `materials`, `lights`, `light_power`, `bvh` and `frame`, and
// includes scene, rng, sampler, sampling, bsdf, mis, bvh, surface, texture, shading_point,
// light_sample and light_select.
#include "emitters.wgsl"
#include "environment.wgsl"

// A pass param: one light per shading point, chosen by light_select.wgsl, instead of all.
override light_selection: bool = false;

// Light reaching p from the emitters by light sampling, toward wo. `dim_select` and `dim_light`
// are the sampler pairs (sampler.wgsl) of the light choice and of the point on the light.
fn direct_light(p: ShadingPoint, wo: vec3<f32>, source: SampleSource, dim_select: u32, dim_light: u32) -> vec3<f32> {
    // Without light sampling only delta lights are sampled (light_contribution skips others).
    let delta_lights = scene_has_light_kind(LIGHT_POINT) || scene_has_light_kind(LIGHT_SPOT) || scene_has_light_kind(LIGHT_SPOT_TEXTURED) || scene_has_light_kind(LIGHT_DIRECTIONAL);
    if (!mis_uses_light() && !delta_lights) || bsdf_is_delta(p.b) {
        return vec3<f32>(0.0);
    }
    if light_selection {
        return selected_light(p, wo, source, dim_select, dim_light);
    }
    return all_lights(p, wo, source, dim_light);
}

// f cos * Le / pdf for the point u picks on light i (light_sample.wgsl), times its MIS weight,
// 0 if occluded. pmf: the probability light i was chosen (1 when every light is sampled).
// The light is sampled, and its geometry taken, from the shading point itself; `origin` (p
// moved off its surface) only starts the shadow ray. Taken from `origin`, the estimate was of
// the light at a point some hundred ulps nearer the light: 6-14 % too dark on a wall 0.2 mm
// behind a light facing it at z = 559 (tests/robust_render.rs, the light in a gap).
fn light_contribution(p: ShadingPoint, wo: vec3<f32>, origin: vec3<f32>, i: u32, u: vec2<f32>, pmf: f32) -> vec3<f32> {
    let light = scene_light(lights, i);
    let kind = light_kind(light);
    let delta = kind == LIGHT_POINT || is_spot(kind) || kind == LIGHT_DIRECTIONAL;
    if !mis_uses_light() && !delta {
        return vec3<f32>(0.0);
    }
    if kind != LIGHT_AREA {
        return emitter_contribution(p, wo, origin, light, kind, u, pmf);
    }
    // p may lie in the light's plane (the light's own back face, a surface glued to it) by
    // its rounding, where cosines of rounding's sign and distances near 0 would light it: a
    // point whose rays leave from behind the light's plane gets nothing from it.
    if dot(cross(light.e1, light.e2), origin - light.p0) <= 0.0 {
        return vec3<f32>(0.0);
    }
    let l = sample_light(p.s, p.s.p, light, u);
    if l.cos_x <= 0.0 || l.cos_y <= 0.0 {
        return vec3<f32>(0.0);
    }
    let f = point_eval(p, wo, l.wi);
    if all(f == vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    if shadow_hit(origin, l.end - origin, 0.0, 1.0 - 1e-4) {
        return vec3<f32>(0.0);
    }
    // geometry is cos_x over the point's solid-angle density; f already holds the cosine.
    let inverse_pdf = l.geometry / l.cos_x;
    let weight = mis_light_weight(pmf / inverse_pdf, point_pdf(p, wo, l.wi));
    return f * scene_material_ke(materials, light.material) * (inverse_pdf * weight / pmf);
}

// light_contribution for a light that is not an area light: a delta light (no MIS: no BSDF
// sample can meet it) or the environment, whose shadow ray runs to infinity through the whole
// scene (the hull faces block it too: it is no segment between scene points).
fn emitter_contribution(p: ShadingPoint, wo: vec3<f32>, origin: vec3<f32>, light: Light, kind: u32, u: vec2<f32>, pmf: f32) -> vec3<f32> {
    var e: EmitterSample;
    if kind == LIGHT_ENVIRONMENT_MAP || kind == LIGHT_ENVIRONMENT_CONSTANT {
        e = environment_sample(light, u);
    } else {
        e = sample_delta_light(light, kind, p.s.p);
        if scene_has_light_kind(LIGHT_SPOT_TEXTURED) && kind == LIGHT_SPOT_TEXTURED && any(e.value > vec3<f32>(0.0)) {
            // Only inside the cone: the uv of a direction outside it is meaningless.
            e.value *= texture_bilinear(textures, bitcast<u32>(light.e1.x), spot_texture_uv(light, -e.wi)).rgb;
        }
    }
    if dot(p.s.n, e.wi) <= 0.0 || all(e.value == vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    let f = point_eval(p, wo, e.wi);
    if all(f == vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    if e.infinite {
        if any_hit(origin, e.wi, 0.0, 3.0e38) {
            return vec3<f32>(0.0);
        }
    } else if shadow_hit(origin, e.end - origin, 0.0, 1.0 - 1e-4) {
        return vec3<f32>(0.0);
    }
    var weight = 1.0;
    if e.pdf > 0.0 {
        weight = mis_light_weight(pmf * e.pdf, point_pdf(p, wo, e.wi));
    }
    return f * e.value * (weight / pmf);
}

// The environment's radiance a BSDF sample meets when its ray leaves the scene, times its MIS
// weight against light sampling from the vertex it left (at xp, geometric normal xn), as
// emission_weighted for an emitter it hits.
fn environment_weighted(xp: vec3<f32>, xn: vec3<f32>, bs: BsdfSample) -> vec3<f32> {
    if !scene_has_environment() || (!bs.delta && !mis_uses_bsdf()) {
        return vec3<f32>(0.0);
    }
    let env = scene_light(lights, scene_environment);
    let le = environment_radiance(env, bs.wi);
    var pdf_light = 0.0;
    if !bs.delta && mis_uses_light() && dot(xn, bs.wi) > 0.0 {
        pdf_light = environment_pdf(env, bs.wi);
        if light_selection {
            pdf_light *= light_pmf(xp, xn, scene_environment);
        }
    }
    return le * mis_bsdf_weight(bs.pdf, bs.delta, pdf_light);
}

// One light, drawn with probability pmf, and its contribution divided by pmf.
fn selected_light(p: ShadingPoint, wo: vec3<f32>, source: SampleSource, dim_select: u32, dim_light: u32) -> vec3<f32> {
    let origin = ray_origin(p.s, p.s.n);
    let choice = select_light(p.s.p, p.s.n, sample_1d(source, dim_select));
    if choice.index == LIGHT_NONE {
        return vec3<f32>(0.0);
    }
    return light_contribution(p, wo, origin, choice.index, sample_2d(source, dim_light), choice.pmf);
}

// One point on every light and a shadow ray to each; light i takes its point from
// its own sampler pair.
fn all_lights(p: ShadingPoint, wo: vec3<f32>, source: SampleSource, dim_light: u32) -> vec3<f32> {
    let origin = ray_origin(p.s, p.s.n);
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < scene_light_count; i++) {
        let u = sample_2d(source, dim_light + SAMPLER_LIGHT_STRIDE * i);
        sum += light_contribution(p, wo, origin, i, u, 1.0);
    }
    return sum;
}

// The emitted radiance a BSDF sample meets at hit q, times its MIS weight against light
// sampling from the vertex it left (at xp, geometric normal xn): what a path needs of
// that vertex, so a wavefront pass can keep it in a path's state.
fn emission_weighted(xp: vec3<f32>, xn: vec3<f32>, bs: BsdfSample, q: ShadingPoint) -> vec3<f32> {
    // Light sampling alone counts the emitters a non-delta sample meets.
    if all(q.emitted == vec3<f32>(0.0)) || (!bs.delta && !mis_uses_bsdf()) {
        return vec3<f32>(0.0);
    }
    // The density light sampling (from the vertex itself) gives this direction: 0 below its
    // tangent plane, where no light sample is taken, or for an emitter that is not a light
    // (zero area).
    var pdf_light = 0.0;
    if !bs.delta && mis_uses_light() && q.light != NO_LIGHT && dot(xn, bs.wi) > 0.0 {
        pdf_light = light_pdf(xp, scene_light(lights, q.light), bs.wi);
        if light_selection {
            pdf_light *= light_pmf(xp, xn, q.light);
        }
    }
    return q.emitted * mis_bsdf_weight(bs.pdf, bs.delta, pdf_light);
}

// Whether a vertex takes a BSDF sample for the emitters it hits (besides any it needs to go on).
fn samples_bsdf_for_light(p: ShadingPoint) -> bool {
    return mis_uses_bsdf() || bsdf_is_delta(p.b) || (scene_has_null_masks && p.opacity < 1.0);
}
