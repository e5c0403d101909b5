//! Sample ranges, partial files and their merge (src/render/partial.rs, src/render/merge.rs,
//! docs/distributed.md): ranges of a render merge to the unsplit render within the bound
//! merge.rs derives, in a canonical order, and bad inputs are refused naming files and ranges.
//!
//! GPU renders are 32x32 of the Cornell box (one session per sampler, restarted at each range);
//! the error cases use small partials made on the CPU.

mod common;

use common::assert_mentions;
use common::render::{PATHTRACER, settings};
use passgraph::render::accumulate::CompensatedMean;
use passgraph::render::channels::{Channel, ChannelSelection};
use passgraph::render::fingerprint::Fingerprint;
use passgraph::render::merge::merge;
use passgraph::render::partial::{Packing, Partial, Plane, SampleRange, TileProgress};
use passgraph::render::session::{RenderSettings, Session};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

const SCENE: &str = "scenes/cornell/scene.ron";
const SIZE: u32 = 32;

fn range(start: u32, end: u32) -> SampleRange {
    SampleRange { start, end }
}

/// The passes of graphs/pathtracer.ron that draw samples, set to `kind`.
fn sampler_settings(kind: u32) -> RenderSettings {
    let set: Vec<String> = ["intersect", "ambient", "direct", "indirect"]
        .iter()
        .map(|p| format!("{p}.sampler_kind={kind}"))
        .collect();
    let set: Vec<&str> = set.iter().map(String::as_str).collect();
    RenderSettings {
        max_frames: u32::MAX,
        ..settings(PATHTRACER, SCENE, SIZE, 0, &set)
    }
}

/// Renders each range in turn on one session (each restarts the accumulation at its start).
fn render_ranges(s: &RenderSettings, ranges: &[SampleRange]) -> Vec<Partial> {
    let channel = ChannelSelection::Planes(vec![Channel::Sum]);
    let mut session = Session::builder(s)
        .showing(&channel)
        .partial()
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    let fingerprint = Fingerprint::of(s, &session).unwrap();
    ranges
        .iter()
        .map(|&r| {
            let dropped_before = session.dropped().unwrap();
            session.start_at_sample(r.start);
            for _ in 0..r.len() {
                assert!(session.render_frame().unwrap());
            }
            Partial::from_buffers(
                s.size,
                r,
                u64::from(session.dropped().unwrap() - dropped_before),
                fingerprint.clone(),
                String::new(),
                &session.result().unwrap(),
                &session.compensation().unwrap(),
            )
            .unwrap()
        })
        .collect()
}

/// Per sampler (0 independent, 1 Sobol): the render of 0..64, then 0..16, 16..32, 32..48,
/// 48..64.
fn renders(kind: u32) -> &'static [Partial] {
    static RENDERS: [OnceLock<Vec<Partial>>; 2] = [OnceLock::new(), OnceLock::new()];
    RENDERS[kind as usize].get_or_init(|| {
        let ranges = [
            range(0, 64),
            range(0, 16),
            range(16, 32),
            range(32, 48),
            range(48, 64),
        ];
        render_ranges(&sampler_settings(kind), &ranges)
    })
}

fn unnamed(partials: &[Partial]) -> Vec<(PathBuf, Partial)> {
    partials
        .iter()
        .map(|p| (PathBuf::from(format!("part-{}.exr", p.samples)), p.clone()))
        .collect()
}

/// Distance in ulps between two f32 of the same sign (the renderer's channels are >= 0).
fn ulps(a: f32, b: f32) -> u32 {
    assert!(
        a.is_sign_positive() == b.is_sign_positive() || a == b,
        "{a} and {b} differ in sign"
    );
    a.to_bits().abs_diff(b.to_bits())
}

