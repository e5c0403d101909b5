//! What a scene without Beckmann microfacets or complex-index conductors pays for them:
//! nothing. The BSDF library (through tests/data/bsdf/bsdf_probe.wgsl) specialised as the
//! renderer specialises a pass (crates/gpu/src/specialise.rs) to `scene_has_beckmann` and
//! `scene_has_conductor_fresnel` false keeps none of their code, and with them true keeps it.

mod common;

use common::root;
use passgraph::gpu::specialise::specialise;
use passgraph::graph::shader_source::ShaderSource;

/// The names of the functions left in the probe after specialising to `constants`.
fn functions_left(constants: &[(&str, f64)]) -> Vec<String> {
    let path = root().join("tests/data/bsdf/bsdf_probe.wgsl");
    let source = ShaderSource::load(&path, &root().join("shaders")).expect("includes resolve");
    let module = specialise(
        &source.code,
        Some((naga::ShaderStage::Compute, "main")),
        constants,
    )
    .expect("the probe specialises");
    module
        .functions
        .iter()
        .filter_map(|(_, f)| f.name.clone())
        .collect()
}

/// The functions only Beckmann materials and complex-index conductors use.
const FEATURE_FUNCTIONS: [&str; 5] = [
    "beckmann_d",
    "beckmann_g1",
    "beckmann_sample_visible",
    "erfinv_approx",
    "fresnel_conductor",
];

/// Fails when Beckmann's or the complex Fresnel term's code escapes its override (a call
/// outside the `scene_has_*` guard), or when the guard removes it from scenes that need it.
#[test]
fn beckmann_and_conductor_fresnel_code_is_gone_without_them() {
    let without = functions_left(&[
        ("scene_has_beckmann", 0.0),
        ("scene_has_conductor_fresnel", 0.0),
    ]);
    for f in FEATURE_FUNCTIONS {
        assert!(
            !without.iter().any(|n| n == f),
            "{f} is left in a scene without the feature"
        );
    }
    let with = functions_left(&[
        ("scene_has_beckmann", 1.0),
        ("scene_has_conductor_fresnel", 1.0),
    ]);
    for f in FEATURE_FUNCTIONS {
        assert!(
            with.iter().any(|n| n == f),
            "{f} is missing from a scene with the feature"
        );
    }
    // Each override alone keeps only its own feature.
    let beckmann_only = functions_left(&[
        ("scene_has_beckmann", 1.0),
        ("scene_has_conductor_fresnel", 0.0),
    ]);
    assert!(beckmann_only.iter().any(|n| n == "beckmann_d"));
    assert!(!beckmann_only.iter().any(|n| n == "fresnel_conductor"));
    println!(
        "{} functions without the features, {} with them",
        without.len(),
        with.len()
    );
}
