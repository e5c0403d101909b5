//! glTF 2.0 loading (src/scene/gltf/): what a file says arrives in the scene (meshes through
//! the node tree, materials, cameras, KHR_lights_punctual in Blender's units), `.gltf` and
//! `.glb` alike, and bad files are refused with the file and the fault named, no panic.

mod common;

use common::gltf::GltfWriter;
use glam::{Vec2, Vec3};
use passgraph::scene::emitters::AnalyticLight;
use passgraph::scene::{
    FovAxis, LoadedScene, MATERIAL_DIELECTRIC, MATERIAL_METALLIC_ROUGHNESS, NO_TEXTURE, Projection,
    SceneError, SceneOptions, load_scene_with,
};
use serde_json::json;
use std::path::Path;

fn load(path: &Path) -> Result<LoadedScene, SceneError> {
    load_scene_with(path, &SceneOptions::default())
}

fn load_camera(path: &Path, camera: &str) -> Result<LoadedScene, SceneError> {
    let options = SceneOptions {
        camera: Some(camera.to_string()),
        ..SceneOptions::default()
    };
    load_scene_with(path, &options)
}

/// The error's text, which must name the file.
fn error_of(path: &Path) -> String {
    let e = match load(path) {
        Ok(_) => panic!("{} loaded, but it is bad", path.display()),
        Err(e) => e.to_string(),
    };
    assert!(
        e.contains(&path.display().to_string()),
        "the error names the file: {e}"
    );
    e
}

fn assert_mentions(text: &str, parts: &[&str]) {
    for p in parts {
        assert!(text.contains(p), "'{p}' missing from: {text}");
    }
}

/// A lit, framed square: a rough metallic-roughness material, a named camera, a point light.
fn square_scene() -> GltfWriter {
    let mut g = GltfWriter::new();
    let m = g.material(json!({"name": "paint", "pbrMetallicRoughness": {
        "baseColorFactor": [0.8, 0.4, 0.2, 1.0], "metallicFactor": 0.25, "roughnessFactor": 0.5}}));
    let mesh = g.quad(1.0, Some(m));
    g.root(json!({"mesh": mesh}));
    let cam = g.camera(json!({"name": "overhead", "type": "perspective",
        "perspective": {"yfov": 0.8, "znear": 0.1}}));
    // Looking down -y from (0, 3, 0): the camera's -z turned onto -y.
    let s = std::f32::consts::FRAC_1_SQRT_2;
    g.root(
        json!({"name": "camera node", "camera": cam, "translation": [0.0, 3.0, 0.0],
        "rotation": [-s, 0.0, 0.0, s]}),
    );
    let light = g.light(json!({"type": "point", "intensity": 683.0, "color": [1.0, 0.5, 0.25]}));
    g.root(
        json!({"extensions": {"KHR_lights_punctual": {"light": light}},
        "translation": [0.5, 2.0, 0.0]}),
    );
    g
}

#[test]
fn a_square_loads_with_its_material_camera_and_light() {
    let dir = tempfile::tempdir().unwrap();
    let path = square_scene().write_gltf(dir.path(), "square");
    let scene = load(&path).unwrap().scene;
    let mesh = &scene.mesh;
    assert_eq!(mesh.triangles.len(), 2);
    assert_eq!(mesh.material_names, ["paint"]);
    let m = &mesh.materials[0];
    assert_eq!(m.kind, MATERIAL_METALLIC_ROUGHNESS);
    assert_eq!(m.kd, [0.8, 0.4, 0.2]);
    assert_eq!(m.ks[0], 0.25);
    assert_eq!(m.alpha, 0.25, "alpha = roughness^2");
    for t in &mesh.triangles {
        let n = (t.vertices[1] - t.vertices[0]).cross(t.vertices[2] - t.vertices[0]);
        assert!(n.y > 0.0, "counter-clockwise seen from +y: {n}");
        assert_eq!(t.normals, Some([Vec3::Y; 3]));
    }
    // glTF's uv (0, 0) is the image's top left, passgraph's v runs up: (0, 1).
    assert_eq!(mesh.triangles[0].uvs.unwrap()[0], Vec2::new(0.0, 1.0));
    assert!((scene.camera.eye() - Vec3::new(0.0, 3.0, 0.0)).length() < 1e-6);
    assert!((scene.camera.target() - scene.camera.eye()).normalize().y < -0.999);
    match scene.camera.projection() {
        Projection::Perspective {
            fov_degrees,
            fov_axis,
            ..
        } => {
            assert!((fov_degrees - 0.8f32.to_degrees()).abs() < 1e-4);
            assert_eq!(fov_axis, FovAxis::Y);
        }
        p => panic!("perspective expected, got {p:?}"),
    }
    // 683 cd of white is 1 W/sr (Blender's importer: W = cd / 683 for point lights).
    match &scene.emitters.lights[..] {
        [
            AnalyticLight::Point {
                position,
                intensity,
            },
        ] => {
            assert_eq!(*position, Vec3::new(0.5, 2.0, 0.0));
            assert!((*intensity - Vec3::new(1.0, 0.5, 0.25)).abs().max_element() < 1e-6);
        }
        l => panic!("one point light expected: {l:?}"),
    }
    assert_eq!(scene.max_depth, passgraph::scene::gltf::GLTF_MAX_DEPTH);
}