/// The bound src/render/merge.rs derives for a pixel of `n` non-negative samples with mean
/// `mu`: `|M - U| <= (1 + 3 (2 + ln n)) 2^-23 mu` (the two final roundings, and the
/// uncompensated roundings of both sides in the worst case, all in one direction).
fn merge_bound(mu: f32, n: u32) -> f64 {
    (1.0 + 3.0 * (2.0 + f64::from(n.max(1)).ln())) * f64::from(mu.abs()) / f64::from(1u32 << 23)
}

/// Checks `merged` against `whole` within [`merge_bound`] (counts equal exactly) and returns
/// the worst distance in ulps and how many values differ at all.
fn compare(merged: &Partial, whole: &Partial) -> (u32, usize) {
    let (mut worst, mut differ) = (0, 0);
    for (c, (m, w)) in merged.planes.iter().zip(&whole.planes).enumerate() {
        assert_eq!(m.count, w.count, "plane {c}: counts differ");
        for (i, (a, b)) in m.mean.iter().zip(&w.mean).enumerate() {
            for k in 0..3 {
                let d = ulps(a[k], b[k]);
                worst = worst.max(d);
                differ += usize::from(d > 0);
                let bound = merge_bound(a[k].abs().max(b[k].abs()), w.count[i]);
                assert!(
                    f64::from((a[k] - b[k]).abs()) <= bound,
                    "plane {c} pixel {i}.{k}: merged {} against {} ({d} ulps) is beyond the bound {bound:e}",
                    a[k],
                    b[k]
                );
            }
        }
    }
    (worst, differ)
}

fn check_four_ranges_against_the_whole(kind: u32) {
    let all = renders(kind);
    let (whole, ranges) = (&all[0], &all[1..]);
    let merged = merge(unnamed(ranges)).unwrap();
    assert_eq!(merged.samples, range(0, 64));
    assert_eq!(merged.dropped, whole.dropped);
    let (worst, differ) = compare(&merged, whole);
    eprintln!(
        "sampler {kind}: 4 x 16 merged against 64: worst {worst} ulps, {differ} of {} values differ",
        5 * 3 * SIZE * SIZE
    );
    // The ranges are different samples, not copies of one: each alone is far from the whole.
    let alone = (ranges[0].planes[4].mean.iter().flatten())
        .zip(whole.planes[4].mean.iter().flatten())
        .map(|(a, b)| ulps(*a, *b))
        .max()
        .unwrap();
    assert!(
        alone > 1000,
        "samples 0..16 alone are within {alone} ulps of 0..64"
    );
}

#[test]
fn four_ranges_of_16_merge_to_the_sobol_render_of_64_within_the_bound() {
    check_four_ranges_against_the_whole(1);
}

#[test]
fn four_ranges_of_16_merge_to_the_independent_render_of_64_within_the_bound() {
    check_four_ranges_against_the_whole(0);
}

#[test]
fn merge_is_bitwise_identical_whatever_the_order_and_hierarchy() {
    let ranges = &renders(1)[1..];
    let reference = merge(unnamed(ranges))
        .unwrap()
        .encode(Packing::Small)
        .unwrap();
    for order in [[3, 1, 0, 2], [2, 3, 1, 0], [0, 1, 2, 3], [3, 2, 1, 0]] {
        let shuffled: Vec<Partial> = order.iter().map(|&i| ranges[i].clone()).collect();
        let bytes = merge(unnamed(&shuffled))
            .unwrap()
            .encode(Packing::Small)
            .unwrap();
        assert!(bytes == reference, "order {order:?} merges to other bytes");
    }
    // Merging the files, one in memory at a time, gives the same bytes.
    let dir = tempfile::tempdir().unwrap();
    let mut paths = Vec::new();
    for p in ranges.iter().rev() {
        let path = dir.path().join(format!("{}.exr", p.samples));
        p.write(&path, Packing::Small).unwrap();
        paths.push(path);
    }
    let from_files = passgraph::render::merge::merge_files(&paths).unwrap();
    assert!(from_files.encode(Packing::Small).unwrap() == reference);
    // A merged partial merges again: (0..16 + 16..32) + (32..48 + 48..64) has the flat
    // merge's counts and is within a rounding of it (each level rounds t to f32 + f32).
    let low = merge(unnamed(&ranges[..2])).unwrap();
    let high = merge(unnamed(&ranges[2..])).unwrap();
    assert_eq!(low.samples, range(0, 32));
    let nested = merge(unnamed(&[high, low])).unwrap();
    let (worst, _) = compare(&nested, &Partial::decode(&reference).unwrap());
    assert!(
        worst <= 1,
        "a two-level merge is {worst} ulps from the flat one"
    );
}

