//! Point, spot and directional lights and the uniform environment against closed forms, on the
//! GPU (lavapipe in CI), with the default graph (graphs/pathtracer.ron):
//!
//! - a point light over a Lambertian plane: radiance rho / pi * I cos(theta) / r^2 at every
//!   pixel (one plane sees nothing else, so nothing but direct light reaches it); with the
//!   jitter off each pixel is one exact evaluation, so the bound is f32 rounding (1e-4);
//! - a directional light: rho / pi * E cos(theta), the same at every pixel;
//! - a spot light: the point light times Mitsuba's falloff (1 inside the beam width, linear in
//!   angle to 0 at the cutoff), pixel by pixel; with a texture, times Mitsuba's bitmap lookup
//!   at the spot's uv in its lookat frame (an image of distinct texels, a non-default up);
//! - the white furnace: a Lambertian convex polyhedron inside a uniform environment L reflects
//!   rho L at every pixel (no facet sees another) and the background is L; the environment is
//!   sampled uniformly on the sphere, so pixels are noisy: their mean is within 5 standard
//!   errors (of that mean, from the pixels' spread) of rho L;
//! - shadow rays of lights outside the scene's hull and of the environment cross hull faces
//!   (src/scene/hull.rs): each is blocked where it must be.

mod common;

use common::geometry::{Mtl, ObjWriter, icosphere};
use common::render::{assert_clean, image, render, settings};
use glam::Vec3;
use passgraph::render::image::RgbImage;
use passgraph::scene::load_scene;
use std::path::{Path, PathBuf};

const SIZE: u32 = 48;
const RHO: f32 = 0.5;
const CHANNELS: &str = "l0+direct+indirect";

fn plane_scene(dir: &Path, extra: &str) -> PathBuf {
    let mut obj = ObjWriter::new(&[Mtl {
        name: "floor",
        kd: [RHO; 3],
        ke: [0.0; 3],
    }]);
    obj.material("floor").polygon(&[
        Vec3::new(-10.0, 0.0, -10.0),
        Vec3::new(-10.0, 0.0, 10.0),
        Vec3::new(10.0, 0.0, 10.0),
        Vec3::new(10.0, 0.0, -10.0),
    ]);
    let scene = obj.write(dir, Vec3::new(0.0, 5.0, 0.0), Vec3::ZERO, Vec3::Z, 60.0);
    add_to_scene(&scene, extra);
    scene
}

/// Inserts `extra` (scene-file fields) before the scene's closing parenthesis.
fn add_to_scene(scene: &Path, extra: &str) {
    let text = std::fs::read_to_string(scene).unwrap();
    let end = text.rfind(')').unwrap();
    std::fs::write(scene, format!("{}{extra}\n)\n", &text[..end])).unwrap();
}

/// One frame, pixel centres, the physical channels.
fn render_exact(scene: &Path) -> RgbImage {
    let s = settings(
        common::render::PATHTRACER,
        scene,
        SIZE,
        0,
        &["intersect.pixel_jitter=false"],
    );
    let session = render(&s, 1);
    assert_clean(&session, 1, "render");
    image(&session, CHANNELS)
}

/// Where the centre ray of pixel (x, y) meets the plane y = 0.
fn plane_hit(scene: &Path, x: u32, y: u32) -> Option<Vec3> {
    let camera = load_scene(scene).unwrap().camera;
    let d = camera
        .to_gpu(SIZE, SIZE)
        .ray_direction(SIZE, SIZE, x as f32 + 0.5, y as f32 + 0.5);
    let t = -camera.eye().y / d.y;
    let p = camera.eye() + t * d;
    (t > 0.0 && p.x.abs() < 10.0 && p.z.abs() < 10.0).then_some(p)
}

