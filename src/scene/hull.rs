//! Triangles no shadow ray can meet: a triangle whose plane has every vertex of the scene on one
//! closed side (a face of the scene's convex hull: the walls, floor and ceiling of a room, a
//! ground plane). A shadow ray is a segment between two points of the scene (a shading point
//! and a point on a light), both on that closed side, so it can reach the plane only at a point
//! in it: where it starts or ends, which the traversal excludes (the t error bound at the
//! origin, `tmax < 1` at the light), or all along the plane, where the watertight test reports
//! no hit. Next-event estimation traces its shadow rays through a BVH without them
//! (`Bvh::build_with_occluders`). Ambient-occlusion rays are not segments between scene points
//! and keep the whole scene.

use super::bvh::is_degenerate;
use glam::Vec3;
use rayon::prelude::*;

/// Side tests allowed per vertex of the scene, on top of a fixed allowance, for the triangles
/// the extreme vertices leave unsettled. A hull face is tested against every vertex, so a scene
/// made only of hull faces (a fine convex mesh) would cost triangles x vertices; past this
/// budget the remaining triangles simply stay occluders.
const TESTS_PER_VERTEX: usize = 8;
const TESTS_FIXED: usize = 1 << 20;
/// The unsettled triangles are tested in batches of this many, in their order, each batch in
/// parallel, while budget is left before it: the answer does not depend on the thread count.
const BATCH: usize = 64;
/// The scene's extreme vertices along each axis, both ways.
const EXTREMES: usize = 6;

/// `result[i]`: triangle i is a hull face (see the module). Degenerate triangles are not
/// (they are in no BVH leaf anyway), and their vertices do not count as the scene's. The side
/// tests are exact (Shewchuk's orientation predicate), so rounding never marks a triangle that
/// some vertex lies strictly beyond.
pub fn hull_faces(triangles: &[[Vec3; 3]]) -> Vec<bool> {
    hull_faces_with(triangles, &[])
}

/// As [`hull_faces`], with `points` (point and spot lights, where shadow rays end) counted among
/// the scene's vertices.
pub fn hull_faces_with(triangles: &[[Vec3; 3]], points: &[Vec3]) -> Vec<bool> {
    let usable: Vec<bool> = triangles.par_iter().map(|t| !is_degenerate(t)).collect();
    let mut points: Vec<robust::Coord3D<f64>> = triangles
        .par_iter()
        .zip(&usable)
        .filter(|&(_, &u)| u)
        .flat_map_iter(|(t, _)| t.iter().map(|&p| coord(p)))
        .chain(points.par_iter().map(|&p| coord(p)))
        .collect();
    // The scene's extreme vertices first: most planes through the inside of the scene have one
    // of them on each side, so most triangles are settled by them alone.
    let extremes = EXTREMES.min(points.len());
    for rank in 0..extremes {
        let (axis, sign) = (rank / 2, if rank % 2 == 0 { -1.0 } else { 1.0 });
        let key = |p: &robust::Coord3D<f64>| sign * [p.x, p.y, p.z][axis];
        // The first of equal ones, among those not yet moved to the front.
        let best = (rank..points.len())
            .into_par_iter()
            .max_by(|&a, &b| key(&points[a]).total_cmp(&key(&points[b])).then(b.cmp(&a)))
            .unwrap_or(rank);
        points.swap(rank, best);
    }
    let (front, rest) = points.split_at(extremes);
    // Whether some vertex of `of` lies strictly on each side of t's plane (the tests made).
    let sides = |t: &[Vec3; 3], of: &[robust::Coord3D<f64>]| -> (bool, usize) {
        let [a, b, c] = t.map(coord);
        let (mut above, mut below) = (false, false);
        for (k, p) in of.iter().enumerate() {
            let side = robust::orient3d(a, b, c, *p);
            above |= side > 0.0;
            below |= side < 0.0;
            if above && below {
                return (true, k + 1);
            }
        }
        (false, of.len())
    };
    let unsettled: Vec<usize> = (0..triangles.len())
        .into_par_iter()
        .filter(|&i| usable[i] && !sides(&triangles[i], front).0)
        .collect();
    let mut budget = TESTS_FIXED + TESTS_PER_VERTEX * points.len();
    let mut result = vec![false; triangles.len()];
    for batch in unsettled.chunks(BATCH) {
        if budget == 0 {
            break;
        }
        let tested: Vec<(bool, usize)> = batch
            .par_iter()
            .map(|&i| sides(&triangles[i], rest))
            .collect();
        for (&i, &(split, tests)) in batch.iter().zip(&tested) {
            result[i] = !split;
            budget = budget.saturating_sub(tests);
        }
    }
    result
}

