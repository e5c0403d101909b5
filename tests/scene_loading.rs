//! Loading the built-in Cornell box and the other mesh forms into GPU buffers.

use glam::Vec3;
use passgraph::scene::camera::project;
use passgraph::scene::{DEFAULT_SCENE, Material, Ray, Scene, load_mesh, load_scene};
use std::path::{Path, PathBuf};

fn crate_path(relative: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(relative)
}

fn data(name: &str) -> PathBuf {
    crate_path("tests/data/scenes").join(name)
}

fn cornell() -> Scene {
    load_scene(&crate_path(DEFAULT_SCENE)).expect("the built-in scene loads")
}

/// The material name of each triangle of a mesh, in file order.
fn material_names(scene: &Scene) -> Vec<&str> {
    scene
        .mesh
        .triangles
        .iter()
        .map(|t| scene.mesh.material_names[t.material as usize].as_str())
        .collect()
}

#[test]
fn cornell_box_has_32_triangles_from_16_quads() {
    let scene = cornell();
    // 5 walls + the light + 5 faces on each of the 2 blocks = 16 quads.
    assert_eq!(scene.mesh.triangles.len(), 32);
    assert_eq!(
        scene.mesh.material_names,
        ["white", "red", "green", "light"]
    );
    let names = material_names(&scene);
    assert_eq!(names.iter().filter(|&&n| n == "red").count(), 2);
    assert_eq!(names.iter().filter(|&&n| n == "green").count(), 2);
    assert_eq!(names.iter().filter(|&&n| n == "light").count(), 2);
    assert_eq!(names.iter().filter(|&&n| n == "white").count(), 26);
    // Fan triangulation of the floor quad 1 2 3 4: (1 2 3), (1 3 4).
    let floor = &scene.mesh.triangles[..2];
    let v = |x, y, z| Vec3::new(x, y, z);
    assert_eq!(
        floor[0].vertices,
        [v(552.8, 0.0, 0.0), v(0.0, 0.0, 0.0), v(0.0, 0.0, 559.2)]
    );
    assert_eq!(
        floor[1].vertices,
        [v(552.8, 0.0, 0.0), v(0.0, 0.0, 559.2), v(549.6, 0.0, 559.2)]
    );
}

#[test]
fn cornell_light_is_one_parallelogram_of_its_two_emissive_triangles_facing_down() {
    let scene = cornell();
    let gpu = scene.to_gpu();
    // The quad's two triangles are one light: one shadow ray per shading point, not two.
    assert_eq!(gpu.light_count, 1);
    assert_eq!(gpu.lights.len(), 1);
    assert!(!gpu.has_specular);
    let light = gpu.lights[0];
    assert!(light.is_parallelogram());
    let normal = Vec3::from(light.e1).cross(Vec3::from(light.e2));
    assert!(
        normal.y < 0.0,
        "the light's front face must point down, got {normal}"
    );
    assert_eq!(
        gpu.materials[light.material as usize].ke,
        [18.387, 13.9873, 6.75357]
    );
    for i in light.triangles() {
        let triangle = gpu.triangles[i as usize];
        assert_eq!(triangle.material, light.material);
        let [p0, p1, p2] = triangle.vertices();
        // Each triangle faces the way the light does.
        assert!((p1 - p0).cross(p2 - p0).dot(normal) > 0.0);
        assert!(p0.y == 548.7 && p1.y == 548.7 && p2.y == 548.7);
    }
    // It covers the 130 x 105 light.
    assert!(
        (light.area() - 130.0 * 105.0).abs() < 1e-2,
        "{}",
        light.area()
    );
}

#[test]
fn cornell_red_wall_is_on_the_left_and_green_on_the_right() {
    let scene = cornell();
    let camera = scene.camera.to_gpu(256, 256);
    // right = normalize(cross(forward, up)) = cross(+z, +y) = -x: larger x is further left.
    assert_eq!(camera.right[0].signum(), -1.0);
    for (triangle, name) in scene.mesh.triangles.iter().zip(material_names(&scene)) {
        let centre = (triangle.vertices[0] + triangle.vertices[1] + triangle.vertices[2]) / 3.0;
        let (sx, _) = project(&camera, centre).expect("in front of the camera");
        match name {
            "red" => assert!(sx < -0.5, "red wall at sx = {sx}"),
            "green" => assert!(sx > 0.5, "green wall at sx = {sx}"),
            _ => {}
        }
    }
}