#[test]
fn glb_and_gltf_of_one_scene_load_the_same() {
    let dir = tempfile::tempdir().unwrap();
    let g = square_scene();
    let a = load(&g.write_gltf(dir.path(), "square")).unwrap().scene;
    let b = load(&g.write_glb(dir.path(), "square")).unwrap().scene;
    assert_eq!(a.mesh.triangles, b.mesh.triangles);
    assert_eq!(a.mesh.materials, b.mesh.materials);
    assert_eq!(a.emitters.lights, b.emitters.lights);
    assert_eq!(a.camera, b.camera);
}

#[test]
fn node_transforms_compose_and_a_mirroring_node_keeps_faces_outward() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = GltfWriter::new();
    let mesh = g.quad(1.0, None);
    // Child: translated by (0, 1, 0) and mirrored in y; parent: scaled by 2, moved by +x 10.
    let child = g.node(json!({"mesh": mesh, "translation": [0.0, 1.0, 0.0],
        "scale": [1.0, -1.0, 1.0]}));
    g.root(
        json!({"children": [child], "matrix": [2.0, 0.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0,
        0.0, 0.0, 2.0, 0.0, 10.0, 0.0, 0.0, 1.0]}),
    );
    let scene = load(&g.write_gltf(dir.path(), "nodes")).unwrap().scene;
    for t in &scene.mesh.triangles {
        for v in t.vertices {
            assert!((v.y - 2.0).abs() < 1e-6, "y = 2 (1 * 2): {v}");
            assert!((v.x - 10.0).abs() <= 2.0 + 1e-6, "x within 10 +- 2: {v}");
        }
        // Mirrored in y, the face and its normals turn to -y together.
        let n = (t.vertices[1] - t.vertices[0]).cross(t.vertices[2] - t.vertices[0]);
        assert!(n.y < 0.0, "the winding flips with the mirror: {n}");
        for normal in t.normals.unwrap() {
            assert!((normal - Vec3::NEG_Y).length() < 1e-6, "{normal}");
        }
    }
    // The default material: white, fully metallic, fully rough (the specification's defaults).
    let m = &scene.mesh.materials[0];
    assert_eq!(
        (m.kind, m.kd, m.ks[0], m.alpha),
        (MATERIAL_METALLIC_ROUGHNESS, [1.0; 3], 1.0, 1.0)
    );
}

#[test]
fn a_file_without_a_camera_is_framed_from_the_front() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = GltfWriter::new();
    let mesh = g.quad(1.0, None);
    // Stand the square up facing +z, centred at (3, 4, 5).
    let s = std::f32::consts::FRAC_1_SQRT_2;
    g.root(json!({"mesh": mesh, "translation": [3.0, 4.0, 5.0], "rotation": [s, 0.0, 0.0, s]}));
    let scene = load(&g.write_glb(dir.path(), "framed")).unwrap().scene;
    let c = &scene.camera;
    assert!((c.target() - Vec3::new(3.0, 4.0, 5.0)).length() < 1e-5);
    let back = c.eye() - c.target();
    assert!(back.normalize().z > 0.999, "from +z: {back}");
    // The bounding sphere (radius sqrt 2) fills the 39.6-degree view.
    let expected = 2f32.sqrt() / (39.6f32.to_radians() / 2.0).sin();
    assert!((back.length() - expected).abs() < 1e-3, "{back}");
}

