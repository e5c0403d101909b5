//! The Slurm job scripts refuse, before any work, what would make the job write one file over
//! another: a render option that the job sets for each chunk itself (`--out` would have every
//! chunk write its own image of a fraction of the samples over one file), and a merged image
//! named like the merged partial or placed outside the output folder. jobs/test runs the
//! scripts end to end; these need no Slurm.

mod common;

use common::root;
use std::process::{Command, Output};

fn run(script: &str, args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut command = Command::new("bash");
    command.arg(root().join(script)).args(args);
    for (key, value) in env {
        command.env(key, value);
    }
    command.output().unwrap()
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Exit 1, naming the option (without its `=value`) as the job's own.
fn assert_refused_as_the_jobs_own(result: &Output, option: &str) {
    let err = stderr(result);
    let name = option.split('=').next().unwrap();
    assert_eq!(result.status.code(), Some(1), "{option}: {err}");
    assert!(
        err.contains(&format!("render option '{name}' is the job's own")),
        "{option}: {err}"
    );
}

const OWN_OPTIONS: [&str; 9] = [
    "--out",
    "--out=x.exr",
    "--partial",
    "--samples=0..4",
    "--frames",
    "--checkpoint",
    "--checkpoint-every=0",
    "--resume",
    "--resume=c.exr",
];

#[test]
fn a_chunk_refuses_render_options_that_are_the_jobs_own_before_rendering() {
    let out = tempfile::tempdir().unwrap();
    let dir = out.path().to_str().unwrap();
    for option in OWN_OPTIONS {
        // A passgraph that does not exist: the script must stop before it would run it.
        let result = run(
            "jobs/slurm/render.sbatch",
            &[
                "4",
                "64",
                dir,
                "/nonexistent/passgraph",
                "--size",
                "8x8",
                option,
                "x.exr",
            ],
            &[("SLURM_ARRAY_TASK_ID", "1")],
        );
        assert_refused_as_the_jobs_own(&result, option);
        assert!(
            !out.path().join("partials").exists(),
            "{option}: the chunk began before refusing"
        );
    }
}

#[test]
fn submit_refuses_the_jobs_own_options_and_images_named_over_its_other_outputs() {
    let out = tempfile::tempdir().unwrap();
    let dir = out.path().to_str().unwrap();
    let base = ["--samples", "64", "--chunks", "4", "--out", dir];
    // No sbatch on PATH: each refusal must come before the script looks for it.
    let env = [("PATH", "/usr/bin:/bin")];
    for option in OWN_OPTIONS {
        let args: Vec<&str> = base.iter().copied().chain(["--", option, "x"]).collect();
        let result = run("jobs/slurm/submit", &args, &env);
        assert_refused_as_the_jobs_own(&result, option);
    }
    for (image, says) in [
        ("merged.exr", "the merged partial's name"),
        ("partials/0-16.exr", "without a folder"),
        ("../image.exr", "without a folder"),
    ] {
        let args: Vec<&str> = base.iter().copied().chain(["--image", image]).collect();
        let result = run("jobs/slurm/submit", &args, &env);
        let err = stderr(&result);
        assert_eq!(result.status.code(), Some(1), "{image}: {err}");
        assert!(err.contains(says), "{image}: {err}");
    }
    assert!(
        std::fs::read_dir(out.path()).unwrap().next().is_none(),
        "submit wrote into --out before refusing"
    );
}
