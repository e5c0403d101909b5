//! `render --camera-path P --segment K`: one segment of a camera path rendered alone, the unit a
//! job system distributes (docs/distributed.md), is bitwise the image the whole path renders
//! for it: its samples (also where the sample index runs on over restarts) and its camera.
//! Run on the GPU (lavapipe in CI).

use std::path::Path;
use std::process::{Command, Output};

const PATH: &str = "CameraPath([\n    (frames: 3),\n    (frames: 4, eye: (290, 273, -800)),\n])\n";

fn passgraph(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_passgraph"))
        .current_dir(dir)
        .args(["--size", "16x16"])
        .args(args)
        .output()
        .unwrap()
}

fn render(dir: &Path, args: &[&str], out: &str) -> Vec<u8> {
    let o = passgraph(dir, &[args, &["--out", out]].concat());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    std::fs::read(dir.join(out)).unwrap()
}

#[test]
fn a_camera_path_reports_the_frames_of_every_segment() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("path.ron"), PATH).unwrap();
    let o = passgraph(d, &["--camera-path", "path.ron", "--out", "p.exr"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    // 3 + 4 frames, not the last segment's 4.
    assert!(stdout.starts_with("7 frames in "), "{stdout}");
    let o = passgraph(
        d,
        &[
            "--camera-path",
            "path.ron",
            "--segment",
            "2",
            "--out",
            "p.exr",
        ],
    );
    assert!(String::from_utf8_lossy(&o.stdout).starts_with("4 frames in "));
}

#[test]
fn a_segment_alone_is_bitwise_the_whole_paths_image_of_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("path.ron"), PATH).unwrap();
    let path = ["--camera-path", "path.ron"];
    // The path's image is its last segment's accumulation.
    let whole = render(d, &path, "whole.exr");
    let last = render(d, &[&path[..], &["--segment", "2"]].concat(), "last.exr");
    assert!(whole == last, "segment 2 alone differs from the whole path");
    // The first segment is the scene's camera: --frames 3.
    let first = render(d, &[&path[..], &["--segment", "1"]].concat(), "first.exr");
    assert!(first == render(d, &["--frames", "3"], "three.exr"));
    // Passes whose sample index runs on over restarts draw segment 2's samples from frame 3:
    // alone it must skip the frames before it, or it would draw segment 1's.
    let run_on: Vec<String> = ["intersect", "ambient", "direct", "indirect"]
        .iter()
        .flat_map(|p| {
            [
                "--set".to_string(),
                format!("{p}.sample_index_restarts=false"),
            ]
        })
        .collect();
    let run_on: Vec<&str> = run_on.iter().map(String::as_str).collect();
    let whole = render(d, &[&path[..], &run_on].concat(), "whole_on.exr");
    let last_on = render(
        d,
        &[&path[..], &run_on, &["--segment", "2"]].concat(),
        "last_on.exr",
    );
    assert!(
        whole == last_on,
        "run-on sample index: segment 2 alone differs"
    );
    assert!(
        last_on != last,
        "the run-on graph should draw other samples"
    );
}

#[test]
fn segments_that_cannot_stand_alone_are_refused_naming_the_path() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("path.ron"), PATH).unwrap();
    std::fs::write(
        d.join("same.ron"),
        "CameraPath([\n    (frames: 3),\n    (frames: 4),\n])\n",
    )
    .unwrap();
    let cases = [
        (
            vec!["--camera-path", "path.ron", "--segment", "3"],
            1,
            "path.ron: --segment 3: the path has 2 segments",
        ),
        (
            vec!["--camera-path", "same.ron", "--segment", "2"],
            1,
            "continues that accumulation",
        ),
        (vec!["--segment", "1"], 2, "--camera-path"),
        (
            vec!["--camera-path", "path.ron", "--segment", "0"],
            2,
            "'0'",
        ),
    ];
    for (args, code, message) in cases {
        let o = passgraph(d, &[&args[..], &["--out", "x.png"]].concat());
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(code), "{args:?}: {err}");
        assert!(err.contains(message), "{args:?}: {err}");
        assert!(!d.join("x.png").exists(), "{args:?} wrote an image");
    }
}
