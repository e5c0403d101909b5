// Sampling helpers: directions around a normal, points on triangles.

const PI: f32 = 3.14159265358979;

// An orthonormal basis around unit n without a branch on a special axis (Duff et al. 2017).
fn basis(n: vec3<f32>) -> mat3x3<f32> {
    let s = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    let t = vec3<f32>(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    let bt = vec3<f32>(b, s + n.y * n.y * a, -n.y);
    return mat3x3<f32>(t, bt, n);
}

// Cosine-weighted direction around n (pdf cos(theta) / pi), by Malley's method.
fn sample_cosine(n: vec3<f32>, u1: f32, u2: f32) -> vec3<f32> {
    let r = sqrt(u1);
    let phi = 2.0 * PI * u2;
    let local = vec3<f32>(r * cos(phi), r * sin(phi), sqrt(max(0.0, 1.0 - u1)));
    return normalize(basis(n) * local);
}

// Uniform point on a triangle p0 + a e1 + b e2 from a uniform square sample (Turk 1990): its
// (a, b), with a, b >= 0 and a + b <= 1.
fn square_to_triangle(u: vec2<f32>) -> vec2<f32> {
    let su = sqrt(u.x);
    return vec2<f32>(su * (1.0 - u.y), su * u.y);
}

// Moves a ray origin off a surface by a few ulps along n, scale-independently (Wächter and
// Binder, Ray Tracing Gems ch. 6): integer steps on the float bits, a fixed step near zero.
// 16 ulps, not their 256: a shading point is already on its side of the plane (ray_origin
// lifts it by its error bound first), and every ulp of the step is a gap the ray skips (at
// z = 1e4, 256 ulps are 0.25 mm: a light 0.2 mm from a wall was behind every ray leaving it).
fn offset_ray(p: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let of_i = vec3<i32>(16.0 * n);
    let p_i = vec3<f32>(
        bitcast<f32>(bitcast<i32>(p.x) + select(of_i.x, -of_i.x, p.x < 0.0)),
        bitcast<f32>(bitcast<i32>(p.y) + select(of_i.y, -of_i.y, p.y < 0.0)),
        bitcast<f32>(bitcast<i32>(p.z) + select(of_i.z, -of_i.z, p.z < 0.0)),
    );
    let near = 1.0 / 32.0;
    let step = (1.0 / 65536.0) * n;
    return select(p_i, p + step, abs(p) < vec3<f32>(near));
}

// Shirley and Chiu's concentric map of the unit square onto the unit disk (Mitsuba's
// square_to_uniform_disk_concentric): uniform, and the sampler's strata stay compact.
fn square_to_disk_concentric(u: vec2<f32>) -> vec2<f32> {
    let a = 2.0 * u - vec2<f32>(1.0);
    if all(a == vec2<f32>(0.0)) {
        return vec2<f32>(0.0);
    }
    var r: f32;
    var phi: f32;
    if abs(a.x) > abs(a.y) {
        r = a.x;
        phi = 0.25 * PI * (a.y / a.x);
    } else {
        r = a.y;
        phi = 0.5 * PI - 0.25 * PI * (a.x / a.y);
    }
    return r * vec2<f32>(cos(phi), sin(phi));
}
