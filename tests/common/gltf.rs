//! Small glTF 2.0 files for the tests: meshes from positions (and normals, UVs, indices) in one
//! binary buffer, nodes, materials and extensions as JSON, written as `.gltf` + `.bin` or as
//! one `.glb`.

use glam::{Vec2, Vec3};
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

pub struct GltfWriter {
    pub json: Value,
    pub bin: Vec<u8>,
}

impl Default for GltfWriter {
    fn default() -> Self {
        Self::new()
    }
}

impl GltfWriter {
    pub fn new() -> GltfWriter {
        GltfWriter {
            json: json!({
                "asset": {"version": "2.0", "generator": "passgraph tests"},
                "scene": 0,
                "scenes": [{"nodes": []}],
                "nodes": [],
                "meshes": [],
                "accessors": [],
                "bufferViews": [],
                "buffers": [{"byteLength": 0}],
            }),
            bin: Vec::new(),
        }
    }

    fn push(&mut self, key: &str, value: Value) -> usize {
        let list = self.json[key].as_array_mut().expect("a list");
        list.push(value);
        list.len() - 1
    }

    /// Appends `bytes` (4-aligned) as a buffer view and returns its index.
    pub fn view(&mut self, bytes: &[u8]) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.json["buffers"][0]["byteLength"] = json!(self.bin.len());
        self.push(
            "bufferViews",
            json!({"buffer": 0, "byteOffset": offset, "byteLength": bytes.len()}),
        )
    }

    /// A float accessor of `kind` ("VEC3", "VEC2") over `values`, with min and max.
    pub fn floats(&mut self, values: &[f32], kind: &str, width: usize) -> usize {
        let view = self.view(bytemuck::cast_slice(values));
        let mut min = vec![f32::MAX; width];
        let mut max = vec![f32::MIN; width];
        for v in values.chunks_exact(width) {
            for i in 0..width {
                min[i] = min[i].min(v[i]);
                max[i] = max[i].max(v[i]);
            }
        }
        self.push(
            "accessors",
            json!({"bufferView": view, "componentType": 5126, "count": values.len() / width,
                   "type": kind, "min": min, "max": max}),
        )
    }

    pub fn indices(&mut self, indices: &[u32]) -> usize {
        let view = self.view(bytemuck::cast_slice(indices));
        self.push(
            "accessors",
            json!({"bufferView": view, "componentType": 5125, "count": indices.len(),
                   "type": "SCALAR"}),
        )
    }

    /// A mesh of one triangle-list primitive.
    pub fn mesh(
        &mut self,
        positions: &[Vec3],
        normals: Option<&[Vec3]>,
        uvs: Option<&[Vec2]>,
        indices: Option<&[u32]>,
        material: Option<usize>,
    ) -> usize {
        let p: Vec<f32> = positions.iter().flat_map(|v| v.to_array()).collect();
        let mut attributes = json!({"POSITION": self.floats(&p, "VEC3", 3)});
        if let Some(n) = normals {
            let n: Vec<f32> = n.iter().flat_map(|v| v.to_array()).collect();
            attributes["NORMAL"] = json!(self.floats(&n, "VEC3", 3));
        }
        if let Some(uv) = uvs {
            let uv: Vec<f32> = uv.iter().flat_map(|v| v.to_array()).collect();
            attributes["TEXCOORD_0"] = json!(self.floats(&uv, "VEC2", 2));
        }
        let mut primitive = json!({"attributes": attributes});
        if let Some(i) = indices {
            primitive["indices"] = json!(self.indices(i));
        }
        if let Some(m) = material {
            primitive["material"] = json!(m);
        }
        self.push("meshes", json!({"primitives": [primitive]}))
    }

    /// A square of half-width `half` in the plane y = 0 facing +y, centred at the origin, with
    /// normals and UVs.
    pub fn quad(&mut self, half: f32, material: Option<usize>) -> usize {
        let p = [
            Vec3::new(-half, 0.0, -half),
            Vec3::new(-half, 0.0, half),
            Vec3::new(half, 0.0, half),
            Vec3::new(half, 0.0, -half),
        ];
        let n = [Vec3::Y; 4];
        let uv = [
            Vec2::new(0.0, 0.0),
            Vec2::new(0.0, 1.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(1.0, 0.0),
        ];
        self.mesh(&p, Some(&n), Some(&uv), Some(&[0, 1, 2, 0, 2, 3]), material)
    }

    /// A node (JSON object) at the scene's root.
    pub fn root(&mut self, node: Value) -> usize {
        let i = self.push("nodes", node);
        self.json["scenes"][0]["nodes"]
            .as_array_mut()
            .unwrap()
            .push(json!(i));
        i
    }

    /// A node that is not at the root (a child, referenced by another node).
    pub fn node(&mut self, node: Value) -> usize {
        self.push("nodes", node)
    }

    pub fn material(&mut self, material: Value) -> usize {
        if self.json.get("materials").is_none() {
            self.json["materials"] = json!([]);
        }
        self.push("materials", material)
    }

    pub fn camera(&mut self, camera: Value) -> usize {
        if self.json.get("cameras").is_none() {
            self.json["cameras"] = json!([]);
        }
        self.push("cameras", camera)
    }

    /// A KHR_lights_punctual light, the extension declared used.
    pub fn light(&mut self, light: Value) -> usize {
        self.uses("KHR_lights_punctual");
        let ext = &mut self.json["extensions"]["KHR_lights_punctual"]["lights"];
        if ext.is_null() {
            *ext = json!([]);
        }
        let list = ext.as_array_mut().unwrap();
        list.push(light);
        list.len() - 1
    }

    pub fn uses(&mut self, extension: &str) {
        if self.json.get("extensionsUsed").is_none() {
            self.json["extensionsUsed"] = json!([]);
        }
        let used = self.json["extensionsUsed"].as_array_mut().unwrap();
        if !used.iter().any(|e| e == extension) {
            used.push(json!(extension));
        }
    }

    pub fn requires(&mut self, extension: &str) {
        self.uses(extension);
        if self.json.get("extensionsRequired").is_none() {
            self.json["extensionsRequired"] = json!([]);
        }
        self.json["extensionsRequired"]
            .as_array_mut()
            .unwrap()
            .push(json!(extension));
    }

    /// `dir/name.gltf` with its buffer beside it as `dir/name.bin`.
    pub fn write_gltf(&self, dir: &Path, name: &str) -> PathBuf {
        let mut json = self.json.clone();
        json["buffers"][0]["uri"] = json!(format!("{name}.bin"));
        std::fs::write(dir.join(format!("{name}.bin")), &self.bin).unwrap();
        let path = dir.join(format!("{name}.gltf"));
        std::fs::write(&path, serde_json::to_string_pretty(&json).unwrap()).unwrap();
        path
    }

    /// The GLB container's bytes: header, JSON chunk (space-padded), BIN chunk (zero-padded).
    pub fn glb_bytes(&self) -> Vec<u8> {
        let mut json = serde_json::to_vec(&self.json).unwrap();
        while !json.len().is_multiple_of(4) {
            json.push(b' ');
        }
        let mut bin = self.bin.clone();
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let total = 12 + 8 + json.len() + 8 + bin.len();
        let mut out = Vec::with_capacity(total);
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&(total as u32).to_le_bytes());
        out.extend_from_slice(&(json.len() as u32).to_le_bytes());
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&json);
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&bin);
        out
    }

    pub fn write_glb(&self, dir: &Path, name: &str) -> PathBuf {
        let path = dir.join(format!("{name}.glb"));
        std::fs::write(&path, self.glb_bytes()).unwrap();
        path
    }
}
