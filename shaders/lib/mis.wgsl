// Multiple importance sampling (Veach 1997) between light sampling (next-event estimation) and
// BSDF sampling at each path vertex, with the power heuristic (exponent 2). The including
// shader includes scene.wgsl (scene_has_specular).

// A pass param: 0 both strategies weighted by the power heuristic, 1 light sampling alone,
// 2 BSDF sampling alone (each alone is unbiased too: tests/materials_mis.rs compares them).
// Delta lobes (mirrors, smooth glass) are always BSDF-sampled: no light sample can find them;
// delta lights (point, spot, directional) are always light-sampled: no BSDF sample can.
override mis_strategy: u32 = 0u;

const MIS_BOTH: u32 = 0u;
const MIS_LIGHT_ONLY: u32 = 1u;
const MIS_BSDF_ONLY: u32 = 2u;

// Whether next-event estimation runs.
fn mis_uses_light() -> bool {
    return mis_strategy != MIS_BSDF_ONLY;
}

// Whether BSDF-sampled rays that hit an emitter count (at non-delta vertices). With only
// Lambertian surfaces (scene_has_specular false) and no environment the combination leaves
// light sampling alone: a cosine lobe is much wider than the lights, so BSDF samples would add
// a ray per vertex and almost nothing to the estimate. An environment is as wide as the lobe:
// its light sample is uniform on the sphere (or follows the map), half of it below the surface
// and none of it cosine-weighted, and alone it had 3x Mitsuba's per-sample variance on a
// diffuse floor under a uniform sky (tests/data/conformance/orthographic.xml, independent
// sampler).
fn mis_uses_bsdf() -> bool {
    return mis_strategy == MIS_BSDF_ONLY
        || (mis_strategy == MIS_BOTH && (scene_has_specular || scene_environment != NO_LIGHT));
}

// The power heuristic's weight of a sample drawn with density `own` when `other` would also
// have drawn it.
fn mis_power(own: f32, other: f32) -> f32 {
    let a = own * own;
    let b = other * other;
    return select(a / (a + b), 1.0, b == 0.0);
}

// The weight of a light sample whose direction the BSDF samples with density pdf_bsdf.
fn mis_light_weight(pdf_light: f32, pdf_bsdf: f32) -> f32 {
    return select(1.0, mis_power(pdf_light, pdf_bsdf), mis_uses_bsdf());
}

// The weight of a BSDF sample (density pdf_bsdf, delta or not) that hits an emitter which
// light sampling would pick with density pdf_light.
fn mis_bsdf_weight(pdf_bsdf: f32, delta: bool, pdf_light: f32) -> f32 {
    if delta || !mis_uses_light() {
        return 1.0;
    }
    if !mis_uses_bsdf() {
        return 0.0;
    }
    return mis_power(pdf_bsdf, pdf_light);
}
