// The primary ray through a point of a pixel (src/scene/camera.rs mirrors it: CameraDesc::ray).
// The projection is the scene_camera_kind override, so a pinhole specialises to its plain ray.
// The including shader declares `camera` and `frame` and includes scene.wgsl, rng.wgsl and
// sampler.wgsl.
#include "sampling.wgsl"
#include "pixel_filter.wgsl"

const CAMERA_PINHOLE: u32 = 0u;
const CAMERA_THIN_LENS: u32 = 1u;
const CAMERA_ORTHOGRAPHIC: u32 = 2u;

struct CameraRay {
    origin: vec3<f32>,
    dir: vec3<f32>,
}

// The direction from camera.eye through pixel `pixel` of the frame (of its tile, when the image
// is rendered in tiles) at sub-pixel position u (in [0, 1)^2 for a box filter): the pinhole's.
fn camera_ray_dir(pixel: vec2<u32>, u: vec2<f32>) -> vec3<f32> {
    let size = vec2<f32>(frame.image_size);
    let s = (vec2<f32>(pixel + frame.image_origin) + u) / size;
    let sx = 2.0 * s.x - 1.0;
    let sy = 1.0 - 2.0 * s.y;
    return normalize(camera.forward + sx * camera.right + sy * camera.up);
}

// The ray through sub-pixel position u of `pixel`, from lens sample `lens` in [0, 1)^2 (unused
// without a lens). Thin lens (Mitsuba's thinlens): from a point uniform on the aperture disk
// (concentric map) in the image plane, through the point where the pinhole ray of u meets the
// focus plane, focus_distance along forward (a unit vector, so at focus_distance * d).
// Orthographic: along forward from eye + sx right + sy up.
fn camera_ray(pixel: vec2<u32>, u: vec2<f32>, lens: vec2<f32>) -> CameraRay {
    if scene_camera_kind == CAMERA_PINHOLE {
        return CameraRay(camera.eye, camera_ray_dir(pixel, u));
    }
    let size = vec2<f32>(frame.image_size);
    let s = (vec2<f32>(pixel + frame.image_origin) + u) / size;
    let sx = 2.0 * s.x - 1.0;
    let sy = 1.0 - 2.0 * s.y;
    if scene_camera_kind == CAMERA_ORTHOGRAPHIC {
        return CameraRay(camera.eye + sx * camera.right + sy * camera.up, camera.forward);
    }
    let d = camera.forward + sx * camera.right + sy * camera.up;
    let disk = camera.aperture_radius * square_to_disk_concentric(lens);
    let offset = disk.x * normalize(camera.right) + disk.y * normalize(camera.up);
    return CameraRay(camera.eye + offset, normalize(camera.focus_distance * d - offset));
}

// The lens sample of `source` (DIM_LENS; none drawn without a lens).
fn camera_lens_sample(source: SampleSource) -> vec2<f32> {
    if scene_camera_kind != CAMERA_THIN_LENS {
        return vec2<f32>(0.5);
    }
    return sample_2d(source, DIM_LENS);
}

// The primary ray of `pixel` for `source`: its film sample (DIM_PIXEL) through the pixel filter
// (cut to the image, as Mitsuba's film), or the pixel's centre when `jitter` is off, and its
// lens sample.
fn camera_sample_ray(pixel: vec2<u32>, source: SampleSource, jitter: bool) -> CameraRay {
    let corner = vec2<f32>(pixel + frame.image_origin);
    let film = pixel_filter_position_in_image(sample_2d(source, DIM_PIXEL), corner, vec2<f32>(frame.image_size));
    let u = select(vec2<f32>(0.5), film, jitter);
    return camera_ray(pixel, u, camera_lens_sample(source));
}
