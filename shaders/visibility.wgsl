// Visibility: the raster pass of graphs/pathtracer-raster.ron. Draws every scene triangle
// without vertex buffers (vertex i is corner i % 3 of triangle i / 3, read from scene.triangles)
// through the frame's jittered camera (lib/frame_jitter.wgsl), and keeps per pixel the triangle
// nearest along the pixel's ray: the fragment intersects that ray with the triangle's plane and
// writes the distance as its depth, so the depth test compares exactly what intersect compares.
// vbuffer (rgba32uint): triangle + 1 (0: none), barycentrics u, v (of p1, p2) and t as f32 bits.
#include "lib/provided_view.wgsl"
#include "lib/rng.wgsl"
#include "lib/sampler.wgsl"
#include "lib/camera_ray.wgsl"
#include "lib/frame_jitter.wgsl"

@group(0) @binding(0) var triangles: texture_2d<u32>;

// Depth = t / (t + DEPTH_SCALE): increasing in t, and in the low range of [0, 1) where f32 keeps
// t's relative precision for any scene size up to about DEPTH_SCALE.
const DEPTH_SCALE: f32 = 1.0e6;
// Clip space's near plane, in scene units along the view axis: only geometry behind the camera
// (or touching it) is clipped; the fragment depth replaces the fixed-function one.
const NEAR: f32 = 1.0e-5;

struct Varyings {
    @builtin(position) position: vec4<f32>,
    @location(0) @interpolate(flat) triangle: u32,
}

// Texel i of the triangles' texel view (see scene_texel), as a sampled texture: vertex shaders
// read no storage textures.
fn triangle_texel(i: u32) -> vec3<f32> {
    let width = textureDimensions(triangles).x;
    let texel = textureLoad(triangles, vec2<u32>(i & (width - 1u), i >> countTrailingZeros(width)), 0);
    return bitcast<vec3<f32>>(texel.xyz);
}

@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> Varyings {
    let p = triangle_texel(index);
    // The camera's frame: forward is the view axis, right and up are scaled so that a pixel's
    // direction is forward + sx right + sy up (sx, sy in [-1, 1]).
    let d = p - camera.eye;
    let z = dot(d, camera.forward) / dot(camera.forward, camera.forward);
    let sx = dot(d, camera.right) / dot(camera.right, camera.right);
    let sy = dot(d, camera.up) / dot(camera.up, camera.up);
    // The fragment of pixel (x, y) is shaded at its centre, (x + 0.5, y + 0.5) in framebuffer
    // coordinates; shifting the image by (0.5, 0.5) - jitter makes it see pixel + jitter.
    let size = vec2<f32>(f32(frame.width), f32(frame.height));
    let shift = 2.0 * (vec2<f32>(0.5) - frame_jitter()) / size;
    var out: Varyings;
    out.position = vec4<f32>(sx + shift.x * z, sy - shift.y * z, z - NEAR, z);
    out.triangle = index / 3u;
    return out;
}

struct FragmentOut {
    @location(0) ids: vec4<u32>,
    @builtin(frag_depth) depth: f32,
}

@fragment
fn fs_main(in: Varyings) -> FragmentOut {
    let pixel = vec2<u32>(in.position.xy);
    let dir = camera_ray_dir(pixel, frame_jitter());
    let p0 = triangle_texel(3u * in.triangle);
    let e1 = triangle_texel(3u * in.triangle + 1u) - p0;
    let e2 = triangle_texel(3u * in.triangle + 2u) - p0;
    let n = cross(e1, e2);
    let nn = dot(n, n);
    // The ray meets the triangle's plane at t; barycentrics of that point. A plane seen
    // edge-on gives no usable t (infinite, NaN, or behind through rounding): such a fragment is
    // kept behind everything else drawn here.
    let t_plane = dot(p0 - camera.eye, n) / dot(dir, n);
    let usable = t_plane > 0.0 && t_plane < 3.0e38;
    let t = select(0.0, t_plane, usable);
    let q = camera.eye + t * dir - p0;
    let u = dot(cross(q, e2), n) / nn;
    let v = dot(cross(e1, q), n) / nn;
    var out: FragmentOut;
    out.ids = vec4<u32>(in.triangle + 1u, bitcast<u32>(u), bitcast<u32>(v), bitcast<u32>(t));
    out.depth = select(1.0, t / (t + DEPTH_SCALE), usable);
    return out;
}
