//! The reuse pass's groups do not depend on how wide the device's subgroups are (issue 25:
//! "reuse groups must not assume lavapipe's 8-lane subgroups"). A group is an aligned run of
//! `reuse_pixels` lanes (at most 8: a 4x2 block of pixels, shaders/path_reuse.wgsl), so on any
//! subgroup of at least that many lanes the image must be the same. lavapipe's subgroups are
//! its SIMD vectors, LP_NATIVE_VECTOR_WIDTH bits of 32-bit lanes, a setting read once per
//! process: each render below runs in its own process forced to 8 or 16 lanes, with Mesa's
//! shader cache off (its key leaves the width out, so a cached 8-lane binary would run at every
//! width: measured), and the images must agree bit for bit. A pass that sized or placed its
//! groups by the subgroup (every lane sharing, or each group taking its sample sequence from
//! the subgroup's first lane: tried, half the pixels differ) renders another image at 16.
//! 32 and 64 lanes (1024 and 2048 bits) are not tried: Mesa 25.0.7's lavapipe (LLVM 15)
//! aborts compiling these passes at those widths ("stack smashing detected").
//!
//! On another adapter the variable does nothing: the test then checks only that the renders
//! agree.

mod common;

use common::render::differing_pixels;
use common::root;
use passgraph::render::image::RgbImage;
use std::process::Command;

/// lavapipe's vector widths in bits, and the subgroup each gives (32-bit lanes).
const WIDTHS: [(u32, u32); 2] = [(256, 8), (512, 16)];

/// The reported subgroup width ("subgroups: A..B lanes") and the image of one render of
/// `graphs/pathtracer-reuse.ron` at 32x32 in a process with LP_NATIVE_VECTOR_WIDTH = `bits`.
fn render_with_vector_width(bits: u32, args: &[&str]) -> (bool, String, RgbImage) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.exr");
    let output = Command::new(env!("CARGO_BIN_EXE_passgraph"))
        .current_dir(root())
        .args(["render", "--graph", "graphs/pathtracer-reuse.ron"])
        .args(["--size", "32x32", "--frames", "2", "--seed", "3", "--out"])
        .arg(&out)
        .args(args)
        .env("LP_NATIVE_VECTOR_WIDTH", bits.to_string())
        // Mesa's shader cache keys lavapipe's binaries without the vector width: a binary
        // compiled for 8 lanes would be run again at every width.
        .env("MESA_SHADER_CACHE_DISABLE", "true")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(
        output.status.success(),
        "LP_NATIVE_VECTOR_WIDTH={bits}:\n{err}"
    );
    let line = |prefix: &str| {
        err.lines()
            .find_map(|l| l.strip_prefix(prefix))
            .unwrap_or_else(|| panic!("no {prefix:?} line in:\n{err}"))
            .to_string()
    };
    let lavapipe = line("adapter: ").contains("llvmpipe");
    (
        lavapipe,
        line("subgroups: "),
        RgbImage::read_exr(&out).unwrap(),
    )
}

fn same_image_at_every_subgroup_width(args: &[&str]) {
    let mut first: Option<(String, RgbImage)> = None;
    for (bits, lanes) in WIDTHS {
        let (lavapipe, subgroups, image) = render_with_vector_width(bits, args);
        if lavapipe {
            assert_eq!(
                subgroups,
                format!("{lanes}..{lanes} lanes"),
                "lavapipe should give subgroups of {lanes} lanes at {bits} bits"
            );
        }
        match &first {
            None => {
                assert!(
                    image.mean().iter().all(|&m| m > 0.0),
                    "a black image proves nothing ({args:?})"
                );
                first = Some((subgroups, image));
            }
            Some((first_subgroups, first_image)) => {
                let differing = differing_pixels(&image, first_image);
                assert_eq!(
                    differing,
                    0,
                    "{differing} of {} pixels differ between subgroups of {first_subgroups} and {subgroups} ({args:?})",
                    image.pixels.len()
                );
            }
        }
    }
}

#[test]
fn groups_of_8_share_the_same_bounces_on_subgroups_of_8_and_16_lanes() {
    // The Cornell box: Lambertian, so every pixel shares its bounces with its group.
    same_image_at_every_subgroup_width(&[]);
}

#[test]
fn groups_of_4_share_the_same_bounces_on_subgroups_of_8_and_16_lanes() {
    same_image_at_every_subgroup_width(&["--set", "path.reuse_pixels=4"]);
}

#[test]
fn per_sample_sharing_beside_glossy_and_glass_is_the_same_on_subgroups_of_8_and_16_lanes() {
    // The materials showcase, deciding per sample which pixels share (glass traces alone).
    same_image_at_every_subgroup_width(&[
        "--scene",
        "scenes/materials/scene.ron",
        "--set",
        "path.per_pixel_sharing=true",
    ]);
}
