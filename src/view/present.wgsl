// Shows the linear image on the window: one triangle covering the target, each fragment takes
// the nearest image texel (the target may be larger than the image).

// 1 when the target format stores what the shader writes (not *Srgb): encode here instead.
override encode_srgb: bool = false;

@group(0) @binding(0) var image: texture_2d<f32>;

struct Varyings {
    @builtin(position) position: vec4f,
    @location(0) uv: vec2f,
}

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> Varyings {
    // (-1,-1), (3,-1), (-1,3): a triangle whose inside covers clip space.
    let xy = vec2f(f32((i << 1u) & 2u), f32(i & 2u)) * 2.0 - 1.0;
    var out: Varyings;
    out.position = vec4f(xy, 0.0, 1.0);
    // Image rows go down, clip-space y goes up.
    out.uv = vec2f(xy.x * 0.5 + 0.5, 0.5 - xy.y * 0.5);
    return out;
}

fn to_srgb(c: f32) -> f32 {
    if c <= 0.0031308 {
        return 12.92 * c;
    }
    return 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}

@fragment
fn fs_main(in: Varyings) -> @location(0) vec4f {
    let dims = textureDimensions(image);
    let texel = min(vec2u(max(in.uv, vec2f(0.0)) * vec2f(dims)), dims - 1u);
    var rgb = textureLoad(image, texel, 0).rgb;
    // max(NaN, 0) may be NaN on some drivers; the select keeps a broken pixel black.
    rgb = select(vec3f(0.0), clamp(rgb, vec3f(0.0), vec3f(1.0)), rgb == rgb);
    if encode_srgb {
        rgb = vec3f(to_srgb(rgb.r), to_srgb(rgb.g), to_srgb(rgb.b));
    }
    return vec4f(rgb, 1.0);
}
