//! Checkpoint and resume (`render --checkpoint`, `--resume`; src/render/checkpoint.rs): a render
//! killed at any moment, even by SIGKILL, continues from its last checkpoint to the very bytes
//! of the render that was never stopped; SIGTERM writes a checkpoint first; a checkpoint being
//! written when the process dies leaves the previous one whole. A render in tiles checkpoints
//! and resumes inside any tile, to the bytes of the whole render.

use passgraph::render::partial::Partial;
use std::io::{BufRead, BufReader};
use std::os::unix::process::ExitStatusExt;
use std::path::Path;
use std::process::{Child, Command, Output, Stdio};

const GRAPH: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/graphs/pathtracer-fused.ron");
const FRAMES: &str = "300";

fn passgraph(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_passgraph"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the passgraph binary runs")
}

/// A 32x32 render of the Cornell box with the fused graph: `extra` adds options.
fn render_args<'a>(out: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec![
        "render", "--graph", GRAPH, "--size", "32x32", "--frames", FRAMES, "--out", out,
    ];
    args.extend_from_slice(extra);
    args
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn ok(out: &Output) {
    assert!(
        out.status.success(),
        "{:?}: {}",
        out.status,
        text(&out.stderr)
    );
}

/// Starts a checkpointing render (a checkpoint after every frame) and returns it once it has
/// reported `checkpoints` checkpoints on stderr, with the rest of stderr still to read.
fn start_checkpointing(
    dir: &Path,
    checkpoints: usize,
) -> (Child, BufReader<std::process::ChildStderr>) {
    start_checkpointing_with(dir, checkpoints, &[])
}

/// [`start_checkpointing`] with more options.
fn start_checkpointing_with(
    dir: &Path,
    checkpoints: usize,
    extra: &[&str],
) -> (Child, BufReader<std::process::ChildStderr>) {
    let mut args = vec!["--checkpoint", "c.exr", "--checkpoint-every", "0"];
    args.extend_from_slice(extra);
    let mut child = Command::new(env!("CARGO_BIN_EXE_passgraph"))
        .args(render_args("x.exr", &args))
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the passgraph binary runs");
    let mut stderr = BufReader::new(child.stderr.take().expect("piped stderr"));
    let mut seen = 0;
    let mut line = String::new();
    while seen < checkpoints {
        line.clear();
        let n = stderr.read_line(&mut line).expect("stderr reads");
        assert!(n > 0, "the render ended before {checkpoints} checkpoints");
        if line.starts_with("checkpoint: ") {
            seen += 1;
        }
    }
    (child, stderr)
}

fn signal(child: &Child, name: &str) {
    let status = Command::new("kill")
        .args([&format!("-{name}"), &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(status.success());
}

/// No temporary file of an atomic write is left in `dir`.
fn no_temporaries(dir: &Path) {
    let left: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(".passgraph-"))
        .collect();
    assert!(left.is_empty(), "temporary files left: {left:?}");
}

/// Resumes from c.exr to r.exr and returns r.exr's bytes.
fn resume(dir: &Path) -> Vec<u8> {
    let out = passgraph(
        dir,
        &render_args("r.exr", &["--resume", "c.exr", "--checkpoint", "c.exr"]),
    );
    ok(&out);
    assert!(text(&out.stderr).contains("resumed from c.exr"));
    std::fs::read(dir.join("r.exr")).unwrap()
}

fn unbroken(dir: &Path) -> Vec<u8> {
    ok(&passgraph(dir, &render_args("u.exr", &[])));
    std::fs::read(dir.join("u.exr")).unwrap()
}

#[test]
fn a_render_killed_by_sigkill_at_any_moment_resumes_to_the_bytes_of_the_unbroken_render() {
    let dir = tempfile::tempdir().unwrap();
    let whole = unbroken(dir.path());
    // Kill moments from a fixed sequence: after the 1st, a middle and a late checkpoint (the
    // kill lands while the next frame or checkpoint write runs, wherever that is).
    let mut x = 0x9e37_79b9_u32;
    for _ in 0..3 {
        x = x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        let after = 1 + (x >> 8) as usize % 200;
        let (mut child, _stderr) = start_checkpointing(dir.path(), after);
        child.kill().unwrap(); // SIGKILL: nothing can be cleaned up
        let status = child.wait().unwrap();
        assert_eq!(status.signal(), Some(9), "killed after {after} checkpoints");
        let checkpoint = Partial::read(&dir.path().join("c.exr")).unwrap();
        assert!(checkpoint.samples.len() >= after as u32);
        assert_eq!(
            resume(dir.path()),
            whole,
            "resumed after a SIGKILL following checkpoint {after}"
        );
        std::fs::remove_file(dir.path().join("c.exr")).unwrap();
    }
}

#[test]
fn sigterm_writes_a_checkpoint_then_ends_as_the_signal_and_the_resumed_render_is_the_same() {
    let dir = tempfile::tempdir().unwrap();
    let whole = unbroken(dir.path());
    let (mut child, mut stderr) = start_checkpointing(dir.path(), 5);
    signal(&child, "TERM");
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut stderr, &mut rest).unwrap();
    let status = child.wait().unwrap();
    assert_eq!(status.signal(), Some(15), "{rest}");
    assert!(
        rest.contains("signal 15: the checkpoint is written; continue with --resume c.exr"),
        "{rest}"
    );
    no_temporaries(dir.path());
    assert!(
        !dir.path().join("x.exr").exists(),
        "no image of an unfinished render"
    );
    assert_eq!(resume(dir.path()), whole);
}