#[test]
fn a_partial_file_round_trips_exactly_zip_or_rle_packed() {
    let dir = tempfile::tempdir().unwrap();
    let packings = [Packing::Small, Packing::Fast];
    for (p, packing) in renders(1)[1..3].iter().zip(packings) {
        let path = dir.path().join(format!("{}.exr", p.samples.start));
        p.write(&path, packing).unwrap();
        let back = Partial::read(&path).unwrap();
        // Bit for bit (PartialEq on f32 would take -0.0 for 0.0).
        assert_eq!(back.samples, p.samples);
        assert_eq!(back.fingerprint, p.fingerprint);
        for (a, b) in back.planes.iter().zip(&p.planes) {
            assert_eq!(a.count, b.count);
            let bits = |v: &[[f32; 3]]| v.iter().flatten().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&a.mean), bits(&b.mean));
            assert_eq!(bits(&a.compensation), bits(&b.compensation));
        }
        assert_eq!(&back, p);
    }
    // Compensation is really there: a render of 16 frames carries some nonzero terms.
    let p = &renders(1)[1];
    assert!(
        p.planes
            .iter()
            .any(|q| q.compensation.iter().flatten().any(|&c| c != 0.0))
    );
}

#[test]
fn a_range_past_the_default_1000_frames_renders_its_own_samples() {
    // 1000..1003 renders three frames (max_frames is the range's length, not 1000), whose
    // samples are not frames 0..3's.
    let s = RenderSettings {
        max_frames: 3,
        ..sampler_settings(1)
    };
    let parts = render_ranges(&s, &[range(1000, 1003), range(0, 3)]);
    let [late, early] = [&parts[0], &parts[1]];
    assert_eq!(late.samples, range(1000, 1003));
    assert!(late.planes.iter().all(|p| p.count.iter().all(|&n| n == 3)));
    assert_ne!(late.planes[4].mean, early.planes[4].mean);
    // And 1000..1003 is the frames 1000..1002 a restart at 1000 would draw one at a time.
    let singles = render_ranges(
        &s,
        &[range(1000, 1001), range(1001, 1002), range(1002, 1003)],
    );
    let merged = merge(unnamed(&singles)).unwrap();
    compare(&merged, late);
}

// --- Merging on the CPU: the bound over many pixels, and the refusals. ---

/// A deterministic heavy-tailed series: uniform noise with rare fireflies 100x brighter.
fn sample(pixel: u32, frame: u32, k: u32) -> f32 {
    let mut h = pixel.wrapping_mul(0x9e3779b9) ^ frame.wrapping_mul(0x85ebca6b) ^ (k << 29);
    for _ in 0..3 {
        h ^= h >> 16;
        h = h.wrapping_mul(0x7feb352d);
        h ^= h >> 15;
        h = h.wrapping_mul(0x846ca68b);
    }
    let u = (h >> 8) as f32 / 16777216.0;
    let scale = (1 + pixel % 7) as f32 * 0.37;
    if h & 0xff == 0 {
        100.0 * scale
    } else {
        u * scale
    }
}

