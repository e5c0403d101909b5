//! `passgraph bench` end to end on a tiny image: CSV per variant, chart and report.

mod common;

use common::root;
use passgraph::bench::metrics::downsample_2x;
use passgraph::render::image::RgbImage;
use std::path::Path;
use std::process::Command;

#[test]
fn bench_writes_csv_chart_and_report_for_each_variant() {
    let root = root();
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
    // The adapter with its driver and version, in the report and on stderr.
    let ctx = passgraph::gpu::GpuContext::new(None).unwrap();
    let adapter = passgraph::gpu::context::describe(ctx.adapter_info());
    assert!(
        report.starts_with(&format!("Adapter: {adapter}\n")),
        "{report}"
    );
    let stderr = String::from_utf8_lossy(&status.stderr);
    assert!(
        stderr.contains(&format!("adapter: {adapter}\n")),
        "{stderr}"
    );
    let chart = image::open(out.join("error-vs-time.png")).unwrap();
    assert_eq!((chart.width(), chart.height()), (900, 600));
}

#[test]
fn bench_takes_per_variant_params_labelled_mitsuba_curves_and_combines_rounds() {
    let root = root();
    let dir = tempfile::tempdir().unwrap();
    let reference =
        RgbImage::read_exr(&root.join("tests/data/references/cornell-128-depth3.exr")).unwrap();
    let reference_path = dir.path().join("ref32.exr");
    downsample_2x(&downsample_2x(&reference))
        .write(&reference_path)
        .unwrap();
    let csv = |name: &str, text: &str| {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        path
    };
    // Two rounds of two samplers; "best" only reached 16 spp in one of them.
    let independent1 = csv(
        "i1.csv",
        "spp,seconds,rmse,relmse\n1,0.01,0.3,0.2\n4,0.04,0.15,0.05\n",
    );
    let independent2 = csv(
        "i2.csv",
        "spp,seconds,rmse,relmse\n1,0.03,0.3,0.2\n4,0.06,0.15,0.05\n",
    );
    let best1 = csv(
        "b1.csv",
        "spp,seconds,rmse,relmse\n4,0.04,0.1,0.01\n16,0.2,0.05,0.002\n",
    );
    let best2 = csv("b2.csv", "spp,seconds,rmse,relmse\n4,0.02,0.1,0.01\n");
    let graph = root.join("graphs/pathtracer.ron");
    // The same graph three times: as it is, with a param of its own (labelled by it), and with
    // the seed's PCG sampler in every pass under a label of its own.
    let with_set = format!("{}:intersect.sample_index_restarts=true", graph.display());
    let pcg = format!(
        "pcg={}:intersect.sampler_kind=0,ambient.sampler_kind=0,direct.sampler_kind=0,indirect.sampler_kind=0",
        graph.display()
    );
    let bench = |out: &Path, extra: &[&std::ffi::OsStr]| {
        let output = Command::new(env!("CARGO_BIN_EXE_passgraph"))
            .arg("bench")
            .args(extra)
            .arg("--out")
            .arg(out)
            .output()
            .unwrap();
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
        std::fs::read_to_string(out.join("report.md")).unwrap()
    };
    let mut rounds = Vec::new();
    for round in 0..2 {
        let out = dir.path().join(format!("round{round}"));
        let report = bench(
            &out,
            &[
                "--size".as_ref(),
                "32x32".as_ref(),
                "--frames".as_ref(),
                "4".as_ref(),
                "--reference".as_ref(),
                reference_path.as_os_str(),
                "--graph".as_ref(),
                graph.as_os_str(),
                "--graph".as_ref(),
                with_set.as_ref(),
                "--graph".as_ref(),
                pcg.as_ref(),
            ],
        );
        assert!(report.contains("| pathtracer | 4 |"), "{report}");
        assert!(
            report.contains("| pathtracer:intersect.sample_index_restarts=true | 4 |"),
            "{report}"
        );
        assert!(out.join("runs.ron").exists());
        rounds.push(out);
    }
    let mut args: Vec<std::ffi::OsString> = Vec::new();
    for r in &rounds {
        args.extend(["--combine".into(), r.clone().into_os_string()]);
    }
    for (label, path) in [
        ("independent", &independent1),
        ("best", &best1),
        ("independent", &independent2),
        ("best", &best2),
    ] {
        args.push("--mitsuba".into());
        args.push(format!("Mitsuba {label}={}", path.display()).into());
    }
    let out = dir.path().join("combined");
    let args: Vec<&std::ffi::OsStr> = args.iter().map(|a| a.as_os_str()).collect();
    let report = bench(&out, &args);
    // Both variants, each with the frames every round reached.
    assert!(report.contains("| pathtracer | 4 |"), "{report}");
    assert!(
        report.contains("| pathtracer:intersect.sample_index_restarts=true | 4 |"),
        "{report}"
    );
    // Each Mitsuba curve is a row of its own, with the median time of its rounds at its last
    // sample count: 16 spp for "best", where the round that stopped at 4 spp (0.02 s) counts
    // as 0.08 s, extrapolated (median of 0.2 and 0.08).
    assert!(
        report.contains("| Mitsuba independent | – | 0.05 |"),
        "{report}"
    );
    assert!(report.contains("| Mitsuba best | – | 0.14 |"), "{report}");
    // The race: passgraph's best variant against Mitsuba's best curve at each time, then
    // every variant against Mitsuba's best.
    let race = report
        .find("The race at equal time: the lowest relMSE of passgraph's variants")
        .expect(&report);
    let ratios = report
        .find("relMSE(variant) / the lowest relMSE of Mitsuba's curves at equal time")
        .expect(&report);
    assert!(race < ratios);
    for row in [
        "| passgraph, best |",
        "| Mitsuba, best |",
        "| ratio (below 1: passgraph ahead) |",
    ] {
        assert!(report[race..ratios].contains(row), "{report}");
    }
    assert!(
        report[ratios..].contains("| pcg |"),
        "every variant has a ratio row: {report}"
    );
    assert!(
        out.join("pathtracer:intersect.sample_index_restarts=true.csv")
            .exists()
    );
    // The labelled variant ran with its own params: the PCG sampler's image is not Sobol's.
    assert!(report.contains("| pcg | 4 |"), "{report}");
    let last_relmse = |name: &str| {
        let csv = std::fs::read_to_string(out.join(name)).unwrap();
        let last = csv.lines().last().unwrap().to_string();
        last.split(',').nth(3).unwrap().parse::<f64>().unwrap()
    };
    assert_ne!(last_relmse("pcg.csv"), last_relmse("pathtracer.csv"));
    let chart = image::open(out.join("error-vs-time.png")).unwrap();
    assert_eq!((chart.width(), chart.height()), (900, 600));
}

#[test]
fn bench_refuses_a_reference_of_another_size() {
    let root = root();
    let out = Command::new(env!("CARGO_BIN_EXE_passgraph"))
        .args(["bench", "--size", "64x64", "--frames", "1", "--reference"])
        .arg(root.join("tests/data/references/cornell-128-depth3.exr"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("128x128 but --size is 64x64"), "{stderr}");
}
