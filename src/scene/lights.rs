//! The scene's lights: what next-event estimation samples. An emissive triangle is a light; two
//! emissive triangles of one material that together form a parallelogram (a quad split along a
//! diagonal, as OBJ quads and most modelled area lights are) are one light, sampled uniformly
//! over both with one 2D sample and one shadow ray instead of two.

use super::bvh::is_degenerate;
use super::gpu_layout::Triangle;
use crate::material::Material;
use bytemuck::{Pod, Zeroable};
use glam::Vec3;

/// `second` of a light that is one triangle.
pub const NO_TRIANGLE: u32 = u32::MAX;

/// A light's `material` at or above this is no material but the tag of a light that is not
/// an area light: `LIGHT_TAG + kind` (`shaders/lib/scene.wgsl` reads it the same way).
pub const LIGHT_TAG: u32 = 0xffff_fff0;
/// Light kinds: bit `1 << kind` of the `scene_light_kinds` override.
pub const LIGHT_AREA: u32 = 0;
pub const LIGHT_POINT: u32 = 1;
pub const LIGHT_SPOT: u32 = 2;
pub const LIGHT_DIRECTIONAL: u32 = 3;
pub const LIGHT_ENVIRONMENT_MAP: u32 = 4;
pub const LIGHT_ENVIRONMENT_CONSTANT: u32 = 5;
/// A spot with a projected texture (src/scene/emitters.rs has its record).
pub const LIGHT_SPOT_TEXTURED: u32 = 6;

/// One light as `shaders/lib/scene.wgsl` reads it (three texels): the points p0 + a e1 + b e2
/// with a, b >= 0 and a + b <= 1 (a triangle) or a, b in [0, 1] (a parallelogram). The front
/// face, the only one that emits, is the side cross(e1, e2) points to.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Light {
    pub p0: [f32; 3],
    pub material: u32,
    pub e1: [f32; 3],
    /// The parallelogram's other triangle, or [`NO_TRIANGLE`].
    pub second: u32,
    pub e2: [f32; 3],
    /// The (first) triangle, an index into the scene's triangles.
    pub first: u32,
}

impl Light {
    /// The light's kind (`LIGHT_AREA`, `LIGHT_POINT`, ...).
    pub fn kind(&self) -> u32 {
        if self.material >= LIGHT_TAG {
            self.material - LIGHT_TAG
        } else {
            LIGHT_AREA
        }
    }

    pub fn is_parallelogram(&self) -> bool {
        self.kind() == LIGHT_AREA && self.second != NO_TRIANGLE
    }

    /// The triangles the light covers (none but for an area light).
    pub fn triangles(&self) -> impl Iterator<Item = u32> {
        let area = self.kind() == LIGHT_AREA;
        area.then_some(self.first)
            .into_iter()
            .chain((area && self.second != NO_TRIANGLE).then_some(self.second))
    }

    pub fn area(&self) -> f32 {
        let parallelogram = Vec3::from(self.e1).cross(Vec3::from(self.e2)).length();
        if self.is_parallelogram() {
            parallelogram
        } else {
            0.5 * parallelogram
        }
    }

    fn triangle(i: u32, t: &Triangle) -> Light {
        let [p0, p1, p2] = t.vertices();
        Light {
            p0: p0.into(),
            material: t.material,
            e1: (p1 - p0).into(),
            second: NO_TRIANGLE,
            e2: (p2 - p0).into(),
            first: i,
        }
    }
}

/// Whether a triangle is a light: its material has some `Ke` > 0 and its area is nonzero (a
/// zero-area emitter can never be sampled: its pdf would divide by zero).
fn is_emitter(t: &Triangle, materials: &[Material]) -> bool {
    materials
        .get(t.material as usize)
        .is_some_and(Material::is_emissive)
        && !is_degenerate(&t.vertices())
}