/// The accumulate pass's arithmetic (src/render/accumulate.rs) over frames `r` of each of
/// `pixels` pixels, as a partial of one plane repeated.
fn cpu_partial(r: SampleRange, pixels: u32) -> Partial {
    let mut plane = Plane {
        mean: Vec::new(),
        compensation: Vec::new(),
        count: Vec::new(),
    };
    for i in 0..pixels {
        let mut means = [CompensatedMean::default(); 3];
        for (n, f) in (r.start..r.end).enumerate() {
            for (k, m) in means.iter_mut().enumerate() {
                *m = m.step(sample(i, f, k as u32), n as f32);
            }
        }
        plane.mean.push(means.map(|m| m.mean));
        plane.compensation.push(means.map(|m| m.compensation));
        plane.count.push(r.len());
    }
    Partial {
        size: [pixels, 1],
        samples: r,
        dropped: 0,
        fingerprint: fingerprint("size"),
        source: String::new(),
        planes: vec![plane; 5],
        progress: None,
    }
}

fn fingerprint(settings: &str) -> Fingerprint {
    Fingerprint {
        graph: 1,
        scene: 2,
        settings: settings.to_string(),
    }
}

#[test]
fn merged_means_stay_within_the_bound_of_the_unsplit_mean_on_the_cpu() {
    // Uneven splits of 64 and 1024 frames, 2000 heavy-tailed pixels each.
    let cases: [&[u32]; 3] = [
        &[0, 16, 32, 48, 64],
        &[0, 1, 7, 40, 64],
        &[0, 100, 512, 513, 1024],
    ];
    for cuts in cases {
        let pixels = 2000;
        let end = *cuts.last().unwrap();
        let whole = cpu_partial(range(0, end), pixels);
        let parts: Vec<Partial> = cuts
            .windows(2)
            .map(|w| cpu_partial(range(w[0], w[1]), pixels))
            .collect();
        let merged = merge(unnamed(&parts)).unwrap();
        let (worst, differ) = compare(&merged, &whole);
        eprintln!(
            "cuts {cuts:?}: worst {worst} ulps, {differ} of {} values differ",
            15 * pixels
        );
    }
}

#[test]
fn overlapping_ranges_are_refused_naming_both_files_and_ranges() {
    let a = cpu_partial(range(0, 8), 4);
    let b = cpu_partial(range(4, 12), 4);
    let e = merge(vec![("b.exr".into(), b), ("a.exr".into(), a.clone())]).unwrap_err();
    assert_mentions(
        &e,
        &[
            "a.exr (samples 0..8)",
            "b.exr (samples 4..12)",
            "overlap",
            "4..8",
        ],
    );
    // The same range twice overlaps too.
    let e = merge(vec![("x.exr".into(), a.clone()), ("y.exr".into(), a)]).unwrap_err();
    assert_mentions(&e, &["x.exr", "y.exr", "0..8", "overlap"]);
}

#[test]
fn a_gap_between_ranges_is_refused_naming_the_missing_samples() {
    let a = cpu_partial(range(0, 8), 4);
    let c = cpu_partial(range(10, 12), 4);
    let e = merge(vec![("c.exr".into(), c), ("a.exr".into(), a)]).unwrap_err();
    assert_mentions(
        &e,
        &[
            "samples 8..10 are missing",
            "a.exr (samples 0..8)",
            "c.exr (samples 10..12)",
        ],
    );
}

#[test]
fn partials_of_other_renders_or_sizes_are_refused() {
    let a = cpu_partial(range(0, 8), 4);
    let mut b = cpu_partial(range(8, 16), 4);
    b.fingerprint.scene = 3;
    let e = merge(vec![("a.exr".into(), a.clone()), ("b.exr".into(), b)]).unwrap_err();
    assert_mentions(
        &e,
        &[
            "a.exr (samples 0..8)",
            "b.exr (samples 8..16)",
            "different renders",
            "the scene",
        ],
    );
    let mut b = cpu_partial(range(8, 16), 4);
    b.fingerprint = fingerprint("size 4x1, seed 1, max_depth 3");
    let e = merge(vec![("a.exr".into(), a.clone()), ("b.exr".into(), b)]).unwrap_err();
    assert_mentions(&e, &["the settings", "seed 1"]);
    let b = cpu_partial(range(8, 16), 6);
    let e = merge(vec![("a.exr".into(), a), ("b.exr".into(), b)]).unwrap_err();
    assert_mentions(&e, &["a.exr is 4x1", "b.exr is 6x1"]);
}

