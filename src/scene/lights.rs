//! Which triangles emit light: next-event estimation samples exactly these.

use super::bvh::is_degenerate;
use super::gpu::{Material, Triangle};

/// Indices (into `triangles`) of the triangles whose material has some `Ke` > 0 and whose area
/// is nonzero: a zero-area emitter can never be sampled (its pdf would divide by zero).
pub fn emissive_triangles(triangles: &[Triangle], materials: &[Material]) -> Vec<u32> {
    triangles
        .iter()
        .enumerate()
        .filter(|(_, t)| {
            materials
                .get(t.material as usize)
                .is_some_and(Material::is_emissive)
                && !is_degenerate(&t.vertices())
        })
        .map(|(i, _)| i as u32)
        .collect()
}

/// Each light's power up to a constant factor (pi for a Lambertian emitter): area times the
/// luminance of `Ke` (Rec. 709 weights, all positive: an emitter's luminance is never 0), in
/// `lights` order. Light selection picks emitters in proportion to it.
pub fn light_power(lights: &[u32], triangles: &[Triangle], materials: &[Material]) -> Vec<f32> {
    lights
        .iter()
        .map(|&i| {
            let t = &triangles[i as usize];
            let [p0, p1, p2] = t.vertices();
            let area = 0.5 * (p1 - p0).cross(p2 - p0).length();
            let ke = materials[t.material as usize].ke;
            let luminance = 0.2126 * ke[0] + 0.7152 * ke[1] + 0.0722 * ke[2];
            area * luminance
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_is_area_times_luminance() {
        let materials = [Material::diffuse([0.5; 3]), {
            let mut m = Material::diffuse([0.5; 3]);
            m.ke = [1.0, 2.0, 4.0];
            m
        }];
        // A right triangle with legs 2 and 3: area 3.
        let t = Triangle::new(
            [
                glam::Vec3::ZERO,
                glam::Vec3::new(2.0, 0.0, 0.0),
                glam::Vec3::new(0.0, 3.0, 0.0),
            ],
            1,
        );
        let power = light_power(&[0], &[t], &materials);
        let luminance = 0.2126 + 0.7152 * 2.0 + 0.0722 * 4.0;
        assert!((power[0] - 3.0 * luminance).abs() < 1e-5, "{power:?}");
    }
}
