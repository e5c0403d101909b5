//! The Mitsuba 3 XML loader (src/scene/mitsuba_xml/): structure (defaults and defines,
//! include, path, id/ref), transforms in Mitsuba's order, spectra against pip Mitsuba 3.9.0's
//! numbers, each shape, the errors (file:line, plugin, parameter), every conformance scene
//! (loads, or fails with its documented error), renders of small conformance scenes against
//! their references, and the round trip through `passgraph mitsuba-scene`.

mod common;

use glam::{DMat4, DVec3, Vec3};
use passgraph::scene::mitsuba_xml::shapes;
use passgraph::scene::mitsuba_xml::spectrum::{
    SpectrumValue, parse_spectrum, spectrum_list_to_srgb, spectrum_to_rgb,
};
use passgraph::scene::mitsuba_xml::transform::{TransformOp, compose};
use passgraph::scene::{LoadedScene, SceneError, SceneOptions, load_scene_with};
use std::path::{Path, PathBuf};

fn conformance(feature: &str) -> PathBuf {
    common::root().join(format!("tests/data/conformance/{feature}.xml"))
}

fn load(path: &Path, defines: &[(&str, &str)]) -> Result<LoadedScene, SceneError> {
    let options = SceneOptions {
        defines: defines
            .iter()
            .map(|(n, v)| (n.to_string(), v.to_string()))
            .collect(),
        max_depth: None,
        camera: None,
    };
    load_scene_with(path, &options)
}

/// A sensor and a light, for scenes written by the tests.
const SENSOR: &str = r#"
    <integrator type="path"><integer name="max_depth" value="$depth"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="45"/>
        <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="16"/></sampler>
        <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="24"/><rfilter type="box"/></film>
    </sensor>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
"#;

/// Writes `scene.xml` (a version 3 scene with `body` after the sensor) in a temporary folder.
fn scene_file(dir: &Path, body: &str) -> PathBuf {
    let text = format!(
        "<?xml version=\"1.0\"?>\n<scene version=\"3.0.0\">\n    <default name=\"depth\" value=\"3\"/>{SENSOR}{body}\n</scene>\n"
    );
    let path = dir.join("scene.xml");
    std::fs::write(&path, text).unwrap();
    path
}

fn error_of(path: &Path) -> String {
    match load(path, &[]) {
        Ok(_) => panic!("{} loaded; an error was expected", path.display()),
        Err(e) => e.to_string(),
    }
}

/// The line of `needle` in the file (1-based).
fn line_of(path: &Path, needle: &str) -> usize {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines().position(|l| l.contains(needle)).unwrap() + 1
}

const SPHERE: &str = r#"<shape type="sphere"><bsdf type="diffuse"/></shape>"#;

#[test]
fn a_conformance_scene_gives_camera_film_sampler_and_depth() {
    let loaded = load(&conformance("diffuse_rgb"), &[]).unwrap();
    assert_eq!(loaded.film_size, Some([48, 48]));
    assert_eq!(loaded.sample_count, Some(868));
    let s = &loaded.scene;
    assert_eq!(s.max_depth, 3);
    assert_eq!(s.camera.eye(), Vec3::new(0.0, 1.2, 4.5));
    assert!(s.emitters.environment.is_some());
    assert!(s.mesh.materials.iter().any(|m| m.is_emissive()));
}

#[test]
fn defaults_are_substituted_and_defines_override_them() {
    let dir = tempfile::tempdir().unwrap();
    let path = scene_file(dir.path(), SPHERE);
    assert_eq!(load(&path, &[]).unwrap().scene.max_depth, 3);
    assert_eq!(load(&path, &[("depth", "7")]).unwrap().scene.max_depth, 7);
    // An undefined $name is an error at its line.
    let text = std::fs::read_to_string(&path)
        .unwrap()
        .replace("<default name=\"depth\" value=\"3\"/>", "");
    std::fs::write(&path, text).unwrap();
    let e = error_of(&path);
    let line = line_of(&path, "$depth");
    assert!(e.contains(&format!("scene.xml:{line}:")), "{e}");
    assert!(e.contains("$depth is not defined"), "{e}");
    assert_eq!(load(&path, &[("depth", "2")]).unwrap().scene.max_depth, 2);
}

