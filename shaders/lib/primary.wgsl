// A primary ray and its closest hit, as intersect stores it (ray_texture.wgsl) or a fused pass
// traces it.

const NO_HIT: u32 = 0xffffffffu;

struct Primary {
    origin: vec3<f32>,
    dir: vec3<f32>,
    t: f32,
    u: f32,
    v: f32,
    triangle: u32,
}