#[test]
fn a_second_sigterm_while_a_checkpoint_is_written_leaves_the_previous_checkpoint_whole() {
    let dir = tempfile::tempdir().unwrap();
    let whole = unbroken(dir.path());
    for _ in 0..3 {
        // The first signal asks for a checkpoint; the second, straight after it, ends the
        // process at once, mostly while that checkpoint (or another) is being written.
        let (mut child, _stderr) = start_checkpointing(dir.path(), 3);
        signal(&child, "TERM");
        signal(&child, "TERM");
        let status = child.wait().unwrap();
        assert_eq!(status.signal(), Some(15));
        no_temporaries(dir.path());
        Partial::read(&dir.path().join("c.exr")).expect("the checkpoint on disk is whole");
        assert_eq!(resume(dir.path()), whole);
        std::fs::remove_file(dir.path().join("c.exr")).unwrap();
    }
}

#[test]
fn a_checkpoint_of_another_render_or_past_the_frames_is_refused_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    ok(&passgraph(
        dir.path(),
        &render_args("a.exr", &["--checkpoint", "c.exr"]),
    ));
    // Another seed: the settings differ.
    let out = passgraph(
        dir.path(),
        &render_args("b.exr", &["--resume", "c.exr", "--seed", "7"]),
    );
    assert_eq!(out.status.code(), Some(1));
    let err = text(&out.stderr);
    assert!(
        err.contains("c.exr: the checkpoint is of another render: the settings"),
        "{err}"
    );
    // Fewer frames than the checkpoint holds.
    let out = passgraph(
        dir.path(),
        &[
            "render", "--graph", GRAPH, "--size", "32x32", "--frames", "10", "--resume", "c.exr",
            "--out", "b.exr",
        ],
    );
    assert_eq!(out.status.code(), Some(1));
    let err = text(&out.stderr);
    assert!(err.contains("give --frames 300 or more"), "{err}");
    // A finished checkpoint resumes to the same image without rendering a frame.
    let out = passgraph(dir.path(), &render_args("b.exr", &["--resume", "c.exr"]));
    ok(&out);
    assert!(
        text(&out.stdout).starts_with("0 frames"),
        "{}",
        text(&out.stdout)
    );
    assert_eq!(
        std::fs::read(dir.path().join("a.exr")).unwrap(),
        std::fs::read(dir.path().join("b.exr")).unwrap()
    );
    // So does it in tiles, and the rays this process traced are none, not "not counted".
    let out = passgraph(
        dir.path(),
        &render_args("t.exr", &["--resume", "c.exr", "--tile", "16x16"]),
    );
    ok(&out);
    let stdout = text(&out.stdout);
    assert!(stdout.starts_with("0 frames"), "{stdout}");
    assert!(stdout.contains(" 0.00 Mrays/s"), "{stdout}");
    assert_eq!(
        std::fs::read(dir.path().join("a.exr")).unwrap(),
        std::fs::read(dir.path().join("t.exr")).unwrap()
    );
}

#[test]
fn a_graph_with_history_beyond_its_accumulation_cannot_checkpoint() {
    let dir = tempfile::tempdir().unwrap();
    let graph = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/graphs/pathtracer-reproject.ron"
    );
    let out = passgraph(
        dir.path(),
        &[
            "render",
            "--graph",
            graph,
            "--size",
            "32x32",
            "--frames",
            "4",
            "--checkpoint",
            "c.exr",
        ],
    );
    assert_eq!(out.status.code(), Some(1));
    let err = text(&out.stderr);
    assert!(
        err.contains("keeps state in 'guide_") && err.contains("from frame to frame"),
        "{err}"
    );
    assert!(!dir.path().join("c.exr").exists());
}

