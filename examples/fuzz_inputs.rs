//! A bounded mutation fuzzer over the shipped inputs (CI's fuzz step, see .ci/run): graphs
//! (which extend and include each other), graph tests, pass files, shaders and their includes,
//! scenes (RON, and Mitsuba XML through its loader), OBJ/MTL and PLY meshes (ASCII and binary),
//! camera paths and viewer scripts; a textured scene (PBR, glass and cut-out MTL keys, PNG
//! maps, vt/vn, max_depth); glTF 2.0 (the shipped `.glb`, and a `.gltf` with its `.bin` and
//! PNGs beside it using every extension the loader reads, also as a RON scene's mesh under an
//! environment). Each case mutates one file of a fresh scratch copy, then
//! runs what `check` and the loaders run (no GPU): load and compile the graph, check the render
//! contract, print the plan and dot; load the scene and build its BVH and GPU layout; parse the
//! camera path and the script. Errors are the expected outcome; a panic, a crash (signal) or a
//! case that runs longer than `--case-seconds` fails the run.
//!
//! ```sh
//! cargo run --example fuzz_inputs -- --seed 1 --seconds 120
//! ```
//!
//! Deterministic for a seed: case i is the same on every machine; `--seconds` bounds the run
//! (it stops after the case in progress), `--cases` bounds the count. A crash leaves its case in
//! the scratch folder printed at the start.

// The tests' writer; `requires` is for their bad-input cases.
#[allow(dead_code)]
#[path = "../tests/common/gltf.rs"]
mod gltf_writer;

use glam::{Vec2, Vec3};
use gltf_writer::GltfWriter;
use passgraph::graph::load::load_graph;
use passgraph::render::channels::{Channel, ChannelSelection};
use passgraph::render::session::check_render_contract;
use serde_json::json;
use std::panic::AssertUnwindSafe;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// SplitMix64: a tiny, well-known generator; the cases need reproducibility, not quality.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
    fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// Tokens that have broken parsers and size arithmetic before: numbers at the edges of their
/// types, non-finite values, brackets, directives, line endings, invalid UTF-8.
const TOKENS: &[&[u8]] = &[
    b"0",
    b"-1",
    b"1e19",
    b"1e30",
    b"1e39",
    b"-1e-45",
    b"NaN",
    b"inf",
    b"-inf",
    b"4294967295",
    b"4294967296",
    b"18446744073709551615",
    b"4611686018427387905",
    b"2147483648",
    b"65536",
    b"(",
    b")",
    b"[",
    b"]",
    b"{",
    b"}",
    b",",
    b":",
    b";",
    b"\"",
    b"'",
    b"//",
    b"/*",
    b"*/",
    b"\n",
    b"\r",
    b"\r\n",
    b"\t",
    b"\0",
    b"\xff",
    b"\xc3",
    b"#include \"",
    b"#include \"lib/rng.wgsl\"\n",
    b"layers: ",
    b"size: Scaled(",
    b"Scaled(0.5)",
    b"Absolute(",
    b"PerPixel(",
    b"Bytes(",
    b"Workgroups(",
    b"persistent: true",
    b"@workgroup_size(1024, 1024)",
    b"enable f16;\n",
    b"textureStore(",
    b"array<f32, 65536>",
    b"override ",
    b"@id(0) ",
    b"var<storage, read_write>",
    b"texture_storage_2d_array<rgba32float, write>",
    b"F32(",
    b"U32(",
    b"Vec3(",
    b"Bool(",
    b"v ",
    b"f ",
    b"vt ",
    b"vn ",
    b"usemtl ",
    b"mtllib ",
    b"newmtl ",
    b"Ke ",
    b"Kd ",
    b"Ns ",
    b"Pm ",
    b"Pr ",
    b"Ni ",
    b"Tf ",
    b"d ",
    b"illum 7",
    b"map_Kd ",
    b"map_Ks ",
    b"map_Pr ",
    b"map_d ",
    b"map_Bump ",
    b"-s 1 1 1 ",
    b"tex.png",
    b"max_depth: ",
    b"IHDR",
    b"IDAT",
    b"element vertex ",
    b"element face ",
    b"property list uchar int vertex_indices\n",
    b"property float ",
    b"format binary_little_endian 1.0\n",
    b"end_header\n",
    b"key ",
    b"wait ",
    b"hold ",
    b"drag ",
    b"scroll ",
    b"screenshot ",
];

