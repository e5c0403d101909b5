// Image textures from scene.textures (a texel view: src/scene/texture.rs): texel i < count is
// texture i's header (first texel, width, height, mode: bit 0 nearest, bits 1-2 the wrap
// mode, 0 repeat, 1 mirror, 2 clamp: Mitsuba's bitmap filter_type and wrap_mode); the images follow as linear RGBA f32 texels,
// row-major, row 0 the image's top row.
//
// The includer includes lib/scene.wgsl first (scene_texel, Material, NO_TEXTURE,
// scene_has_textures) and binds scene.textures as texture_storage_2d<rgba32uint, read>.

// Mitsuba's luminance weights: a scalar map (map_Pr, map_d) of an RGB image reads its luminance,
// as Mitsuba's bitmap eval_1 does (a grey image: its value).
const TEXTURE_LUMINANCE: vec3<f32> = vec3<f32>(0.212671, 0.715160, 0.072169);

fn texture_wrap(i: i32, size: i32) -> i32 {
    let r = i % size;
    return select(r, r + size, r < 0);
}

// Texel index i of an axis of `size` texels under wrap mode `wrap` (drjit's texture wrap).
fn texture_wrap_mode(i: i32, size: i32, wrap: u32) -> i32 {
    if (wrap == 2u) {
        return clamp(i, 0, size - 1);
    }
    if (wrap == 1u) {
        let r = texture_wrap(i, 2 * size);
        return select(r, 2 * size - 1 - r, r >= size);
    }
    return texture_wrap(i, size);
}

// Texture `index` at uv, as Mitsuba 3's bitmap texture looks it up: bilinear between texel
// centres, repeat wrap, v = 0 at the image's bottom row (Mitsuba's loaders store 1 - v and its
// rows run top to bottom).
fn texture_bilinear(view: texture_storage_2d<rgba32uint, read>, index: u32, uv: vec2<f32>) -> vec4<f32> {
    let header = scene_texel(view, index);
    let size = vec2<i32>(header.yz);
    let wrap = (header.w >> 1u) & 3u;
    if ((header.w & 1u) != 0u) {
        // Nearest: the texel (u, 1 - v) * size lies in.
        let n = floor(vec2<f32>(uv.x, 1.0 - uv.y) * vec2<f32>(size));
        let x = texture_wrap_mode(i32(n.x), size.x, wrap);
        let y = texture_wrap_mode(i32(n.y), size.y, wrap);
        return bitcast<vec4<f32>>(scene_texel(view, header.x + u32(y * size.x + x)));
    }
    let p = fma(vec2<f32>(uv.x, 1.0 - uv.y), vec2<f32>(size), vec2<f32>(-0.5));
    let i = floor(p);
    let w1 = p - i;
    let w0 = 1.0 - w1;
    let x0 = texture_wrap_mode(i32(i.x), size.x, wrap);
    let x1 = texture_wrap_mode(i32(i.x) + 1, size.x, wrap);
    let y0 = u32(texture_wrap_mode(i32(i.y), size.y, wrap) * size.x);
    let y1 = u32(texture_wrap_mode(i32(i.y) + 1, size.y, wrap) * size.x);
    let f00 = bitcast<vec4<f32>>(scene_texel(view, header.x + y0 + u32(x0)));
    let f10 = bitcast<vec4<f32>>(scene_texel(view, header.x + y0 + u32(x1)));
    let f01 = bitcast<vec4<f32>>(scene_texel(view, header.x + y1 + u32(x0)));
    let f11 = bitcast<vec4<f32>>(scene_texel(view, header.x + y1 + u32(x1)));
    return (f00 * w0.x + f10 * w1.x) * w0.y + (f01 * w0.x + f11 * w1.x) * w1.y;
}

// The derivative of texture `index`'s bilinear luminance with respect to (u, v), as Mitsuba 3's
// bitmap eval_1_grad: the four texels' luminance differences times the resolution (a bump map's
// slope). Mitsuba's v runs down the rows, so its v derivative is this one's negative.
fn texture_gradient(view: texture_storage_2d<rgba32uint, read>, index: u32, uv: vec2<f32>) -> vec2<f32> {
    let header = scene_texel(view, index);
    let size = vec2<i32>(header.yz);
    let p = fma(vec2<f32>(uv.x, 1.0 - uv.y), vec2<f32>(size), vec2<f32>(-0.5));
    let i = floor(p);
    let w1 = p - i;
    let w0 = 1.0 - w1;
    let x0 = texture_wrap(i32(i.x), size.x);
    let x1 = texture_wrap(i32(i.x) + 1, size.x);
    let y0 = u32(texture_wrap(i32(i.y), size.y) * size.x);
    let y1 = u32(texture_wrap(i32(i.y) + 1, size.y) * size.x);
    let f00 = dot(bitcast<vec4<f32>>(scene_texel(view, header.x + y0 + u32(x0))).rgb, TEXTURE_LUMINANCE);
    let f10 = dot(bitcast<vec4<f32>>(scene_texel(view, header.x + y0 + u32(x1))).rgb, TEXTURE_LUMINANCE);
    let f01 = dot(bitcast<vec4<f32>>(scene_texel(view, header.x + y1 + u32(x0))).rgb, TEXTURE_LUMINANCE);
    let f11 = dot(bitcast<vec4<f32>>(scene_texel(view, header.x + y1 + u32(x1))).rgb, TEXTURE_LUMINANCE);
    let d_row = fma(w0.y, f10 - f00, w1.y * (f11 - f01));
    let d_column = fma(w0.x, f01 - f00, w1.x * (f11 - f10));
    return vec2<f32>(f32(size.x) * d_row, -f32(size.y) * d_column);
}

// The material at uv: each map replaces its constant (map_kd: kd, map_ks: ks, map_pr: the
// roughness r, alpha = r^2, map_d: opacity). m unchanged when no used material has a map
// (specialised away).
fn material_at(m: Material, textures: texture_storage_2d<rgba32uint, read>, uv: vec2<f32>) -> Material {
    if (!scene_has_textures) {
        return m;
    }
    var r = m;
    if (m.map_kd != NO_TEXTURE) {
        r.kd = texture_bilinear(textures, m.map_kd, uv).rgb;
    }
    if (m.map_ks != NO_TEXTURE) {
        r.ks = texture_bilinear(textures, m.map_ks, uv).rgb;
    }
    if (m.map_pr != NO_TEXTURE) {
        let roughness = dot(texture_bilinear(textures, m.map_pr, uv).rgb, TEXTURE_LUMINANCE);
        r.alpha = roughness * roughness;
    }
    if (m.map_d != NO_TEXTURE) {
        r.opacity = dot(texture_bilinear(textures, m.map_d, uv).rgb, TEXTURE_LUMINANCE);
    }
    return r;
}