#[test]
fn include_path_and_references_build_the_same_scene() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("parts")).unwrap();
    std::fs::write(
        dir.path().join("parts/ball.xml"),
        r#"<scene version="2.1.0"><shape type="sphere"><ref id="orange"/></shape></scene>"#,
    )
    .unwrap();
    let path = scene_file(
        dir.path(),
        r#"<path value="parts"/>
        <bsdf type="diffuse" id="orange"><rgb name="reflectance" value="0.8, 0.4, 0.1"/></bsdf>
        <include filename="ball.xml"/>
        <shape type="rectangle"><ref name="bsdf" id="orange"/></shape>"#,
    );
    let s = load(&path, &[]).unwrap().scene;
    // One material for both shapes (the referenced BSDF), and its black back face.
    assert_eq!(s.mesh.materials.len(), 2);
    assert_eq!(s.mesh.materials[0].kd, [0.8, 0.4, 0.1]);
    assert_eq!(s.mesh.back_materials.len(), 1);
    assert_eq!(s.mesh.triangles.len(), shapes::sphere().triangles.len() + 2);
    // An unknown id is an error at the <ref>.
    std::fs::write(
        dir.path().join("parts/ball.xml"),
        r#"<scene version="2.1.0"><shape type="sphere"><ref id="apple"/></shape></scene>"#,
    )
    .unwrap();
    let e = error_of(&path);
    assert!(e.contains("ball.xml:1:") && e.contains("\"apple\""), "{e}");
}

#[test]
fn transforms_compose_in_mitsubas_order_each_new_element_on_the_left() {
    let scale_then_move = compose(&[
        TransformOp::Scale(DVec3::splat(2.0)),
        TransformOp::Translate(DVec3::X),
    ])
    .unwrap();
    assert_eq!(
        scale_then_move.transform_point3(DVec3::X),
        DVec3::new(3.0, 0.0, 0.0)
    );
    let move_then_scale = compose(&[
        TransformOp::Translate(DVec3::X),
        TransformOp::Scale(DVec3::splat(2.0)),
    ])
    .unwrap();
    assert_eq!(
        move_then_scale.transform_point3(DVec3::X),
        DVec3::new(4.0, 0.0, 0.0)
    );
    // rotate is right-handed: +90 degrees about z takes x to y.
    let r = compose(&[TransformOp::Rotate {
        axis: DVec3::Z,
        degrees: 90.0,
    }])
    .unwrap();
    assert!(r.transform_vector3(DVec3::X).abs_diff_eq(DVec3::Y, 1e-12));
    // lookat: local +z toward the target, +y up, +x = up x dir (the image's left).
    let l = compose(&[TransformOp::LookAt {
        origin: DVec3::new(0.0, 0.0, 4.0),
        target: DVec3::ZERO,
        up: DVec3::Y,
    }])
    .unwrap();
    assert!(l.transform_vector3(DVec3::Z).abs_diff_eq(-DVec3::Z, 1e-12));
    assert!(l.transform_vector3(DVec3::X).abs_diff_eq(-DVec3::X, 1e-12));
    assert_eq!(l.transform_point3(DVec3::ZERO), DVec3::new(0.0, 0.0, 4.0));
    // A matrix is written row by row.
    let dir = tempfile::tempdir().unwrap();
    let path = scene_file(
        dir.path(),
        r#"<shape type="rectangle"><transform name="to_world"><matrix value="1 0 0 5  0 1 0 0  0 0 1 0  0 0 0 1"/></transform></shape>"#,
    );
    let s = load(&path, &[]).unwrap().scene;
    let xs: Vec<f32> = s
        .mesh
        .triangles
        .iter()
        .flat_map(|t| t.vertices)
        .map(|v| v.x)
        .collect();
    assert_eq!(xs.iter().copied().fold(f32::MAX, f32::min), 4.0);
    let _ = DMat4::IDENTITY;
}

fn close(a: [f64; 3], b: [f64; 3], tolerance: f64) -> bool {
    (0..3).all(|i| (a[i] - b[i]).abs() <= tolerance * b[i].abs().max(1e-3))
}