#[test]
fn cornell_camera_rays_hit_the_tall_block_back_wall_and_light() {
    let scene = cornell();
    let gpu = scene.to_gpu();
    let camera = scene.camera.to_gpu(256, 256);
    let cast = |px: f32, py: f32| {
        let ray = Ray {
            origin: Vec3::from(camera.eye),
            dir: camera.ray_direction(256, 256, px, py),
        };
        let hit = gpu
            .closest_hit(&ray, 0.0, f32::MAX)
            .expect("inside the box");
        ray.origin + hit.t * ray.dir
    };
    // The image centre (278, 273) sees the tall block's front face, on the line from
    // (265, 296) to (423, 247) in xz.
    let centre = cast(128.0, 128.0);
    let expected_z = 296.0 - 13.0 * 49.0 / 158.0;
    assert!((centre.z - expected_z).abs() < 1e-3, "{centre}");
    // Higher up the same column: the back wall.
    let back = cast(128.0, 80.0);
    assert!((back.z - 559.2).abs() < 1e-3, "{back}");
    // Straight up from the floor's centre: the light.
    let up = Ray {
        origin: Vec3::new(278.0, 1.0, 280.0),
        dir: Vec3::Y,
    };
    let hit = gpu.closest_hit(&up, 0.0, f32::MAX).expect("the light");
    assert!(
        gpu.lights
            .iter()
            .any(|l| l.triangles().any(|t| t == hit.triangle))
    );
    assert!((hit.t - 547.7).abs() < 1e-3);
}

#[test]
fn cornell_bvh_stats_are_reported() {
    let gpu = cornell().to_gpu();
    assert_eq!(gpu.bvh.triangle_count, 32);
    assert_eq!(gpu.bvh.degenerate_count, 0);
    assert_eq!(gpu.bvh.node_count, gpu.nodes.len());
    assert_eq!(gpu.nodes.len(), 2 * gpu.bvh.leaf_count - 1);
    assert_eq!(gpu.triangles.len(), 32);
}

#[test]
fn obj_forms_materials_and_default_material_load() {
    let mesh = load_mesh(&data("mixed.obj")).unwrap();
    // 1 triangle + a pentagon (3) + 1 triangle.
    assert_eq!(mesh.triangles.len(), 5);
    assert_eq!(
        mesh.material_names,
        ["shiny", "lamp", "unused", "default"],
        "library materials in order, then the default"
    );
    let names: Vec<&str> = mesh
        .triangles
        .iter()
        .map(|t| mesh.material_names[t.material as usize].as_str())
        .collect();
    assert_eq!(names, ["default", "shiny", "shiny", "shiny", "lamp"]);
    assert_eq!(mesh.materials[3], Material::DEFAULT);
    assert_eq!(Material::DEFAULT.kd, [0.8; 3]);
    let shiny = mesh.materials[0];
    assert_eq!(
        (shiny.kd, shiny.ks, shiny.ns),
        ([0.2, 0.3, 0.4], [0.5; 3], 64.0)
    );
    assert_eq!(mesh.materials[1].ke, [1.0, 2.0, 3.0]);
    // The pentagon, fan-triangulated from its first vertex; `v 2 2 2 2` is (1, 1, 1).
    let v = |x, y, z| Vec3::new(x, y, z);
    let fan: Vec<[Vec3; 3]> = mesh.triangles[1..4].iter().map(|t| t.vertices).collect();
    assert_eq!(
        fan,
        [
            [v(0.0, 0.0, 1.0), v(2.0, 0.0, 1.0), v(1.0, 1.0, 1.0)],
            [v(0.0, 0.0, 1.0), v(1.0, 1.0, 1.0), v(1.0, 3.0, 1.0)],
            [v(0.0, 0.0, 1.0), v(1.0, 3.0, 1.0), v(0.0, 2.0, 1.0)],
        ]
    );
}

#[test]
fn specular_flag_counts_only_materials_in_use() {
    let mut mesh = load_mesh(&data("mixed.obj")).unwrap();
    let gpu = passgraph::scene::SceneGpu::build(&mesh);
    assert!(gpu.has_specular, "shiny is used");
    assert_eq!(gpu.light_count, 1, "the lamp triangle");
    // Without the shiny faces only `unused` has Ks, and no triangle uses it.
    mesh.triangles.retain(|t| t.material != 0);
    let gpu = passgraph::scene::SceneGpu::build(&mesh);
    assert!(!gpu.has_specular);
}

