//! The CPU twin of `texture_bilinear` (which tests/shading_gpu.rs holds the WGSL to) against
//! Mitsuba 3.9.0's `bitmap` texture itself: lookups recorded by
//! tests/data/textures/make-mitsuba-bitmap.py at OBJ uvs (Mitsuba's OBJ loader stores 1 - v),
//! of an 8-bit RGB image read as colour (sRGB) and raw, and of a grey image read raw.

mod common;

use glam::Vec2;
use passgraph::scene::texture::{Encoding, LUMINANCE, Texture};

#[test]
fn bilinear_lookups_match_mitsubas_bitmap() {
    let dir = common::root().join("tests/data/textures");
    let csv = std::fs::read_to_string(dir.join("mitsuba-bitmap.csv")).unwrap();
    let mut checked = 0;
    for line in csv.lines().skip(1) {
        let fields: Vec<&str> = line.split(',').collect();
        let encoding = if fields[1] == "1" {
            Encoding::Raw
        } else {
            Encoding::Srgb
        };
        let texture = Texture::load(&dir.join(fields[0]), encoding).unwrap();
        let number = |i: usize| fields[i].parse::<f32>().unwrap();
        let uv = Vec2::new(number(2), number(3));
        let expected = [number(4), number(5), number(6)];
        let c = texture.bilinear(uv);
        let got = if fields[0].starts_with("grey") {
            // Mitsuba's scalar lookup: the luminance (of r = g = b).
            [c.truncate().dot(LUMINANCE.into()); 3]
        } else {
            [c.x, c.y, c.z]
        };
        for k in 0..3 {
            assert!(
                (got[k] - expected[k]).abs() <= 2e-6,
                "{line}: passgraph {got:?}"
            );
        }
        checked += 1;
    }
    assert_eq!(checked, 192);
}