/// The colours pip Mitsuba 3.9.0 (scalar_rgb) makes of these spectra, read back with
/// `mi.traverse` after `mi.load_string` (a diffuse's reflectance, an area emitter's radiance).
#[test]
fn spectra_become_the_colours_pip_mitsuba_makes_of_them() {
    let reflectance = |text: &str| spectrum_to_rgb(&parse_spectrum(text).unwrap(), false);
    let radiance = |text: &str| spectrum_to_rgb(&parse_spectrum(text).unwrap(), true);
    let cases = [
        (
            reflectance("400:0.7, 450:0.6, 500:0.3, 550:0.1, 600:0.1, 650:0.2, 700:0.3"),
            [0.103739, 0.135619, 0.598362],
        ),
        (
            reflectance("400:0.05, 500:0.2, 550:0.5, 600:0.8, 700:0.85"),
            [0.946782, 0.449074, 0.080058],
        ),
        (reflectance("0.6"), [0.6, 0.6, 0.6]),
        (
            radiance("400:4, 500:6, 600:8, 700:9"),
            [10.1915, 6.54549, 4.29862],
        ),
        (radiance("0.35"), [0.421678, 0.331902, 0.318121]),
    ];
    for (ours, mitsuba) in cases {
        assert!(
            close(ours, mitsuba, 2e-5),
            "{ours:?} against Mitsuba's {mitsuba:?}"
        );
    }
    // `mi.spectrum_list_to_srgb` without D65 (an emitter's) and with it (a reflectance's).
    let w = [400.0, 450.0, 500.0, 550.0, 600.0, 650.0, 700.0];
    let v = [0.7, 0.6, 0.3, 0.1, 0.1, 0.2, 0.3];
    assert!(close(
        spectrum_list_to_srgb(&w, &v, false, false),
        [0.138909, 0.124454, 0.553355],
        2e-5
    ));
    // Bad lists are errors.
    assert!(parse_spectrum("500:1, 400:2").is_err());
    assert!(parse_spectrum("500:1").is_err());
    assert!(parse_spectrum("red").is_err());
    assert_eq!(
        parse_spectrum(" 0.5 ").unwrap(),
        SpectrumValue::Uniform(0.5)
    );
}

fn area(t: &shapes::Triangle) -> f64 {
    0.5 * (t.p[1] - t.p[0]).cross(t.p[2] - t.p[0]).length()
}

/// The tessellations' error against Mitsuba's analytic shapes, as shapes.rs states it.
#[test]
fn tessellated_shapes_are_within_their_stated_error_of_the_analytic_ones() {
    let total = |g: &shapes::Geometry| g.triangles.iter().map(area).sum::<f64>();
    assert!((total(&shapes::rectangle()) - 4.0).abs() < 1e-12);
    assert!((total(&shapes::cube()) - 24.0).abs() < 1e-12);
    let pi = std::f64::consts::PI;
    let disk = total(&shapes::disk());
    assert!((disk - pi).abs() / pi < 1.1e-4, "disk area {disk}");
    let sphere = shapes::sphere();
    let mut deepest = 0.0f64;
    for t in &sphere.triangles {
        for p in t.p {
            assert!((p.length() - 1.0).abs() < 1e-12);
        }
        // Counter-clockwise seen from outside, and the face's plane (its deepest point) within
        // 6.1e-4 of the surface, as shapes.rs states.
        let centroid = (t.p[0] + t.p[1] + t.p[2]) / 3.0;
        let n = (t.p[1] - t.p[0]).cross(t.p[2] - t.p[0]).normalize();
        assert!(n.dot(centroid) > 0.0);
        deepest = deepest.max(1.0 - n.dot(t.p[0]));
    }
    assert!(
        deepest < 6.1e-4 && deepest > 5.0e-4,
        "deepest face {deepest}"
    );
    let s = total(&sphere);
    assert!((s - 4.0 * pi).abs() / (4.0 * pi) < 6e-4, "sphere area {s}");
    let cylinder = total(&shapes::cylinder());
    assert!((cylinder - 2.0 * pi).abs() / (2.0 * pi) < 1.1e-4);
}

