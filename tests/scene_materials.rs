//! MTL keys to materials (issue 14's contract), texture maps, and OBJ `vt`/`vn` per triangle;
//! every bad value an error naming the MTL or OBJ file and line.

use glam::{Vec2, Vec3, Vec4};
use passgraph::scene::texture::Encoding;
use passgraph::scene::{
    Distribution, FRESNEL_CONDUCTOR, FRESNEL_NONE, MATERIAL_CONDUCTOR, MATERIAL_DIELECTRIC,
    MATERIAL_LAMBERT, MATERIAL_PHONG, MATERIAL_PLASTIC, MATERIAL_THIN_DIELECTRIC, Mesh, NO_TEXTURE,
    SURFACE_MAP_BUMP, load_mesh,
};
use std::path::Path;

/// Writes `files` (name, content) into a fresh temp dir.
fn files(list: &[(&str, &[u8])]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for (name, content) in list {
        std::fs::write(dir.path().join(name), content).unwrap();
    }
    dir
}

/// A 2 x 1 8-bit RGB PNG: left texel (sRGB) 128 grey, right white.
fn png() -> Vec<u8> {
    let image = image::RgbImage::from_raw(2, 1, vec![128, 128, 128, 255, 255, 255]).unwrap();
    let mut bytes = Vec::new();
    image
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .unwrap();
    bytes
}

/// One triangle per material named in `materials`, with uvs and normals.
fn obj(materials: &[&str]) -> String {
    let mut text = String::from(
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 2\nvn 0 0 1\nvn 1 0 1\n",
    );
    for m in materials {
        text += &format!("usemtl {m}\nf 1/1/1 2/2/2 3/3/3\n");
    }
    text
}

fn load(mtl: &str, materials: &[&str]) -> (tempfile::TempDir, Mesh) {
    let dir = files(&[
        ("m.obj", obj(materials).as_bytes()),
        ("m.mtl", mtl.as_bytes()),
        ("tex.png", &png()),
    ]);
    let mesh = load_mesh(&dir.path().join("m.obj")).unwrap_or_else(|e| panic!("{e}"));
    (dir, mesh)
}

fn error(mtl: &str) -> (tempfile::TempDir, String) {
    let dir = files(&[
        ("m.obj", obj(&["a"]).as_bytes()),
        ("m.mtl", mtl.as_bytes()),
        ("tex.png", &png()),
    ]);
    let message = match load_mesh(&dir.path().join("m.obj")) {
        Ok(_) => panic!("should not load: {mtl}"),
        Err(e) => e.to_string(),
    };
    (dir, message)
}

fn assert_names(message: &str, path: &Path, line: usize, words: &str) {
    let at = format!("{}:{line}", path.display());
    assert!(message.contains(&at), "expected '{at}' in: {message}");
    assert!(message.contains(words), "expected '{words}' in: {message}");
}

#[test]
fn each_key_set_gives_its_kind() {
    let mtl = "newmtl lambert\nKd 0.5 0.6 0.7\n\
               newmtl phong\nKd 0.5 0.5 0.5\nKs 0.2 0.2 0.2\nNs 50\n\
               newmtl gold\nPm 1\nPr 0.5\nKd 1 0.8 0.3\n\
               newmtl plastic\nPm 0\nPr 0\nKd 0.1 0.2 0.3\nNi 1.6\n\
               newmtl glass\nillum 7\nNi 1.33\nTf 0.9 1 1\n\
               newmtl rough\nPr 0.2\nNs 1000\n";
    let names = ["lambert", "phong", "gold", "plastic", "glass", "rough"];
    let (_dir, mesh) = load(mtl, &names);
    let m =
        |name: &str| mesh.materials[mesh.material_names.iter().position(|n| n == name).unwrap()];
    assert_eq!(m("lambert").kind, MATERIAL_LAMBERT);
    assert_eq!(m("lambert").kd, [0.5, 0.6, 0.7]);
    assert_eq!(m("phong").kind, MATERIAL_PHONG);
    assert_eq!((m("phong").ns, m("phong").ks), (50.0, [0.2; 3]));
    let gold = m("gold");
    assert_eq!(
        (gold.kind, gold.kd, gold.alpha),
        (MATERIAL_CONDUCTOR, [1.0, 0.8, 0.3], 0.25)
    );
    let plastic = m("plastic");
    assert_eq!(plastic.kind, MATERIAL_PLASTIC);
    assert_eq!(
        (plastic.ks, plastic.ior, plastic.alpha),
        ([1.0; 3], 1.6, 0.0)
    );
    let glass = m("glass");
    assert_eq!(
        (glass.kind, glass.ior, glass.tf),
        (MATERIAL_DIELECTRIC, 1.33, [0.9, 1.0, 1.0])
    );
    // Pr wins over Ns; Pr alone (no Pm) is plastic.
    assert_eq!(m("rough").kind, MATERIAL_PLASTIC);
    assert!((m("rough").alpha - 0.04).abs() < 1e-7);
}

