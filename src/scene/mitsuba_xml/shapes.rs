//! Shapes as triangles. Meshes (`obj`, `ply`, `serialized`) load as written; Mitsuba's analytic
//! shapes are tessellated in their object space, with their exact normals at the vertices and
//! Mitsuba's texture coordinates:
//!
//! - `rectangle`: [-1, 1]^2 at z = 0, normal +z: two triangles, exact.
//! - `cube`: [-1, 1]^3, 12 triangles with face normals, exact.
//! - `disk`: the unit disk at z = 0, normal +z: a fan of [`DISK_SEGMENTS`] triangles, its rim a
//!   polygon inside the circle by at most 1 - cos(pi / 256) = 7.5e-5 of the radius (area
//!   short by 1e-4 of the disk's).
//! - `cylinder`: the open unit cylinder from z = 0 to 1 (p0 to p1): [`CYLINDER_SEGMENTS`]
//!   quads, radial normals; straight along z, so exact there, and inside the circle by at most
//!   7.5e-5 of the radius around it.
//! - `sphere`: [`SPHERE_STACKS`] x [`SPHERE_SLICES`] latitude-longitude quads (triangles at the
//!   poles), vertices on the sphere with its normals: a face's plane lies at sqrt(1 - R^2) from
//!   the centre, R its circumradius (at most (pi / 64) / sqrt(2) at the equator), so the faces
//!   lie inside the sphere by at most 6.1e-4 of the radius (measured in tests/mitsuba_xml.rs;
//!   the area is short by 5e-4 of 4 pi r^2), and the interpolated shading normals follow the
//!   sphere's. At 48x48 a sphere of radius 0.5 four units away spans ~10 pixels: the deviation
//!   is a few thousandths of a pixel.
//!
//! Texture coordinates are Mitsuba's own (its shapes' `uv`, with v down the image rows) until
//! [`Triangle::passgraph_uv`] turns them into passgraph's (OBJ) convention, v = 0 at the
//! bottom row: (u, 1 - v).

use glam::{DMat3, DMat4, DVec2, DVec3};
use std::collections::HashMap;
use std::f64::consts::PI;

pub const DISK_SEGMENTS: usize = 256;
pub const CYLINDER_SEGMENTS: usize = 256;
pub const SPHERE_STACKS: usize = 64;
pub const SPHERE_SLICES: usize = 128;

/// A triangle in f64: corners counter-clockwise seen from its front; normals and Mitsuba uvs
/// per corner where the shape has them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    pub p: [DVec3; 3],
    pub n: Option<[DVec3; 3]>,
    pub uv: Option<[DVec2; 3]>,
}

impl Triangle {
    /// Mitsuba's (u, v) as passgraph's texture lookup reads them: (u, 1 - v).
    pub fn passgraph_uv(uv: DVec2) -> DVec2 {
        DVec2::new(uv.x, 1.0 - uv.y)
    }

    fn reversed(self) -> Triangle {
        fn swap<T>([a, b, c]: [T; 3]) -> [T; 3] {
            [a, c, b]
        }
        Triangle {
            p: swap(self.p),
            n: self.n.map(swap),
            uv: self.uv.map(swap),
        }
    }
}

/// A shape's triangles.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Geometry {
    pub triangles: Vec<Triangle>,
}

impl Geometry {
    /// `to_world` applied: points by the matrix, normals by its inverse transpose. `analytic`:
    /// a tessellated Mitsuba shape, whose front stays its outside (Mitsuba computes an analytic
    /// shape's normal from its definition), so a mirroring matrix also reverses the corners; a
    /// mesh keeps the corners' order, as Mitsuba's meshes take their normal from it.
    pub fn transformed(&self, m: &DMat4, analytic: bool) -> Geometry {
        let normal_matrix = DMat3::from_mat4(*m).inverse().transpose();
        let mirror = m.determinant() < 0.0;
        let triangles = self
            .triangles
            .iter()
            .map(|t| {
                let t = Triangle {
                    p: t.p.map(|p| m.transform_point3(p)),
                    n: t.n
                        .map(|n| n.map(|n| (normal_matrix * n).normalize_or_zero())),
                    uv: t.uv,
                };
                if analytic && mirror { t.reversed() } else { t }
            })
            .collect();
        Geometry { triangles }
    }

