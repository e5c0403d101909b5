//! Geometry for the robustness suites: a deterministic generator, closed meshes, and scene
//! files (OBJ, MTL, RON) written to a folder.

use glam::Vec3;
use std::collections::HashMap;
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// A small deterministic generator (SplitMix64), so failures reproduce.
pub struct Rng(pub u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }

    pub fn vec2(&mut self) -> glam::Vec2 {
        glam::Vec2::new(self.unit(), self.unit())
    }

    /// Uniform on the unit sphere (by its z and azimuth).
    pub fn sphere(&mut self) -> Vec3 {
        let z = 1.0 - 2.0 * self.unit();
        let phi = 2.0 * std::f32::consts::PI * self.unit();
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }

    /// Uniform in 0..n.
    pub fn index(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    pub fn vec(&mut self, lo: f32, hi: f32) -> Vec3 {
        let mut c = || lo + (hi - lo) * self.unit();
        Vec3::new(c(), c(), c())
    }

    /// A uniformly distributed unit direction.
    pub fn dir(&mut self) -> Vec3 {
        loop {
            let d = self.vec(-1.0, 1.0);
            let l2 = d.length_squared();
            if l2 > 1e-4 && l2 <= 1.0 {
                return d / l2.sqrt();
            }
        }
    }

    /// A point uniformly inside the ball of `radius` around the origin.
    pub fn in_ball(&mut self, radius: f32) -> Vec3 {
        loop {
            let p = self.vec(-1.0, 1.0);
            if p.length_squared() <= 1.0 {
                return p * radius;
            }
        }
    }
}

/// An indexed closed mesh: shared vertices are one entry, so neighbours share them bit for bit.
pub struct IndexedMesh {
    pub vertices: Vec<Vec3>,
    pub faces: Vec<[u32; 3]>,
}

impl IndexedMesh {
    pub fn triangles(&self) -> Vec<[Vec3; 3]> {
        self.faces
            .iter()
            .map(|f| f.map(|i| self.vertices[i as usize]))
            .collect()
    }

    /// Every edge once (as a sorted vertex pair).
    pub fn edges(&self) -> Vec<[u32; 2]> {
        let mut edges: Vec<[u32; 2]> = self
            .faces
            .iter()
            .flat_map(|f| (0..3).map(move |k| [f[k].min(f[(k + 1) % 3]), f[k].max(f[(k + 1) % 3])]))
            .collect();
        edges.sort_unstable();
        edges.dedup();
        edges
    }

    /// Every vertex and every edge midpoint (rounded to f32): the points where a ray is most
    /// likely to slip between neighbouring triangles.
    pub fn vertex_and_edge_targets(&self) -> Vec<Vec3> {
        let mut targets = self.vertices.clone();
        for [a, b] in self.edges() {
            targets.push((self.vertices[a as usize] + self.vertices[b as usize]) * 0.5);
        }
        targets
    }

    /// Whether every edge is shared by exactly two faces (a closed surface).
    pub fn is_closed(&self) -> bool {
        let mut count: HashMap<[u32; 2], u32> = HashMap::new();
        for f in &self.faces {
            for k in 0..3 {
                let (a, b) = (f[k], f[(k + 1) % 3]);
                *count.entry([a.min(b), a.max(b)]).or_default() += 1;
            }
        }
        count.values().all(|&c| c == 2)
    }
}

