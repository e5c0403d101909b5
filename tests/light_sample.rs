//! shaders/lib/light_sample.wgsl against the closed form: for points near and far, head-on and
//! tilted, the mean of next-event estimation's unoccluded weight (cos_x over the pdf) over 2^16
//! samples is the light's projected solid angle within five standard errors, for rectangles sampled by solid
//! angle (spherical_rectangle.wgsl) and for lights sampled by area. Run on the GPU (lavapipe).

mod common;

use common::bvh_gpu::{Gpu, bind_buffers, dispatch_and_read, gpu, output_buffer, test_pipeline};
use glam::{DVec3, Mat3, Vec3};
use passgraph::scene::lights::{Light, NO_TRIANGLE};

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Query {
    origin: [f32; 3],
    pad0: f32,
    normal: [f32; 3],
    pad1: f32,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct Answer {
    mean: f32,
    mean_square: f32,
    solid_angle: f32,
    rejected: u32,
}

/// The light's corners, in order around it, in f64: summed in f32 far from the origin they
/// would move by half an ulp of the coordinates, which seen at a grazing angle from close by is
/// a visible part of the solid angle.
fn corners(light: &Light) -> Vec<DVec3> {
    let p0 = Vec3::from(light.p0).as_dvec3();
    let (e1, e2) = (
        Vec3::from(light.e1).as_dvec3(),
        Vec3::from(light.e2).as_dvec3(),
    );
    if light.second == NO_TRIANGLE {
        vec![p0, p0 + e1, p0 + e2]
    } else {
        vec![p0, p0 + e1, p0 + e1 + e2, p0 + e2]
    }
}

/// The projected solid angle of a polygon wholly above the tangent plane at x (normal n): the
/// integral of cos over the directions it covers, Lambert's formula
/// 1/2 |sum over edges of angle(a, b) n . normalize(a x b)| (in f64).
fn projected_solid_angle(polygon: &[DVec3], x: Vec3, n: Vec3) -> f64 {
    let n = n.as_dvec3();
    let dirs: Vec<DVec3> = polygon
        .iter()
        .map(|p| (*p - x.as_dvec3()).normalize())
        .collect();
    let mut sum = 0.0;
    for k in 0..dirs.len() {
        let (a, b) = (dirs[k], dirs[(k + 1) % dirs.len()]);
        sum += a.angle_between(b) * n.dot(a.cross(b).normalize());
    }
    0.5 * sum.abs()
}

fn run(gpu: &Gpu, light: &Light, queries: &[Query]) -> Vec<Answer> {
    use wgpu::util::DeviceExt;
    let pipeline = test_pipeline(gpu, "light_sample_check");
    let init = |contents: &[u8], usage| {
        gpu.device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: None,
                contents,
                usage,
            })
    };
    let light_buffer = init(bytemuck::bytes_of(light), wgpu::BufferUsages::UNIFORM);
    let query_buffer = init(bytemuck::cast_slice(queries), wgpu::BufferUsages::STORAGE);
    let answers = output_buffer(gpu, (queries.len() * size_of::<Answer>()) as u64);
    let bind_group = bind_buffers(gpu, &pipeline, &[&light_buffer, &query_buffer, &answers]);
    dispatch_and_read(gpu, &pipeline, &bind_group, queries.len(), &answers)
}

/// Points in front of the light at distances from 0.001 to 100 times its size, head-on and
/// tilted, kept only where the whole light is above the point's tangent plane (the closed form
/// does not clip).
fn queries_for(light: &Light) -> Vec<Query> {
    let polygon: Vec<Vec3> = corners(light).iter().map(|p| p.as_vec3()).collect();
    let centre = polygon.iter().sum::<Vec3>() / polygon.len() as f32;
    let normal = Vec3::from(light.e1).cross(Vec3::from(light.e2)).normalize();
    let side = Vec3::from(light.e1).normalize();
    let mut queries = Vec::new();
    let size = Vec3::from(light.e1)
        .length()
        .max(Vec3::from(light.e2).length());
    for distance in [0.001f32, 0.003, 0.01, 0.03, 0.1, 0.3, 1.0, 3.0, 10.0, 100.0] {
        for lateral in [0.0f32, 0.3, 0.6] {
            for tilt in [0.0f32, 0.4, 1.0] {
                let x = centre + (normal * distance + side * lateral) * size;
                let n = Mat3::from_axis_angle(Vec3::from(light.e2).normalize(), tilt) * -normal;
                if polygon.iter().all(|p| n.dot(*p - x) > 0.0) {
                    // pad0 carries the distance in light sizes to the check.
                    queries.push(Query {
                        origin: x.into(),
                        pad0: distance,
                        normal: n.into(),
                        pad1: 0.0,
                    });
                }
            }
        }
    }
    queries
}