#[test]
fn each_shape_loads_where_its_parameters_put_it() {
    let dir = tempfile::tempdir().unwrap();
    let data = common::root().join("tests/data/conformance");
    let body = format!(
        r#"<shape type="sphere"><point name="center" x="5" y="0" z="0"/><float name="radius" value="0.5"/></shape>
        <shape type="cylinder"><point name="p0" x="0" y="10" z="0"/><point name="p1" x="0" y="12" z="0"/><float name="radius" value="0.25"/></shape>
        <shape type="disk"><transform name="to_world"><translate z="20"/></transform></shape>
        <shape type="cube"><transform name="to_world"><translate z="30"/></transform></shape>
        <shape type="obj"><string name="filename" value="{0}/sphere.obj"/><transform name="to_world"><translate x="40"/></transform></shape>
        <shape type="ply"><string name="filename" value="{0}/torus.ply"/><transform name="to_world"><translate x="50"/></transform></shape>
        <shape type="serialized"><string name="filename" value="{0}/shapes.serialized"/><integer name="shape_index" value="1"/><transform name="to_world"><translate x="60"/></transform></shape>
        <shape type="shapegroup" id="g"><shape type="cube"/></shape>
        <shape type="instance"><ref id="g"/><transform name="to_world"><translate x="70"/></transform></shape>
        <shape type="instance"><ref id="g"/><transform name="to_world"><translate x="80"/></transform></shape>"#,
        data.display()
    );
    let path = scene_file(dir.path(), &body);
    let s = load(&path, &[]).unwrap().scene;
    let within = |lo: Vec3, hi: Vec3| {
        s.mesh
            .triangles
            .iter()
            .filter(|t| {
                t.vertices
                    .iter()
                    .all(|v| v.cmpge(lo).all() && v.cmple(hi).all())
            })
            .count()
    };
    let e = 1e-4;
    assert_eq!(
        within(
            Vec3::new(4.5 - e, -0.5 - e, -0.5 - e),
            Vec3::new(5.5 + e, 0.5 + e, 0.5 + e)
        ),
        shapes::sphere().triangles.len()
    );
    assert_eq!(
        within(
            Vec3::new(-0.25 - e, 10.0 - e, -0.25 - e),
            Vec3::new(0.25 + e, 12.0 + e, 0.25 + e)
        ),
        shapes::cylinder().triangles.len()
    );
    assert_eq!(
        within(
            Vec3::new(-1.0 - e, -1.0 - e, 20.0 - e),
            Vec3::new(1.0 + e, 1.0 + e, 20.0 + e)
        ),
        shapes::DISK_SEGMENTS
    );
    assert_eq!(
        within(Vec3::new(-1.0, -1.0, 29.0), Vec3::new(1.0, 1.0, 31.0)),
        12
    );
    for x in [40.0, 50.0, 60.0] {
        assert!(
            within(Vec3::new(x - 2.0, -2.0, -2.0), Vec3::new(x + 2.0, 2.0, 2.0)) > 8,
            "mesh at x = {x}"
        );
    }
    assert_eq!(
        within(Vec3::new(69.0, -1.0, -1.0), Vec3::new(71.0, 1.0, 1.0)),
        12
    );
    assert_eq!(
        within(Vec3::new(79.0, -1.0, -1.0), Vec3::new(81.0, 1.0, 1.0)),
        12
    );
    // Every triangle of a loaded mesh or analytic shape has shading normals except the cube's
    // and the disk's (flat); the serialized cone had none in the file: Mitsuba's are computed.
    let cone = s
        .mesh
        .triangles
        .iter()
        .filter(|t| t.vertices[0].x > 59.0 && t.vertices[0].x < 61.0);
    assert!(cone.clone().count() > 0 && cone.clone().all(|t| t.normals.is_some()));
}

#[test]
fn flip_normals_turns_the_front_and_face_normals_drops_the_vertex_normals() {
    let dir = tempfile::tempdir().unwrap();
    let obj = common::root().join("tests/data/conformance/sphere.obj");
    let path = scene_file(
        dir.path(),
        &format!(
            r#"<shape type="rectangle"><boolean name="flip_normals" value="true"/></shape>
            <shape type="obj"><string name="filename" value="{}"/><boolean name="face_normals" value="true"/></shape>"#,
            obj.display()
        ),
    );
    let s = load(&path, &[]).unwrap().scene;
    let normal = |t: &passgraph::scene::MeshTriangle| {
        let [a, b, c] = t.vertices;
        (b - a).cross(c - a)
    };
    assert!(normal(&s.mesh.triangles[0]).z < 0.0);
    assert!(s.mesh.triangles[2..].iter().all(|t| t.normals.is_none()));
}

#[test]
fn an_unsupported_plugin_is_an_error_naming_file_line_and_what_is_supported() {
    let dir = tempfile::tempdir().unwrap();
    let path = scene_file(
        dir.path(),
        r#"<shape type="hair"><string name="filename" value="x"/></shape>"#,
    );
    let e = error_of(&path);
    let line = line_of(&path, "hair");
    assert!(
        e.contains(&format!("scene.xml:{line}: shape 'hair'")),
        "{e}"
    );
    assert!(e.contains("supported: obj, ply, serialized"), "{e}");
}

#[test]
fn an_unknown_parameter_is_an_error_at_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let path = scene_file(
        dir.path(),
        r#"<shape type="sphere">
        <bsdf type="diffuse">
            <float name="roughness" value="0.5"/>
        </bsdf>
    </shape>"#,
    );
    let e = error_of(&path);
    let line = line_of(&path, "roughness");
    assert!(
        e.contains(&format!("scene.xml:{line}: bsdf 'diffuse'")),
        "{e}"
    );
    assert!(
        e.contains("'roughness'") && e.contains("supported: reflectance"),
        "{e}"
    );
}

