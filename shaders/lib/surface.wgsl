// The shading point of a hit.
#include "sampling.wgsl"

// pbrt's gamma(7) = 7 u / (1 - 7 u), u = 2^-24: the relative error bound of the barycentric
// point's roundings (PBR 3rd ed., section 3.9.6).
const SURFACE_GAMMA7: f32 = 4.1723268e-7;

struct Surface {
    // The point from barycentrics: where lights are sampled from and distances measured.
    p: vec3<f32>,
    // Geometric normal flipped toward the incoming ray: shading is two-sided.
    n: vec3<f32>,
    // True when the ray hit the front (counter-clockwise) face: emission is one-sided.
    front: bool,
    material: u32,
    // A bound on p's rounding error along n (pbrt's pError): rays leave from p moved this far
    // off the plane (ray_origin), so they start on the intended side of it.
    lift: f32,
}

fn surface_at(tri: Triangle, u: f32, v: f32, dir: vec3<f32>) -> Surface {
    // The point from barycentrics, not origin + t * dir: off the triangle's plane by a few ulps
    // of the vertices' coordinates, however far along the ray it lies.
    let b0 = 1.0 - u - v;
    let p = b0 * tri.p0 + u * tri.p1 + v * tri.p2;
    let ng = normalize(cross(tri.p1 - tri.p0, tri.p2 - tri.p0));
    let front = dot(ng, dir) < 0.0;
    let n = select(-ng, ng, front);
    // The bound on that error (pbrt's pError) along n: rays leaving p are moved off it by this
    // much before offset_ray, so that they start on their side of the plane even when the
    // vertices are much larger than the point's own coordinates (a huge triangle near the
    // origin), where offset_ray's few ulps of the point are not enough.
    let error = SURFACE_GAMMA7 * (abs(b0 * tri.p0) + abs(u * tri.p1) + abs(v * tri.p2));
    return Surface(p, n, front, tri.material, dot(abs(n), error));
}

// The origin of a ray leaving s on the side of `side` (n or -n): off the plane by the bound on
// p's error, then by offset_ray's ulps. Only rays start here; lights are sampled from s.p, or
// the estimate would be of the light at a point nearer it (on a wall 0.2 mm behind a light
// facing it, at z = 559, the lift alone made it 0.2 % too dark; see robust_render.rs).
fn ray_origin(s: Surface, side: vec3<f32>) -> vec3<f32> {
    return offset_ray(s.p + s.lift * side, side);
}
