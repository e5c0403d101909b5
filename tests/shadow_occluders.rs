//! Shadow rays skip the scene's hull faces (src/scene/hull.rs): which triangles those are, the
//! BVH subtree shadow rays traverse, and that for segments between points of the scene the
//! answer is exactly any_hit's over every triangle. (The GPU's shadow_hit is held to this CPU
//! twin in tests/bvh_wgsl.rs.)

mod common;

use common::geometry::{Rng, grid_cube, icosphere};
use common::root;
use glam::Vec3;
use passgraph::scene::{DEFAULT_SCENE, Mesh, Ray, SceneGpu, load_scene};

/// The triangles the leaves from `root` on reference.
fn referenced_from(scene: &SceneGpu, root: usize) -> Vec<u32> {
    let mut triangles: Vec<u32> = scene.nodes[root..]
        .iter()
        .filter(|n| n.count > 0)
        .flat_map(|n| n.a..n.a + n.count)
        .collect();
    triangles.sort_unstable();
    triangles
}

/// A point inside triangle t (barycentrics away from the edges).
fn point_on(rng: &mut Rng, t: [Vec3; 3]) -> Vec3 {
    let (a, b) = (0.05 + 0.45 * rng.unit(), 0.05 + 0.45 * rng.unit());
    t[0] + a * (t[1] - t[0]) + b * (t[2] - t[0])
}

/// Shadow rays as next-event estimation casts them: from a point on a random triangle, moved
/// off it toward the light by a small relative offset, to a point on a random light
/// triangle, with t in (0, 1 - 1e-4). Asserts shadow_hit == any_hit on each; returns how many
/// were blocked.
fn assert_shadow_rays_agree(name: &str, scene: &SceneGpu, lights: &[usize], rays: usize) -> usize {
    let mut rng = Rng(7);
    let mut blocked = 0;
    for _ in 0..rays {
        let t = scene.triangles[rng.index(scene.triangles.len())].vertices();
        let light = scene.triangles[lights[rng.index(lights.len())]].vertices();
        let (p, q) = (point_on(&mut rng, t), point_on(&mut rng, light));
        let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize();
        let n = if n.dot(q - p) < 0.0 { -n } else { n };
        let origin = p + n * (p.abs().max_element().max(1.0) * 1e-5);
        let ray = Ray {
            origin,
            dir: q - origin,
        };
        let any = scene.any_hit(&ray, 0.0, 1.0 - 1e-4);
        assert_eq!(
            scene.shadow_hit(&ray, 0.0, 1.0 - 1e-4),
            any,
            "{name}: shadow_hit differs from any_hit for {ray:?}"
        );
        blocked += usize::from(any);
    }
    blocked
}

#[test]
fn the_cornell_box_traces_shadow_rays_past_its_five_walls_with_the_same_answers() {
    let scene = load_scene(&root().join(DEFAULT_SCENE)).unwrap().to_gpu();
    let root_node = scene.occluder_root as usize;
    assert!(root_node > 0 && root_node < scene.nodes.len());
    // Floor, ceiling and three walls: 10 of 32 triangles; the blocks and the light remain.
    let occluders = referenced_from(&scene, root_node);
    assert_eq!(occluders.len(), 22, "{occluders:?}");
    for &i in &occluders {
        let y: Vec<f32> = scene.triangles[i as usize]
            .vertices()
            .iter()
            .map(|p| p.y)
            .collect();
        // The blocks stand between the floor and 330; the light hangs at 548.7.
        assert!(
            y.iter().all(|&y| y <= 330.0) || y.iter().all(|&y| y == 548.7),
            "{y:?}"
        );
    }
    // Every triangle is in the whole tree, once.
    assert_eq!(referenced_from(&scene, 0), (0..32).collect::<Vec<u32>>());
    let lights: Vec<usize> = (0..scene.triangles.len())
        .filter(|&i| scene.materials[scene.triangles[i].material as usize].is_emissive())
        .collect();
    let blocked = assert_shadow_rays_agree("cornell", &scene, &lights, 20_000);
    // The blocks shadow part of the floor and walls: the comparison sees both answers.
    assert!(blocked > 500 && blocked < 15_000, "{blocked}");
}

#[test]
fn a_sphere_in_a_room_and_a_convex_scene_keep_exactly_what_can_block() {
    // A closed room (a cube seen from inside) with a sphere and a light inside.
    let room = icosphere(0)
        .triangles()
        .iter()
        .map(|t| t.map(|p| p * 40.0))
        .collect::<Vec<_>>();
    let sphere: Vec<[Vec3; 3]> = icosphere(3)
        .triangles()
        .iter()
        .map(|t| t.map(|p| p * 5.0 + Vec3::new(3.0, -4.0, 1.0)))
        .collect();
    let light = [
        Vec3::new(-4.0, 20.0, -4.0),
        Vec3::new(4.0, 20.0, -4.0),
        Vec3::new(0.0, 20.0, 4.0),
    ];
    let mut triangles = room.clone();
    triangles.extend(&sphere);
    triangles.push(light);
    let scene = SceneGpu::build(&Mesh::from_triangles("room", &triangles));
    // The room's 20 faces are the hull; the sphere and the light remain.
    let occluders = referenced_from(&scene, scene.occluder_root as usize);
    assert_eq!(occluders.len(), sphere.len() + 1);
    let light_index = (0..scene.triangles.len())
        .find(|&i| scene.triangles[i].vertices() == light)
        .unwrap();
    let blocked = assert_shadow_rays_agree("room", &scene, &[light_index], 20_000);
    assert!(blocked > 500, "{blocked}");

    // A convex scene (a cube of 3 x 3 grids, exact in f32) is all hull: nothing can block a
    // segment between two of its points, and shadow rays visit no node at all. (The sphere
    // alone would not do: its vertices, rounded onto the sphere, are not exactly convex, and
    // the exact side tests keep every facet some neighbour pokes through.)
    let cube = grid_cube(3).triangles();
    let convex = SceneGpu::build(&Mesh::from_triangles("cube", &cube));
    assert_eq!(convex.occluder_root as usize, convex.nodes.len());
    assert!(referenced_from(&convex, convex.occluder_root as usize).is_empty());
    assert_eq!(
        assert_shadow_rays_agree("cube", &convex, &[0, 7, 30], 5_000),
        0
    );
}