#[test]
fn a_bad_value_and_a_missing_file_are_errors_at_their_lines() {
    let dir = tempfile::tempdir().unwrap();
    let path = scene_file(
        dir.path(),
        r#"<shape type="sphere"><float name="radius" value="big"/></shape>"#,
    );
    let e = error_of(&path);
    assert!(
        e.contains(&format!("scene.xml:{}:", line_of(&path, "big"))) && e.contains("'big'"),
        "{e}"
    );
    let path = scene_file(
        dir.path(),
        r#"<shape type="obj"><string name="filename" value="nothere.obj"/></shape>"#,
    );
    let e = error_of(&path);
    assert!(
        e.contains(&format!("scene.xml:{}:", line_of(&path, "nothere")))
            && e.contains("file not found"),
        "{e}"
    );
    let path = scene_file(
        dir.path(),
        r#"<shape type="sphere"><rgb name="radius" value="1, 2"/></shape>"#,
    );
    assert!(error_of(&path).contains("<rgb>"));
    let serialized = common::root().join("tests/data/conformance/shapes.serialized");
    let path = scene_file(
        dir.path(),
        &format!(
            r#"<shape type="serialized"><string name="filename" value="{}"/><integer name="shape_index" value="7"/></shape>"#,
            serialized.display()
        ),
    );
    let e = error_of(&path);
    assert!(
        e.contains("shape_index 7 is out of range: the file has 2 meshes"),
        "{e}"
    );
}

#[test]
fn rough_models_default_to_beckmann_and_conductors_take_presets_eta_k_and_thin_sheets() {
    use passgraph::scene::{Distribution, FRESNEL_CONDUCTOR, MATERIAL_THIN_DIELECTRIC};
    let dir = tempfile::tempdir().unwrap();
    let material = |body: &str| {
        let path = scene_file(dir.path(), body);
        load(&path, &[])
            .unwrap_or_else(|e| panic!("{body}: {e}"))
            .scene
            .mesh
            .materials[0]
    };
    // Mitsuba's default distribution is Beckmann: it must not be read as GGX.
    for (body, want) in [
        (
            r#"<shape type="sphere"><bsdf type="roughconductor"/></shape>"#,
            Distribution::Beckmann,
        ),
        (
            r#"<shape type="sphere"><bsdf type="roughplastic"><string name="distribution" value="beckmann"/></bsdf></shape>"#,
            Distribution::Beckmann,
        ),
        (
            r#"<shape type="sphere"><bsdf type="roughdielectric"><string name="distribution" value="ggx"/></bsdf></shape>"#,
            Distribution::Ggx,
        ),
    ] {
        assert_eq!(material(body).distribution, want as u32, "{body}");
    }
    let gold = material(
        r#"<shape type="sphere"><bsdf type="conductor"><string name="material" value="Au"/></bsdf></shape>"#,
    );
    let (eta, k) = passgraph::material::conductor::presets::conductor_preset("Au").unwrap();
    assert_eq!(
        (gold.fresnel, gold.eta, gold.k),
        (FRESNEL_CONDUCTOR, eta.to_array(), k.to_array())
    );
    let written = material(
        r#"<shape type="sphere"><bsdf type="conductor"><rgb name="eta" value="0.2"/><rgb name="k" value="3, 2, 1"/></bsdf></shape>"#,
    );
    assert_eq!((written.eta, written.k), ([0.2; 3], [3.0, 2.0, 1.0]));
    // Mitsuba's "none" is a mirror tinted by specular_reflectance alone.
    let none = material(
        r#"<shape type="sphere"><bsdf type="conductor"><string name="material" value="none"/></bsdf></shape>"#,
    );
    assert_ne!(none.fresnel, FRESNEL_CONDUCTOR);
    let sheet = material(
        r#"<shape type="sphere"><bsdf type="thindielectric"><float name="int_ior" value="1.5"/></bsdf></shape>"#,
    );
    // int_ior over Mitsuba's "air", 1.000277.
    assert_eq!(sheet.kind, MATERIAL_THIN_DIELECTRIC);
    assert!((sheet.ior - 1.5 / 1.000_277).abs() < 1e-6, "{}", sheet.ior);
    let path = scene_file(
        dir.path(),
        r#"<shape type="sphere"><bsdf type="conductor"><string name="material" value="Unobtainium"/></bsdf></shape>"#,
    );
    let e = error_of(&path);
    assert!(e.contains("Unobtainium") && e.contains("Au"), "{e}");
}