/// The parallelogram two triangles form, if they share an edge as its diagonal, face the same
/// way and have one material: a's far vertex x, b's far vertex y and the shared s1, s2 with
/// x + y = s1 + s2 (to a few ulps of the coordinates). e1 and e2 keep a's winding, so the
/// front face stays the emitting one.
fn parallelogram(ia: u32, a: &Triangle, ib: u32, b: &Triangle) -> Option<Light> {
    if a.material != b.material {
        return None;
    }
    let va = a.vertices();
    let vb = b.vertices();
    // a's vertex k is the one b does not share; the other two must be b's.
    let k = (0..3).find(|&k| {
        let (s1, s2) = (va[(k + 1) % 3], va[(k + 2) % 3]);
        vb.contains(&s1) && vb.contains(&s2) && !vb.contains(&va[k])
    })?;
    let (x, s1, s2) = (va[k], va[(k + 1) % 3], va[(k + 2) % 3]);
    let y = *vb.iter().find(|&&v| v != s1 && v != s2)?;
    let na = (s1 - x).cross(s2 - x);
    let nb = (vb[1] - vb[0]).cross(vb[2] - vb[0]);
    let scale = [x, y, s1, s2]
        .iter()
        .map(|v| v.abs().max_element())
        .fold(0.0f32, f32::max);
    // The fourth corner x + e1 + e2 is y (within a few ulps of the largest coordinate), which
    // also makes the two coplanar; and both face the same way.
    let closes = ((s1 + s2 - x) - y).abs().max_element() <= 8.0 * f32::EPSILON * scale;
    if !(closes && na.dot(nb) > 0.0) {
        return None;
    }
    // Spanned from x or from y (same winding either way): take the corner that comes first in
    // coordinate order, so that the same light gets the same parametrisation, and so the same
    // points for the same samples, whatever order the BVH puts its triangles in.
    let (p0, e1, e2) = if y.to_array() < x.to_array() {
        (y, s2 - y, s1 - y)
    } else {
        (x, s1 - x, s2 - x)
    };
    Some(Light {
        p0: p0.into(),
        material: a.material,
        e1: e1.into(),
        second: ib,
        e2: e2.into(),
        first: ia,
    })
}

/// The scene's lights, ordered by their first triangle: each emissive triangle once, paired
/// with a neighbour into a parallelogram where [`parallelogram`] allows.
pub fn scene_lights(triangles: &[Triangle], materials: &[Material]) -> Vec<Light> {
    let emitters: Vec<u32> = (0..triangles.len() as u32)
        .filter(|&i| is_emitter(&triangles[i as usize], materials))
        .collect();
    // Emitters by their vertices' bits, so a partner is found without comparing all pairs.
    let mut by_vertex: std::collections::HashMap<[u32; 3], Vec<u32>> = Default::default();
    for &i in &emitters {
        for v in triangles[i as usize].vertices() {
            by_vertex
                .entry(v.to_array().map(f32::to_bits))
                .or_default()
                .push(i);
        }
    }
    let mut taken = vec![false; triangles.len()];
    let mut lights = Vec::with_capacity(emitters.len());
    for &i in &emitters {
        if taken[i as usize] {
            continue;
        }
        taken[i as usize] = true;
        let a = &triangles[i as usize];
        let partner = a
            .vertices()
            .iter()
            .flat_map(|v| &by_vertex[&v.to_array().map(f32::to_bits)])
            .filter(|&&j| !taken[j as usize])
            .find_map(|&j| parallelogram(i, a, j, &triangles[j as usize]));
        match partner {
            Some(light) => {
                taken[light.second as usize] = true;
                lights.push(light);
            }
            None => lights.push(Light::triangle(i, a)),
        }
    }
    lights
}