#[test]
fn reading_refuses_truncated_foreign_and_inconsistent_files_naming_them() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("part.exr");
    let p = cpu_partial(range(0, 8), 64);
    p.write(&path, Packing::Small).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    for cut in [bytes.len() / 2, bytes.len() - 1, 40, 0] {
        let truncated = dir.path().join(format!("cut{cut}.exr"));
        std::fs::write(&truncated, &bytes[..cut]).unwrap();
        let e = Partial::read(&truncated).unwrap_err();
        assert_mentions(&e, &[truncated.to_str().unwrap(), "not a readable OpenEXR"]);
    }
    // An ordinary EXR image is not a partial.
    let image = dir.path().join("image.exr");
    passgraph::render::image::RgbImage {
        width: 2,
        height: 2,
        pixels: vec![[0.5; 3]; 4],
    }
    .write(&image)
    .unwrap();
    let e = Partial::read(&image).unwrap_err();
    assert_mentions(&e, &["image.exr", "not a passgraph partial file"]);
    // A count above the range's length, or a damaged fingerprint, is caught on reading.
    let mut bad = p.clone();
    bad.planes[2].count[5] = 9;
    bad.write(&path, Packing::Small).unwrap();
    assert_mentions(
        &Partial::read(&path).unwrap_err(),
        &["part.exr", "'indirect' counts 9", "(5, 0)", "0..8"],
    );
    assert!(
        Partial::read(Path::new("/nonexistent/part.exr"))
            .unwrap_err()
            .contains("/nonexistent/part.exr: cannot read")
    );
}

#[test]
fn a_partial_missing_a_channel_is_refused_naming_it() {
    use exr::prelude::*;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("part.exr");
    cpu_partial(range(0, 8), 4)
        .write(&path, Packing::Small)
        .unwrap();
    // Rewrite the file without one channel, keeping every attribute.
    let mut image = read_all_flat_layers_from_file(&path).unwrap();
    image.layer_data[0]
        .channel_data
        .list
        .retain(|c| c.name != *"direct.compensation.G");
    image.write().to_file(&path).unwrap();
    let e = Partial::read(&path).unwrap_err();
    assert_mentions(&e, &["part.exr", "missing channel 'direct.compensation.G'"]);
}

// --- The command line. ---

