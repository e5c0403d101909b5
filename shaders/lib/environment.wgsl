// The environment (src/scene/environment.rs is the CPU twin): radiance from infinitely far
// away, seen by rays that leave the scene and sampled by next-event estimation. Its record in
// scene.lights is entry scene_environment:
//   map (LIGHT_ENVIRONMENT_MAP): p0, e1, e2 the rows of the world-to-image rotation, second the
//     image's index in scene.textures (Mitsuba's layout: W + 1 columns, the last a copy of the
//     first; H rows, row 0 at theta = 0), first where its sampling tables start in
//     scene.light_power (the marginal CDF over the H - 1 rows of cells, then each row's CDF over
//     its W cells).
//   uniform (LIGHT_ENVIRONMENT_CONSTANT): e1 the radiance.
// The includer declares `lights`, `light_power` and `textures` and includes scene.wgsl and
// emitters.wgsl.

fn scene_has_environment() -> bool {
    return scene_environment != NO_LIGHT;
}

fn environment_is_map(env: Light) -> bool {
    return scene_has_light_kind(LIGHT_ENVIRONMENT_MAP) && env.material == LIGHT_TAG + LIGHT_ENVIRONMENT_MAP;
}

// The map's image coordinates of the world direction d: Mitsuba's uv, u shifted by half a
// texel and wrapped into [0, 1); t at most 1, so straight down reads the bottom row, as
// Mitsuba does (its acos(-1) / pi stays just below 1; src/scene/environment_image.rs).
fn environment_uv(env: Light, d: vec3<f32>, columns: f32) -> vec2<f32> {
    let v = vec3<f32>(dot(env.p0, d), dot(env.e1, d), dot(env.e2, d));
    let u = atan2(v.x, -v.z) * (0.5 / PI) - 0.5 / columns;
    return vec2<f32>(u - floor(u), min(acos(clamp(v.y, -1.0, 1.0)) / PI, 1.0));
}

fn environment_texel(i: u32) -> vec3<f32> {
    return bitcast<vec4<f32>>(scene_texel(textures, i)).rgb;
}

// Radiance arriving along -d (seen looking along d): bilinear between the four texels around
// (u W, t (H - 1)), as Mitsuba's envmap eval.
fn environment_radiance(env: Light, d: vec3<f32>) -> vec3<f32> {
    if !environment_is_map(env) {
        return env.e1;
    }
    let header = scene_texel(textures, env.second);
    let columns = header.y - 1u;
    let rows = header.z - 1u;
    let p = environment_uv(env, d, f32(columns)) * vec2<f32>(f32(columns), f32(rows));
    let pos = min(vec2<u32>(p), vec2<u32>(columns - 1u, rows - 1u));
    let f = p - vec2<f32>(pos);
    let i = header.x + pos.y * header.y + pos.x;
    let top = mix(environment_texel(i), environment_texel(i + 1u), f.x);
    let bottom = mix(environment_texel(i + header.y), environment_texel(i + header.y + 1u), f.x);
    return mix(top, bottom, f.y);
}

fn environment_cdf(i: u32) -> f32 {
    return scene_light_power(light_power, i);
}

// The last k in [0, n) with cdf[k] <= x, for the n steps of the CDF at `base`.
fn environment_invert(base: u32, n: u32, x: f32) -> u32 {
    var lo = 0u;
    var hi = n - 1u;
    while lo < hi {
        let mid = (lo + hi + 1u) / 2u;
        if environment_cdf(base + mid) <= x {
            lo = mid;
        } else {
            hi = mid - 1u;
        }
    }
    return lo;
}

// The probability of cell (i, j): the product of its two CDF steps.
fn environment_cell(env: Light, columns: u32, rows: u32, i: u32, j: u32) -> f32 {
    let row = env.first + rows + 1u + j * (columns + 1u);
    let pj = environment_cdf(env.first + j + 1u) - environment_cdf(env.first + j);
    return pj * (environment_cdf(row + i + 1u) - environment_cdf(row + i));
}

// The solid-angle density with which environment_sample draws the world direction d.
fn environment_pdf(env: Light, d: vec3<f32>) -> f32 {
    if !environment_is_map(env) {
        return 0.25 / PI;
    }
    let header = scene_texel(textures, env.second);
    let columns = header.y - 1u;
    let rows = header.z - 1u;
    let uv = environment_uv(env, d, f32(columns));
    let i = min(u32(uv.x * f32(columns)), columns - 1u);
    let j = min(u32(uv.y * f32(rows)), rows - 1u);
    let v = vec3<f32>(dot(env.p0, d), dot(env.e1, d), dot(env.e2, d));
    let sin_theta = sqrt(v.x * v.x + v.z * v.z);
    if sin_theta <= 0.0 {
        return 0.0;
    }
    return environment_cell(env, columns, rows, i, j) * f32(columns * rows) / (2.0 * PI * PI * sin_theta);
}

// x's place in [0, 1) inside the CDF step [a, b).
fn environment_within(x: f32, a: f32, b: f32) -> f32 {
    return select(0.0, clamp((x - a) / (b - a), 0.0, 0.99999994), b > a);
}

// A direction toward the environment drawn with the 2D sample u: a cell by its two CDFs, a
// point uniform in it; a uniform environment: uniform on the sphere.
fn environment_sample(env: Light, u: vec2<f32>) -> EmitterSample {
    if !environment_is_map(env) {
        let z = 1.0 - 2.0 * u.x;
        let r = sqrt(max(0.0, 1.0 - z * z));
        let phi = 2.0 * PI * u.y;
        let wi = vec3<f32>(r * cos(phi), r * sin(phi), z);
        return EmitterSample(wi, env.e1 * (4.0 * PI), 0.25 / PI, vec3<f32>(0.0), true);
    }
    let header = scene_texel(textures, env.second);
    let columns = header.y - 1u;
    let rows = header.z - 1u;
    let j = environment_invert(env.first, rows, u.y);
    let fy = environment_within(u.y, environment_cdf(env.first + j), environment_cdf(env.first + j + 1u));
    let row = env.first + rows + 1u + j * (columns + 1u);
    let i = environment_invert(row, columns, u.x);
    let fx = environment_within(u.x, environment_cdf(row + i), environment_cdf(row + i + 1u));
    let phi = 2.0 * PI * ((f32(i) + fx) / f32(columns) + 0.5 / f32(columns));
    let theta = PI * (f32(j) + fy) / f32(rows);
    let sin_theta = sin(theta);
    let local = vec3<f32>(sin(phi) * sin_theta, cos(theta), -cos(phi) * sin_theta);
    let wi = env.p0 * local.x + env.e1 * local.y + env.e2 * local.z;
    let pdf = environment_cell(env, columns, rows, i, j) * f32(columns * rows) / (2.0 * PI * PI * sin_theta);
    if !(sin_theta > 0.0 && pdf > 0.0) {
        return EmitterSample(wi, vec3<f32>(0.0), 0.0, vec3<f32>(0.0), true);
    }
    return EmitterSample(wi, environment_radiance(env, wi) / pdf, pdf, vec3<f32>(0.0), true);
}

// What a ray leaving the scene along d sees.
fn environment_seen(d: vec3<f32>) -> vec3<f32> {
    if !scene_has_environment() {
        return vec3<f32>(0.0);
    }
    return environment_radiance(scene_light(lights, scene_environment), d);
}
