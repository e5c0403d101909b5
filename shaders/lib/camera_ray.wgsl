// The primary ray through a point of a pixel. The including shader declares `camera` and
// `frame` and includes scene.wgsl.

// The direction from camera.eye through pixel `pixel` of the frame (of its tile, when the image
// is rendered in tiles) at sub-pixel position u in [0, 1)^2.
fn camera_ray_dir(pixel: vec2<u32>, u: vec2<f32>) -> vec3<f32> {
    let size = vec2<f32>(frame.image_size);
    let s = (vec2<f32>(pixel + frame.image_origin) + u) / size;
    let sx = 2.0 * s.x - 1.0;
    let sy = 1.0 - 2.0 * s.y;
    return normalize(camera.forward + sx * camera.right + sy * camera.up);
}
