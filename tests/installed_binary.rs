//! A passgraph binary copied out of its build tree (to a farm worker, by `cargo install`) still
//! renders its defaults: the graph, passes, shaders and Cornell box built into it
//! (src/builtin.rs).

use std::process::Command;

#[test]
fn a_copied_binary_renders_its_built_in_defaults_from_an_empty_folder() {
    let dir = tempfile::tempdir().unwrap();
    let exe = dir.path().join("passgraph");
    std::fs::copy(env!("CARGO_BIN_EXE_passgraph"), &exe).unwrap();
    let work = dir.path().join("work");
    std::fs::create_dir(&work).unwrap();
    let out = Command::new(&exe)
        .args(["--frames", "2", "--size", "16x16", "--out", "x.png"])
        .current_dir(&work)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(work.join("x.png").is_file());
    // The extracted copy is gone with the process.
    let builtin = std::env::temp_dir().join(format!("passgraph-builtin-{}", std::process::id()));
    assert!(!builtin.exists());
    let left: Vec<_> = std::fs::read_dir(std::env::temp_dir())
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with("passgraph-builtin-"))
        .filter(|n| {
            // Only directories of processes that have ended (other tests may be running).
            let pid = n.trim_start_matches("passgraph-builtin-");
            !std::path::Path::new(&format!("/proc/{pid}")).exists()
        })
        .collect();
    assert!(left.is_empty(), "left behind: {left:?}");
    // The same binary inside its build tree reads the tree's files (no copy is made).
    let out = Command::new(env!("CARGO_BIN_EXE_passgraph"))
        .args([
            "plan",
            &format!("{}/graphs/pathtracer.ron", env!("CARGO_MANIFEST_DIR")),
        ])
        .output()
        .unwrap();
    assert!(out.status.success());
}
