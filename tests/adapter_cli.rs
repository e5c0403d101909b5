//! The adapter as the binary reports and picks it: named with its driver and the driver's
//! version, matched by what the list prints, never wgpu's GL backend; a machine without a
//! Vulkan driver is told what to install.

mod common;

use common::root;
use passgraph::gpu::GpuContext;
use passgraph::gpu::context::describe;
use std::process::{Command, Output};

/// `passgraph render` of one 8x8 frame into a temporary folder, with `env` set.
fn render(extra: &[&str], env: &[(&str, &str)]) -> (Output, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let mut command = Command::new(env!("CARGO_BIN_EXE_passgraph"));
    command
        .current_dir(root())
        .args(["render", "--size", "8x8", "--frames", "1", "--out"])
        .arg(dir.path().join("out.png"))
        .args(extra)
        .env_remove("PASSGRAPH_ADAPTER")
        .env_remove("WGPU_BACKEND");
    for (key, value) in env {
        command.env(key, value);
    }
    (command.output().unwrap(), dir)
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn render_prints_the_adapter_with_its_driver_and_version() {
    let ctx = GpuContext::new(None).unwrap();
    let info = ctx.adapter_info();
    // lavapipe names its driver and Mesa's version (e.g. "llvmpipe, Mesa 25.0.7 (LLVM 19.1.7)").
    assert!(!info.driver_info.is_empty(), "{info:?}");
    let (out, _dir) = render(&[], &[]);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    let line = format!("adapter: {}\n", describe(info));
    assert!(err.contains(&line), "expected {line:?} in:\n{err}");
    assert!(line.contains(&info.driver_info), "{line}");
}

#[test]
fn without_a_vulkan_driver_the_error_says_what_to_install() {
    // The Vulkan loader reads its driver list from these (old and new names): a missing file
    // leaves it no driver, as on a machine without mesa-vulkan-drivers.
    let none = "/nonexistent/passgraph-test-icd.json";
    let (out, dir) = render(
        &[],
        &[("VK_ICD_FILENAMES", none), ("VK_DRIVER_FILES", none)],
    );
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    for part in [
        "error: no Vulkan adapter found",
        "scripts/setup",
        "apt-get install -t bookworm-backports mesa-vulkan-drivers",
    ] {
        assert!(err.contains(part), "{part:?} missing from:\n{err}");
    }
    assert!(!err.contains("panicked") && !err.contains("GLSL"), "{err}");
    assert!(!dir.path().join("out.png").exists());
}

#[test]
fn the_gl_backend_alone_is_refused_with_the_reason() {
    let (out, _dir) = render(&[], &[("WGPU_BACKEND", "gl")]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("WGPU_BACKEND='gl'") && err.contains("GL backend"),
        "{err}"
    );
}

#[test]
fn adapter_filters_match_the_backend_as_the_list_prints_it() {
    let backend = format!(
        "({:?})",
        GpuContext::new(None).unwrap().adapter_info().backend
    );
    let (out, _dir) = render(&["--adapter", &backend.to_uppercase()], &[]);
    assert!(out.status.success(), "{}", stderr(&out));

    let (out, _dir) = render(&["--adapter", "(Gl)"], &[]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("'(Gl)'")
            && err.contains(&backend)
            && err.contains("GL adapters are never used"),
        "{err}"
    );
}
