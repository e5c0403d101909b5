//! The CPU ray generation (src/scene/camera.rs `CameraDesc::ray`, the mirror of
//! shaders/lib/camera_ray.wgsl): Mitsuba's field-of-view axes, the thin lens's focus plane and
//! aperture, the orthographic camera's parallel rays and its extent.

use glam::{Vec2, Vec3};
use passgraph::scene::camera::square_to_disk_concentric;
use passgraph::scene::{CameraDesc, CameraKind, FovAxis, Lens, Projection};

fn perspective(fov_degrees: f32, fov_axis: FovAxis, lens: Option<Lens>) -> CameraDesc {
    CameraDesc::with_projection(
        Vec3::ZERO,
        Vec3::new(0.0, 0.0, -1.0),
        Vec3::Y,
        Projection::Perspective {
            fov_degrees,
            fov_axis,
            lens,
        },
    )
    .unwrap()
}

/// (x, y) of the top-left corner ray's direction over its depth: tan of the half fields of view.
fn corner_tangents(camera: &CameraDesc, w: u32, h: u32) -> (f32, f32) {
    let (_, d) = camera.ray(w, h, 0.0, 0.0, Vec2::splat(0.5));
    let depth = -d.z;
    // right is +x and up +y for this camera; the corner is left and up.
    (-d.x / depth, d.y / depth)
}

#[test]
fn fov_axes_match_mitsubas_perspective_sensor() {
    // Mitsuba 3.9.0's perspective sensor, fov 50, top-left film corner (sample (0, 0)): the
    // direction's x / z and y / z (its camera x points left, so the signs are its own).
    let mitsuba = [
        (FovAxis::X, 64, 32, 0.466_307_63, 0.233_153_82),
        (FovAxis::X, 32, 64, 0.466_307_6, 0.932_615_2),
        (FovAxis::Y, 64, 32, 0.932_615_1, 0.466_307_57),
        (FovAxis::Y, 32, 64, 0.233_153_85, 0.466_307_7),
        (FovAxis::Diagonal, 64, 32, 0.417_078_24, 0.208_539_12),
        (FovAxis::Diagonal, 32, 64, 0.208_539_12, 0.417_078_24),
        (FovAxis::Smaller, 64, 32, 0.932_615_1, 0.466_307_57),
        (FovAxis::Smaller, 32, 64, 0.466_307_6, 0.932_615_2),
        (FovAxis::Larger, 64, 32, 0.466_307_63, 0.233_153_82),
        (FovAxis::Larger, 32, 64, 0.233_153_85, 0.466_307_7),
    ];
    for (axis, w, h, tx, ty) in mitsuba {
        let (x, y) = corner_tangents(&perspective(50.0, axis, None), w, h);
        assert!(
            (x - tx).abs() < 1e-5 && (y - ty).abs() < 1e-5,
            "{axis:?} {w}x{h}: ({x}, {y}) vs Mitsuba ({tx}, {ty})"
        );
    }
}

#[test]
fn fov_y_is_the_pinhole_it_always_was() {
    let old = CameraDesc::new(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0), Vec3::Y, 40.0).unwrap();
    assert_eq!(old, perspective(40.0, FovAxis::Y, None));
    assert_eq!(old.kind(), CameraKind::Pinhole);
    let gpu = old.to_gpu(64, 32);
    assert_eq!((gpu.aperture_radius, gpu.focus_distance), (0.0, 0.0));
}

const LENS: Lens = Lens {
    aperture_radius: 0.5,
    focus_distance: 7.0,
};

#[test]
fn thin_lens_rays_of_one_film_point_meet_on_the_focus_plane() {
    let camera = perspective(60.0, FovAxis::X, Some(LENS));
    assert_eq!(camera.kind(), CameraKind::ThinLens);
    let pinhole = perspective(60.0, FovAxis::X, None);
    for (px, py) in [(3.25, 10.5), (0.0, 0.0), (31.9, 15.1)] {
        let (_, through) = pinhole.ray(32, 16, px, py, Vec2::splat(0.5));
        // The pinhole ray meets the focus plane (z = -7, forward -z) here.
        let focus = through * (LENS.focus_distance / -through.z);
        for lens in [
            Vec2::new(0.1, 0.9),
            Vec2::new(0.99, 0.5),
            Vec2::new(0.3, 0.02),
        ] {
            let (o, d) = camera.ray(32, 16, px, py, lens);
            // The origin lies in the lens plane (z = 0) within the aperture.
            assert!(
                o.z.abs() < 1e-6 && o.length() <= LENS.aperture_radius * 1.0001,
                "{o}"
            );
            assert!((d.length() - 1.0).abs() < 1e-5);
            let t = (-LENS.focus_distance - o.z) / d.z;
            let hit = o + t * d;
            assert!((hit - focus).length() < 1e-4, "{hit} vs {focus}");
        }
        // The lens's centre is the pinhole.
        let (o, d) = camera.ray(32, 16, px, py, Vec2::splat(0.5));
        assert!(o.length() < 1e-7 && (d - through).length() < 1e-6);
    }
}

#[test]
fn lens_points_are_uniform_on_the_disk() {
    // The concentric map is measure-preserving: the fraction of a stratified grid of the square
    // inside radius r is r^2.
    let n = 200;
    for r in [0.3f32, 0.6, 0.9] {
        let inside = (0..n * n)
            .filter(|i| {
                let u = Vec2::new(
                    ((i % n) as f32 + 0.5) / n as f32,
                    ((i / n) as f32 + 0.5) / n as f32,
                );
                square_to_disk_concentric(u).length() < r
            })
            .count();
        let fraction = inside as f32 / (n * n) as f32;
        assert!((fraction - r * r).abs() < 0.005, "r {r}: {fraction}");
    }
}

#[test]
fn orthographic_rays_are_parallel_and_span_the_width() {
    let camera = CameraDesc::with_projection(
        Vec3::new(1.0, 2.0, 3.0),
        Vec3::new(1.0, 2.0, -10.0),
        Vec3::Y,
        Projection::Orthographic { width: 4.0 },
    )
    .unwrap();
    assert_eq!(camera.kind(), CameraKind::Orthographic);
    // 32x16: 4 units wide, 2 high; Mitsuba's sensor maps film (0, 0) to camera (+1, +1/aspect),
    // its x pointing left: the top-left corner.
    let (top_left, d0) = camera.ray(32, 16, 0.0, 0.0, Vec2::splat(0.5));
    let (bottom_right, d1) = camera.ray(32, 16, 32.0, 16.0, Vec2::splat(0.5));
    assert!(
        (top_left - Vec3::new(-1.0, 3.0, 3.0)).length() < 1e-5,
        "{top_left}"
    );
    assert!(
        (bottom_right - Vec3::new(3.0, 1.0, 3.0)).length() < 1e-5,
        "{bottom_right}"
    );
    assert_eq!(d0, Vec3::new(0.0, 0.0, -1.0));
    assert_eq!(d1, d0);
}