fn check(gpu: &Gpu, name: &str, light: &Light) -> (usize, usize) {
    let queries = queries_for(light);
    assert!(queries.len() > 20, "{name}: {} queries", queries.len());
    let answers = run(gpu, light, &queries);
    let (mut spherical, mut by_area) = (0, 0);
    let rectangle = light.second != NO_TRIANGLE
        && Vec3::from(light.e1).dot(Vec3::from(light.e2)).abs()
            <= 1e-6 * Vec3::from(light.e1).length() * Vec3::from(light.e2).length();
    for (q, a) in queries.iter().zip(&answers) {
        let expected = projected_solid_angle(&corners(light), q.origin.into(), q.normal.into());
        let sphere = rectangle && (0.01..=6.2).contains(&a.solid_angle);
        assert_eq!(a.rejected, 0, "{name}: samples rejected at {:?}", q.origin);
        // Closer than a tenth of the light's size, area sampling's weights (1/d^2) have so
        // heavy a tail that 2^16 samples say nothing of their mean (which is why sample_light
        // samples by solid angle there): nothing to compare.
        if !sphere && q.pad0 < 0.1 {
            continue;
        }
        // Five standard errors of the mean of 2^16 independent samples, plus the f32
        // rounding: of S (a sum of four angles less 2 pi: 8 ulps of 2 pi) where sampled by
        // solid angle, and 1e-5 of the value for the sums.
        let n = 65536.0;
        let variance = (f64::from(a.mean_square) - f64::from(a.mean).powi(2)).max(0.0);
        let rounding = if sphere {
            8.0 * 4.8e-7 / f64::from(a.solid_angle)
        } else {
            0.0
        } + 1e-5;
        let bound = 5.0 * (variance / n).sqrt() + rounding * expected;
        let error = (f64::from(a.mean) - expected).abs();
        assert!(
            error <= bound,
            "{name}: at {:?} (normal {:?}, S = {}) mean {} expected {expected}: error {error:e} > bound {bound:e}",
            q.origin,
            q.normal,
            a.solid_angle,
            a.mean
        );
        if sphere { spherical += 1 } else { by_area += 1 }
    }
    (spherical, by_area)
}

#[test]
fn next_event_weights_integrate_to_the_projected_solid_angle_near_and_far() {
    let gpu = gpu();
    let light = |p0: Vec3, e1: Vec3, e2: Vec3, second: u32| Light {
        p0: p0.into(),
        material: 0,
        e1: e1.into(),
        second,
        e2: e2.into(),
        first: 0,
    };
    // The Cornell box's light (130 x 105 mm, facing down).
    let cornell = light(
        Vec3::new(343.0, 548.7, 227.0),
        Vec3::new(0.0, 0.0, 105.0),
        Vec3::new(-130.0, 0.0, 0.0),
        1,
    );
    let (spherical, by_area) = check(&gpu, "cornell light", &cornell);
    assert!(
        spherical >= 10 && by_area >= 10,
        "{spherical} by solid angle, {by_area} by area"
    );
    // A rectangle turned about two axes, far from the origin (coordinates near 1e3).
    let r = Mat3::from_euler(glam::EulerRot::XYZ, 0.3, -0.7, 1.1);
    let turned = light(
        Vec3::splat(1000.0),
        r * Vec3::new(2.0, 0.0, 0.0),
        r * Vec3::new(0.0, 0.5, 0.0),
        1,
    );
    let (spherical, _) = check(&gpu, "turned rectangle", &turned);
    assert!(spherical >= 10);
    // A parallelogram that is not a rectangle, and a triangle: by area everywhere.
    let skewed = light(
        Vec3::ZERO,
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.5, 1.0, 0.0),
        1,
    );
    assert_eq!(check(&gpu, "parallelogram", &skewed).0, 0);
    let triangle = light(
        Vec3::ZERO,
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        NO_TRIANGLE,
    );
    assert_eq!(check(&gpu, "triangle", &triangle).0, 0);
}
