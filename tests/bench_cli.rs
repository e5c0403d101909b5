//! `passgraph bench` end to end on a tiny image: CSV per variant, chart and report.

use passgraph::bench::metrics::downsample_2x;
use passgraph::render::image::RgbImage;
use std::path::Path;
use std::process::Command;

#[test]
fn bench_writes_csv_chart_and_report_for_each_variant() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = tempfile::tempdir().unwrap();
    // A 32x32 reference: the 128x128 Mitsuba render averaged down twice (box filter).
    let reference =
        RgbImage::read_exr(&root.join("tests/data/references/cornell-128-depth3.exr")).unwrap();
    let small = downsample_2x(&downsample_2x(&reference));
    let reference_path = dir.path().join("ref32.exr");
    small.write(&reference_path).unwrap();
    let mitsuba = dir.path().join("mitsuba.csv");
    std::fs::write(
        &mitsuba,
        "spp,seconds,rmse,relmse\n1,0.01,0.3,0.2\n4,0.04,0.15,0.05\n",
    )
    .unwrap();
    let out = dir.path().join("bench");
    let denoised = root.join("graphs/pathtracer-denoise.ron@denoised");
    let status = Command::new(env!("CARGO_BIN_EXE_passgraph"))
        .args(["bench", "--size", "32x32", "--frames", "4", "--reference"])
        .arg(&reference_path)
        .arg("--graph")
        .arg(root.join("graphs/pathtracer.ron"))
        .arg("--graph")
        .arg(&denoised)
        .arg("--mitsuba")
        .arg(&mitsuba)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        status.status.success(),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    let csv = std::fs::read_to_string(out.join("pathtracer.csv")).unwrap();
    let rows: Vec<&str> = csv.lines().collect();
    assert!(rows[0].starts_with("frames,seconds,rmse,relmse,bias,gpu_ms_intersect"));
    let frames: Vec<u32> = rows[1..]
        .iter()
        .map(|r| r.split(',').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(frames, vec![1, 2, 4], "a checkpoint per doubling");
    // The error falls as frames accumulate (1 to 4 frames: relMSE about 4x lower).
    let relmse = |r: &str| r.split(',').nth(3).unwrap().parse::<f64>().unwrap();
    assert!(relmse(rows[3]) < relmse(rows[1]));
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("| pathtracer | 4 |"), "{report}");
    // GRAPH@CHANNEL: the denoiser's output texture is compared, under its own label; at 4
    // frames it is closer to the reference than the raw image (tests/denoise.rs).
    assert!(
        report.contains("| pathtracer-denoise@denoised | 4 |"),
        "{report}"
    );
    let denoised_csv =
        std::fs::read_to_string(out.join("pathtracer-denoise@denoised.csv")).unwrap();
    let last = |csv: &str| relmse(csv.lines().last().unwrap());
    assert!(last(&denoised_csv) < last(&csv), "{denoised_csv}\n{csv}");
    assert!(report.contains("Mitsuba 3"), "{report}");
    let chart = image::open(out.join("error-vs-time.png")).unwrap();
    assert_eq!((chart.width(), chart.height()), (900, 600));
}

#[test]
fn bench_refuses_a_reference_of_another_size() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = Command::new(env!("CARGO_BIN_EXE_passgraph"))
        .args(["bench", "--size", "64x64", "--frames", "1", "--reference"])
        .arg(root.join("tests/data/references/cornell-128-depth3.exr"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("128x128 but --size is 64x64"), "{stderr}");
}