/// Fails when `distribution`, `eta`/`k`, `conductor NAME` or `thin 1` do not reach the material (or
/// reach a model they do not belong to), or a bad value is not named with its line.
#[test]
fn distribution_complex_index_and_thin_keys_reach_the_material() {
    let mtl = "newmtl au\nPm 1\nPr 0.4\nconductor Au\ndistribution beckmann\n\
               newmtl custom\nPm 1\nPr 0.3\neta 0.2 0.9 1.1\nk 3.9 2.4 2.1\n\
               newmtl tinted\nPm 1\nPr 0.3\nKd 0.9 0.8 0.7\n\
               newmtl coat\nPm 0\nPr 0.3\ndistribution BECKMANN\n\
               newmtl window\nillum 7\nNi 1.5\nTf 0.9 0.9 1\nthin 1\nPr 0.2\n";
    let names = ["au", "custom", "tinted", "coat", "window"];
    let (_dir, mesh) = load(mtl, &names);
    let m =
        |name: &str| mesh.materials[mesh.material_names.iter().position(|n| n == name).unwrap()];
    let (eta, k) = passgraph::material::conductor::presets::conductor_preset("Au").unwrap();
    let au = m("au");
    assert_eq!(
        (au.kind, au.fresnel, au.eta, au.k),
        (
            MATERIAL_CONDUCTOR,
            FRESNEL_CONDUCTOR,
            eta.to_array(),
            k.to_array()
        )
    );
    assert_eq!(au.distribution, Distribution::Beckmann as u32);
    let custom = m("custom");
    assert_eq!(
        (custom.fresnel, custom.eta, custom.k),
        (FRESNEL_CONDUCTOR, [0.2, 0.9, 1.1], [3.9, 2.4, 2.1])
    );
    assert_eq!(custom.distribution, Distribution::Ggx as u32);
    // Without eta, k or a preset: Mitsuba's material none, the tinted mirror as before.
    assert_eq!(m("tinted").fresnel, FRESNEL_NONE);
    assert_eq!(m("coat").kind, MATERIAL_PLASTIC);
    assert_eq!(m("coat").distribution, Distribution::Beckmann as u32);
    let window = m("window");
    assert_eq!(
        (window.kind, window.ior, window.tf, window.alpha),
        (MATERIAL_THIN_DIELECTRIC, 1.5, [0.9, 0.9, 1.0], 0.0)
    );

    let (dir, message) = error("newmtl a\nPm 1\nconductor Unobtainium\n");
    assert_names(&message, &dir.path().join("m.mtl"), 3, "Au");
    let (dir, message) = error("newmtl a\nPm 1\ndistribution phong\n");
    assert_names(&message, &dir.path().join("m.mtl"), 3, "beckmann");
    let (dir, message) = error("newmtl a\nPm 1\neta 1 2\n");
    assert_names(&message, &dir.path().join("m.mtl"), 3, "eta");
    let (dir, message) = error("newmtl a\nillum 7\nthin yes\n");
    assert_names(&message, &dir.path().join("m.mtl"), 3, "thin");
}

#[test]
fn roughness_from_ns_follows_blender() {
    let (_dir, mesh) = load("newmtl a\nPm 1\nNs 250\n", &["a"]);
    // r = 1 - sqrt(250 / 1000) = 0.5.
    assert!((mesh.materials[0].alpha - 0.25).abs() < 1e-6);
}

