//! Environment images (src/scene/environment_image.rs): the lookup against Mitsuba 3.9.0's
//! `envmap` itself (tests/data/environment/mitsuba-envmap-eval.txt, written by
//! scripts/envmap-mitsuba-table), the readers against Mitsuba's and OpenEXR's own decoding, the
//! test HDRIs (scripts/make-test-hdris), and each bad input's message.

use exr::prelude::WritableImage;
use glam::{Mat3, Vec3};
use passgraph::scene::environment_image::{EnvironmentImage, load_environment_image};
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/environment")
        .join(name)
}

/// The Mitsuba table: its texels, its decoding of the .hdr, and its lookups.
struct Table {
    image: EnvironmentImage,
    hdr: Vec<[f32; 3]>,
    /// (to_world rotation about +y in degrees, world direction, radiance)
    evals: Vec<(f32, Vec3, Vec3)>,
    /// (file, world direction, radiance)
    files: Vec<(String, Vec3, Vec3)>,
}

fn table() -> Table {
    let text = std::fs::read_to_string(data("mitsuba-envmap-eval.txt")).unwrap();
    let (mut size, mut texels, mut hdr, mut evals, mut files) =
        ((0, 0), vec![], vec![], vec![], vec![]);
    for line in text.lines() {
        let f: Vec<&str> = line.split(' ').collect();
        let n = |i: usize| f[i].parse::<f32>().unwrap();
        let v = |i: usize| Vec3::new(n(i), n(i + 1), n(i + 2));
        match f[0] {
            "size" => size = (f[1].parse().unwrap(), f[2].parse().unwrap()),
            "texel" => texels.push(v(3).to_array()),
            "hdr" => hdr.push(v(3).to_array()),
            "eval" => evals.push((n(1), v(2), v(5))),
            "file" => files.push((f[1].to_string(), v(2), v(5))),
            other => panic!("unknown line kind {other}"),
        }
    }
    let image = EnvironmentImage::from_texels(size.0, size.1, texels).unwrap();
    Table {
        image,
        hdr,
        evals,
        files,
    }
}

/// Mitsuba computes in f32 too, but its atan2/acos are Dr.Jit's polynomials, which differ from
/// libm's by an ulp or two (~1.2e-7 in u or t). An error du moves the lookup by du * W texels,
/// so the result by du * W * (neighbouring texels' difference, < 5 here): at most
/// 2 * 1.2e-7 * 9 * 5 = 1.1e-5 absolute. Measured: 5.5e-6 (identity), 1.2e-5 (rotated: the f32
/// rotation matrix adds its own rounding); median 5e-7 relative. Bound: 2e-5 absolute plus 1e-6
/// relative. A model difference (half-texel shift, H for H - 1, clamping instead of the periodic
/// column, a flipped axis) moves results by a sizeable part of a texel difference, ~0.1 or more.
fn close(got: Vec3, expected: Vec3) -> bool {
    (got - expected)
        .abs()
        .cmple(expected.abs() * 1e-6 + Vec3::splat(2e-5))
        .all()
}

#[test]
fn eval_matches_mitsubas_envmap_including_to_world_rotations() {
    let t = table();
    assert_eq!((t.image.width, t.image.height), (9, 5));
    let (mut checked, mut worst) = (0, 0f32);
    for (rot, d, expected) in &t.evals {
        // Within 1e-3 of a pole, u = atan2(x, -z) is ill-conditioned: the rotation's f32
        // rounding (cos 90 degrees = -4.4e-8 in f32, in Mitsuba's matrix and glam's alike, but
        // not in the same places) moves u by ~4e-8 / sin(theta) there. Unrotated, they count.
        if *rot != 0.0 && d.x.hypot(d.z) < 1.5e-3 {
            continue;
        }
        // Mitsuba: eval(to_world^-1 d); its `rotate` about +y is right-handed, as glam's.
        let local = Mat3::from_rotation_y(rot.to_radians()).transpose() * *d;
        let got = t.image.eval(local);
        worst = worst.max((got - *expected).abs().max_element());
        assert!(
            close(got, *expected),
            "rotate {rot}, direction {d}: passgraph {got}, Mitsuba {expected}"
        );
        checked += 1;
    }
    assert_eq!((t.evals.len(), checked), (720, 720 - 18));
    println!("worst absolute difference from Mitsuba: {worst:e}");
}

