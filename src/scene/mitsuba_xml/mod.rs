//! Mitsuba 3 XML scenes (`passgraph render --scene scene.xml`), for the subset of Mitsuba that
//! passgraph's models cover (README.md lists it). Anything outside it is an error naming the
//! file, line, plugin and parameter, and what is supported: nothing is silently dropped.
//!
//! - parse.rs: the document as a plugin tree (defaults, `$name`, include, path, id/ref);
//! - params.rs: typed parameters, and the error for any left unread;
//! - transform.rs, spectrum.rs (+ cie.rs): values as Mitsuba computes them;
//! - shapes.rs, serialized.rs: geometry; bsdf.rs, textures.rs: materials;
//! - emitters.rs, sensor.rs: lights, environment, camera, film;
//! - builder.rs: what the readers add to (triangles, materials, textures, lights);
//! - build.rs: the walk over the tree, and passgraph's [`Scene`] of it.

mod bsdf;
mod build;
mod builder;
mod cie;
mod emitters;
mod params;
mod parse;
mod sensor;
mod serialized;
pub mod shapes;
pub mod spectrum;
mod textures;
pub mod transform;

use crate::scene::description::SceneOptions;
use crate::scene::error::SceneError;
pub use build::Built;
use std::path::Path;

/// Loads a Mitsuba 3 (or 2) XML scene: the scene, its film's size and its sampler's sample
/// count (the defaults of `--size` and `--frames`).
pub fn load_mitsuba_xml(path: &Path, options: &SceneOptions) -> Result<Built, SceneError> {
    let parsed = parse::parse_scene(
        path,
        &parse::ParseOptions {
            defines: options.defines.clone(),
        },
    )?;
    build::build(parsed, path, options)
}

/// A Mitsuba scene's film size and sample count alone (the sensor is read, the shapes are
/// not): what `render` takes for `--size` and `--frames` when they are not given.
pub fn film_defaults(
    path: &Path,
    defines: &[(String, String)],
) -> Result<([u32; 2], u32), SceneError> {
    let parsed = parse::parse_scene(
        path,
        &parse::ParseOptions {
            defines: defines.to_vec(),
        },
    )?;
    let sensors = parsed.root.children_of("sensor");
    match sensors.first() {
        Some(c) => {
            let s = sensor::sensor(&c.plugin)?;
            Ok((s.size, s.sample_count))
        }
        None => Err(SceneError::Mitsuba {
            at: parsed.root.at.location(),
            plugin: "scene".into(),
            message: "the scene has no <sensor> (passgraph needs its camera and film)".into(),
        }),
    }
}
