//! What a render's samples depend on, hashed, so that `merge` can refuse partial files of
//! different renders (docs/distributed.md).
//!
//! Three parts, kept apart so that an error can say which differs:
//! - **graph**: the contents of every file the graph is built from (graph files, pass files,
//!   shaders and their includes, in path order), then every pass instance's name, pass and
//!   params after `--set` (so `--set intersect.sampler_kind=0` changes it);
//! - **scene**: the contents of the scene file and its mesh, then everything the session
//!   uploads from them (triangles, materials and their tables, textures, lights, BVH, camera)
//!   and the scene constants (light count, `max_depth` after `--max-depth`, ...), not the
//!   frame uniform (size and seed are settings);
//! - **settings**: size, seed and `max_depth`, as text.
//!
//! File paths are not hashed, only contents: a farm's workers may check the project out in
//! different directories. The hash is 128-bit FNV-1a: stable across Rust versions and
//! machines (std's hasher is not), and ample against accidents (it is no defence against a
//! forged file, which no merge needs).

use super::provided::{CAMERA_PREVIOUS, FRAME, ProvidedInputs, provided_data};
use super::session::{RenderSettings, Session};
use crate::graph::load::load_graph;
use crate::graph::set_param::set_param;
use std::fmt;
use std::path::Path;

/// A render's fingerprint (see the module documentation).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Fingerprint {
    pub graph: u128,
    pub scene: u128,
    /// `size WxH, seed K, max_depth D`.
    pub settings: String,
}

impl Fingerprint {
    /// The fingerprint of `session`, rendering what `settings` describe.
    pub fn of(settings: &RenderSettings, session: &Session) -> Result<Fingerprint, String> {
        Ok(Fingerprint {
            graph: graph_hash(settings)?,
            scene: scene_hash(session)?,
            settings: format!(
                "size {}x{}, seed {}, max_depth {}",
                settings.size[0],
                settings.size[1],
                session.seed(),
                session.scene_description().max_depth
            ),
        })
    }

    /// The three parts in one hash, as 32 hex digits.
    pub fn combined(&self) -> String {
        let mut h = Fnv128::new();
        h.write(&self.graph.to_le_bytes());
        h.write(&self.scene.to_le_bytes());
        h.write_str(&self.settings);
        format!("{:032x}", h.finish())
    }

    /// What differs from `other`, one phrase per part: for an error message.
    pub fn differences(&self, other: &Fingerprint) -> Vec<String> {
        let mut out = Vec::new();
        if self.graph != other.graph {
            out.push("the graph (its files' contents or params after --set)".to_string());
        }
        if self.scene != other.scene {
            out.push("the scene (its files' contents or --max-depth)".to_string());
        }
        if self.settings != other.settings {
            out.push(format!(
                "the settings ({} against {})",
                self.settings, other.settings
            ));
        }
        out
    }
}

impl fmt::Display for Fingerprint {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "{} ({})", self.combined(), self.settings)
    }
}

/// Hashes what the graph's samples depend on; loads the graph again so that the result does
/// not depend on which outputs the session keeps (a kept texture changes the plan, not the
/// samples).
fn graph_hash(settings: &RenderSettings) -> Result<u128, String> {
    let mut graph = load_graph(&settings.graph).map_err(|e| e.to_string())?;
    for s in &settings.set {
        set_param(&mut graph, s, crate::render::provided::path_tracer())
            .map_err(|e| e.to_string())?;
    }
    let mut h = Fnv128::new();
    for file in super::session::graph_files(&graph) {
        h.write_file(&file)?;
    }
    for pass in &graph.decl.passes {
        // Debug of a BTreeMap is in key order, and of a float the shortest exact digits.
        h.write_str(&format!("{} {} {:?}", pass.name, pass.pass, pass.params));
    }
    Ok(h.finish())
}

fn scene_hash(session: &Session) -> Result<u128, String> {
    let scene = session.scene_description();
    let mut h = Fnv128::new();
    h.write_file(&scene.path)?;
    h.write_file(&scene.mesh.path)?;
    let data = provided_data(&ProvidedInputs {
        scene,
        gpu: session.scene(),
        tile: session.tile(),
        seed: session.seed(),
    });
    for (name, bytes) in &data.buffers {
        // The frame uniform holds size and seed, which `settings` has: hashed here, a seed
        // change would also be reported as a different scene.
        if [FRAME, CAMERA_PREVIOUS].contains(&name.as_str()) {
            continue;
        }
        h.write_str(name);
        h.write(bytes);
    }
    for (name, value) in &data.overrides {
        h.write_str(name);
        h.write(&value.to_bits().to_le_bytes());
    }
    Ok(h.finish())
}

/// 128-bit FNV-1a; every item is length-prefixed so that two items never read as one.
struct Fnv128(u128);

impl Fnv128 {
    const OFFSET: u128 = 0x6c62272e07bb014262b821756295c58d;
    const PRIME: u128 = 0x0000000001000000000000000000013b;

    fn new() -> Fnv128 {
        Fnv128(Self::OFFSET)
    }

    fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u128::from(b)).wrapping_mul(Self::PRIME);
        }
    }

    fn write(&mut self, bytes: &[u8]) {
        self.bytes(&(bytes.len() as u64).to_le_bytes());
        self.bytes(bytes);
    }

    fn write_str(&mut self, s: &str) {
        self.write(s.as_bytes());
    }

    fn write_file(&mut self, path: &Path) -> Result<(), String> {
        let bytes =
            std::fs::read(path).map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
        self.write(&bytes);
        Ok(())
    }

    fn finish(&self) -> u128 {
        self.0
    }
}

/// Parses the 32 hex digits [`Fingerprint`] parts are stored as.
pub fn parse_hash(text: &str) -> Option<u128> {
    if text.len() != 32 {
        return None;
    }
    u128::from_str_radix(text, 16).ok()
}

/// A hash as 32 hex digits.
pub fn hash_text(hash: u128) -> String {
    format!("{hash:032x}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv128_matches_the_published_empty_and_a_values() {
        // FNV-1a 128 of "" is the offset basis, of "a" the published d228cb69...
        let mut h = Fnv128::new();
        h.bytes(b"");
        assert_eq!(h.finish(), Fnv128::OFFSET);
        h.bytes(b"a");
        assert_eq!(hash_text(h.finish()), "d228cb696f1a8caf78912b704e4a8964");
    }

    #[test]
    fn length_prefixes_keep_items_apart() {
        let mut a = Fnv128::new();
        a.write_str("ab");
        a.write_str("c");
        let mut b = Fnv128::new();
        b.write_str("a");
        b.write_str("bc");
        assert_ne!(a.finish(), b.finish());
    }

    #[test]
    fn parse_hash_takes_back_hash_text() {
        let h = 0x0123456789abcdef_fedcba9876543210u128;
        assert_eq!(parse_hash(&hash_text(h)), Some(h));
        assert_eq!(parse_hash("xyz"), None);
    }
}