#[test]
fn openexr_and_hdr_readers_give_mitsubas_texels() {
    let t = table();
    let exr = load_environment_image(&data("random-9x5.exr")).unwrap();
    assert_eq!(exr, t.image, "float32 ZIP EXR read back exactly");
    let hdr = load_environment_image(&data("random-9x5.hdr")).unwrap();
    assert_eq!((hdr.width, hdr.height), (9, 5));
    // RGBE is decoded exactly (m * 2^(e - 136)): bitwise Mitsuba's decoding.
    assert_eq!(hdr.texels, t.hdr);
}

#[test]
fn files_look_up_as_mitsubas_envmap_loads_them() {
    // RGB float, RGBE, RGBA (alpha 0.25 dropped, colour not divided), half floats, Y alone.
    let t = table();
    let mut names: Vec<&str> = t.files.iter().map(|f| f.0.as_str()).collect();
    names.dedup();
    assert_eq!(names.len(), 5);
    for name in names {
        let image = load_environment_image(&data(name)).unwrap();
        for (_, d, expected) in t.files.iter().filter(|f| f.0 == name) {
            let got = image.eval(*d);
            assert!(
                close(got, *expected),
                "{name}, {d}: passgraph {got}, Mitsuba {expected}"
            );
        }
    }
}

const LUMINANCE: Vec3 = Vec3::new(0.212_671, 0.715_160, 0.072_169);

fn mean_luminance(image: &EnvironmentImage) -> f64 {
    let sum: f64 = image
        .texels
        .iter()
        .map(|t| Vec3::from(*t).dot(LUMINANCE) as f64)
        .sum();
    sum / image.texels.len() as f64
}

#[test]
fn test_hdris_keep_their_sources_light_and_sun() {
    // scripts/make-test-hdris prints the sources' mean luminance (after clamping their
    // negative texels): sunrise 0.486071, studio 0.254886; box-averaging keeps it, up to the
    // f32 storage (relative 1e-7 per texel) and the 6 printed digits.
    for (name, size, mean) in [
        ("sunrise-256x128.exr", (256, 128), 0.486071),
        ("sunrise-64x32.exr", (64, 32), 0.486071),
        ("studio-64x32.exr", (64, 32), 0.254886),
    ] {
        let image = load_environment_image(&data(name)).unwrap();
        assert_eq!((image.width, image.height), size, "{name}");
        let got = mean_luminance(&image);
        assert!((got - mean).abs() < 1e-6, "{name}: mean luminance {got}");
    }
    // The sun: the source's brightest texel is at (614, 233) of 1024x512, so texel
    // (614 / 16, 233 / 16) = (38, 14) of the 64x32 (row 0 at the top, as OpenEXR stores it).
    let sunrise = load_environment_image(&data("sunrise-64x32.exr")).unwrap();
    let brightest = (0..sunrise.texels.len())
        .max_by(|&a, &b| {
            let l = |i: usize| Vec3::from(sunrise.texels[i]).dot(LUMINANCE);
            l(a).total_cmp(&l(b))
        })
        .unwrap();
    assert_eq!((brightest % 64, brightest / 64), (38, 14));
}

#[test]
fn dwab_files_decode_as_openexr_decodes_them() {
    // OpenEXR 3.5.3's decoding, stored losslessly beside each DWAB file (scripts/make-test-hdris).
    // DWA is lossy (a DCT of 16-bit values, for float32 R, G, B too); the exr crate's decoder is a
    // port of OpenEXRCore's and lands on the same halves: bitwise equal (measured; the
    // blender-data originals too, all eight).
    for name in ["sunrise-64x32-dwab-float", "sunrise-64x32-dwab-half"] {
        let dwab = load_environment_image(&data(&format!("{name}.exr"))).unwrap();
        let reference = load_environment_image(&data(&format!("{name}.decoded.exr"))).unwrap();
        assert_eq!((dwab.width, dwab.height), (64, 32));
        assert!(dwab == reference, "{name}: not OpenEXR's decoding");
        // Lossy indeed: not the float32 image it was written from.
        let source = load_environment_image(&data("sunrise-64x32.exr")).unwrap();
        assert!(dwab != source);
    }
}