    /// `flip_normals`: the back becomes the front (emission and the normals turn around).
    pub fn flipped(mut self) -> Geometry {
        for t in &mut self.triangles {
            *t = t.reversed();
            if let Some(n) = &mut t.n {
                *n = n.map(|n| -n);
            }
        }
        self
    }

    /// `face_normals`: flat shading (no vertex normals).
    pub fn without_normals(mut self) -> Geometry {
        for t in &mut self.triangles {
            t.n = None;
        }
        self
    }

    /// Mitsuba's vertex normals for a mesh that has none: at each vertex (corners at the same
    /// position), the sum of its faces' normals weighted by the face's angle there, normalised.
    pub fn with_smooth_normals(mut self) -> Geometry {
        let key = |p: DVec3| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
        let mut sums: HashMap<[u64; 3], DVec3> = HashMap::new();
        for t in &self.triangles {
            let n = (t.p[1] - t.p[0]).cross(t.p[2] - t.p[0]).normalize_or_zero();
            for j in 0..3 {
                let d0 = (t.p[(j + 1) % 3] - t.p[j]).normalize_or_zero();
                let d1 = (t.p[(j + 2) % 3] - t.p[j]).normalize_or_zero();
                let angle = d0.dot(d1).clamp(-1.0, 1.0).acos();
                if angle.is_finite() {
                    *sums.entry(key(t.p[j])).or_default() += n * angle;
                }
            }
        }
        for t in &mut self.triangles {
            let face = (t.p[1] - t.p[0])
                .cross(t.p[2] - t.p[0])
                .normalize_or(DVec3::Z);
            t.n = Some(t.p.map(|p| {
                sums.get(&key(p))
                    .and_then(|s| s.try_normalize())
                    .unwrap_or(face)
            }));
        }
        self
    }
}

fn quad(p: [DVec3; 4], n: Option<[DVec3; 4]>, uv: [DVec2; 4], out: &mut Vec<Triangle>) {
    for [a, b, c] in [[0, 1, 2], [0, 2, 3]] {
        out.push(Triangle {
            p: [p[a], p[b], p[c]],
            n: n.map(|n| [n[a], n[b], n[c]]),
            uv: Some([uv[a], uv[b], uv[c]]),
        });
    }
}

/// Mitsuba's `rectangle`: uv = ((x + 1) / 2, (y + 1) / 2).
pub fn rectangle() -> Geometry {
    let p = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    let mut triangles = Vec::new();
    quad(
        p.map(|(x, y)| DVec3::new(x, y, 0.0)),
        None,
        p.map(|(x, y)| DVec2::new(0.5 * (x + 1.0), 0.5 * (y + 1.0))),
        &mut triangles,
    );
    Geometry { triangles }
}

/// Mitsuba's `cube`: [-1, 1]^3, each face a quad with its face's normal.
pub fn cube() -> Geometry {
    let mut triangles = Vec::new();
    for axis in 0..3 {
        for sign in [1.0, -1.0] {
            let n = DVec3::from_array(std::array::from_fn(|i| if i == axis { sign } else { 0.0 }));
            // Two tangents with u x v = n, so the quad is counter-clockwise seen from outside.
            let u = DVec3::from_array(std::array::from_fn(|i| {
                if i == (axis + 1) % 3 { 1.0 } else { 0.0 }
            }));
            let v = n.cross(u);
            let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
            quad(
                corners.map(|(a, b)| n + u * a + v * b),
                Some([n; 4]),
                corners.map(|(a, b)| DVec2::new(0.5 * (a + 1.0), 0.5 * (b + 1.0))),
                &mut triangles,
            );
        }
    }
    Geometry { triangles }
}

