// The rough models' microfacet distribution chosen per material (src/bsdf/microfacet.rs): GGX
// (lib/ggx.wgsl) or Beckmann (lib/beckmann.wgsl) by Bsdf.distribution. Beckmann's branch sits
// behind the scene_has_beckmann override, so a scene without it runs GGX's code alone, as
// before. Local frame, normal +z.

const DISTRIBUTION_GGX: u32 = 0u;
const DISTRIBUTION_BECKMANN: u32 = 1u;

// Mitsuba's floor on alpha (its MicrofacetDistribution's, whatever the type): below it the
// distribution is a delta the float maths cannot hold.
fn microfacet_alpha(alpha: f32) -> f32 {
    return max(alpha, 1e-4);
}

fn microfacet_d(distribution: u32, alpha: f32, m: vec3<f32>) -> f32 {
    if scene_has_beckmann && distribution == DISTRIBUTION_BECKMANN {
        return beckmann_d(alpha, m);
    }
    return ggx_d(alpha, m);
}

fn microfacet_g1(distribution: u32, alpha: f32, v: vec3<f32>, m: vec3<f32>) -> f32 {
    if scene_has_beckmann && distribution == DISTRIBUTION_BECKMANN {
        return beckmann_g1(alpha, v, m);
    }
    return ggx_g1(alpha, v, m);
}

fn microfacet_sample_visible(distribution: u32, alpha: f32, wi: vec3<f32>, u: vec2<f32>)
    -> vec3<f32> {
    if scene_has_beckmann && distribution == DISTRIBUTION_BECKMANN {
        return beckmann_sample_visible(alpha, wi, u);
    }
    return ggx_sample_visible(alpha, wi, u);
}

fn microfacet_pdf_visible(distribution: u32, alpha: f32, wi: vec3<f32>, m: vec3<f32>) -> f32 {
    if scene_has_beckmann && distribution == DISTRIBUTION_BECKMANN {
        return beckmann_pdf_visible(alpha, wi, m);
    }
    return ggx_pdf_visible(alpha, wi, m);
}
