//! The built-in defaults: `graphs/` with the passes and shaders they use, and the Cornell box
//! (`scenes/cornell/`), compiled into the binary, so that a passgraph copied to a farm worker
//! or installed with `cargo install` renders its default scene from any folder. A binary that
//! runs inside the tree it was built from reads the tree's files instead, so that edits to them
//! take effect (and the viewer's reload sees them).

use include_dir::{Dir, include_dir};
use std::path::{Path, PathBuf};

static GRAPHS: Dir = include_dir!("$CARGO_MANIFEST_DIR/graphs");
static PASSES: Dir = include_dir!("$CARGO_MANIFEST_DIR/passes");
static SHADERS: Dir = include_dir!("$CARGO_MANIFEST_DIR/shaders");
static CORNELL: Dir = include_dir!("$CARGO_MANIFEST_DIR/scenes/cornell");

/// The default graph and scene, relative to the project's root (or to the extracted copy).
pub const GRAPH: &str = "graphs/pathtracer.ron";
pub const SCENE: &str = "scenes/cornell/scene.ron";
/// The tree this binary was built from.
pub const BUILD_TREE: &str = env!("CARGO_MANIFEST_DIR");

/// The default graph and scene in the build tree (the command line's defaults).
pub fn build_tree_graph() -> PathBuf {
    Path::new(BUILD_TREE).join(GRAPH)
}

pub fn build_tree_scene() -> PathBuf {
    Path::new(BUILD_TREE).join(SCENE)
}

/// Whether the running binary lies inside the tree it was built from (`cargo run`,
/// `target/release/passgraph`) and that tree still holds the defaults.
pub fn in_build_tree() -> bool {
    let tree = match std::fs::canonicalize(BUILD_TREE) {
        Ok(t) => t,
        Err(_) => return false,
    };
    let exe = std::env::current_exe().and_then(std::fs::canonicalize);
    exe.is_ok_and(|e| e.starts_with(&tree)) && build_tree_graph().is_file()
}

/// Writes the built-in files under `dir`: `graphs/`, `passes/`, `shaders/`, `scenes/cornell/`.
pub fn extract(dir: &Path) -> std::io::Result<()> {
    for (sub, files) in [
        ("graphs", &GRAPHS),
        ("passes", &PASSES),
        ("shaders", &SHADERS),
        ("scenes/cornell", &CORNELL),
    ] {
        let to = dir.join(sub);
        std::fs::create_dir_all(&to)?;
        files.extract(&to)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_extracted_defaults_are_the_trees_files_and_compile() {
        let dir = tempfile::tempdir().unwrap();
        extract(dir.path()).unwrap();
        for rel in [
            GRAPH,
            SCENE,
            "scenes/cornell/cornell.obj",
            "shaders/lib/bvh.wgsl",
        ] {
            assert_eq!(
                std::fs::read(dir.path().join(rel)).unwrap(),
                std::fs::read(Path::new(BUILD_TREE).join(rel)).unwrap(),
                "{rel}"
            );
        }
        crate::compile_file(&dir.path().join(GRAPH), [32, 32]).unwrap();
        crate::scene::load_scene(&dir.path().join(SCENE)).unwrap();
    }
}
