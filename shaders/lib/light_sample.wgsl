// One sample of next-event estimation's light: a point on a light (a triangle or a
// parallelogram) and the shadow ray to it. Shared by nee.wgsl and the acne census
// (tests/fixtures), so the census checks exactly the rays the passes cast. The including
// shader includes scene, sampling and surface.
#include "spherical_rectangle.wgsl"

struct LightSample {
    // The shadow ray runs from the shading point's offset origin to `end` (t in (0, 1)).
    end: vec3<f32>,
    wi: vec3<f32>,
    cos_x: f32,
    cos_y: f32,
    // What multiplies f * Le in the estimate (the integrand over the pdf, but for them):
    // cos_x * cos_y * area / d^2 for a point uniform in area, cos_x * S for a point uniform in
    // the light's solid angle S.
    geometry: f32,
}

// Solid angles between which a rectangular light is sampled by solid angle: below, the light
// is small or far, 1/d^2 hardly varies over it and uniform area sampling is as good and cheaper;
// S (a difference of angles near 2 pi) also loses digits as it shrinks: at 0.01 sr its f32
// rounding is below 1e-4 of it. Above, the point nearly touches the light's plane.
const LIGHT_SOLID_ANGLE_MIN: f32 = 0.01;
const LIGHT_SOLID_ANGLE_MAX: f32 = 6.2;

// The point on `light` that the 2D sample u picks: uniform in solid angle for a rectangle that
// subtends between LIGHT_SOLID_ANGLE_MIN and _MAX from a point in front of it (points next to
// the light: the 1/d^2 of area sampling would give a few samples huge weights), uniform by area
// otherwise. The choice depends on the shading point only, so the estimate stays unbiased.
// The spherical rectangle `light` is sampled over from `origin`, or one of solid angle 0 when
// sample_light samples it by area.
fn light_solid_angle_rectangle(origin: vec3<f32>, light: Light) -> SphericalRectangle {
    let parallelogram = light.second != LIGHT_NO_TRIANGLE;
    let c = cross(light.e1, light.e2);
    let nl = c / length(c);
    let rectangle = parallelogram && abs(dot(light.e1, light.e2)) <= 1e-6 * length(light.e1) * length(light.e2);
    if rectangle && dot(nl, origin - light.p0) > 0.0 {
        let r = spherical_rectangle(origin, light.p0, light.e1, light.e2);
        if r.solid_angle >= LIGHT_SOLID_ANGLE_MIN && r.solid_angle <= LIGHT_SOLID_ANGLE_MAX {
            return r;
        }
    }
    var none: SphericalRectangle;
    none.solid_angle = 0.0;
    return none;
}

fn sample_light(s: Surface, origin: vec3<f32>, light: Light, u: vec2<f32>) -> LightSample {
    let parallelogram = light.second != LIGHT_NO_TRIANGLE;
    let c = cross(light.e1, light.e2);
    let twice = length(c);
    let nl = c / twice;
    let r = light_solid_angle_rectangle(origin, light);
    if r.solid_angle > 0.0 {
        let q = spherical_rectangle_point(r, u);
        let wi = normalize(q - origin);
        let cos_x = dot(s.n, wi);
        return LightSample(offset_ray(q, nl), wi, cos_x, -dot(nl, wi), cos_x * r.solid_angle);
    }
    // A parallelogram takes the square's points as they are.
    let ab = select(square_to_triangle(u), u, parallelogram);
    let q = light.p0 + ab.x * light.e1 + ab.y * light.e2;
    let area = select(0.5 * twice, twice, parallelogram);
    let to_light = q - origin;
    let d2 = dot(to_light, to_light);
    let wi = to_light * inverseSqrt(d2);
    // The shadow ray ends just short of the sample point moved off the light, to its front
    // (the side this point is on), by offset_ray's 16 ulps: q is rounded by a few ulps
    // of its coordinates, which far from the origin (1e5) can put it behind the light's plane,
    // and the light would occlude itself.
    let end = offset_ray(q, nl);
    // Emission leaves the front face only: cos_y is taken against the front normal.
    let cos_x = dot(s.n, wi);
    let cos_y = -dot(nl, wi);
    return LightSample(end, wi, cos_x, cos_y, cos_x * cos_y / d2 * area);
}

// The solid-angle density with which sample_light picks the direction wi from the point x, a
// direction that meets `light`'s front face: what multiple importance sampling weighs a
// BSDF-sampled ray that hit the light against. That ray started at an offset origin; the
// distance is taken from x along wi to the light's plane, where light sampling from x would
// have put the point.
fn light_pdf(x: vec3<f32>, light: Light, wi: vec3<f32>) -> f32 {
    let r = light_solid_angle_rectangle(x, light);
    if r.solid_angle > 0.0 {
        return 1.0 / r.solid_angle;
    }
    let c = cross(light.e1, light.e2);
    let twice = length(c);
    let nl = c / twice;
    let area = select(0.5 * twice, twice, light.second != LIGHT_NO_TRIANGLE);
    let cos_y = -dot(nl, wi);
    let t = dot(x - light.p0, nl) / cos_y;
    return select(0.0, t * t / (cos_y * area), cos_y > 0.0 && t > 0.0);
}
