//! The WGSL the registry decides, generated so that the shaders and the CPU agree on it by
//! construction: `shaders/lib/material_kinds.wgsl` (each model's kind constant) and
//! `shaders/lib/material_models.wgsl` (each model's WGSL included, and `bsdf_eval`, `bsdf_pdf`,
//! `bsdf_sample`, `bsdf_is_delta` dispatching on a material's kind, each model behind
//! `scene_has_kind` so a scene's shaders keep only its models). Both are committed, so the
//! shaders read like any others and the built-in copy carries them; the test below rewrites
//! them when the registry changes, and fails so the change is seen.

use super::model::{Model, Space};
use super::registry::MATERIAL_KIND_BITS;
use std::fmt::Write;

pub const KINDS_FILE: &str = "shaders/lib/material_kinds.wgsl";
pub const MODELS_FILE: &str = "shaders/lib/material_models.wgsl";

const HEADER: &str = "// Generated from the material registry (src/material/registry.rs) by src/material/wgsl.rs:\n\
// do not edit. `cargo test --lib material::wgsl` rewrites it when the registry changes.\n";

/// `material_kinds.wgsl`'s text.
pub fn kinds_wgsl(models: &[Model]) -> String {
    let mut s = String::from(HEADER);
    s.push_str(
        "\n// The record's kind word holds the model in its low MATERIAL_KIND_BITS and above them the\n\
         // back face's material + 1, or 0 where both faces shade alike (src/material/tables.rs).\n",
    );
    writeln!(s, "const MATERIAL_KIND_BITS: u32 = {MATERIAL_KIND_BITS}u;").unwrap();
    s.push_str("\n// Material::kind of each model; bit 1 << kind of scene_material_kinds.\n");
    for m in models {
        writeln!(s, "const {}: u32 = {}u;", m.constant(), m.kind).unwrap();
    }
    s
}

/// The path, relative to `shaders/lib/`, of a model's WGSL.
fn model_include(m: &Model) -> String {
    format!("material/{}.wgsl", m.name)
}

/// `material_models.wgsl`'s text: World models first, then the shading frame built once for
/// the Local ones.
pub fn models_wgsl(models: &[Model]) -> String {
    let world: Vec<&Model> = models.iter().filter(|m| m.space == Space::World).collect();
    let local: Vec<&Model> = models.iter().filter(|m| m.space == Space::Local).collect();
    let test = |m: &Model| {
        let k = m.constant();
        format!("scene_has_kind({k}) && b.kind == {k}")
    };
    let mut s = String::from(HEADER);
    s.push_str(
        "\n// Each model's functions (lib/material/NAME.wgsl: src/material/model.rs lists them) and\n\
         // the dispatch on a material's kind; lib/bsdf.wgsl includes this file and states the\n\
         // conventions.\n\n",
    );
    for m in models {
        writeln!(s, "#include \"{}\"", model_include(m)).unwrap();
    }

    // eval and pdf share their shape.
    for (function, ty, zero) in [
        ("eval", "vec3<f32>", "vec3<f32>(0.0)"),
        ("pdf", "f32", "0.0"),
    ] {
        writeln!(
            s,
            "\nfn bsdf_{function}(b: Bsdf, n: vec3<f32>, outside: bool, wo: vec3<f32>, wi: vec3<f32>) -> {ty} {{"
        )
        .unwrap();
        for m in &world {
            writeln!(
                s,
                "    if {} {{\n        return {}_{function}(b, n, outside, wo, wi);\n    }}",
                test(m),
                m.name
            )
            .unwrap();
        }
        if !local.is_empty() {
            s.push_str("    let frame = bsdf_frame(n);\n");
        }
        for m in &local {
            writeln!(
                s,
                "    if {} {{\n        return {}_{function}(b, outside, wo * frame, wi * frame);\n    }}",
                test(m),
                m.name
            )
            .unwrap();
        }
        writeln!(s, "    return {zero};\n}}").unwrap();
    }

    s.push_str(
        "\n// u picks the direction within a lobe, u_lobe the lobe.\n\
         fn bsdf_sample(b: Bsdf, n: vec3<f32>, outside: bool, wo: vec3<f32>, u: vec2<f32>, u_lobe: f32)\n    -> BsdfSample {\n",
    );
    for m in &world {
        writeln!(
            s,
            "    if {} {{\n        return {}_sample(b, n, outside, wo, u, u_lobe);\n    }}",
            test(m),
            m.name
        )
        .unwrap();
    }
    s.push_str("    var s = BsdfSample(n, vec3<f32>(0.0), 0.0, false, 1.0);\n");
    if !local.is_empty() {
        s.push_str("    let frame = bsdf_frame(n);\n");
        for (i, m) in local.iter().enumerate() {
            let keyword = if i == 0 { "    if" } else { " else if" };
            write!(
                s,
                "{keyword} {} {{\n        s = {}_sample(b, outside, wo * frame, u, u_lobe);\n    }}",
                test(m),
                m.name
            )
            .unwrap();
        }
        s.push_str(" else {\n        return s;\n    }\n    s.wi = frame * s.wi;\n");
    }
    s.push_str("    return s;\n}\n");

    s.push_str(
        "\n// True when every lobe is delta: light sampling cannot contribute, so the shadow ray can\n\
         // be skipped.\nfn bsdf_is_delta(b: Bsdf) -> bool {\n",
    );
    for m in models {
        writeln!(
            s,
            "    if {} {{\n        return {}_is_delta(b);\n    }}",
            test(m),
            m.name
        )
        .unwrap();
    }
    s.push_str("    return false;\n}\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::registry::MODELS;
    use std::path::Path;

    /// Fails when a committed file is not what the registry generates (a model added, renamed
    /// or moved without the shaders knowing); rewrites it, so rerunning the test passes and the
    /// diff shows the change to commit.
    #[test]
    fn the_committed_material_wgsl_is_what_the_registry_generates() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut stale = Vec::new();
        for (file, text) in [
            (KINDS_FILE, kinds_wgsl(&MODELS)),
            (MODELS_FILE, models_wgsl(&MODELS)),
        ] {
            let path = root.join(file);
            if std::fs::read_to_string(&path).ok().as_deref() != Some(text.as_str()) {
                crate::atomic_write::write_text(&path, &text).unwrap();
                stale.push(file);
            }
        }
        assert!(
            stale.is_empty(),
            "rewrote {stale:?} from the registry: review and commit them"
        );
    }

    /// Fails when a registered model has no WGSL where the generated include looks for it, or
    /// its WGSL lacks a function the dispatch calls.
    #[test]
    fn every_model_has_the_wgsl_functions_the_dispatch_calls() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        for m in &MODELS {
            let path = root.join("shaders/lib").join(model_include(m));
            let text = std::fs::read_to_string(&path)
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            for function in ["eval", "pdf", "sample", "is_delta"] {
                let name = format!("fn {}_{function}(", m.name);
                assert!(text.contains(&name), "{} lacks `{name}`", path.display());
            }
        }
    }
}
