// The shading point of a hit.

// pbrt's gamma(7) = 7 u / (1 - 7 u), u = 2^-24: the relative error bound of the barycentric
// point's roundings (PBR 3rd ed., section 3.9.6).
const SURFACE_GAMMA7: f32 = 4.1723268e-7;

struct Surface {
    // On the side of the triangle's plane the ray came from (see surface_at).
    p: vec3<f32>,
    // Geometric normal flipped toward the incoming ray: shading is two-sided.
    n: vec3<f32>,
    // True when the ray hit the front (counter-clockwise) face: emission is one-sided.
    front: bool,
    material: u32,
}

fn surface_at(tri: Triangle, u: f32, v: f32, dir: vec3<f32>) -> Surface {
    // The point from barycentrics, not origin + t * dir: off the triangle's plane by a few ulps
    // of the vertices' coordinates, however far along the ray it lies.
    let b0 = 1.0 - u - v;
    let p = b0 * tri.p0 + u * tri.p1 + v * tri.p2;
    let ng = normalize(cross(tri.p1 - tri.p0, tri.p2 - tri.p0));
    let front = dot(ng, dir) < 0.0;
    let n = select(-ng, ng, front);
    // Moved along n by the bound on that error (pbrt's pError), so that rays leaving it
    // (offset_ray) start on the ray's side of the plane even when the vertices are much larger
    // than the point's own coordinates (a huge triangle near the origin), where offset_ray's
    // few ulps of the point are not enough. A few ulps of the vertices: no visible shift.
    let error = SURFACE_GAMMA7 * (abs(b0 * tri.p0) + abs(u * tri.p1) + abs(v * tri.p2));
    return Surface(p + dot(abs(n), error) * n, n, front, tri.material);
}
