//! Test support, one module for every test: the repository's root, a scratch copy of the
//! fixtures that a test may edit without touching others, sessions and images (`render`),
//! statistics over seeds (`stats`), meshes and scene files (`geometry`), glTF files (`gltf`),
//! Mitsuba's render test
//! against the conformance references (`conformance`), and
//! `shaders/lib/bvh.wgsl` run on the GPU (`bvh_gpu`). Each test uses part of it.
#![allow(dead_code, clippy::result_large_err)]

pub mod bvh_gpu;
pub mod conformance;
pub mod geometry;
pub mod gltf;
pub mod reference;
pub mod render;
pub mod stats;

use passgraph::{GraphError, Plan, compile_file};
use std::path::{Path, PathBuf};

pub const SIZE: [u32; 2] = [256, 256];

/// The repository (paths in tests are relative to it).
pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

pub fn fixtures() -> PathBuf {
    root().join("tests/fixtures")
}

/// Compiles a fixture graph in place (for graphs tests do not edit).
pub fn compile_fixture(graph: &str) -> Plan {
    let path = fixtures().join("graphs").join(graph);
    compile_file(&path, SIZE).unwrap_or_else(|e| panic!("{graph} should compile: {e}"))
}

pub struct Scratch {
    dir: tempfile::TempDir,
}

/// Copies a directory tree.
pub fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let target = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_dir(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), &target).unwrap();
        }
    }
}

impl Scratch {
    /// A private copy of `tests/fixtures`.
    pub fn new() -> Scratch {
        let dir = tempfile::tempdir().unwrap();
        copy_dir(&fixtures(), dir.path());
        Scratch { dir }
    }

    pub fn path(&self, rel: &str) -> PathBuf {
        self.dir.path().join(rel)
    }

    /// Replaces the one occurrence of `from` in `rel`; panics if it is absent or repeated, so an
    /// edit that stops matching the fixture cannot make its test pass vacuously.
    pub fn edit(&self, rel: &str, from: &str, to: &str) -> &Scratch {
        let path = self.path(rel);
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(
            text.matches(from).count(),
            1,
            "{rel} should contain {from:?} exactly once"
        );
        std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
        self
    }

    pub fn write(&self, rel: &str, text: &str) -> &Scratch {
        let path = self.path(rel);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, text).unwrap();
        self
    }

    pub fn compile(&self, graph: &str) -> Result<Plan, GraphError> {
        compile_file(&self.path(graph), SIZE)
    }

    /// Compiles a graph that must fail and returns the error and its message.
    pub fn error(&self, graph: &str) -> (GraphError, String) {
        match self.compile(graph) {
            Ok(_) => panic!("{graph} should not compile"),
            Err(e) => {
                let message = e.to_string();
                (e, message)
            }
        }
    }
}

/// A graph file that declares `inputs` is a subgraph (graphs/denoiser.ron): it runs only
/// where a graph includes it.
pub fn is_subgraph(path: &Path) -> bool {
    std::fs::read_to_string(path).is_ok_and(|t| t.contains("inputs: ["))
}

/// Asserts that `message` contains every one of `parts`.
pub fn assert_mentions(message: &str, parts: &[&str]) {
    for part in parts {
        assert!(
            message.contains(part),
            "message should mention {part:?}:\n{message}"
        );
    }
}
