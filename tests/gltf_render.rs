//! glTF scenes rendered on the GPU (lavapipe in CI) with the default graph against closed forms
//! through the metallic-roughness BSDF's CPU twin: a plane of one material under a
//! KHR_lights_punctual point light sees nothing else, so each pixel's radiance is
//! f(wo, wi) |cos wi| I / r^2. With the jitter off each pixel is one exact evaluation, so the
//! bound is f32 rounding, relative 1e-4 as in tests/lights_analytic.rs (measured: 1.8e-5 at
//! most). A GPU model that differed from the twin by a Fresnel or albedo term would be off by
//! percents.

mod common;

use common::gltf::GltfWriter;
use common::render::{assert_clean, image, render, settings};
use glam::Vec3;
use passgraph::material::materials_texels;
use passgraph::material::{Bsdf, eval};
use passgraph::scene::{SceneOptions, load_scene, load_scene_with};
use serde_json::json;
use std::path::{Path, PathBuf};

const SIZE: u32 = 48;
const LIGHT: Vec3 = Vec3::new(1.0, 2.0, 0.5);
/// 683 cd of this colour: 1 W/sr times it.
const COLOUR: [f32; 3] = [1.0, 0.8, 0.6];

/// A 20 x 20 plane at y = 0 of `material`, seen from (0, 5, 0) looking down, a point light.
fn plane(dir: &Path, material: serde_json::Value) -> PathBuf {
    let mut g = GltfWriter::new();
    let m = g.material(material);
    let mesh = g.quad(10.0, Some(m));
    g.root(json!({"mesh": mesh}));
    let cam = g.camera(
        json!({"type": "perspective", "perspective": {"yfov": std::f32::consts::FRAC_PI_3,
        "znear": 0.1}}),
    );
    let s = std::f32::consts::FRAC_1_SQRT_2;
    g.root(json!({"camera": cam, "translation": [0.0, 5.0, 0.0],
        "rotation": [-s, 0.0, 0.0, s]}));
    let light = g.light(json!({"type": "point", "intensity": 683.0, "color": COLOUR}));
    g.root(
        json!({"extensions": {"KHR_lights_punctual": {"light": light}},
        "translation": LIGHT.to_array()}),
    );
    g.write_glb(dir, "plane")
}

fn check_plane(material: serde_json::Value, what: &str) {
    let dir = tempfile::tempdir().unwrap();
    let scene = plane(dir.path(), material);
    let s = settings(
        common::render::PATHTRACER,
        &scene,
        SIZE,
        0,
        &["intersect.pixel_jitter=false"],
    );
    let session = render(&s, 1);
    assert_clean(&session, 1, what);
    let img = image(&session, "l0+direct+indirect");
    let loaded = load_scene_with(&scene, &SceneOptions::default())
        .unwrap()
        .scene;
    let (materials, texels) = materials_texels(&loaded.mesh.materials);
    let b = Bsdf::from_material(&materials[0], &texels);
    let camera = load_scene(&scene).unwrap().camera;
    let gpu = camera.to_gpu(SIZE, SIZE);
    let mut lit = 0;
    let mut worst = 0.0f32;
    for y in 0..SIZE {
        for x in 0..SIZE {
            let d = gpu.ray_direction(SIZE, SIZE, x as f32 + 0.5, y as f32 + 0.5);
            let t = -camera.eye().y / d.y;
            let p = camera.eye() + t * d;
            assert!(
                p.x.abs() < 10.0 && p.z.abs() < 10.0,
                "the plane fills the view"
            );
            let to = LIGHT - p;
            let r2 = to.length_squared();
            let f = eval(&b, Vec3::Y, true, -d, to / r2.sqrt());
            let want = f * Vec3::from(COLOUR) / r2;
            let got = Vec3::from(img.pixels[(y * SIZE + x) as usize]);
            let err = (got - want).abs().max_element();
            assert!(
                err <= 1e-4 * want.max_element() + 1e-7,
                "{what}: pixel ({x}, {y}) at {p}: {got}, expected {want}"
            );
            lit += usize::from(want.max_element() > 0.0);
            worst = worst.max(err / want.max_element().max(1e-7));
        }
    }
    println!("{what}: largest relative difference {worst:e}");
    assert!(lit > 0, "{what}: no pixel is lit, so nothing was checked");
}

#[test]
fn a_rough_dielectric_plane_under_a_point_light_matches_the_cpu_twin() {
    check_plane(
        json!({"pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.5, 0.3, 1.0],
            "metallicFactor": 0.0, "roughnessFactor": 0.6}}),
        "dielectric",
    );
}

#[test]
fn a_half_metal_plane_under_a_point_light_matches_the_cpu_twin() {
    check_plane(
        json!({"pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.6, 0.2, 1.0],
            "metallicFactor": 0.5, "roughnessFactor": 0.4}}),
        "half metal",
    );
}
