// Points on a rectangle distributed uniformly in the solid angle it subtends from a viewpoint
// (Ureña, Fajardo and King 2013, "An Area-Preserving Parametrization for Spherical
// Rectangles"): next-event estimation's weight is then the solid angle itself, with no 1/d^2
// left to vary. light_sample.wgsl uses it where the solid angle is large enough to pay.

struct SphericalRectangle {
    // The viewpoint and a frame with x, y along the rectangle's edges and z away from the
    // rectangle (z0 < 0: the rectangle's plane is z = z0).
    o: vec3<f32>,
    x: vec3<f32>,
    y: vec3<f32>,
    z: vec3<f32>,
    z0: f32,
    // The rectangle is [x0, x1] x [y0, y1] in that frame.
    x0: f32,
    x1: f32,
    y0: f32,
    y1: f32,
    // The paper's b0, b1 and k, and the solid angle S.
    b0: f32,
    b1: f32,
    k: f32,
    solid_angle: f32,
}

// The rectangle corner + a ex + b ey (a, b in [0, 1]; ex and ey orthogonal) seen from o.
fn spherical_rectangle(o: vec3<f32>, corner: vec3<f32>, ex: vec3<f32>, ey: vec3<f32>) -> SphericalRectangle {
    let exl = length(ex);
    let eyl = length(ey);
    let x = ex / exl;
    let y = ey / eyl;
    var z = normalize(cross(x, y));
    let d = corner - o;
    var z0 = dot(d, z);
    if z0 > 0.0 {
        z = -z;
        z0 = -z0;
    }
    let x0 = dot(d, x);
    let y0 = dot(d, y);
    let x1 = x0 + exl;
    let y1 = y0 + eyl;
    // Normals of the four planes through o and an edge, and the spherical rectangle's inner
    // angles between them.
    let n0 = normalize(vec3<f32>(0.0, z0, -y0));
    let n1 = normalize(vec3<f32>(-z0, 0.0, x1));
    let n2 = normalize(vec3<f32>(0.0, -z0, y1));
    let n3 = normalize(vec3<f32>(z0, 0.0, -x0));
    let g0 = spherical_rectangle_angle(n0, n1);
    let g1 = spherical_rectangle_angle(n1, n2);
    let g2 = spherical_rectangle_angle(n2, n3);
    let g3 = spherical_rectangle_angle(n3, n0);
    let k = 2.0 * PI - g2 - g3;
    return SphericalRectangle(o, x, y, z, z0, x0, x1, y0, y1, n0.z, n2.z, k, g0 + g1 - k);
}

// The angle between the planes of normals a and b (the paper's acos(-a . b)), by atan2: acos
// near +-1 turns a rounding of the dot product into an error of its square root (3e-4 rad), which
// at a grazing view is much of the solid angle.
fn spherical_rectangle_angle(a: vec3<f32>, b: vec3<f32>) -> f32 {
    return atan2(length(cross(a, b)), -dot(a, b));
}

// The point of the rectangle that u in [0, 1)^2 maps to: uniform in solid angle.
fn spherical_rectangle_point(r: SphericalRectangle, u: vec2<f32>) -> vec3<f32> {
    // u.x picks the cut x = xu with the solid angle left of it u.x * S ...
    // The paper's fu = num / sin(au) and cu = sign(fu) / sqrt(fu^2 + b0^2), multiplied through
    // by |sin(au)| so that nothing overflows where sin(au) is 0.
    let au = u.x * r.solid_angle + r.k;
    let s = sin(au);
    let num = cos(au) * r.b0 - r.b1;
    let den = sqrt(num * num + r.b0 * r.b0 * s * s);
    let cu = clamp(select(-1.0, 1.0, num * s > 0.0) * abs(s) / max(den, 1e-30), -1.0, 1.0);
    let sin_cu = sqrt(1.0 - cu * cu);
    let edge = select(r.x0, r.x1, cu > 0.0);
    let xu = select(edge, clamp(-(cu * r.z0) / sin_cu, r.x0, r.x1), sin_cu > 0.0);
    // ... and u.y the height along it, uniform in the cosine of the angle to the y axis.
    let dist = sqrt(xu * xu + r.z0 * r.z0);
    let h0 = r.y0 / sqrt(dist * dist + r.y0 * r.y0);
    let h1 = r.y1 / sqrt(dist * dist + r.y1 * r.y1);
    let hv = h0 + u.y * (h1 - h0);
    let hv2 = hv * hv;
    let yv = select(r.y1, hv * dist / sqrt(1.0 - hv2), hv2 < 1.0 - 1e-6);
    return r.o + xu * r.x + clamp(yv, r.y0, r.y1) * r.y + r.z0 * r.z;
}
