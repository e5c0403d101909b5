// The shading point of a hit.

struct Surface {
    p: vec3<f32>,
    // Geometric normal flipped toward the incoming ray: shading is two-sided.
    n: vec3<f32>,
    // True when the ray hit the front (counter-clockwise) face: emission is one-sided.
    front: bool,
    material: u32,
}

fn surface_at(tri: Triangle, u: f32, v: f32, dir: vec3<f32>) -> Surface {
    // The point from barycentrics, not origin + t * dir: exact on the triangle's plane.
    let p = (1.0 - u - v) * tri.p0 + u * tri.p1 + v * tri.p2;
    let ng = normalize(cross(tri.p1 - tri.p0, tri.p2 - tri.p0));
    let front = dot(ng, dir) < 0.0;
    return Surface(p, select(-ng, ng, front), front, tri.material);
}