/// Mitsuba's bare reflecting models are black from behind, `twosided` of one BSDF shades both
/// faces, of two shows the second from behind: each as a back-face material.
#[test]
fn one_sided_and_two_sided_bsdfs_get_their_back_face_materials() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = |body: &str| {
        let path = scene_file(dir.path(), body);
        load(&path, &[])
            .unwrap_or_else(|e| panic!("{body}: {e}"))
            .scene
            .mesh
    };
    let bare = mesh(
        r#"<shape type="sphere"><bsdf type="diffuse"><rgb name="reflectance" value="0.3"/></bsdf></shape>"#,
    );
    let back = bare.back_materials[&0];
    assert_eq!(bare.materials[0].kd, [0.3; 3]);
    assert_eq!(bare.materials[back as usize].kd, [0.0; 3]);
    assert!(bare.materials[back as usize].ke == [0.0; 3]);
    // The default BSDF is a bare diffuse too; the dielectrics shade both faces.
    let default =
        mesh(r#"<shape type="sphere"/><shape type="sphere"><bsdf type="dielectric"/></shape>"#);
    assert_eq!(
        default.back_materials.len(),
        1,
        "{:?}",
        default.back_materials
    );
    let both =
        mesh(r#"<shape type="sphere"><bsdf type="twosided"><bsdf type="diffuse"/></bsdf></shape>"#);
    assert!(both.back_materials.is_empty());
    let two = mesh(
        r#"<shape type="sphere"><bsdf type="twosided"><bsdf type="diffuse"><rgb name="reflectance" value="0.2"/></bsdf><bsdf type="roughconductor"/></bsdf></shape>"#,
    );
    let back = two.materials[two.back_materials[&0] as usize];
    assert_eq!(two.materials[0].kd, [0.2; 3]);
    assert_eq!(back.kind, passgraph::scene::MATERIAL_CONDUCTOR);
    // Equal fronts with different backs stay two materials.
    let pair = mesh(
        r#"<shape type="sphere"><bsdf type="diffuse"/></shape><shape type="sphere"><bsdf type="twosided"><bsdf type="diffuse"/></bsdf></shape>"#,
    );
    let fronts: Vec<_> = pair.materials.iter().filter(|m| m.kd == [0.5; 3]).collect();
    assert_eq!(fronts.len(), 2);
    let path = scene_file(
        dir.path(),
        r#"<shape type="sphere"><bsdf type="twosided"><bsdf type="diffuse"/><bsdf type="diffuse"/><bsdf type="diffuse"/></bsdf></shape>"#,
    );
    assert!(
        error_of(&path).contains("one or two nested"),
        "{}",
        error_of(&path)
    );
}

/// Mitsuba's mask is a mixture with a null interaction: its triangles stop every ray (shadow
/// rays stop at it) and its record keeps the opacity that shading mixes by; an MTL cut-out
/// stays in its triangles, which the traversal passes at no depth.
#[test]
fn a_mask_is_a_null_interaction_and_an_mtl_cutout_stays_a_cutout() {
    use passgraph::scene::{Material, SceneGpu};
    let dir = tempfile::tempdir().unwrap();
    let path = scene_file(
        dir.path(),
        r#"<shape type="sphere"><bsdf type="mask"><float name="opacity" value="0.4"/><bsdf type="diffuse"/></bsdf></shape><shape type="sphere"><bsdf type="diffuse"/></shape>"#,
    );
    let mesh = load(&path, &[]).unwrap().scene.mesh;
    assert_eq!(mesh.null_masks.len(), 1, "{:?}", mesh.null_masks);
    let mask = *mesh.null_masks.iter().next().unwrap();
    assert_eq!(mesh.materials[mask as usize].opacity, 0.4);
    let gpu = SceneGpu::build(&mesh);
    assert!(gpu.has_null_masks && !gpu.has_cutouts);
    assert!(gpu.triangles.iter().all(|t| t.opacity == 1.0));
    assert_eq!(gpu.materials[mask as usize].opacity, 0.4);

    let mut cutout =
        passgraph::scene::mesh::Mesh::from_triangles("cutout", &[[Vec3::ZERO, Vec3::X, Vec3::Y]]);
    cutout.materials[0] = Material {
        opacity: 0.5,
        ..Material::DEFAULT
    };
    let gpu = SceneGpu::build(&cutout);
    assert!(gpu.has_cutouts && !gpu.has_null_masks);
    assert_eq!(gpu.triangles[0].opacity, 0.5);
    assert_eq!(
        gpu.materials[0].opacity, 1.0,
        "shading must not mix a cut-out again"
    );
}

/// Every conformance scene loads (each is inside the subset).
#[test]
fn every_conformance_scene_loads() {
    let features = common::conformance::features();
    for feature in &features {
        let scene = load(&conformance(feature), &[]).unwrap_or_else(|e| panic!("{feature}: {e}"));
        assert!(!scene.scene.mesh.triangles.is_empty(), "{feature}");
    }
    assert_eq!(features.len(), 34, "{features:?}");
}

/// A small render of conformance scenes against their references: the mean over the image
/// within five standard errors (from the reference's per-sample variance) and 1 %.
#[test]
fn small_conformance_scenes_render_as_bright_as_mitsubas_references() {
    // bitmap: nearest and bilinear, repeat, mirror and clamp, on the GPU.
    for feature in ["diffuse_rgb", "point_spot", "bitmap"] {
        let frames = 64;
        let settings =
            common::render::settings(common::render::PATHTRACER, conformance(feature), 48, 3, &[]);
        let session = common::render::render(&settings, frames);
        let image = common::render::image(&session, "l0+direct+indirect");
        let reference = common::conformance::read(feature, "ref");
        let variance = common::conformance::read(feature, "var");
        let pixels = reference.pixels.len() as f64;
        let ours = image.mean();
        let theirs = reference.mean();
        for k in 0..3 {
            // The XYZ variance is stored through Mitsuba's XYZ -> RGB matrix: its mean over
            // the pixels bounds the per-channel variance loosely, which is all this needs.
            let var = variance
                .pixels
                .iter()
                .map(|p| f64::from(p[k]).abs())
                .sum::<f64>()
                / pixels;
            let standard_error = (var / (f64::from(frames) * pixels)).sqrt();
            let allowed = 5.0 * standard_error + 0.01 * theirs[k];
            assert!(
                (ours[k] - theirs[k]).abs() <= allowed,
                "{feature} channel {k}: mean {} against Mitsuba's {} (allowed {allowed})",
                ours[k],
                theirs[k]
            );
        }
    }
}

/// Issue 23 item 4: the Cornell box written by `passgraph mitsuba-scene` and read back by the
/// loader renders the same image as the RON scene, bit for bit.
#[test]
fn a_scene_exported_to_mitsuba_xml_and_read_back_renders_bit_for_bit_the_same() {
    let out = tempfile::tempdir().unwrap();
    let ron = common::root().join("scenes/cornell/scene.ron");
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_passgraph"))
        .arg("mitsuba-scene")
        .arg(&ron)
        .arg("--out")
        .arg(out.path())
        .args(["--size", "24x24"])
        .output()
        .unwrap();
    assert!(
        status.status.success(),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    let xml = out.path().join("scene.xml");
    let original = passgraph::scene::load_scene(&ron).unwrap();
    let read_back = load(&xml, &[]).unwrap().scene;
    assert_eq!(read_back.camera, original.camera);
    assert_eq!(read_back.max_depth, original.max_depth);
    let render = |scene: &Path| {
        let settings = common::render::settings(common::render::PATHTRACER, scene, 24, 5, &[]);
        common::render::image(&common::render::render(&settings, 4), "l0+direct+indirect")
    };
    let a = render(&ron);
    let b = render(&xml);
    assert!(a.pixels == b.pixels, "the images differ");
}

#[test]
fn texture_lookups_wrap_and_filter_as_mitsubas_bitmap() {
    use passgraph::scene::texture::{Filter, Texture, Wrap};
    // drjit's wrap: mirror flips every other tile, clamp extends the edge.
    let mirror: Vec<i64> = (-4..8).map(|i| Wrap::Mirror.index(i, 3)).collect();
    assert_eq!(mirror, [2, 2, 1, 0, 0, 1, 2, 2, 1, 0, 0, 1]);
    let clamp: Vec<i64> = (-2..5).map(|i| Wrap::Clamp.index(i, 3)).collect();
    assert_eq!(clamp, [0, 0, 0, 1, 2, 2, 2]);
    assert_eq!(Wrap::Repeat.index(-1, 3), 2);
    // Nearest: the texel the point lies in (v = 0 at the bottom row, as bilinear).
    let mut t = Texture::from_texels(2, 2, vec![[1.0; 4], [2.0; 4], [3.0; 4], [4.0; 4]]);
    t.filter = Filter::Nearest;
    assert_eq!(t.bilinear(glam::Vec2::new(0.9, 0.9)).x, 2.0);
    assert_eq!(t.bilinear(glam::Vec2::new(0.1, 0.1)).x, 3.0);
    t.wrap = Wrap::Clamp;
    assert_eq!(t.bilinear(glam::Vec2::new(5.0, -3.0)).x, 4.0);
}

/// `render --scene X.xml` takes the film's size and the sampler's sample count unless
/// `--size` and `--frames` are given, and `-D NAME=VALUE` replaces a `<default>`.
#[test]
fn render_takes_the_films_size_and_sample_count_and_defines() {
    let out = tempfile::tempdir().unwrap();
    let image = out.path().join("x.exr");
    let run = |extra: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_passgraph"))
            .current_dir(common::root())
            .args(["render", "--scene"])
            .arg(conformance("structure"))
            .arg("--out")
            .arg(&image)
            .args(extra)
            .output()
            .unwrap()
    };
    let result = run(&["-D", "depth=2", "--frames", "2"]);
    let printed = String::from_utf8_lossy(&result.stderr).to_string()
        + &String::from_utf8_lossy(&result.stdout);
    assert!(result.status.success(), "{printed}");
    assert!(printed.contains("scene_max_depth=2"), "{printed}");
    assert!(printed.contains("2 frames in"), "{printed}");
    let img = passgraph::render::image::RgbImage::read_exr(&image).unwrap();
    assert_eq!((img.width, img.height), (48, 48));
    let result = run(&["--size", "8x4", "--frames", "1", "--define", "radius=0.3"]);
    assert!(
        result.status.success(),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    let img = passgraph::render::image::RgbImage::read_exr(&image).unwrap();
    assert_eq!((img.width, img.height), (8, 4));
    // A define that is not NAME=VALUE is a usage error.
    let result = run(&["-D", "depth"]);
    assert!(!result.status.success());
    assert!(String::from_utf8_lossy(&result.stderr).contains("NAME=VALUE"));
}

/// Mitsuba's `focal_length` (default 50mm) as pip Mitsuba 3.9.0 computes its x field of view
/// (`mi.traverse(sensor)['x_fov']`): 39.5978 degrees on a 48x32 film at 50mm, 34.0221 on a
/// square one, 37.8493 on 32x48 at 35mm.
#[test]
fn focal_length_gives_mitsubas_field_of_view() {
    use passgraph::scene::camera::{Projection, fov_tangents};
    let dir = tempfile::tempdir().unwrap();
    for (focal, [w, h], x_fov) in [
        (Some("50mm"), [48, 32], 39.59775),
        (None, [48, 48], 34.02206),
        (Some("35mm"), [32, 48], 37.84929),
    ] {
        let text = format!(
            r#"<?xml version="1.0"?>
<scene version="3.0.0">
    <integrator type="path"><integer name="max_depth" value="2"/></integrator>
    <sensor type="perspective">
        {}
        <film type="hdrfilm"><integer name="width" value="{w}"/><integer name="height" value="{h}"/></film>
    </sensor>
    <shape type="sphere"/>
</scene>"#,
            focal.map_or(String::new(), |f| format!(
                "<string name=\"focal_length\" value=\"{f}\"/>"
            ))
        );
        let path = dir.path().join("focal.xml");
        std::fs::write(&path, text).unwrap();
        let s = load(&path, &[]).unwrap().scene;
        let Projection::Perspective {
            fov_degrees,
            fov_axis,
            ..
        } = s.camera.projection()
        else {
            panic!("not a perspective camera");
        };
        let (tx, _) = fov_tangents(fov_degrees, fov_axis, w as f32 / h as f32);
        let ours = 2.0 * tx.atan().to_degrees();
        assert!(
            (ours - x_fov).abs() < 1e-3,
            "{focal:?} {w}x{h}: {ours} against Mitsuba's {x_fov}"
        );
    }
}

/// Mitsuba's `obj` ignores the file's materials: a missing library or an undefined `usemtl`
/// does not stop it, and the shape's BSDF applies to every face.
#[test]
fn an_obj_shape_ignores_the_files_materials() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("m.obj"),
        "mtllib missing.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl nowhere\nf 1 2 3\n",
    )
    .unwrap();
    let path = scene_file(
        dir.path(),
        r#"<shape type="obj"><string name="filename" value="m.obj"/><bsdf type="diffuse"><rgb name="reflectance" value="0.25"/></bsdf></shape>"#,
    );
    let s = load(&path, &[]).unwrap().scene;
    assert_eq!(s.mesh.triangles.len(), 1);
    assert_eq!(
        s.mesh.materials[s.mesh.triangles[0].material as usize].kd,
        [0.25; 3]
    );
}