/// Asserts loading fails with a message naming the file and holding each of `parts`.
fn refused(path: &Path, parts: &[&str]) -> String {
    let message = load_environment_image(path).expect_err("must be refused");
    assert!(
        message.contains(&path.display().to_string()),
        "the message must name the file: {message}"
    );
    for part in parts {
        assert!(message.contains(part), "expected {part:?} in: {message}");
    }
    message
}

fn write_exr(
    path: &Path,
    width: usize,
    height: usize,
    texel: impl Fn(usize, usize) -> [f32; 3] + Sync,
) {
    exr::prelude::write_rgb_file(path, width, height, |x, y| {
        let [r, g, b] = texel(x, y);
        (r, g, b)
    })
    .unwrap();
}

#[test]
fn bad_texels_are_refused_naming_the_first_and_counting_them() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.exr");
    let cases: [(&str, f32, &str); 3] = [
        ("nan", f32::NAN, "(1 NaN, 0 infinite, 0 negative)"),
        ("inf", f32::INFINITY, "(0 NaN, 1 infinite, 0 negative)"),
        ("negative", -0.5, "(0 NaN, 0 infinite, 1 negative)"),
    ];
    for (what, value, counts) in cases {
        write_exr(&path, 4, 3, |x, y| {
            if (x, y) == (2, 1) {
                [0.5, value, 0.5]
            } else {
                [0.5; 3]
            }
        });
        let message = refused(&path, &["texel (x 2, y 1)", "1 texels are not", counts]);
        assert!(
            message.contains("clamp") == (what == "negative"),
            "{message}"
        );
    }
    // Several: the first in row-major order, all counted.
    write_exr(&path, 4, 3, |x, y| match (x, y) {
        (3, 0) | (0, 2) => [-1.0, 0.5, 0.5],
        (1, 1) => [f32::NAN; 3],
        _ => [0.5; 3],
    });
    refused(
        &path,
        &[
            "texel (x 3, y 0)",
            "3 texels are not (1 NaN, 0 infinite, 2 negative)",
        ],
    );
}

#[test]
fn too_small_images_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    for (w, h) in [(1, 3), (2, 2), (8, 1)] {
        let path = dir.path().join(format!("small-{w}x{h}.exr"));
        write_exr(&path, w, h, |_, _| [1.0; 3]);
        refused(&path, &[&format!("is {w}x{h} texels"), "at least 2x3"]);
    }
    write_exr(&dir.path().join("ok.exr"), 2, 3, |_, _| [1.0; 3]);
    assert!(load_environment_image(&dir.path().join("ok.exr")).is_ok());
    let from = EnvironmentImage::from_texels(3, 3, vec![[1.0; 3]; 8]);
    assert!(from.unwrap_err().contains("8 texels for a 3x3"));
}

#[test]
fn unreadable_files_are_refused_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    refused(&dir.path().join("missing.exr"), &["cannot read"]);
    // A compression the exr crate cannot decode: named, with how to convert.
    refused(
        &data("htj2k-16x8.exr"),
        &["HTJ2K256 compression", "oiiotool", "OpenEXR"],
    );
    let text = dir.path().join("sky.exr");
    std::fs::write(&text, "not an image\n").unwrap();
    refused(&text, &["not an OpenEXR (.exr) or Radiance (.hdr) image"]);
    // Neither colour nor luminance.
    let depth = dir.path().join("depth.exr");
    let channels = exr::prelude::SpecificChannels::build()
        .with_channel("Z")
        .with_pixel_fn(|_| (0.5f32,));
    exr::prelude::Image::from_channels((4, 3), channels)
        .write()
        .to_file(&depth)
        .unwrap();
    refused(&depth, &["channels [Z]", "needs R, G and B"]);
    for name in [
        "sunrise-64x32.exr",
        "sunrise-64x32-dwab-float.exr",
        "random-9x5.hdr",
    ] {
        let bytes = std::fs::read(data(name)).unwrap();
        let cut = dir.path().join(format!("cut-{name}"));
        std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
        refused(&cut, &["cannot decode"]);
    }
}