/// Runs the binary in `dir` (its default graph and scene are absolute paths).
fn passgraph(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_passgraph"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the passgraph binary runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn render_samples_then_merge_in_any_order_on_the_command_line() {
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    for r in ["0..2", "2..3"] {
        let out = passgraph(
            dir.path(),
            &[
                "render",
                "--size",
                "8x8",
                "--samples",
                r,
                "--partial",
                &p(&format!("{r}.exr")),
            ],
        );
        assert!(out.status.success(), "{}", text(&out.stderr));
        assert_mentions(&text(&out.stdout), &[&format!("(samples {r})")]);
    }
    // No image unless asked for.
    assert!(!dir.path().join("render.png").exists());
    let forward = passgraph(
        dir.path(),
        &[
            "merge",
            &p("0..2.exr"),
            &p("2..3.exr"),
            "--out",
            &p("f.exr"),
            "--partial",
            &p("fp.exr"),
        ],
    );
    assert!(forward.status.success(), "{}", text(&forward.stderr));
    assert_mentions(&text(&forward.stdout), &["merged 2 partials: samples 0..3"]);
    let backward = passgraph(
        dir.path(),
        &[
            "merge",
            &p("2..3.exr"),
            &p("0..2.exr"),
            "--out",
            &p("b.exr"),
            "--partial",
            &p("bp.exr"),
        ],
    );
    assert!(backward.status.success(), "{}", text(&backward.stderr));
    let read = |n: &str| std::fs::read(dir.path().join(n)).unwrap();
    assert!(read("f.exr") == read("b.exr") && read("fp.exr") == read("bp.exr"));
    // The merged partial merges again, and refuses to merge with a range it holds.
    let again = passgraph(
        dir.path(),
        &["merge", &p("fp.exr"), &p("0..2.exr"), "--out", &p("x.png")],
    );
    assert_eq!(again.status.code(), Some(1));
    assert_mentions(
        &text(&again.stderr),
        &[
            "overlap",
            "fp.exr (samples 0..3)",
            "0..2.exr (samples 0..2)",
        ],
    );
    // Another seed is another render, and the error says which part differs.
    let seeded = passgraph(
        dir.path(),
        &[
            "render",
            "--size",
            "8x8",
            "--samples",
            "2..3",
            "--seed",
            "1",
            "--partial",
            &p("seed1.exr"),
        ],
    );
    assert!(seeded.status.success(), "{}", text(&seeded.stderr));
    let other = passgraph(
        dir.path(),
        &[
            "merge",
            &p("0..2.exr"),
            &p("seed1.exr"),
            "--out",
            &p("s.png"),
        ],
    );
    assert_eq!(other.status.code(), Some(1));
    let stderr = text(&other.stderr);
    assert_mentions(&stderr, &["different renders", "the settings", "seed 1"]);
    assert!(
        !stderr.contains("the scene") && !stderr.contains("the graph"),
        "{stderr}"
    );
    // A truncated partial is an error naming it, not a panic.
    let bytes = read("fp.exr");
    std::fs::write(dir.path().join("cut.exr"), &bytes[..bytes.len() / 2]).unwrap();
    let cut = passgraph(dir.path(), &["merge", &p("cut.exr"), "--out", &p("y.png")]);
    assert_eq!(cut.status.code(), Some(1));
    assert_mentions(&text(&cut.stderr), &["cut.exr", "truncated"]);
    assert!(!text(&cut.stderr).contains("panicked"));
}

#[test]
fn sample_range_usage_errors_exit_2_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    let dir = dir.path();
    for (args, says) in [
        (
            &["--samples", "5..5", "--partial", "p.exr"][..],
            "empty sample range",
        ),
        (
            &["--samples", "0..4", "--frames", "4", "--partial", "p.exr"][..],
            "cannot be used with",
        ),
        (
            &["--samples", "0..4", "--partial", "p.png"][..],
            "name it .exr",
        ),
        (&["--samples", "0..4"][..], "writes nothing"),
        (
            &["--samples", "0..4", "--partial", "p.exr", "--out", "p.exr"][..],
            "both --partial and --out",
        ),
        (
            &["--samples", "0..20000000", "--partial", "p.exr"][..],
            "at most 16777216",
        ),
    ] {
        let out = passgraph(dir, &[&["render"][..], args].concat());
        assert_eq!(
            out.status.code(),
            Some(2),
            "{args:?}: {}",
            text(&out.stderr)
        );
        assert_mentions(&text(&out.stderr), &[says]);
    }
    let out = passgraph(
        dir,
        &["merge", "a.exr", "--out", "x.png", "--channel", "denoised"],
    );
    assert_eq!(out.status.code(), Some(2));
    assert_mentions(&text(&out.stderr), &["accumulation's channels only"]);
    let out = passgraph(dir, &["merge", "a.exr"]);
    assert_eq!(out.status.code(), Some(2));
    assert_mentions(&text(&out.stderr), &["merge writes nothing"]);
}