/// `expected(p)`: the radiance at plane point p and an absolute slack besides f32 rounding.
fn assert_pixels(
    scene: &Path,
    img: &RgbImage,
    mut expected: impl FnMut(Vec3) -> (Vec3, f32),
    what: &str,
) {
    let mut lit = 0;
    for y in 0..SIZE {
        for x in 0..SIZE {
            let p = plane_hit(scene, x, y).expect("the plane fills the view");
            let (want, slack) = expected(p);
            let got = Vec3::from(img.pixels[(y * SIZE + x) as usize]);
            let err = (got - want).abs().max_element();
            assert!(
                err <= 1e-4 * want.max_element() + 1e-7 + slack,
                "{what}: pixel ({x}, {y}) at {p}: {got}, expected {want}"
            );
            lit += usize::from(want.max_element() > 0.0);
        }
    }
    assert!(lit > 0, "{what}: no pixel is lit, so nothing was checked");
}

#[test]
fn a_point_light_gives_intensity_cos_over_r_squared() {
    let dir = tempfile::tempdir().unwrap();
    let light = Vec3::new(1.0, 2.0, 0.5);
    let intensity = Vec3::new(10.0, 20.0, 30.0);
    let scene = plane_scene(
        dir.path(),
        "    lights: [Point(position: (1, 2, 0.5), intensity: (10, 20, 30))],",
    );
    let img = render_exact(&scene);
    assert_pixels(
        &scene,
        &img,
        |p| {
            let to = light - p;
            let r2 = to.length_squared();
            (
                intensity * (RHO / std::f32::consts::PI) * (to.y / r2.sqrt()) / r2,
                0.0,
            )
        },
        "point",
    );
}

#[test]
fn a_directional_light_gives_irradiance_cos() {
    let dir = tempfile::tempdir().unwrap();
    let scene = plane_scene(
        dir.path(),
        "    lights: [Directional(direction: (0.3, -1, 0.2), irradiance: (2, 3, 4))],",
    );
    let img = render_exact(&scene);
    let cos = Vec3::new(0.3, -1.0, 0.2).normalize().y.abs();
    assert_pixels(
        &scene,
        &img,
        |_| {
            (
                Vec3::new(2.0, 3.0, 4.0) * (RHO / std::f32::consts::PI) * cos,
                0.0,
            )
        },
        "directional",
    );
}

/// Mitsuba's spot falloff (src/emitters/spot.cpp) along the unit direction d off the axis.
fn spot_falloff(axis: Vec3, d: Vec3, cutoff_deg: f32, beam_deg: f32) -> f32 {
    let cos = axis.dot(d);
    let (cutoff, beam) = (cutoff_deg.to_radians(), beam_deg.to_radians());
    if cos <= cutoff.cos() {
        0.0
    } else if cos >= beam.cos() {
        1.0
    } else {
        // The angle in f64: the GPU's must agree with the exact one.
        let angle = (f64::from(axis.cross(d).length())).atan2(f64::from(cos)) as f32;
        (cutoff - angle) / (cutoff - beam)
    }
}

#[test]
fn a_spot_light_falls_off_as_mitsubas() {
    let dir = tempfile::tempdir().unwrap();
    let light = Vec3::new(0.5, 3.0, -0.5);
    let target = Vec3::new(-0.5, 0.0, 0.5);
    let scene = plane_scene(
        dir.path(),
        "    lights: [Spot(position: (0.5, 3, -0.5), target: (-0.5, 0, 0.5), intensity: (40, 40, 40), cutoff_angle: 30, beam_width: 12)],",
    );
    let img = render_exact(&scene);
    let axis = (target - light).normalize();
    let mut partial = 0;
    assert_pixels(
        &scene,
        &img,
        |p| {
            let to = light - p;
            let r2 = to.length_squared();
            let falloff = spot_falloff(axis, -to.normalize(), 30.0, 12.0);
            partial += usize::from(falloff > 0.0 && falloff < 1.0);
            let full = 40.0 * (RHO / std::f32::consts::PI) * (to.y / r2.sqrt()) / r2;
            // On the ramp the falloff is (cutoff - angle) / (cutoff - beam): an f32 angle off
            // by a few ulps of 0.5 rad (3e-7 each), over the 0.31 rad ramp, moves it by ~5e-6.
            let ramp = falloff > 0.0 && falloff < 1.0;
            (
                Vec3::splat(full * falloff),
                if ramp { 5e-6 * full } else { 0.0 },
            )
        },
        "spot",
    );
    assert!(partial > 20, "only {partial} pixels in the transition ring");
}