fn coord(p: Vec3) -> robust::Coord3D<f64> {
    robust::Coord3D {
        x: f64::from(p.x),
        y: f64::from(p.y),
        z: f64::from(p.z),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad(p: [Vec3; 4]) -> [[Vec3; 3]; 2] {
        [[p[0], p[1], p[2]], [p[0], p[2], p[3]]]
    }

    /// A unit cube's 12 faces.
    fn cube(lo: Vec3, hi: Vec3) -> Vec<[Vec3; 3]> {
        let c = |x: usize, y: usize, z: usize| {
            Vec3::new([lo.x, hi.x][x], [lo.y, hi.y][y], [lo.z, hi.z][z])
        };
        [
            [c(0, 0, 0), c(1, 0, 0), c(1, 1, 0), c(0, 1, 0)],
            [c(0, 0, 1), c(0, 1, 1), c(1, 1, 1), c(1, 0, 1)],
            [c(0, 0, 0), c(0, 1, 0), c(0, 1, 1), c(0, 0, 1)],
            [c(1, 0, 0), c(1, 0, 1), c(1, 1, 1), c(1, 1, 0)],
            [c(0, 0, 0), c(0, 0, 1), c(1, 0, 1), c(1, 0, 0)],
            [c(0, 1, 0), c(1, 1, 0), c(1, 1, 1), c(0, 1, 1)],
        ]
        .into_iter()
        .flat_map(quad)
        .collect()
    }

    #[test]
    fn a_room_with_a_box_inside_keeps_the_box_as_occluder_and_drops_the_walls() {
        let mut scene = cube(Vec3::ZERO, Vec3::splat(10.0));
        scene.extend(cube(Vec3::splat(3.0), Vec3::splat(5.0)));
        let hull = hull_faces(&scene);
        assert!(hull[..12].iter().all(|&h| h), "{hull:?}");
        assert!(hull[12..].iter().all(|&h| !h), "{hull:?}");
    }

    #[test]
    fn a_skewed_wall_is_a_hull_face_and_a_vertex_one_ulp_beyond_a_plane_keeps_its_face() {
        // The Cornell box's left wall leans: x from 552.8 at the floor to 556 at the ceiling.
        let wall = quad([
            Vec3::new(552.8, 0.0, 0.0),
            Vec3::new(549.6, 0.0, 559.2),
            Vec3::new(556.0, 548.8, 559.2),
            Vec3::new(556.0, 548.8, 0.0),
        ]);
        let mut scene = wall.to_vec();
        scene.push([
            Vec3::ZERO,
            Vec3::new(0.0, 0.0, 559.2),
            Vec3::new(0.0, 548.8, 0.0),
        ]);
        assert_eq!(hull_faces(&scene), vec![true, true, true]);
        // A floor at y = 0 and a triangle dipping one ulp below it: the floor can block.
        let below = -f32::from_bits(1);
        let floor = quad([
            Vec3::ZERO,
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(1.0, 0.0, 1.0),
            Vec3::new(1.0, 0.0, 0.0),
        ]);
        let mut scene = floor.to_vec();
        scene.push([
            Vec3::new(0.5, below, 0.5),
            Vec3::new(0.6, 1.0, 0.5),
            Vec3::new(0.5, 1.0, 0.6),
        ]);
        let hull = hull_faces(&scene);
        assert_eq!(&hull[..2], &[false, false]);
    }

    #[test]
    fn degenerate_triangles_are_never_hull_faces_and_do_not_count_as_scene_points() {
        let mut scene = cube(Vec3::ZERO, Vec3::ONE);
        // Collinear, far outside: were its vertices counted, no face would be a hull face.
        scene.push([Vec3::splat(5.0), Vec3::splat(6.0), Vec3::splat(7.0)]);
        let hull = hull_faces(&scene);
        assert!(hull[..12].iter().all(|&h| h));
        assert!(!hull[12]);
    }

    #[test]
    fn past_the_test_budget_the_remaining_triangles_stay_occluders() {
        // A fine convex mesh is all hull faces: a strip over the parabola z = x^2 at integer x
        // (exact in f32), 2^12 triangles.
        let n = 1usize << 11;
        let p = |k: usize, y: f32| Vec3::new(k as f32, y, (k * k) as f32);
        let scene: Vec<[Vec3; 3]> = (0..n)
            .flat_map(|k| quad([p(k, 0.0), p(k + 1, 0.0), p(k + 1, 1.0), p(k, 1.0)]))
            .collect();
        let hull = hull_faces(&scene);
        let vertices = 3 * scene.len();
        // No extreme vertex settles a hull face: each batch of triangles is tested against
        // every other vertex while budget is left before it; the triangles of the batches
        // after are left occluders.
        let per_batch = BATCH * (vertices - EXTREMES);
        let budget = TESTS_FIXED + TESTS_PER_VERTEX * vertices;
        let complete = budget.div_ceil(per_batch) * BATCH;
        assert!(
            complete >= 2 * BATCH && complete < scene.len() / 2,
            "{complete}"
        );
        assert!(hull[..complete].iter().all(|&h| h));
        assert!(hull[complete..].iter().all(|&h| !h));
    }

    #[test]
    fn the_answer_is_the_same_on_one_thread_and_on_several() {
        // Chunks with budgets of their own: where the budget runs out does not depend on which
        // thread tests what. A room with a box, and the strip past its budget.
        let mut room = cube(Vec3::ZERO, Vec3::splat(10.0));
        room.extend(cube(Vec3::splat(3.0), Vec3::splat(5.0)));
        let p = |k: usize, y: f32| Vec3::new(k as f32, y, (k * k) as f32);
        let strip: Vec<[Vec3; 3]> = (0..1usize << 11)
            .flat_map(|k| quad([p(k, 0.0), p(k + 1, 0.0), p(k + 1, 1.0), p(k, 1.0)]))
            .collect();
        for scene in [room, strip] {
            let one = rayon::ThreadPoolBuilder::new()
                .num_threads(1)
                .build()
                .unwrap()
                .install(|| hull_faces(&scene));
            let many = rayon::ThreadPoolBuilder::new()
                .num_threads(4)
                .build()
                .unwrap()
                .install(|| hull_faces(&scene));
            assert_eq!(one, many);
        }
    }
}