#[test]
fn counts_weigh_each_range_per_pixel() {
    // Pixel 0 has samples in both ranges, pixel 1 dropped all of 0..2, pixel 2 every sample.
    let partial = |r: SampleRange, means: [f32; 3], counts: [u32; 3]| Partial {
        size: [3, 1],
        samples: r,
        dropped: u64::from(3 * r.len() - counts.iter().sum::<u32>()),
        fingerprint: fingerprint("size"),
        source: String::new(),
        planes: vec![
            Plane {
                mean: means.iter().map(|&m| [m; 3]).collect(),
                compensation: vec![[0.0; 3]; 3],
                count: counts.to_vec(),
            };
            5
        ],
        progress: None,
    };
    let a = partial(range(0, 2), [1.0, 0.0, 0.0], [2, 0, 0]);
    let b = partial(range(2, 6), [4.0, 2.0, 0.0], [4, 3, 0]);
    let merged = merge(unnamed(&[b, a])).unwrap();
    let plane = &merged.planes[4];
    assert_eq!(plane.count, [6, 3, 0]);
    assert_eq!(plane.mean, [[3.0; 3], [2.0; 3], [0.0; 3]]);
    assert_eq!(plane.compensation, [[0.0; 3]; 3]);
    assert_eq!(merged.dropped, 4 + 5);
}

#[test]
fn a_graph_without_compensation_cannot_write_a_partial() {
    // What SessionBuilder::partial checks when the graph is compiled, before any GPU work.
    let plan = common::compile_fixture("seed.ron");
    let e = passgraph::render::session::partial_contract()
        .check(&plan)
        .unwrap_err()
        .to_string();
    assert_mentions(&e, &["seed.ron", "'compensation'", "render --partial"]);
}

#[test]
fn a_partial_whose_header_disagrees_with_its_data_is_refused() {
    use exr::prelude::*;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("part.exr");
    cpu_partial(range(0, 8), 4)
        .write(&path, Packing::Small)
        .unwrap();
    // Edit one line of the header attribute, keeping the pixels.
    let edit = |from: &str, to: &str| {
        let mut image = read_all_flat_layers_from_file(&path).unwrap();
        let header = image.layer_data[0]
            .attributes
            .other
            .get_mut(&Text::from("passgraph.partial"))
            .unwrap();
        let AttributeValue::Text(text) = header else {
            panic!("passgraph.partial is text")
        };
        let edited = text.to_string().replace(from, to);
        assert_ne!(edited, text.to_string(), "{from} is in the header");
        *text = Text::from(edited.as_str());
        let edited_path = dir.path().join("edited.exr");
        image.write().to_file(&edited_path).unwrap();
        Partial::read(&edited_path).unwrap_err()
    };
    assert_mentions(
        &edit("size: 4x1", "size: 5x1"),
        &["edited.exr", "'size' says 5x1 but the image is 4x1"],
    );
    assert_mentions(
        &edit("settings: size", "settings: SIZE"),
        &["edited.exr", "does not match its parts", "damaged"],
    );
    assert_mentions(
        &edit("format: passgraph partial 2", "format: passgraph partial 3"),
        &["edited.exr", "this passgraph reads 'passgraph partial 2'"],
    );
    assert_mentions(
        &edit("samples: 0..8", "samples: 8..8"),
        &["edited.exr", "'samples'", "empty sample range"],
    );
    // A range shifted, or a dropped count changed, by hand: the checksum no longer matches.
    assert_mentions(
        &edit("samples: 0..8", "samples: 8..16"),
        &[
            "edited.exr",
            "checksum does not match",
            "changed after it was written",
        ],
    );
    assert_mentions(
        &edit("dropped: 0", "dropped: 18446744073709551614"),
        &["edited.exr", "checksum does not match"],
    );
}