#[test]
fn checkpoint_usage_errors_exit_2_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    for (args, expect) in [
        (vec!["render", "--checkpoint-every", "5"], "--checkpoint"),
        (
            vec!["render", "--checkpoint", "c.exr", "--checkpoint-every=-1"],
            "not a number of seconds",
        ),
        (
            vec![
                "render",
                "--checkpoint",
                "c.exr",
                "--checkpoint-every",
                "inf",
            ],
            "not a number of seconds",
        ),
        (vec!["render", "--checkpoint", "c.png"], "name it .exr"),
    ] {
        let out = passgraph(dir.path(), &args);
        assert_eq!(
            out.status.code(),
            Some(2),
            "{args:?}: {}",
            text(&out.stderr)
        );
        assert!(
            text(&out.stderr).contains(expect),
            "{args:?}: {}",
            text(&out.stderr)
        );
    }
}

/// 300 frames of 4 tiles of 16x16: 1,200 steps, a checkpoint after each.
const TILE: &str = "16x16";
const TILED_STEPS: usize = 1200;

#[test]
fn a_tiled_render_killed_by_sigkill_inside_any_tile_resumes_to_the_bytes_of_the_whole_render() {
    let dir = tempfile::tempdir().unwrap();
    let whole = unbroken(dir.path());
    // The end of the first tile (the checkpoint where the second holds nothing yet), then
    // moments from a fixed sequence over all four tiles.
    let mut x = 0x85eb_ca6b_u32;
    let mut moments = vec![300];
    for _ in 0..3 {
        x = x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        moments.push(1 + (x >> 8) as usize % (TILED_STEPS - 1));
    }
    for after in moments {
        let (mut child, _stderr) = start_checkpointing_with(dir.path(), after, &["--tile", TILE]);
        child.kill().unwrap();
        assert_eq!(child.wait().unwrap().signal(), Some(9));
        let checkpoint = Partial::read(&dir.path().join("c.exr")).unwrap();
        if let Some(progress) = checkpoint.progress {
            let steps = progress.done * 300 + progress.next;
            assert!(
                steps >= after as u32 && progress.tile == [16, 16],
                "killed after {after} checkpoints: {progress}"
            );
        }
        // The resume takes the checkpoint's tiles without being told.
        assert_eq!(
            resume(dir.path()),
            whole,
            "resumed after a SIGKILL following checkpoint {after} of the tiled render"
        );
        std::fs::remove_file(dir.path().join("c.exr")).unwrap();
    }
}

#[test]
fn a_partial_file_rendered_in_tiles_is_the_same_file_as_the_whole_renders() {
    let dir = tempfile::tempdir().unwrap();
    ok(&passgraph(
        dir.path(),
        &render_args("w.exr", &["--partial", "w-part.exr"]),
    ));
    ok(&passgraph(
        dir.path(),
        &render_args("t.exr", &["--partial", "t-part.exr", "--tile", "16x8"]),
    ));
    let read = |name: &str| std::fs::read(dir.path().join(name)).unwrap();
    assert_eq!(read("t-part.exr"), read("w-part.exr"));
    assert_eq!(read("t.exr"), read("w.exr"));
}

#[test]
fn a_checkpoint_inside_a_tiled_render_resumes_only_in_its_tiles_and_frames_and_never_merges() {
    let dir = tempfile::tempdir().unwrap();
    let (mut child, _stderr) = start_checkpointing_with(dir.path(), 450, &["--tile", TILE]);
    child.kill().unwrap();
    child.wait().unwrap();
    let checkpoint = Partial::read(&dir.path().join("c.exr")).unwrap();
    assert!(checkpoint.progress.is_some(), "{}", checkpoint.holds());
    let refused = |args: &[&str], code: i32, says: &[&str]| {
        let out = passgraph(dir.path(), args);
        let err = text(&out.stderr);
        assert_eq!(out.status.code(), Some(code), "{args:?}: {err}");
        for s in says {
            assert!(err.contains(s), "{args:?}: '{s}' not in: {err}");
        }
    };
    refused(
        &["merge", "c.exr", "--out", "m.exr"],
        1,
        &[
            "c.exr: a checkpoint of a tiled render stopped inside its range",
            "in 1 of 4 tiles of 16x16",
            "resume it to the end",
        ],
    );
    refused(
        &render_args("r.exr", &["--resume", "c.exr", "--tile", "8x8"]),
        2,
        &[
            "c.exr: the checkpoint is of a render in tiles of 16x16",
            "--tile 16x16",
        ],
    );
    refused(
        &[
            "render", "--graph", GRAPH, "--size", "32x32", "--frames", "400", "--resume", "c.exr",
            "--out", "r.exr",
        ],
        1,
        &[
            "c.exr: the checkpoint's finished tiles hold samples 0..300",
            "give --frames 300",
        ],
    );
    assert!(!dir.path().join("r.exr").exists());
}