/// Each light's power up to a constant factor (pi for a Lambertian emitter): area times the
/// luminance of `Ke` (Rec. 709 weights, all positive: an emitter's luminance is never 0), in
/// `lights` order. Light selection picks lights in proportion to it.
pub fn light_power(lights: &[Light], materials: &[Material]) -> Vec<f32> {
    lights
        .iter()
        .map(|l| {
            let ke = materials[l.material as usize].ke;
            let luminance = 0.2126 * ke[0] + 0.7152 * ke[1] + 0.0722 * ke[2];
            l.area() * luminance
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn emissive() -> Vec<Material> {
        vec![Material::diffuse([0.5; 3]), {
            let mut m = Material::diffuse([0.5; 3]);
            m.ke = [1.0, 2.0, 4.0];
            m
        }]
    }

    fn v(x: f32, y: f32, z: f32) -> Vec3 {
        Vec3::new(x, y, z)
    }

    #[test]
    fn power_is_area_times_luminance() {
        // A right triangle with legs 2 and 3: area 3.
        let t = Triangle::new([Vec3::ZERO, v(2.0, 0.0, 0.0), v(0.0, 3.0, 0.0)], 1);
        let lights = scene_lights(&[t], &emissive());
        assert_eq!(lights.len(), 1);
        assert!(!lights[0].is_parallelogram());
        let power = light_power(&lights, &emissive());
        let luminance = 0.2126 + 0.7152 * 2.0 + 0.0722 * 4.0;
        assert!((power[0] - 3.0 * luminance).abs() < 1e-5, "{power:?}");
    }

    #[test]
    fn a_quad_split_along_its_diagonal_is_one_parallelogram_light_facing_the_same_way() {
        // A 2 x 3 quad fanned from its first corner, as an OBJ `f 1 2 3 4` loads.
        let q = [
            Vec3::ZERO,
            v(2.0, 0.0, 0.0),
            v(2.0, 3.0, 0.0),
            v(0.0, 3.0, 0.0),
        ];
        let tris = [
            Triangle::new([q[0], q[1], q[2]], 1),
            Triangle::new([q[0], q[2], q[3]], 1),
        ];
        let lights = scene_lights(&tris, &emissive());
        assert_eq!(lights.len(), 1, "{lights:?}");
        let l = lights[0];
        assert!(l.is_parallelogram());
        assert_eq!(l.triangles().collect::<Vec<_>>(), vec![0, 1]);
        assert!((l.area() - 6.0).abs() < 1e-6);
        let n = Vec3::from(l.e1).cross(Vec3::from(l.e2));
        assert!(n.z > 0.0, "front face kept: {n}");
        // Its four corners are the quad's.
        let p0 = Vec3::from(l.p0);
        let corners = [
            p0,
            p0 + Vec3::from(l.e1),
            p0 + Vec3::from(l.e2),
            p0 + Vec3::from(l.e1) + Vec3::from(l.e2),
        ];
        for c in q {
            assert!(corners.contains(&c), "{c} not a corner of {corners:?}");
        }
    }

    #[test]
    fn triangles_that_do_not_form_a_parallelogram_stay_apart() {
        let emissive = emissive();
        let a = Triangle::new([Vec3::ZERO, v(2.0, 0.0, 0.0), v(2.0, 3.0, 0.0)], 1);
        // Shares the diagonal but is not the other half of a parallelogram (a kite).
        let kite = Triangle::new([Vec3::ZERO, v(2.0, 3.0, 0.0), v(-1.0, 3.0, 0.0)], 1);
        // The other half, folded out of the plane.
        let folded = Triangle::new([Vec3::ZERO, v(2.0, 3.0, 0.0), v(0.0, 3.0, 1.0)], 1);
        // The other half, facing the other way.
        let flipped = Triangle::new([Vec3::ZERO, v(0.0, 3.0, 0.0), v(2.0, 3.0, 0.0)], 1);
        // The other half in another material.
        let other = Triangle::new([Vec3::ZERO, v(2.0, 3.0, 0.0), v(0.0, 3.0, 0.0)], 2);
        let mut materials = emissive.clone();
        materials.push(materials[1]);
        for b in [kite, folded, flipped, other] {
            let lights = scene_lights(&[a, b], &materials);
            assert_eq!(lights.len(), 2, "{b:?}: {lights:?}");
            assert!(lights.iter().all(|l| !l.is_parallelogram()));
        }
    }

    #[test]
    fn a_strip_of_quads_pairs_each_triangle_once() {
        // Three unit quads in a row: six triangles, three lights, every triangle in one.
        let mut tris = Vec::new();
        for i in 0..3 {
            let x = i as f32;
            let q = [
                v(x, 0.0, 0.0),
                v(x + 1.0, 0.0, 0.0),
                v(x + 1.0, 1.0, 0.0),
                v(x, 1.0, 0.0),
            ];
            tris.push(Triangle::new([q[0], q[1], q[2]], 1));
            tris.push(Triangle::new([q[0], q[2], q[3]], 1));
        }
        let lights = scene_lights(&tris, &emissive());
        let mut covered: Vec<u32> = lights.iter().flat_map(Light::triangles).collect();
        covered.sort();
        assert_eq!(covered, (0..6).collect::<Vec<_>>());
        let area: f32 = lights.iter().map(Light::area).sum();
        assert!((area - 3.0).abs() < 1e-6, "{area}");
    }
}