/// One mutation of `data`: a byte flipped, inserted or removed, a range deleted or repeated,
/// a token inserted or put in place of a number, or a line of another input spliced in.
fn mutate(rng: &mut Rng, data: &mut Vec<u8>, donors: &[Vec<u8>]) {
    let at = |rng: &mut Rng, data: &Vec<u8>| rng.below(data.len() + 1);
    match rng.below(9) {
        0 if !data.is_empty() => {
            let i = rng.below(data.len());
            data[i] ^= 1 << rng.below(8);
        }
        1 => {
            let i = at(rng, data);
            data.insert(i, rng.next() as u8);
        }
        2 if !data.is_empty() => {
            let i = rng.below(data.len());
            let n = (1 + rng.below(64)).min(data.len() - i);
            data.drain(i..i + n);
        }
        3 if !data.is_empty() => {
            // Repeat a range many times: long lines, deep nesting, huge counts.
            let i = rng.below(data.len());
            let n = (1 + rng.below(16)).min(data.len() - i);
            let piece = data[i..i + n].to_vec();
            let most = if rng.below(8) == 0 { 20_000 } else { 8 };
            let times = 1 + rng.below(most);
            let at = rng.below(data.len() + 1);
            data.splice(at..at, piece.iter().copied().cycle().take(n * times));
        }
        4 | 5 => {
            let token = rng.pick(TOKENS);
            let i = at(rng, data);
            data.splice(i..i, token.iter().copied());
        }
        6 => {
            // A number replaced by a token.
            let starts: Vec<usize> = (0..data.len())
                .filter(|&i| data[i].is_ascii_digit() && (i == 0 || !data[i - 1].is_ascii_digit()))
                .collect();
            if starts.is_empty() {
                return;
            }
            let s = *rng.pick(&starts);
            let e = (s..data.len())
                .find(|&i| !(data[i].is_ascii_digit() || data[i] == b'.'))
                .unwrap_or(data.len());
            let token = rng.pick(TOKENS);
            data.splice(s..e, token.iter().copied());
        }
        7 => {
            let donor = rng.pick(donors);
            let lines: Vec<&[u8]> = donor.split_inclusive(|&b| b == b'\n').collect();
            if lines.is_empty() {
                return;
            }
            let line = rng.pick(&lines).to_vec();
            let i = at(rng, data);
            data.splice(i..i, line);
        }
        _ => {
            // Truncate.
            let n = rng.below(data.len() + 1);
            data.truncate(n);
        }
    }
}

