// The primary ray through a point of a pixel. The including shader declares `camera` and
// `frame` and includes scene.wgsl.

// The direction from camera.eye through pixel `pixel` at sub-pixel position u in [0, 1)^2.
fn camera_ray_dir(pixel: vec2<u32>, u: vec2<f32>) -> vec3<f32> {
    let size = vec2<f32>(f32(frame.width), f32(frame.height));
    let s = (vec2<f32>(pixel) + u) / size;
    let sx = 2.0 * s.x - 1.0;
    let sy = 1.0 - 2.0 * s.y;
    return normalize(camera.forward + sx * camera.right + sy * camera.up);
}