/// Mitsuba's bitmap lookup (src/textures/bitmap.cpp) of an sRGB image at Mitsuba's uv (v = 0
/// at the top row): bilinear between texel centres, repeat wrap; written out here, not taken
/// from passgraph's texture code.
fn mitsuba_bitmap(rgb8: &[[u8; 3]], width: usize, height: usize, uv: glam::Vec2) -> Vec3 {
    let decode = |c: u8| {
        let c = f32::from(c) / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    let texel = |x: i64, y: i64| {
        let (x, y) = (
            x.rem_euclid(width as i64) as usize,
            y.rem_euclid(height as i64) as usize,
        );
        Vec3::from(rgb8[y * width + x].map(decode))
    };
    let p = uv * glam::Vec2::new(width as f32, height as f32) - 0.5;
    let (i, f) = (p.floor(), p - p.floor());
    let (x, y) = (i.x as i64, i.y as i64);
    (texel(x, y) * (1.0 - f.x) + texel(x + 1, y) * f.x) * (1.0 - f.y)
        + (texel(x, y + 1) * (1.0 - f.x) + texel(x + 1, y + 1) * f.x) * f.y
}

#[test]
fn a_textured_spot_projects_its_image_in_mitsubas_lookat_frame() {
    let dir = tempfile::tempdir().unwrap();
    // Every texel distinct, so a mirrored, swapped or rotated projection cannot pass.
    let (w, h) = (4usize, 3usize);
    let texels: Vec<[u8; 3]> = (0..w * h)
        .map(|i| {
            [
                (40 + 17 * i) as u8,
                (230 - 13 * i) as u8,
                (90 + 29 * (i % 5)) as u8,
            ]
        })
        .collect();
    image::RgbImage::from_raw(
        w as u32,
        h as u32,
        texels.iter().flatten().copied().collect(),
    )
    .unwrap()
    .save(dir.path().join("slide.png"))
    .unwrap();
    let (light, target, up) = (
        Vec3::new(0.3, 3.0, -0.2),
        Vec3::new(-0.2, 0.0, 0.3),
        Vec3::new(0.0, 0.0, 1.0),
    );
    let intensity = Vec3::new(40.0, 30.0, 20.0);
    let scene = plane_scene(
        dir.path(),
        "    lights: [Spot(position: (0.3, 3, -0.2), target: (-0.2, 0, 0.3), up: (0, 0, 1), intensity: (40, 30, 20), cutoff_angle: 35, beam_width: 20, texture: \"slide.png\")],",
    );
    let img = render_exact(&scene);
    // Mitsuba's Transform::look_at: x = normalize(up x dir), y = dir x x, z = dir.
    let z = (target - light).normalize();
    let x_axis = up.cross(z).normalize();
    let y_axis = z.cross(x_axis);
    let tan_cutoff = 35f32.to_radians().tan();
    let mut seen = std::collections::HashSet::new();
    assert_pixels(
        &scene,
        &img,
        |p| {
            let to = light - p;
            let r2 = to.length_squared();
            let d = -to.normalize();
            let falloff = spot_falloff(z, d, 35.0, 20.0);
            if falloff == 0.0 {
                return (Vec3::ZERO, 0.0);
            }
            let local = Vec3::new(d.dot(x_axis), d.dot(y_axis), d.dot(z));
            let uv = glam::Vec2::new(local.x, local.y) / (local.z * tan_cutoff) * 0.5 + 0.5;
            seen.insert(((uv.x * w as f32) as i32, (uv.y * h as f32) as i32));
            let full = intensity
                * mitsuba_bitmap(&texels, w, h, uv)
                * (RHO / std::f32::consts::PI)
                * (to.y / r2.sqrt())
                / r2;
            // On the ramp: a few ulps of the angle (1e-6) over the ramp's 15 degrees (the light
            // is seen from the shading point itself, not from the ray origin moved off it).
            // Everywhere: the uv's f32 rounding through the bilinear weights, a few ulps of uv
            // (1e-7) times the texel steps (< 1) times the size (4).
            let ramp = if falloff < 1.0 {
                1e-6 / 15f32.to_radians()
            } else {
                0.0
            };
            (full * falloff, (ramp + 4e-6) * full.max_element())
        },
        "textured spot",
    );
    assert!(seen.len() >= 10, "the cone shows only texels {seen:?}");
}

fn sphere_obj(center: Vec3, radius: f32, material: &str, obj: &mut ObjWriter) {
    let triangles: Vec<[Vec3; 3]> = icosphere(3)
        .triangles()
        .iter()
        .map(|t| t.map(|v| center + radius * v))
        .collect();
    obj.material(material).triangles(&triangles);
}

#[test]
fn white_furnace_a_lambertian_polyhedron_in_a_uniform_environment_reflects_rho_l() {
    let dir = tempfile::tempdir().unwrap();
    let mut obj = ObjWriter::new(&[Mtl {
        name: "white",
        kd: [RHO; 3],
        ke: [0.0; 3],
    }]);
    sphere_obj(Vec3::ZERO, 1.0, "white", &mut obj);
    let scene = obj.write(
        dir.path(),
        Vec3::new(0.0, 0.0, -4.0),
        Vec3::ZERO,
        Vec3::Y,
        40.0,
    );
    let l = Vec3::new(1.0, 0.5, 0.25);
    add_to_scene(
        &scene,
        "    environment: Environment(color: (1, 0.5, 0.25)),",
    );
    let frames = 16;
    let s = settings(common::render::PATHTRACER, &scene, SIZE, 3, &[]);
    let session = render(&s, frames);
    assert_clean(&session, frames, "furnace");
    let img = image(&session, CHANNELS);
    // Sphere pixels: those whose whole footprint is on the sphere (the camera ray through each
    // corner meets the unit sphere, far enough inside its silhouette that facets do not matter).
    let camera = load_scene(&scene).unwrap().camera;
    // Whether the camera ray through image point (px, py) meets the sphere of radius r.
    let meets = |px: f32, py: f32, r: f32| {
        let d = camera.to_gpu(SIZE, SIZE).ray_direction(SIZE, SIZE, px, py);
        let o = camera.eye();
        let b = o.dot(d);
        b * b - (o.length_squared() - r * r) > 0.0
    };
    let hits = |px: f32, py: f32| meets(px, py, 0.9);
    let misses = |px: f32, py: f32| !meets(px, py, 1.0);
    let (mut sphere, mut background) = (Vec::new(), 0);
    for y in 0..SIZE {
        for x in 0..SIZE {
            let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
                .map(|(dx, dy)| (x as f32 + dx, y as f32 + dy));
            let p = Vec3::from(img.pixels[(y * SIZE + x) as usize]);
            if corners.iter().all(|&(px, py)| hits(px, py)) {
                sphere.push(p);
            } else if corners.iter().all(|&(px, py)| misses(px, py)) {
                // Camera rays that miss see the environment exactly.
                assert!(
                    (p - l).abs().max_element() < 1e-6,
                    "background ({x}, {y}): {p}"
                );
                background += 1;
            }
        }
    }
    assert!(
        sphere.len() > 200 && background > 200,
        "{} {background}",
        sphere.len()
    );
    let n = sphere.len() as f64;
    for k in 0..3 {
        let mean = sphere.iter().map(|p| f64::from(p[k])).sum::<f64>() / n;
        let var = sphere
            .iter()
            .map(|p| (f64::from(p[k]) - mean).powi(2))
            .sum::<f64>()
            / (n - 1.0);
        let se = (var / n).sqrt();
        let want = f64::from(RHO * l[k]);
        assert!(
            (mean - want).abs() <= 5.0 * se,
            "channel {k}: mean {mean}, expected {want}, SE {se}"
        );
        assert!(
            se < 0.02 * want,
            "channel {k}: SE {se} too large to test anything"
        );
    }
}

/// A box bottom face at height 1 seen from below, over a ground square at y = 0.
fn ground_and_box(dir: &Path, extra: &str) -> PathBuf {
    let mut obj = ObjWriter::new(&[
        Mtl {
            name: "ground",
            kd: [RHO; 3],
            ke: [0.0; 3],
        },
        Mtl {
            name: "box",
            kd: [RHO; 3],
            ke: [0.0; 3],
        },
    ]);
    let a = 100.0;
    obj.material("ground").polygon(&[
        Vec3::new(-a, 0.0, -a),
        Vec3::new(-a, 0.0, a),
        Vec3::new(a, 0.0, a),
        Vec3::new(a, 0.0, -a),
    ]);
    // The bottom face of a box, facing down (toward the camera below it).
    obj.material("box").polygon(&[
        Vec3::new(-1.0, 1.0, -1.0),
        Vec3::new(1.0, 1.0, -1.0),
        Vec3::new(1.0, 1.0, 1.0),
        Vec3::new(-1.0, 1.0, 1.0),
    ]);
    let scene = obj.write(
        dir,
        Vec3::new(0.0, 0.5, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::Z,
        60.0,
    );
    add_to_scene(&scene, extra);
    scene
}

/// The direct light of the view's centre pixels (all on the box's bottom face).
fn centre_direct(scene: &Path) -> f32 {
    let s = settings(common::render::PATHTRACER, scene, 16, 0, &[]);
    let img = image(&render(&s, 4), "direct");
    (6..10)
        .flat_map(|y| (6..10).map(move |x| (x, y)))
        .map(|(x, y)| Vec3::from(img.pixels[y * 16 + x]).max_element())
        .fold(0.0, f32::max)
}

#[test]
fn a_point_light_below_the_ground_is_blocked_by_it() {
    // Were the light's position not counted among the scene's points, the ground would be a
    // hull face, which shadow rays skip, and the light would shine through it.
    let dir = tempfile::tempdir().unwrap();
    let scene = ground_and_box(
        dir.path(),
        "    lights: [Point(position: (0, -1, 0), intensity: (100, 100, 100))],",
    );
    let blocked = centre_direct(&scene);
    assert_eq!(blocked, 0.0, "the ground must block the light under it");
    // The same light between the ground and the box lights the face: the test can see light.
    let dir = tempfile::tempdir().unwrap();
    let scene = ground_and_box(
        dir.path(),
        "    lights: [Point(position: (0, 0.25, 0), intensity: (100, 100, 100))],",
    );
    assert!(centre_direct(&scene) > 1.0);
}

#[test]
fn environment_shadow_rays_are_blocked_by_hull_faces() {
    // The face looks down at a ground of half-size 100 from height 1: of its cosine-weighted
    // hemisphere only directions beyond atan(100) from the normal miss the ground, a fraction
    // of about 1 / (1 + 100^2) = 1e-4, so its direct light is at most ~1e-4 rho L. Shadow rays
    // that skipped the ground (a hull face) would see the sky below it: direct light rho L.
    let dir = tempfile::tempdir().unwrap();
    let scene = ground_and_box(
        dir.path(),
        "    environment: Environment(color: (1, 1, 1)),",
    );
    let direct = centre_direct(&scene);
    assert!(direct < 1e-2 * RHO, "direct {direct}");
}