#[test]
fn a_partial_with_edited_data_or_counts_that_do_not_add_up_is_refused() {
    use exr::prelude::*;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("part.exr");
    let p = cpu_partial(range(0, 8), 4);
    p.write(&path, Packing::Small).unwrap();
    // One mean changed in the data, the header kept: the checksum catches it.
    let mut image = read_all_flat_layers_from_file(&path).unwrap();
    let channel = image.layer_data[0]
        .channel_data
        .list
        .iter_mut()
        .find(|c| c.name == *"sum.G")
        .unwrap();
    let FlatSamples::F32(values) = &mut channel.sample_data else {
        panic!("sum.G is f32")
    };
    values[2] = f32::from_bits(values[2].to_bits() ^ 1);
    let flipped = dir.path().join("flipped.exr");
    image.write().to_file(&flipped).unwrap();
    assert_mentions(
        &Partial::read(&flipped).unwrap_err(),
        &["flipped.exr", "checksum does not match"],
    );
    // Files whose checksum was recomputed (as a forger would) still have to add up: counts of
    // 0 need that many dropped samples, ...
    let mut zero = p.clone();
    for plane in &mut zero.planes {
        plane.count[1] = 0;
    }
    zero.write(&path, Packing::Small).unwrap();
    assert_mentions(
        &Partial::read(&path).unwrap_err(),
        &[
            "part.exr",
            "'dropped' is 0",
            "leave 8 of the 8 x 4 samples",
            "0..8",
        ],
    );
    // ... dropped samples beyond the range are not there to drop, ...
    let mut many = p.clone();
    many.dropped = u64::MAX - 1;
    many.write(&path, Packing::Small).unwrap();
    assert_mentions(
        &Partial::read(&path).unwrap_err(),
        &["'dropped' is 18446744073709551614", "leave 0"],
    );
    // ... and a sample is dropped in every channel or none.
    let mut uneven = p.clone();
    uneven.planes[3].count[2] = 7;
    uneven.dropped = 1;
    uneven.write(&path, Packing::Small).unwrap();
    assert_mentions(
        &Partial::read(&path).unwrap_err(),
        &[
            "channel 'ambient' counts 7 samples at pixel (2, 0)",
            "'l0' 8",
        ],
    );
}

#[test]
fn a_tiled_checkpoints_progress_round_trips_and_each_tiles_counts_must_fit_it() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("ckpt.exr");
    // 16x1 in tiles of 8x1: the first tile holds 3 of samples 0..8, the second none.
    let mut p = cpu_partial(range(0, 8), 16);
    p.progress = Some(TileProgress {
        tile: [8, 1],
        done: 0,
        next: 3,
    });
    for plane in &mut p.planes {
        for (i, n) in plane.count.iter_mut().enumerate() {
            *n = if i < 8 { 3 } else { 0 };
        }
    }
    p.write(&path, Packing::Fast).unwrap();
    let read = Partial::read(&path).unwrap();
    assert_eq!(read, p);
    assert_eq!(
        read.holds(),
        "samples 0..8 in 0 of 2 tiles of 8x1, 0..3 in the next"
    );
    // Each change below is written with a recomputed checksum, as a forger would: the counts
    // must still fit the tiles' progress.
    let refused = |q: &Partial, says: &[&str]| {
        q.write(&path, Packing::Fast).unwrap();
        assert_mentions(&Partial::read(&path).unwrap_err(), says);
    };
    let mut over = p.clone();
    for plane in &mut over.planes {
        plane.count[10] = 1;
    }
    refused(
        &over,
        &[
            "ckpt.exr",
            "counts 1 samples at pixel (10, 0)",
            "its tile holds (0 of range 0..8: 8x1 done 0 next 3)",
        ],
    );
    let mut short = p.clone();
    for plane in &mut short.planes {
        plane.count[0] = 2;
    }
    refused(
        &short,
        &["'dropped' is 0", "leave 1 of the samples its tiles hold"],
    );
    let with = |progress: TileProgress| Partial {
        progress: Some(progress),
        ..p.clone()
    };
    refused(
        &with(TileProgress {
            tile: [8, 1],
            done: 2,
            next: 0,
        }),
        &["'tiles' (8x1 done 2 next 0) is not the progress of a 16x1 image in 2 tiles"],
    );
    refused(
        &with(TileProgress {
            tile: [8, 1],
            done: 0,
            next: 8,
        }),
        &["the next tile holds 8 samples", "fewer than the range's 8"],
    );
    refused(
        &with(TileProgress {
            tile: [5, 1],
            done: 0,
            next: 3,
        }),
        &["'tiles' (5x1 done 0 next 3)", "multiple of 8"],
    );
}
