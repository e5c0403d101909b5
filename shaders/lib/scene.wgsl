// Scene data as the framework provides it. src/scene/gpu.rs mirrors these layouts byte for byte.

// Set by the framework from the scene (pipeline-overridable constants).
override scene_light_count: u32 = 0u;
override scene_has_specular: bool = true;

// One triangle, in BVH order; `material` indexes `scene.materials`.
struct Triangle {
    p0: vec3<f32>,
    material: u32,
    p1: vec3<f32>,
    pad1: u32,
    p2: vec3<f32>,
    pad2: u32,
}

// Normalised Blinn-Phong: f = kd/pi + ks (ns + 8)/(8 pi) max(0, n.h)^ns; ke is emitted radiance.
struct Material {
    kd: vec3<f32>,
    ns: f32,
    ks: vec3<f32>,
    pad0: f32,
    ke: vec3<f32>,
    pad1: f32,
}

// A threaded BVH node (32 bytes). Interior: count == 0, `a` is the miss link (skip); the hit
// link is implicit (this index + 1). Leaf: count > 0 triangles from index `a`; a leaf's next
// node is always this index + 1. Traversal ends at index == arrayLength.
struct BvhNode {
    lo: vec3<f32>,
    a: u32,
    hi: vec3<f32>,
    count: u32,
}

// Pinhole camera. `right` and `up` are scaled so that a pixel's direction is
// normalize(forward + sx * right + sy * up) with sx, sy in [-1, 1] (sy = +1 at the top row).
struct Camera {
    eye: vec3<f32>,
    pad0: f32,
    forward: vec3<f32>,
    pad1: f32,
    right: vec3<f32>,
    pad2: f32,
    up: vec3<f32>,
    pad3: f32,
}

// Per-frame values. `accumulated` is how many frames the result already holds (0: restart).
struct Frame {
    index: u32,
    accumulated: u32,
    width: u32,
    height: u32,
    seed: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}