/// A binary little-endian PLY tetrahedron: the loader's binary path.
fn binary_ply() -> Vec<u8> {
    let mut out = b"ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n\
property float y\nproperty float z\nelement face 4\nproperty list uchar int vertex_indices\n\
end_header\n"
        .to_vec();
    for v in [
        [0.0f32, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ] {
        for c in v {
            out.extend(c.to_le_bytes());
        }
    }
    for f in [[0i32, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]] {
        out.push(3);
        for i in f {
            out.extend(i.to_le_bytes());
        }
    }
    out
}

/// A 3 x 2 RGBA PNG (the textured scene's maps).
fn png() -> Vec<u8> {
    let pixels: Vec<u8> = (0..24).map(|i| (i * 37 % 256) as u8).collect();
    let image = image::RgbaImage::from_raw(3, 2, pixels).unwrap();
    let mut bytes = Vec::new();
    image
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .unwrap();
    bytes
}

/// A scene with every MTL key and OBJ statement issue 14 reads: PBR, glass, cut-outs, maps,
/// texture coordinates, normals, max_depth.
fn textured_scene(extra: &Path, camera: &str) {
    std::fs::write(extra.join("tex.png"), png()).unwrap();
    std::fs::write(
        extra.join("tex.mtl"),
        "newmtl metal\nPm 1\nPr 0.3\nKd 0.9 0.6 0.2\nmap_Kd tex.png\n\
         newmtl plastic\nPm 0\nPr 0.1\nKd 0.2 0.3 0.8\nKs 1 1 1\nNi 1.5\nmap_Pr tex.png\n\
         newmtl glass\nillum 7\nNi 1.33\nTf 0.9 1 1\nNs 900\n\
         newmtl leaf\nKd 0.2 0.8 0.2\nd 0.5\nmap_d tex.png\nmap_Ks tex.png\nKe 1 1 1\n",
    )
    .unwrap();
    std::fs::write(
        extra.join("tex.obj"),
        "mtllib tex.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 2 0\nvt 2 2\nvt 0 2\n\
         vn 0 0 -1\nvn 0.1 0 -1\nvn 0 0 0\nusemtl metal\nf 1/1/1 2/2/2 3/3/2\n\
         usemtl plastic\nf 1/1 3/3 4/4\nusemtl glass\nf 1//1 2//3 4//1\nusemtl leaf\nf -4/-4/-3 -3/-3/-2 -1/-1/-1\n",
    )
    .unwrap();
    std::fs::write(
        extra.join("tex.ron"),
        format!("Scene(mesh: \"tex.obj\", {camera}, max_depth: 8)\n"),
    )
    .unwrap();
}

/// A `.gltf` + `.bin` + PNG maps with every part of glTF the loader reads: TRS, matrix and
/// child nodes, indexed and plain triangles, normals and UVs, the metallic-roughness material
/// with all its textures (one transformed), MASK and BLEND, transmission with an ior, emissive
/// strength, a camera and the three punctual lights; and a RON scene using it as its mesh.
fn gltf_scene(extra: &Path) {
    std::fs::write(extra.join("maps.png"), png()).unwrap();
    let mut g = GltfWriter::new();
    g.json["images"] = json!([{"uri": "maps.png"}]);
    g.json["textures"] = json!([{"source": 0}]);
    g.uses("KHR_texture_transform");
    g.uses("KHR_materials_emissive_strength");
    g.uses("KHR_materials_transmission");
    g.uses("KHR_materials_ior");
    let paint = g.material(json!({
        "pbrMetallicRoughness": {
            "baseColorFactor": [0.8, 0.3, 0.2, 1.0],
            "baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform":
                {"offset": [0.5, 0], "rotation": 0.3, "scale": [2, 2]}}},
            "metallicFactor": 0.5, "roughnessFactor": 0.4,
            "metallicRoughnessTexture": {"index": 0}},
        "normalTexture": {"index": 0, "scale": 0.7},
        "emissiveFactor": [0.1, 0.1, 0.0],
        "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 3.0}},
        "alphaMode": "MASK", "alphaCutoff": 0.3, "doubleSided": true}));
    let glass = g.material(json!({
        "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.1},
        "alphaMode": "BLEND",
        "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                       "KHR_materials_ior": {"ior": 1.33}}}));
    let floor = g.quad(2.0, Some(paint));
    let tri = g.mesh(
        &[Vec3::ZERO, Vec3::X, Vec3::Y],
        None,
        Some(&[Vec2::ZERO, Vec2::X, Vec2::Y]),
        None,
        Some(glass),
    );
    let camera = g.camera(json!({"type": "perspective", "name": "Cam",
        "perspective": {"yfov": 0.8, "znear": 0.01}}));
    let point = g.light(json!({"type": "point", "color": [1, 0.9, 0.8], "intensity": 500}));
    let spot = g.light(json!({"type": "spot", "intensity": 800,
        "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}}));
    let sun = g.light(json!({"type": "directional", "intensity": 2}));
    let child = g.node(json!({"mesh": tri, "scale": [1, -1, 1]}));
    g.root(
        json!({"mesh": floor, "translation": [0, -1, 0], "rotation": [0, 0.3826834, 0, 0.9238795]}),
    );
    g.root(json!({"children": [child],
        "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.2, 0.1, 0, 1]}));
    g.root(json!({"camera": camera, "translation": [0, 0.5, 4]}));
    // Pointing down: -z turned onto -y.
    let s = std::f32::consts::FRAC_1_SQRT_2;
    for (light, at) in [
        (point, [0.0, 2.0, 0.0]),
        (spot, [1.0, 2.0, 1.0]),
        (sun, [0.0, 0.0, 0.0]),
    ] {
        g.root(json!({"translation": at, "rotation": [-s, 0.0, 0.0, s],
            "extensions": {"KHR_lights_punctual": {"light": light}}}));
    }
    g.write_gltf(extra, "maps");
    // The same file as one binary (images stay external: the GLB's chunks are what differs).
    g.write_glb(extra, "maps-binary");
    std::fs::write(
        extra.join("maps.ron"),
        "Scene(mesh: \"maps.gltf\", max_depth: 5,\n    \
         environment: Environment(color: (0.2, 0.3, 0.4)),\n    \
         lights: [Point(position: (0, 3, 0), intensity: (10, 10, 10))])\n",
    )
    .unwrap();
}

/// The scratch project: graphs, passes, shaders and scenes as shipped, plus inputs made here.
fn lay_out(root: &Path, dir: &Path) {
    for sub in ["graphs", "passes", "shaders", "scenes", "tests/graphs"] {
        copy_dir(&root.join(sub), &dir.join(sub));
    }
    // The reference the graph tests read.
    let reference = "tests/data/references/cornell-128-depth3.exr";
    std::fs::create_dir_all(dir.join("tests/data/references")).unwrap();
    std::fs::copy(root.join(reference), dir.join(reference)).unwrap();
    let extra = dir.join("scenes/extra");
    std::fs::create_dir_all(&extra).unwrap();
    std::fs::copy(
        root.join("tests/data/scenes/polygons.ply"),
        extra.join("polygons.ply"),
    )
    .unwrap();
    std::fs::write(extra.join("binary.ply"), binary_ply()).unwrap();
    let camera =
        "camera: Camera(eye: (0.5, 0.5, -3), target: (0.5, 0.5, 0), up: (0, 1, 0), fov_y: 40)";
    for (name, mesh) in [("ply.ron", "polygons.ply"), ("binary.ron", "binary.ply")] {
        std::fs::write(
            extra.join(name),
            format!("Scene(mesh: \"{mesh}\", {camera})\n"),
        )
        .unwrap();
    }
    textured_scene(&extra, camera);
    gltf_scene(&extra);
    std::fs::write(
        extra.join("path.ron"),
        "CameraPath([\n    (frames: 4),\n    (frames: 2, eye: (1, 2, 3), fov_y: 30),\n])\n",
    )
    .unwrap();
    std::fs::write(extra.join("part.exr"), partial(0..8)).unwrap();
    std::fs::write(extra.join("next.exr"), partial(8..16)).unwrap();
    std::fs::write(extra.join("tiled.exr"), tiled_checkpoint()).unwrap();
    std::fs::write(
        extra.join("view.script"),
        "wait 2\nkey 2\nhold W 3\ndrag 10 -5\nscroll 2\nscreenshot a.png\nquit\n",
    )
    .unwrap();
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let target = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_dir(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), &target).unwrap();
        }
    }
}

fn files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            files(&path, out);
        } else {
            out.push(path);
        }
    }
}

/// What a mutated file is exercised through.
#[derive(Clone, Copy, Debug)]
enum Target {
    /// Compile a graph (the mutated file is the graph, a pass or a shader).
    Graph,
    /// Read a graph test file and compile its cases' graphs (no rendering).
    GraphTest,
    Scene,
    CameraPath,
    Script,
    /// A partial file (or checkpoint): read, checked, and merged with the range after it.
    Partial,
}

/// Runs the loaders a mutated file feeds. Errors are expected and ignored; panics propagate.
fn exercise(dir: &Path, target: Target, graph: &Path, scene: &Path) {
    match target {
        Target::Graph => {
            let size = [64, 48];
            let Ok(mut loaded) = load_graph(graph) else {
                return;
            };
            let _ = passgraph::graph::set_param::set_param(
                &mut loaded,
                "direct.light_selection=true",
                passgraph::render::provided::path_tracer(),
            );
            if let Ok(plan) = passgraph::compile(&loaded, size) {
                let _ = check_render_contract(&plan, &ChannelSelection::Planes(vec![Channel::Sum]));
                let _ = plan.to_string();
                let _ = passgraph::to_dot(&plan);
            }
        }
        Target::GraphTest => {
            let _ = passgraph::graphtest::run::check_file(graph);
        }
        Target::Scene => {
            if let Ok(scene) = passgraph::scene::load_scene(scene) {
                let gpu = scene.to_gpu();
                let _ = scene.camera.to_gpu(64, 48);
                let _ = gpu.triangles.len();
                let _ = (gpu.shading_bytes(), gpu.textures_bytes());
                // The Mitsuba exporter's per-material XML (the files it writes are plain text).
                for i in 0..scene.mesh.materials.len() {
                    let _ = passgraph::scene::mitsuba::bsdf_xml(&scene, i as u32);
                }
            }
        }
        Target::CameraPath => {
            let start = passgraph::scene::CameraDesc::new(
                glam::Vec3::new(0.0, 0.0, -1.0),
                glam::Vec3::ZERO,
                glam::Vec3::Y,
                40.0,
            )
            .unwrap();
            let _ = passgraph::render::camera_path::load_camera_path(
                &dir.join("scenes/extra/path.ron"),
                start,
            );
        }
        Target::Script => {
            let _ = passgraph::view::script::Script::load(&dir.join("scenes/extra/view.script"));
        }
        Target::Partial => {
            let _ = passgraph::render::merge::merge_files(&[
                dir.join("scenes/extra/part.exr"),
                dir.join("scenes/extra/next.exr"),
            ]);
            if let Ok(c) =
                passgraph::render::partial::Partial::read(&dir.join("scenes/extra/tiled.exr"))
            {
                let _ = c.tiles_held();
                let _ = c.holds();
            }
        }
    }
}

/// A small partial file of samples `range` (8x4 pixels, one sample dropped at the first pixel
/// of the second range): the fuzzer's donor for partial files and checkpoints.
fn partial(range: std::ops::Range<u32>) -> Vec<u8> {
    use passgraph::render::partial::{Packing, Partial, Plane, SampleRange};
    let pixels = 32;
    let dropped = u32::from(range.start > 0);
    let count: Vec<u32> = (0..pixels)
        .map(|i| range.len() as u32 - if i == 0 { dropped } else { 0 })
        .collect();
    let plane = Plane {
        mean: (0..pixels).map(|i| [i as f32 * 0.01, 0.5, 0.25]).collect(),
        compensation: vec![[1e-9, 0.0, -1e-9]; pixels],
        count,
    };
    Partial {
        size: [8, 4],
        samples: SampleRange {
            start: range.start,
            end: range.end,
        },
        dropped: u64::from(dropped),
        fingerprint: donor_fingerprint([8, 4]),
        source: "fuzz".into(),
        planes: vec![plane; 5],
        progress: None,
    }
    .encode(Packing::Small)
    .unwrap()
}

fn donor_fingerprint(size: [u32; 2]) -> passgraph::render::fingerprint::Fingerprint {
    passgraph::render::fingerprint::Fingerprint {
        graph: 1,
        scene: 2,
        settings: format!("size {}x{}, seed 0, max_depth 3", size[0], size[1]),
    }
}

/// A checkpoint of a 16x8 render in tiles of 8x8 stopped in the second tile (3 of samples
/// 0..8): the donor for a checkpoint's `tiles` line.
fn tiled_checkpoint() -> Vec<u8> {
    use passgraph::render::partial::{Packing, Partial, Plane, SampleRange, TileProgress};
    let pixels = 128;
    let plane = Plane {
        mean: (0..pixels).map(|i| [i as f32 * 0.01, 0.5, 0.25]).collect(),
        compensation: vec![[1e-9, 0.0, -1e-9]; pixels],
        count: (0..pixels)
            .map(|i| if i % 16 < 8 { 8 } else { 3 })
            .collect(),
    };
    Partial {
        size: [16, 8],
        samples: SampleRange { start: 0, end: 8 },
        dropped: 0,
        fingerprint: donor_fingerprint([16, 8]),
        source: "fuzz".into(),
        planes: vec![plane; 5],
        progress: Some(TileProgress {
            tile: [8, 8],
            done: 1,
            next: 3,
        }),
    }
    .encode(Packing::Fast)
    .unwrap()
}

struct Options {
    seed: u64,
    seconds: f64,
    cases: u64,
    case_seconds: u64,
}

fn options() -> Options {
    let mut o = Options {
        seed: 1,
        seconds: 120.0,
        cases: u64::MAX,
        case_seconds: 30,
    };
    let args: Vec<String> = std::env::args().skip(1).collect();
    for pair in args.chunks(2) {
        let value = pair.get(1).map(String::as_str).unwrap_or("");
        let bad = || -> ! {
            eprintln!("usage: fuzz_inputs [--seed N] [--seconds T] [--cases N] [--case-seconds T]");
            std::process::exit(2)
        };
        match pair[0].as_str() {
            "--seed" => o.seed = value.parse().unwrap_or_else(|_| bad()),
            "--seconds" => o.seconds = value.parse().unwrap_or_else(|_| bad()),
            "--cases" => o.cases = value.parse().unwrap_or_else(|_| bad()),
            "--case-seconds" => o.case_seconds = value.parse().unwrap_or_else(|_| bad()),
            _ => bad(),
        }
    }
    o
}

fn main() {
    let o = options();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let base = tempfile::Builder::new()
        .prefix("passgraph-fuzz-")
        .tempdir()
        .unwrap();
    let pristine = base.path().join("pristine");
    lay_out(root, &pristine);
    // Mutations of an input that does not load would test only its first error.
    for scene in ["tex.ron", "maps.gltf", "maps.ron", "maps-binary.glb"] {
        if let Err(e) = passgraph::scene::load_scene(&pristine.join("scenes/extra").join(scene)) {
            eprintln!("fuzz_inputs: the scene {scene} does not load: {e}");
            std::process::exit(1);
        }
    }
    for part in ["part.exr", "next.exr", "tiled.exr"] {
        if let Err(e) =
            passgraph::render::partial::Partial::read(&pristine.join("scenes/extra").join(part))
        {
            eprintln!("fuzz_inputs: the partial {part} does not read: {e}");
            std::process::exit(1);
        }
    }
    let mut inputs = Vec::new();
    files(&pristine, &mut inputs);
    // The reference image is data the graph tests read, not an input to mutate.
    inputs.retain(|p| !p.starts_with(pristine.join("tests/data")));
    inputs.sort();
    let graphs: Vec<PathBuf> = inputs
        .iter()
        .filter_map(|p| p.strip_prefix(&pristine).ok())
        .filter(|p| p.starts_with("graphs"))
        .map(Path::to_path_buf)
        .collect();
    let donors: Vec<Vec<u8>> = inputs.iter().map(|p| std::fs::read(p).unwrap()).collect();
    let case_dir = base.path().join("case");
    copy_dir(&pristine, &case_dir);
    eprintln!(
        "fuzz_inputs: seed {}, up to {} s, {} inputs; each case is laid out in {} (left there after a crash)",
        o.seed,
        o.seconds,
        inputs.len(),
        case_dir.display()
    );

    // A hang is a case running past --case-seconds: the watchdog names it and ends the run.
    let current = Arc::new(Mutex::new(String::new()));
    let started = Arc::new(AtomicU64::new(0));
    let epoch = Instant::now();
    {
        let current = Arc::clone(&current);
        let started = Arc::clone(&started);
        let limit = o.case_seconds;
        std::thread::spawn(move || {
            loop {
                std::thread::sleep(Duration::from_secs(1));
                let since = epoch.elapsed().as_secs() - started.load(Ordering::Relaxed);
                if since > limit {
                    let case = current.lock().map(|c| c.clone()).unwrap_or_default();
                    eprintln!("fuzz_inputs: HANG: {case} ran over {limit} s");
                    std::process::exit(1);
                }
            }
        });
    }
    // Panics are counted, not printed by the default hook at every case.
    let panics: Arc<Mutex<Vec<String>>> = Arc::default();
    {
        let panics = Arc::clone(&panics);
        let current = Arc::clone(&current);
        std::panic::set_hook(Box::new(move |info| {
            let case = current.lock().map(|c| c.clone()).unwrap_or_default();
            if let Ok(mut p) = panics.lock() {
                p.push(format!("{case}: {info}"));
            }
        }));
    }

    let mut rng = Rng(o.seed);
    let mut done = 0u64;
    while done < o.cases && epoch.elapsed().as_secs_f64() < o.seconds {
        let index = rng.below(inputs.len());
        let file = &inputs[index];
        let rel = file.strip_prefix(&pristine).unwrap().to_path_buf();
        let mut data = donors[index].clone();
        for _ in 0..1 + rng.below(4) {
            mutate(&mut rng, &mut data, &donors);
        }
        // The case folder is the pristine copy with this one file mutated (restored after).
        std::fs::write(case_dir.join(&rel), &data).unwrap();

        let name = rel.to_string_lossy().into_owned();
        let target = if name.starts_with("tests/graphs") {
            Target::GraphTest
        } else if name.starts_with("graphs")
            || name.starts_with("passes")
            || name.starts_with("shaders")
        {
            Target::Graph
        } else if name.ends_with("path.ron") {
            Target::CameraPath
        } else if name.ends_with(".script") {
            Target::Script
        } else if name.ends_with(".exr") && name.contains("extra") {
            Target::Partial
        } else {
            Target::Scene
        };
        // A mutated graph, pass or shader is compiled through one graph using it (any graph
        // for a shared file); a mesh through the scene naming it.
        let graph = if name.starts_with("graphs") || name.starts_with("tests/graphs") {
            case_dir.join(&rel)
        } else {
            case_dir.join(rng.pick(&graphs))
        };
        let scene_dir = case_dir.join(rel.parent().unwrap_or(Path::new("")));
        let scene = if name.ends_with("scene.ron")
            || name.ends_with(".xml")
            || name.ends_with("ply.ron")
            || name.ends_with("binary.ron")
            || name.ends_with("tex.ron")
            || name.ends_with("maps.ron")
            || name.ends_with(".glb")
        {
            case_dir.join(&rel)
        } else if name.contains("/tex.") {
            scene_dir.join("tex.ron")
        } else if name.contains("/maps.") {
            // The .gltf, its .bin or its PNG: through the RON scene on odd cases.
            scene_dir.join(if done.is_multiple_of(2) {
                "maps.gltf"
            } else {
                "maps.ron"
            })
        } else if name.ends_with("binary.ply") {
            scene_dir.join("binary.ron")
        } else if name.ends_with(".ply") {
            scene_dir.join("ply.ron")
        } else {
            scene_dir.join("scene.ron")
        };
        if let Ok(mut c) = current.lock() {
            *c = format!("case {done} (seed {}, {name}, {target:?})", o.seed);
        }
        started.store(epoch.elapsed().as_secs(), Ordering::Relaxed);
        let result = std::panic::catch_unwind(AssertUnwindSafe(|| {
            exercise(&case_dir, target, &graph, &scene)
        }));
        if result.is_err() {
            // Keep the case for the report.
            let kept = base.path().join(format!("panic-{done}"));
            copy_dir(&case_dir, &kept);
        }
        std::fs::write(case_dir.join(&rel), &donors[index]).unwrap();
        done += 1;
    }
    let seconds = epoch.elapsed().as_secs_f64();
    let panics = panics.lock().map(|p| p.clone()).unwrap_or_default();
    println!(
        "fuzz_inputs: {done} cases in {seconds:.1} s (seed {}): {} panics",
        o.seed,
        panics.len()
    );
    if !panics.is_empty() {
        for p in &panics {
            eprintln!("PANIC {p}");
        }
        // Keep the failing cases for inspection.
        let kept = base.keep();
        eprintln!("fuzz_inputs: failing cases kept in {}", kept.display());
        std::process::exit(1);
    }
}