#[test]
fn scene_without_emitters_has_an_empty_light_list() {
    let mut mesh = load_mesh(&data("mixed.obj")).unwrap();
    mesh.triangles.retain(|t| t.material != 1);
    let gpu = passgraph::scene::SceneGpu::build(&mesh);
    assert!(gpu.lights.is_empty());
    assert_eq!(gpu.light_count, 0);
}

#[test]
fn zero_area_emitters_are_not_lights() {
    let mut mesh = load_mesh(&data("mixed.obj")).unwrap();
    let lamp = mesh.triangles.iter_mut().find(|t| t.material == 1).unwrap();
    lamp.vertices[2] = lamp.vertices[1];
    let gpu = passgraph::scene::SceneGpu::build(&mesh);
    assert!(gpu.lights.is_empty());
    // Still in the buffer: kept, but in no leaf.
    assert_eq!(gpu.triangles.len(), 5);
    assert_eq!(gpu.bvh.degenerate_count, 1);
}

#[test]
fn ascii_ply_polygons_are_fan_triangulated_with_one_default_material() {
    let mesh = load_mesh(&data("polygons.ply")).unwrap();
    assert_eq!(mesh.triangles.len(), 5);
    assert_eq!(mesh.materials, [Material::DEFAULT]);
    let v = |x, y, z| Vec3::new(x, y, z);
    assert_eq!(
        mesh.triangles[1].vertices,
        [v(0.0, 0.0, 0.0), v(1.0, 1.0, 0.0), v(0.0, 1.0, 0.0)]
    );
    assert_eq!(
        mesh.triangles[4].vertices,
        [v(0.0, 0.0, 1.0), v(1.0, 3.0, 1.0), v(0.0, 2.0, 1.0)]
    );
}

/// A binary little-endian PLY: float x y z (and an ignored extra property), faces with a
/// `vertex_index` list of `uint` (the other common spelling).
fn binary_ply(vertices: &[[f32; 3]], faces: &[&[u32]]) -> Vec<u8> {
    let mut bytes = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\n\
         property float y\nproperty float z\nproperty uchar flags\nelement face {}\n\
         property list uchar uint vertex_index\nend_header\n",
        vertices.len(),
        faces.len()
    )
    .into_bytes();
    for v in vertices {
        for c in v {
            bytes.extend(c.to_le_bytes());
        }
        bytes.push(7);
    }
    for f in faces {
        bytes.push(f.len() as u8);
        for i in *f {
            bytes.extend(i.to_le_bytes());
        }
    }
    bytes
}

#[test]
fn binary_ply_loads_with_vertex_index_lists() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("quad.ply");
    let vertices = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    std::fs::write(&path, binary_ply(&vertices, &[&[0, 1, 2, 3], &[3, 2, 1]])).unwrap();
    let mesh = load_mesh(&path).unwrap();
    assert_eq!(mesh.triangles.len(), 3);
    assert_eq!(mesh.triangles[2].vertices[0], Vec3::new(0.0, 1.0, 0.0));
}

#[test]
fn mesh_extension_is_case_insensitive() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("QUAD.PLY");
    std::fs::copy(data("polygons.ply"), &path).unwrap();
    assert_eq!(load_mesh(&path).unwrap().triangles.len(), 5);
}

#[test]
fn scene_numbers_may_be_integers_or_floats_and_mesh_is_relative_to_the_scene() {
    let dir = tempfile::tempdir().unwrap();
    let sub = dir.path().join("meshes");
    std::fs::create_dir(&sub).unwrap();
    std::fs::copy(data("polygons.ply"), sub.join("p.ply")).unwrap();
    let path = dir.path().join("scene.ron");
    std::fs::write(
        &path,
        "Scene(mesh: \"meshes/p.ply\", camera: Camera(eye: (1, 2.5, -3), \
         target: (1.0, 2, 0), up: (0, 1, 0), fov_y: 45))",
    )
    .unwrap();
    let scene = load_scene(&path).unwrap();
    assert_eq!(scene.camera.eye(), Vec3::new(1.0, 2.5, -3.0));
    assert_eq!(scene.camera.target(), Vec3::new(1.0, 2.0, 0.0));
    assert_eq!(scene.camera.fov_y_degrees_for(1, 1), Some(45.0));
    assert_eq!(scene.mesh.triangles.len(), 5);
    assert_eq!(scene.path, path);
}