/// Mitsuba's `disk`: uv = (r, phi / 2 pi).
pub fn disk() -> Geometry {
    let n = DISK_SEGMENTS;
    let triangles = (0..n)
        .map(|j| {
            let phi = |j: usize| 2.0 * PI * j as f64 / n as f64;
            let rim = |j: usize| DVec3::new(phi(j).cos(), phi(j).sin(), 0.0);
            let v = |j: usize| j as f64 / n as f64;
            Triangle {
                p: [DVec3::ZERO, rim(j), rim(j + 1)],
                n: None,
                uv: Some([
                    DVec2::new(0.0, 0.5 * (v(j) + v(j + 1))),
                    DVec2::new(1.0, v(j)),
                    DVec2::new(1.0, v(j + 1)),
                ]),
            }
        })
        .collect();
    Geometry { triangles }
}

/// Mitsuba's `cylinder` in its object space: x^2 + y^2 = 1, 0 <= z <= 1, normals outward,
/// uv = (phi / 2 pi, z).
pub fn cylinder() -> Geometry {
    let n = CYLINDER_SEGMENTS;
    let mut triangles = Vec::new();
    for j in 0..n {
        let phi = |j: usize| 2.0 * PI * j as f64 / n as f64;
        let radial = |j: usize| DVec3::new(phi(j).cos(), phi(j).sin(), 0.0);
        let u = |j: usize| j as f64 / n as f64;
        let (a, b) = (radial(j), radial(j + 1));
        quad(
            [a, b, b + DVec3::Z, a + DVec3::Z],
            Some([a, b, b, a]),
            [
                DVec2::new(u(j), 0.0),
                DVec2::new(u(j + 1), 0.0),
                DVec2::new(u(j + 1), 1.0),
                DVec2::new(u(j), 1.0),
            ],
            &mut triangles,
        );
    }
    Geometry { triangles }
}

/// Mitsuba's `sphere` of radius 1 at the origin: uv = (phi / 2 pi, theta / pi), theta from +z.
pub fn sphere() -> Geometry {
    let (stacks, slices) = (SPHERE_STACKS, SPHERE_SLICES);
    let point = |i: usize, j: usize| {
        let theta = PI * i as f64 / stacks as f64;
        let phi = 2.0 * PI * j as f64 / slices as f64;
        DVec3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        )
    };
    let uv = |i: usize, j: usize| DVec2::new(j as f64 / slices as f64, i as f64 / stacks as f64);
    let mut triangles = Vec::new();
    for i in 0..stacks {
        for j in 0..slices {
            // Corners counter-clockwise seen from outside: theta grows toward -z, phi about +z.
            let (p00, p10, p11, p01) = (
                point(i, j),
                point(i + 1, j),
                point(i + 1, j + 1),
                point(i, j + 1),
            );
            let (t00, t10, t11, t01) = (uv(i, j), uv(i + 1, j), uv(i + 1, j + 1), uv(i, j + 1));
            if i > 0 {
                triangles.push(Triangle {
                    p: [p00, p10, p01],
                    n: Some([p00, p10, p01]),
                    uv: Some([t00, t10, t01]),
                });
            }
            if i + 1 < stacks {
                triangles.push(Triangle {
                    p: [p01, p10, p11],
                    n: Some([p01, p10, p11]),
                    uv: Some([t01, t10, t11]),
                });
            }
        }
    }
    Geometry { triangles }
}

/// The frame Mitsuba's cylinder takes from p0, p1 and the radius: z along p1 - p0 (its length),
/// x and y the radius; the rotation about the axis is Mitsuba's `coordinate_system` of the
/// axis (it moves only where u = 0 lies).
pub fn cylinder_frame(p0: DVec3, p1: DVec3, radius: f64) -> Option<DMat4> {
    let d = p1 - p0;
    let length = d.length();
    let n = d.try_normalize()?;
    // Mitsuba's coordinate_system (Duff et al. 2017).
    let sign = 1.0f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let s = DVec3::new(n.x * n.x * a * sign + 1.0, b * sign, -n.x * sign);
    let t = DVec3::new(b, sign + n.y * n.y * a, -n.y);
    Some(DMat4::from_cols(
        (s * radius).extend(0.0),
        (t * radius).extend(0.0),
        (n * length).extend(0.0),
        p0.extend(1.0),
    ))
}
