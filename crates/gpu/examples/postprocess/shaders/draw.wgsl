// Triangle 0 covers the whole viewport at depth 0.75 in colour A; every later triangle k covers
// the left half at depth 0.75 - 0.25 k (nearer) in colour B / k. With two triangles the left
// half is B and the right half A.
struct Varyings {
    @builtin(position) position: vec4<f32>,
    @location(0) @interpolate(flat) triangle: u32,
}

const A: vec4<f32> = vec4<f32>(0.2, 0.4, 0.8, 1.0);
const B: vec4<f32> = vec4<f32>(0.9, 0.3, 0.1, 1.0);

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> Varyings {
    let corner = i % 3u;
    let k = i / 3u;
    var xy = vec2<f32>(select(-1.0, 3.0, corner == 1u), select(-1.0, 3.0, corner == 2u));
    if k > 0u {
        // (-3, -1), (0, -1), (0, 3): its right edge is x = 0 and it covers the left half.
        xy = vec2<f32>(select(-3.0, 0.0, corner != 0u), select(-1.0, 3.0, corner == 2u));
    }
    var out: Varyings;
    out.triangle = k;
    out.position = vec4<f32>(xy, 0.75 - 0.25 * f32(min(k, 2u)), 1.0);
    return out;
}

@fragment
fn fs_main(in: Varyings) -> @location(0) vec4<f32> {
    if in.triangle == 0u {
        return A;
    }
    return B / f32(in.triangle);
}