#[test]
fn camera_is_chosen_by_camera_or_node_name_and_an_unknown_name_lists_them() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = square_scene();
    let side = g.camera(json!({"name": "side", "type": "orthographic",
        "orthographic": {"xmag": 1.5, "ymag": 1.5, "znear": 0.1, "zfar": 100.0}}));
    g.root(json!({"name": "side node", "camera": side, "translation": [0.0, 0.0, 5.0]}));
    let path = g.write_gltf(dir.path(), "cameras");
    let first = load(&path).unwrap().scene.camera;
    assert_eq!(first.eye(), Vec3::new(0.0, 3.0, 0.0), "the first camera");
    for name in ["side", "side node"] {
        let c = load_camera(&path, name).unwrap().scene.camera;
        assert_eq!(c.eye(), Vec3::new(0.0, 0.0, 5.0));
        assert_eq!(c.projection(), Projection::Orthographic { width: 3.0 });
    }
    let e = load_camera(&path, "front").err().unwrap().to_string();
    assert_mentions(&e, &["--camera front", "overhead", "side"]);
}

#[test]
fn punctual_lights_convert_as_blenders_importer_does() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = GltfWriter::new();
    let mesh = g.quad(1.0, None);
    g.root(json!({"mesh": mesh}));
    let sun = g.light(json!({"type": "directional", "intensity": 6.83}));
    let spot = g.light(json!({"type": "spot", "intensity": 68.3,
        "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}}));
    // Both point along their node's -z: turned onto -y.
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let down = json!([-s, 0.0, 0.0, s]);
    g.root(json!({"extensions": {"KHR_lights_punctual": {"light": sun}}, "rotation": down}));
    g.root(
        json!({"extensions": {"KHR_lights_punctual": {"light": spot}}, "rotation": down,
        "translation": [0.0, 2.0, 0.0]}),
    );
    let scene = load(&g.write_gltf(dir.path(), "lights")).unwrap().scene;
    match &scene.emitters.lights[..] {
        [
            AnalyticLight::Directional {
                direction,
                irradiance,
            },
            AnalyticLight::Spot {
                position,
                target,
                intensity,
                cutoff_angle,
                beam_width,
                ..
            },
        ] => {
            assert!((*direction - Vec3::NEG_Y).length() < 1e-6);
            assert!((*irradiance - Vec3::splat(0.01)).abs().max_element() < 1e-7);
            assert_eq!(*position, Vec3::new(0.0, 2.0, 0.0));
            assert!((*target - *position - Vec3::NEG_Y).length() < 1e-6);
            assert!((*intensity - Vec3::splat(0.1)).abs().max_element() < 1e-7);
            assert!((cutoff_angle - 0.5f32.to_degrees()).abs() < 1e-4);
            assert!((beam_width - 0.2f32.to_degrees()).abs() < 1e-4);
        }
        l => panic!("a directional and a spot light expected: {l:?}"),
    }
}

#[test]
fn transmission_makes_a_dielectric_and_blend_a_stochastic_opacity() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = GltfWriter::new();
    g.uses("KHR_materials_transmission");
    g.uses("KHR_materials_ior");
    let glass = g.material(json!({"extensions": {
        "KHR_materials_transmission": {"transmissionFactor": 1.0},
        "KHR_materials_ior": {"ior": 1.33}},
        "pbrMetallicRoughness": {"baseColorFactor": [0.9, 1.0, 0.9, 1.0], "roughnessFactor": 0.0}}));
    let veil = g.material(json!({"alphaMode": "BLEND",
        "pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 0.3]}}));
    let cut = g.material(json!({"alphaMode": "MASK", "alphaCutoff": 0.5,
        "pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 0.3]}}));
    for m in [glass, veil, cut] {
        let mesh = g.quad(1.0, Some(m));
        g.root(json!({"mesh": mesh}));
    }
    let scene = load(&g.write_gltf(dir.path(), "glass")).unwrap().scene;
    let ms = &scene.mesh.materials;
    assert_eq!(ms[0].kind, MATERIAL_DIELECTRIC);
    assert_eq!(
        (ms[0].ior, ms[0].alpha, ms[0].tf),
        (1.33, 0.0, [0.9, 1.0, 0.9])
    );
    assert_eq!(ms[1].opacity, 0.3, "BLEND: passes 70 % of paths through");
    assert_eq!(ms[2].opacity, 0.0, "MASK: 0.3 is below the cutoff, a hole");
}

#[test]
fn a_primitive_without_uvs_gets_its_material_without_textures() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = GltfWriter::new();
    // A 2x1 PNG: its texture applies where there are uvs.
    let png = dir.path().join("texture.png");
    image::RgbaImage::from_raw(2, 1, vec![255, 0, 0, 255, 0, 255, 0, 255])
        .unwrap()
        .save(&png)
        .unwrap();
    g.json["images"] = json!([{"uri": "texture.png"}]);
    g.json["textures"] = json!([{"source": 0}]);
    let m = g.material(json!({"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}));
    let with = g.quad(1.0, Some(m));
    let p = [Vec3::ZERO, Vec3::X, Vec3::Z];
    let without = g.mesh(&p, None, None, None, Some(m));
    g.root(json!({"mesh": with}));
    g.root(json!({"mesh": without}));
    let scene = load(&g.write_gltf(dir.path(), "textured")).unwrap().scene;
    let ms = &scene.mesh.materials;
    assert_eq!(ms.len(), 2);
    assert_ne!(ms[0].map_kd, NO_TEXTURE);
    assert_eq!(ms[1].map_kd, NO_TEXTURE);
    assert_eq!(scene.mesh.triangles[2].material, 1);
}

// Bad input: each refused with the file named and what is wrong.

#[test]
fn a_truncated_glb_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = square_scene().glb_bytes();
    for cut in [6, 20, bytes.len() / 2, bytes.len() - 1] {
        let path = dir.path().join("cut.glb");
        std::fs::write(&path, &bytes[..cut]).unwrap();
        let e = error_of(&path);
        assert_mentions(&e, &["glTF"]);
    }
}

#[test]
fn a_missing_buffer_file_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let path = square_scene().write_gltf(dir.path(), "square");
    std::fs::remove_file(dir.path().join("square.bin")).unwrap();
    assert_mentions(&error_of(&path), &["square.bin"]);
}

#[test]
fn a_buffer_outside_the_files_folder_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let inner = dir.path().join("inner");
    std::fs::create_dir(&inner).unwrap();
    let g = square_scene();
    std::fs::write(dir.path().join("outside.bin"), &g.bin).unwrap();
    for uri in [
        "../outside.bin",
        "/etc/passwd",
        "file:///etc/passwd",
        "sub/../../outside.bin",
    ] {
        let mut j = g.json.clone();
        j["buffers"][0]["uri"] = json!(uri);
        let path = inner.join("escape.gltf");
        std::fs::write(&path, j.to_string()).unwrap();
        assert_mentions(&error_of(&path), &[uri]);
    }
    // A symbolic link inside the folder to a file outside it escapes too.
    std::os::unix::fs::symlink(dir.path().join("outside.bin"), inner.join("link.bin")).unwrap();
    let mut j = g.json.clone();
    j["buffers"][0]["uri"] = json!("link.bin");
    let path = inner.join("link.gltf");
    std::fs::write(&path, j.to_string()).unwrap();
    assert_mentions(&error_of(&path), &["link.bin", "outside"]);
}

#[test]
fn an_accessor_beyond_its_buffer_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = square_scene();
    // POSITION (accessor 0) claims 1000 vertices in a view of 4.
    g.json["accessors"][0]["count"] = json!(1000);
    assert_mentions(
        &error_of(&g.write_gltf(dir.path(), "long")),
        &["POSITION", "mesh 0"],
    );
    let mut g = square_scene();
    g.json["bufferViews"][0]["byteLength"] = json!(1_000_000);
    assert_mentions(&error_of(&g.write_glb(dir.path(), "view")), &["buffer"]);
}

#[test]
fn a_nan_in_an_accessor_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = GltfWriter::new();
    let mesh = g.mesh(
        &[Vec3::ZERO, Vec3::new(f32::NAN, 0.0, 0.0), Vec3::Z],
        None,
        None,
        None,
        None,
    );
    g.root(json!({"mesh": mesh}));
    // min and max (which serde_json writes as null for NaN) as a careless exporter leaves them.
    g.json["accessors"][0]["min"] = json!([0.0, 0.0, 0.0]);
    g.json["accessors"][0]["max"] = json!([0.0, 0.0, 1.0]);
    let e = error_of(&g.write_glb(dir.path(), "nan"));
    assert_mentions(&e, &["POSITION", "NaN"]);
}

#[test]
fn an_image_that_does_not_decode_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = square_scene();
    std::fs::write(dir.path().join("broken.png"), b"not a png at all").unwrap();
    g.json["images"] = json!([{"uri": "broken.png"}]);
    g.json["textures"] = json!([{"source": 0}]);
    g.json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = json!({"index": 0});
    assert_mentions(
        &error_of(&g.write_gltf(dir.path(), "image")),
        &["broken.png"],
    );
}

#[test]
fn compression_extensions_are_named_as_unsupported() {
    let dir = tempfile::tempdir().unwrap();
    for (ext, what) in [
        ("KHR_draco_mesh_compression", "Draco"),
        ("EXT_meshopt_compression", "meshopt"),
        ("EXT_unknown_thing", "not supported"),
    ] {
        let mut g = square_scene();
        g.requires(ext);
        assert_mentions(&error_of(&g.write_glb(dir.path(), "c")), &[ext, what]);
    }
}

#[test]
fn an_unknown_optional_extension_warns_once() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = square_scene();
    g.uses("EXT_some_hint");
    g.json["materials"][0]["extensions"] = json!({"EXT_some_hint": {}});
    let scene = load(&g.write_gltf(dir.path(), "hint")).unwrap().scene;
    let warnings: Vec<_> = scene
        .mesh
        .warnings
        .iter()
        .filter(|w| w.contains("EXT_some_hint"))
        .collect();
    assert_eq!(warnings.len(), 1, "{:?}", scene.mesh.warnings);
}

#[test]
fn lines_and_points_are_refused_with_the_mode() {
    let dir = tempfile::tempdir().unwrap();
    for (mode, name) in [(1, "Lines"), (0, "Points")] {
        let mut g = square_scene();
        g.json["meshes"][0]["primitives"][0]["mode"] = json!(mode);
        assert_mentions(
            &error_of(&g.write_gltf(dir.path(), "lines")),
            &[name, "mesh 0 primitive 0", "triangles"],
        );
    }
}

#[test]
fn a_node_cycle_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = square_scene();
    // Node 0 (the square) becomes its own child.
    g.json["nodes"][0]["children"] = json!([0]);
    let e = error_of(&g.write_gltf(dir.path(), "cycle"));
    assert_mentions(&e, &["node 0"]);
}

#[test]
fn a_ron_scene_takes_a_gltf_mesh_with_its_lights_and_camera_and_adds_an_environment() {
    let dir = tempfile::tempdir().unwrap();
    let g = square_scene();
    let alone = load(&g.write_glb(dir.path(), "square")).unwrap().scene;
    let ron = dir.path().join("lit.ron");
    std::fs::write(
        &ron,
        "Scene(mesh: \"square.glb\", max_depth: 5,\n\
         lights: [Directional(direction: (0, -1, 0), irradiance: (1, 1, 1))],\n\
         environment: Environment(color: (0.5, 0.5, 0.5)))\n",
    )
    .unwrap();
    let scene = load(&ron).unwrap().scene;
    assert_eq!(scene.mesh.triangles, alone.mesh.triangles);
    assert_eq!(scene.mesh.materials, alone.mesh.materials);
    assert_eq!(
        scene.camera, alone.camera,
        "the glTF's camera where the file names none"
    );
    assert_eq!(scene.max_depth, 5);
    // The file's lights first, then the glTF's.
    assert_eq!(scene.emitters.lights.len(), 2);
    assert!(matches!(
        scene.emitters.lights[0],
        AnalyticLight::Directional { .. }
    ));
    assert_eq!(scene.emitters.lights[1], alone.emitters.lights[0]);
    assert!(scene.emitters.environment.is_some());

    // A camera in the file replaces the glTF's.
    std::fs::write(
        &ron,
        "Scene(mesh: \"square.gltf\",\n\
         camera: Camera(eye: (0, 5, 5), target: (0, 0, 0), up: (0, 1, 0), fov_y: 30))\n",
    )
    .unwrap();
    g.write_gltf(dir.path(), "square");
    let scene = load(&ron).unwrap().scene;
    assert_ne!(scene.camera, alone.camera);
    assert_eq!(scene.camera.eye(), Vec3::new(0.0, 5.0, 5.0));
}

#[test]
fn a_ron_scene_with_an_obj_mesh_still_needs_its_camera() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("t.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    let ron = dir.path().join("t.ron");
    std::fs::write(&ron, "Scene(mesh: \"t.obj\")\n").unwrap();
    let e = error_of(&ron);
    assert_mentions(&e, &["camera", "glTF"]);
}
