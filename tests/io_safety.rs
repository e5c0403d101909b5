//! What the command line does with its own inputs and outputs: no output may replace an input
//! (by inode: another spelling or a hard link is the same file), and standard output that is
//! a closed pipe or a full disk ends the command cleanly instead of a panic.

use std::path::Path;
use std::process::{Command, Output, Stdio};

const GRAPH: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/graphs/pathtracer.ron");

fn passgraph(dir: &Path, args: &[&str], stdout: Stdio) -> Output {
    Command::new(env!("CARGO_BIN_EXE_passgraph"))
        .args(args)
        .current_dir(dir)
        .stdout(stdout)
        .stderr(Stdio::piped())
        .output()
        .expect("the passgraph binary runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn merge_refuses_an_output_that_is_one_of_its_partials_however_it_is_named() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("a.exr"), b"partial a").unwrap();
    std::fs::write(dir.path().join("b.exr"), b"partial b").unwrap();
    std::fs::hard_link(dir.path().join("a.exr"), dir.path().join("link.exr")).unwrap();
    for args in [
        vec!["merge", "a.exr", "b.exr", "--out", "a.exr"],
        vec!["merge", "a.exr", "b.exr", "--out", "./b.exr"],
        vec!["merge", "a.exr", "b.exr", "--partial", "link.exr"],
    ] {
        let out = passgraph(dir.path(), &args, Stdio::piped());
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = text(&out.stderr);
        assert!(
            err.contains("is also the partial") && err.contains("would destroy that input"),
            "{args:?}: {err}"
        );
    }
    assert_eq!(
        std::fs::read(dir.path().join("a.exr")).unwrap(),
        b"partial a"
    );
    assert_eq!(
        std::fs::read(dir.path().join("b.exr")).unwrap(),
        b"partial b"
    );
}

#[test]
fn render_refuses_to_overwrite_its_reference_or_the_checkpoint_it_resumes_other_than_as_checkpoint()
{
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("r.exr"), b"reference").unwrap();
    for (args, expect) in [
        (
            vec!["render", "--reference", "r.exr", "--out", "./r.exr"],
            "is also the --reference r.exr",
        ),
        (
            vec!["render", "--reference", "r.exr", "--checkpoint", "r.exr"],
            "is also the --reference r.exr",
        ),
        (
            vec!["render", "--resume", "r.exr", "--partial", "r.exr"],
            "is also the --resume checkpoint r.exr",
        ),
    ] {
        let out = passgraph(dir.path(), &args, Stdio::piped());
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = text(&out.stderr);
        assert!(err.contains(expect), "{args:?}: {err}");
    }
    assert_eq!(
        std::fs::read(dir.path().join("r.exr")).unwrap(),
        b"reference"
    );
}

/// The commands whose work is to print.
fn printing_commands() -> [Vec<&'static str>; 4] {
    [
        vec!["plan", GRAPH],
        vec!["plan", GRAPH, "--chart"],
        vec!["dot", GRAPH],
        vec!["check", GRAPH],
    ]
}

#[test]
fn plan_dot_and_check_end_quietly_on_a_closed_pipe() {
    let dir = tempfile::tempdir().unwrap();
    for args in printing_commands() {
        // A pipe whose reading end is closed before the command writes: as `| head -0`.
        let (reader, writer) = std::io::pipe().unwrap();
        drop(reader);
        let out = passgraph(dir.path(), &args, writer.into());
        let err = text(&out.stderr);
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert_eq!(out.status.code(), Some(0), "{args:?}: {err}");
    }
}

#[test]
fn plan_dot_and_check_report_a_full_disk_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    for args in printing_commands() {
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let out = passgraph(dir.path(), &args, full.into());
        let err = text(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert_eq!(
            err.trim(),
            "error: cannot write to standard output: No space left on device (os error 28)",
            "{args:?}"
        );
    }
}

#[test]
fn a_killed_processs_runtime_directory_is_removed_at_the_next_start() {
    // A process that has ended: its pid names no running process (unless reused at once, when
    // the directory is rightly kept).
    let mut gone = Command::new("true").spawn().unwrap();
    let pid = gone.id();
    gone.wait().unwrap();
    let stale = std::env::temp_dir().join(format!("passgraph-runtime-{pid}"));
    std::fs::create_dir_all(&stale).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_passgraph"))
        .args(["check", GRAPH])
        .current_dir(dir.path())
        .env_remove("XDG_RUNTIME_DIR")
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(!stale.exists(), "{} is left", stale.display());
}
