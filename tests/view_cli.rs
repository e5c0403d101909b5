//! `passgraph view` rejects bad input before opening a window: clear messages naming the file
//! and line, exit status 1, no display needed.

use std::process::Command;

fn view(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_passgraph"))
        .arg("view")
        .args(args)
        // No display: the errors must come before any window is asked for.
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn a_bad_script_is_reported_with_its_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let script = dir.path().join("script.txt");
    std::fs::write(&script, "wait 2\nkey shift\nquit\n").unwrap();
    let (code, stderr) = view(&["--script", script.to_str().unwrap()]);
    assert_eq!(code, 1, "{stderr}");
    assert!(
        stderr.contains(&format!("{}:2: unknown key 'shift'", script.display())),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn a_missing_script_or_graph_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("none.txt");
    let (code, stderr) = view(&["--script", missing.to_str().unwrap()]);
    assert_eq!(code, 1, "{stderr}");
    assert!(
        stderr.contains("none.txt: cannot read the script"),
        "{stderr}"
    );

    let graph = dir.path().join("nope.ron");
    let (code, stderr) = view(&["--graph", graph.to_str().unwrap()]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("nope.ron: cannot read"), "{stderr}");
}