#[test]
fn opacity_and_maps_are_kept_and_textures_decoded() {
    let mtl = "newmtl a\nKd 1 1 1\nd 0.25\nmap_Kd tex.png\nmap_d tex.png\nmap_Pr tex.png\n";
    let (_dir, mesh) = load(mtl, &["a"]);
    let m = mesh.materials[0];
    assert_eq!(m.opacity, 0.25);
    // One decode per encoding: colour (sRGB) and raw.
    assert_eq!(mesh.textures.len(), 2);
    assert_eq!(
        (m.map_kd, m.map_d, m.map_pr, m.map_ks),
        (0, 1, 1, NO_TEXTURE)
    );
    let srgb = &mesh.textures[0];
    assert_eq!(srgb.encoding, Encoding::Srgb);
    assert!(
        (srgb.texels[0][0] - 0.215_861).abs() < 1e-5,
        "{:?}",
        srgb.texels[0]
    );
    assert!((mesh.textures[1].texels[0][0] - 128.0 / 255.0).abs() < 1e-6);
    // The right texel's centre, at any v (one row).
    let white = srgb.bilinear(Vec2::new(0.75, 0.3));
    assert!((white - Vec4::ONE).abs().max_element() < 1e-6);
}

#[test]
fn uvs_and_unit_normals_reach_the_triangles() {
    let (_dir, mesh) = load("newmtl a\nKd 1 1 1\n", &["a"]);
    let t = mesh.triangles[0];
    assert_eq!(
        t.uvs,
        Some([
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(0.0, 1.0)
        ])
    );
    let n = t.normals.unwrap();
    assert_eq!(n[0], Vec3::Z);
    assert!((n[2] - Vec3::new(1.0, 0.0, 1.0).normalize()).length() < 1e-6);
}

#[test]
fn faces_without_vt_or_vn_have_none_and_zero_normals_warn() {
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvn 0 0 0\n\
               f 1 2 3\nf 1/1 2/1 3/1\nf 2//1 4//1 3//1\n";
    let dir = files(&[("m.obj", obj.as_bytes())]);
    let path = dir.path().join("m.obj");
    let mesh = load_mesh(&path).unwrap();
    assert_eq!(mesh.triangles[0].uvs, None);
    assert!(mesh.triangles[1].uvs.is_some());
    assert_eq!(mesh.triangles[1].normals, None);
    assert_eq!(mesh.triangles[2].normals, None);
    let warning = mesh.warnings.join("\n");
    assert!(
        warning.contains(&format!("{}:9", path.display())),
        "{warning}"
    );
}

#[test]
fn bad_vt_vn_and_their_indices_name_the_line() {
    for (obj, line, words) in [
        ("v 0 0 0\nvt 0 x\n", 2, "'x' is not a finite number"),
        ("v 0 0 0\nvn 0 0\n", 2, "vn needs 3 numbers"),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/2 2/1 3/1\n",
            5,
            "texture coordinate 2",
        ),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n",
            4,
            "normal 1",
        ),
    ] {
        let dir = files(&[("m.obj", obj.as_bytes())]);
        let path = dir.path().join("m.obj");
        let message = load_mesh(&path).unwrap_err().to_string();
        assert_names(&message, &path, line, words);
    }
}

#[test]
fn out_of_range_values_name_the_mtl_line() {
    for (mtl, line, words) in [
        ("newmtl a\nNi 0\n", 2, "Ni"),
        ("newmtl a\nPr 1.5\n", 2, "Pr must be in [0, 1]"),
        ("newmtl a\n\nd -0.1\n", 3, "d must be in [0, 1]"),
        ("newmtl a\nPm x\n", 2, "Pm needs a number"),
        ("newmtl a\nTf 1 x 1\n", 2, "Tf needs 3 numbers"),
        (
            "newmtl a\nmap_Kd wood.png\n",
            2,
            "map_Kd: cannot read 'wood.png': No such file or directory",
        ),
        (
            "newmtl a\nmap_Kd -s 2 2 1 tex.png\n",
            2,
            "'-s' are not supported",
        ),
    ] {
        let (dir, message) = error(mtl);
        assert_names(&message, &dir.path().join("m.mtl"), line, words);
    }
}

#[test]
fn pm_between_0_and_1_and_unsupported_maps_warn() {
    let (dir, mesh) = load("newmtl a\nPm 0.7\ndisp tex.png\n", &["a"]);
    assert_eq!(mesh.materials[0].kind, MATERIAL_CONDUCTOR);
    let mtl = dir.path().join("m.mtl");
    let warnings = mesh.warnings.join("\n");
    assert!(
        warnings.contains(&format!("{}:2: Pm 0.7", mtl.display())),
        "{warnings}"
    );
    assert!(
        warnings.contains(&format!("{}:3: disp", mtl.display())),
        "{warnings}"
    );
}

