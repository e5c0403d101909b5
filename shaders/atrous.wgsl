// One iteration of the edge-avoiding à-trous wavelet filter (Dammertz et al. 2010): a 5x5
// B3-spline kernel whose taps are `step` pixels apart (1, 2, 4, ... over the iterations, so five
// passes cover 61x61 pixels with 25 taps each), each tap weighted down by how much its colour,
// normal and position differ from the centre's.
// xyz: (demodulated) colour; w: sample count, carried through.

struct Params {
    step: u32,
    // Colour tolerance of the first iteration at one sample per pixel. Divided by
    // sqrt(samples), since the noise of a Monte Carlo mean falls like that and the tolerance
    // should follow the noise; and by `step`, halving it each iteration as Dammertz et al. do,
    // since each iteration's input is smoother (without it the wide late iterations average
    // away smooth shading gradients: 2.3x the RMSE off the light at 16 frames, 128x128).
    sigma_color: f32,
    // Tolerance on the difference of unit normals (|n_p - n_q|).
    sigma_normal: f32,
    // Tolerance on the tap's distance from the centre's tangent plane, relative to its
    // distance from the centre (a sine): independent of the scene's scale and of `step`.
    sigma_plane: f32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var src: texture_storage_2d<rgba32float, read>;
@group(0) @binding(2) var normal: texture_storage_2d<rgba32float, read>;
@group(0) @binding(3) var position: texture_storage_2d<rgba32float, read>;
@group(0) @binding(4) var dst: texture_storage_2d<rgba32float, write>;

const KERNEL = array<f32, 5>(0.0625, 0.25, 0.375, 0.25, 0.0625);

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<i32>(textureDimensions(dst));
    let p = vec2<i32>(id.xy);
    if any(p >= size) {
        return;
    }
    let centre = textureLoad(src, p);
    let n_p = textureLoad(normal, p).xyz;
    let x_p = textureLoad(position, p).xyz;
    let samples = max(centre.w, 1.0);
    let sigma_color = params.sigma_color / f32(params.step);
    let inv_color = samples / (sigma_color * sigma_color);
    let inv_normal = 1.0 / (params.sigma_normal * params.sigma_normal);
    let inv_plane = 1.0 / (params.sigma_plane * params.sigma_plane);
    // Averaged over the accumulation, a normal at a silhouette is shorter than 1; its plane
    // is still the best guess of the surface the pixel shows.
    let plane_n = n_p / max(length(n_p), 1.0e-6);

    var sum = vec3<f32>(0.0);
    var weights = 0.0;
    for (var j = -2; j <= 2; j++) {
        for (var i = -2; i <= 2; i++) {
            let q = p + vec2<i32>(i, j) * i32(params.step);
            if any(q < vec2<i32>(0)) || any(q >= size) {
                continue;
            }
            let c_q = textureLoad(src, q).xyz;
            let dc = c_q - centre.xyz;
            let dn = textureLoad(normal, q).xyz - n_p;
            let dx = textureLoad(position, q).xyz - x_p;
            let sine = dot(plane_n, dx) / max(length(dx), 1.0e-20);
            let distance = dot(dc, dc) * inv_color + dot(dn, dn) * inv_normal
                + sine * sine * inv_plane;
            let w = KERNEL[i + 2] * KERNEL[j + 2] * exp(-distance);
            sum += w * c_q;
            weights += w;
        }
    }
    // The centre tap always has weight KERNEL[2]^2 > 0, so `weights` is never 0.
    textureStore(dst, p, vec4<f32>(sum / weights, centre.w));
}