/// The unit icosphere: an icosahedron whose faces are split in four `subdivisions` times, new
/// vertices pushed onto the sphere. Counter-clockwise seen from outside.
pub fn icosphere(subdivisions: u32) -> IndexedMesh {
    let t = (1.0 + 5.0f32.sqrt()) / 2.0;
    let mut vertices: Vec<Vec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut faces: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
        let mut midpoint = |a: u32, b: u32, vertices: &mut Vec<Vec3>| -> u32 {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                vertices.push(((vertices[a as usize] + vertices[b as usize]) * 0.5).normalize());
                (vertices.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(faces.len() * 4);
        for [a, b, c] in faces {
            let ab = midpoint(a, b, &mut vertices);
            let bc = midpoint(b, c, &mut vertices);
            let ca = midpoint(c, a, &mut vertices);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = next;
    }
    IndexedMesh { vertices, faces }
}

/// The closed box [-1, 1]^3, each face an n x n grid of quads split along alternating
/// diagonals. Counter-clockwise seen from inside (front faces inward).
pub fn grid_cube(n: u32) -> IndexedMesh {
    let mut index: HashMap<[i32; 3], u32> = HashMap::new();
    let mut vertices = Vec::new();
    let mut faces = Vec::new();
    let coord = |i: u32| -1.0 + 2.0 * i as f32 / n as f32;
    for axis in 0..3 {
        for side in [0, n] {
            let mut id = |i: u32, j: u32| -> u32 {
                let mut key = [0i32; 3];
                key[axis] = side as i32;
                key[(axis + 1) % 3] = i as i32;
                key[(axis + 2) % 3] = j as i32;
                *index.entry(key).or_insert_with(|| {
                    vertices.push(Vec3::from(key.map(|k| coord(k as u32))));
                    (vertices.len() - 1) as u32
                })
            };
            for i in 0..n {
                for j in 0..n {
                    let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                    let pair = if (i + j) % 2 == 0 {
                        [[a, b, c], [a, c, d]]
                    } else {
                        [[a, b, d], [b, c, d]]
                    };
                    // (axis+1, axis+2) is right-handed about +axis: counter-clockwise seen from
                    // the +axis side, which is the inside for the low face.
                    for [p, q, r] in pair {
                        faces.push(if side == 0 { [p, q, r] } else { [p, r, q] });
                    }
                }
            }
        }
    }
    IndexedMesh { vertices, faces }
}

/// A material for [`ObjWriter`]: name, Kd, Ke.
pub struct Mtl {
    pub name: &'static str,
    pub kd: [f32; 3],
    pub ke: [f32; 3],
}

/// Builds an OBJ (one `v` line per triangle corner, so any f32 is written exactly) and its MTL.
#[derive(Default)]
pub struct ObjWriter {
    obj: String,
    mtl: String,
    vertex_count: usize,
}

impl ObjWriter {
    pub fn new(materials: &[Mtl]) -> ObjWriter {
        let mut w = ObjWriter::default();
        for m in materials {
            let [r, g, b] = m.kd;
            let [er, eg, eb] = m.ke;
            writeln!(
                w.mtl,
                "newmtl {}\nKd {r} {g} {b}\nKe {er} {eg} {eb}\n",
                m.name
            )
            .unwrap();
        }
        w.obj.push_str("mtllib scene.mtl\n");
        w
    }

    pub fn material(&mut self, name: &str) -> &mut Self {
        writeln!(self.obj, "usemtl {name}").unwrap();
        self
    }

    /// A polygon (fan-triangulated by the loader), counter-clockwise seen from its front.
    pub fn polygon(&mut self, points: &[Vec3]) -> &mut Self {
        for p in points {
            // `{}` prints the shortest decimal that parses back to the same f32.
            writeln!(self.obj, "v {} {} {}", p.x, p.y, p.z).unwrap();
        }
        let first = self.vertex_count + 1;
        self.vertex_count += points.len();
        let indices: Vec<String> = (first..first + points.len())
            .map(|i| i.to_string())
            .collect();
        writeln!(self.obj, "f {}", indices.join(" ")).unwrap();
        self
    }

    pub fn triangles(&mut self, triangles: &[[Vec3; 3]]) -> &mut Self {
        for t in triangles {
            self.polygon(t);
        }
        self
    }

    /// Writes `scene.obj`, `scene.mtl` and `scene.ron` (camera `eye` -> `target`, up +y unless
    /// given) into `dir`, returning the scene file.
    pub fn write(&self, dir: &Path, eye: Vec3, target: Vec3, up: Vec3, fov_y: f32) -> PathBuf {
        std::fs::create_dir_all(dir).unwrap();
        std::fs::write(dir.join("scene.obj"), &self.obj).unwrap();
        std::fs::write(dir.join("scene.mtl"), &self.mtl).unwrap();
        let scene = format!(
            "Scene(\n    mesh: \"scene.obj\",\n    camera: Camera(eye: ({}, {}, {}), target: ({}, {}, {}), up: ({}, {}, {}), fov_y: {}),\n)\n",
            eye.x, eye.y, eye.z, target.x, target.y, target.z, up.x, up.y, up.z, fov_y
        );
        let path = dir.join("scene.ron");
        std::fs::write(&path, scene).unwrap();
        path
    }
}