#[test]
fn a_file_that_is_not_an_image_is_an_error_naming_the_line() {
    let dir = files(&[
        ("m.obj", obj(&["a"]).as_bytes()),
        ("m.mtl", b"newmtl a\nmap_Ks bad.png\n"),
        ("bad.png", b"not a png"),
    ]);
    let message = load_mesh(&dir.path().join("m.obj"))
        .unwrap_err()
        .to_string();
    assert_names(
        &message,
        &dir.path().join("m.mtl"),
        2,
        "map_Ks: cannot read 'bad.png'",
    );
}

#[test]
fn the_materials_showcase_loads_each_kind_and_its_texture() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/materials/scene.ron");
    let scene = passgraph::scene::load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let mesh = &scene.mesh;
    let kind = |name: &str| {
        let i = mesh.material_names.iter().position(|n| n == name).unwrap();
        mesh.materials[i]
    };
    assert_eq!(kind("gold").kind, MATERIAL_CONDUCTOR);
    assert_eq!(kind("blue_plastic").kind, MATERIAL_PLASTIC);
    assert_eq!(kind("glass").kind, MATERIAL_DIELECTRIC);
    assert_eq!(kind("checker_floor").map_kd, 0);
    assert_eq!(mesh.textures.len(), 1);
    assert!(mesh.warnings.is_empty(), "{:?}", mesh.warnings);
    let gpu = scene.to_gpu();
    assert!(gpu.has_textures && gpu.has_uvs && gpu.has_shading_normals && !gpu.has_cutouts);
}

#[test]
fn normal_and_bump_maps_are_raw_textures_with_the_bump_scale() {
    let (_dir, mesh) = load(
        "newmtl a\nnorm tex.png\nnewmtl b\nmap_Bump -bm 0.25 tex.png\nnewmtl c\nbump tex.png\n",
        &["a", "b", "c"],
    );
    let [a, b, c] = [0, 1, 2].map(|i| mesh.materials[i]);
    assert_eq!(a.surface_map, 0);
    assert_eq!(mesh.textures[0].encoding, Encoding::Raw);
    // One image, one raw texture for all three.
    assert_eq!(mesh.textures.len(), 1);
    assert_eq!((b.surface_map, b.bump_scale), (SURFACE_MAP_BUMP, 0.25));
    assert_eq!((c.surface_map, c.bump_scale), (SURFACE_MAP_BUMP, 1.0));
}

#[test]
fn bad_normal_and_bump_maps_name_the_mtl_line() {
    for (mtl, line, words) in [
        (
            "newmtl a\nmap_Bump -bm tex.png\n",
            2,
            "map_Bump: -bm needs a finite number (the bump scale) before the file name, found 'tex.png'",
        ),
        (
            "newmtl a\n\nbump -bm\n",
            3,
            "bump: -bm needs a finite number",
        ),
        (
            "newmtl a\nnorm missing.png\n",
            2,
            "norm: cannot read 'missing.png': No such file or directory",
        ),
        (
            "newmtl a\nbump one.png\n",
            2,
            "bump: 'one.png' is a single texel: a bump map's heights need at least two texels",
        ),
        (
            "newmtl a\nnorm tex.png\nbump tex.png\n",
            3,
            "this material already has a norm (line 2)",
        ),
    ] {
        let dir = files(&[
            ("m.obj", obj(&["a"]).as_bytes()),
            ("m.mtl", mtl.as_bytes()),
            ("tex.png", &png()),
            ("one.png", &one_texel_png()),
        ]);
        let message = load_mesh(&dir.path().join("m.obj"))
            .unwrap_err()
            .to_string();
        assert_names(&message, &dir.path().join("m.mtl"), line, words);
    }
}

#[test]
fn a_normal_map_on_faces_without_vt_names_the_map_and_the_face() {
    let dir = files(&[
        (
            "m.obj",
            b"mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl a\nf 1/1 2/2 3/3\nf 1 2 3\n",
        ),
        ("m.mtl", b"newmtl a\nKd 1 1 1\nnorm tex.png\n"),
        ("tex.png", &png()),
    ]);
    let obj = dir.path().join("m.obj");
    let message = load_mesh(&obj).unwrap_err().to_string();
    assert_names(
        &message,
        &dir.path().join("m.mtl"),
        3,
        &format!(
            "norm: material 'a' needs texture coordinates (vt) for its tangent frame, but the face at {}:10 has none",
            obj.display()
        ),
    );
}

/// A 1 x 1 8-bit grey PNG.
fn one_texel_png() -> Vec<u8> {
    let image = image::GrayImage::from_raw(1, 1, vec![128]).unwrap();
    let mut bytes = Vec::new();
    image
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .unwrap();
    bytes
}
