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
/// the extreme vertices leave unsettled. Proving a hull face needs every vertex on one side, so a
/// scene made only of hull faces (a fine convex mesh) could cost triangles x vertices; past this
/// budget the remaining triangles simply stay occluders.
const TESTS_PER_VERTEX: usize = 8;
const TESTS_FIXED: usize = 1 << 20;
/// The unsettled triangles are tested in batches of this many, in their order, each batch in
/// parallel, while budget is left before it: the answer does not depend on the thread count.
const BATCH: usize = 64;
/// The scene's extreme vertices along each axis, both ways.
const EXTREMES: usize = 6;
/// The scene's vertices are tested in runs of this many triangles' vertices, each with its box:
/// a run whose box's corners all lie on one closed side of a plane has every vertex there (a
/// side test is affine in the point), so eight tests settle it. A room's wall around a
/// 1M-triangle mesh is proved a hull face in some 30 k tests instead of 3 M.
const RUN_TRIANGLES: usize = 256;

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
    // The light points as triangles of three equal corners, so that they run like the mesh's.
    let lights: Vec<[Vec3; 3]> = points.iter().map(|&p| [p; 3]).collect();
    let everywhere = vec![true; lights.len()];
    let runs: Vec<Run> = Run::split(triangles, &usable)
        .chain(Run::split(&lights, &everywhere))
        .collect::<Vec<_>>()
        .into_par_iter()
        .filter_map(|(triangles, usable)| Run::new(triangles, usable))
        .collect();
    let vertices: usize = runs.iter().map(Run::vertex_count).sum();
    // The scene's extreme vertices first: most planes through the inside of the scene have one
    // of them on each side, so most triangles are settled by them alone.
    let front = extremes(&runs);
    let unsettled: Vec<usize> = (0..triangles.len())
        .into_par_iter()
        .filter(|&i| usable[i] && !Sides::of_points(&triangles[i], &front).split())
        .collect();
    let mut budget = TESTS_FIXED + TESTS_PER_VERTEX * vertices;
    let mut result = vec![false; triangles.len()];
    for batch in unsettled.chunks(BATCH) {
        if budget == 0 {
            break;
        }
        let tested: Vec<(bool, usize)> = batch
            .par_iter()
            .map(|&i| Sides::of_runs(&triangles[i], &runs))
            .collect();
        for (&i, &(split, tests)) in batch.iter().zip(&tested) {
            result[i] = !split;
            budget = budget.saturating_sub(tests);
        }
    }
    result
}

/// Whether some tested point lies strictly above a triangle's plane, and some strictly below.
#[derive(Clone, Copy, Default)]
struct Sides {
    above: bool,
    below: bool,
}

impl Sides {
    fn add(&mut self, side: f64) {
        self.above |= side > 0.0;
        self.below |= side < 0.0;
    }

    fn split(self) -> bool {
        self.above && self.below
    }

    /// Whether these sides include every side of `could` (what a run's box allows it to
    /// hold): then the run can add nothing.
    fn covers(self, could: Sides) -> bool {
        (self.above || !could.above) && (self.below || !could.below)
    }

    fn of_points(t: &[Vec3; 3], points: &[Vec3]) -> Sides {
        let [a, b, c] = t.map(coord);
        let mut sides = Sides::default();
        for &p in points {
            sides.add(robust::orient3d(a, b, c, coord(p)));
            if sides.split() {
                break;
            }
        }
        sides
    }

    /// Whether the scene's vertices lie on both sides of t's plane, and the tests it took: a
    /// run is searched only if its box's corners say it may hold a side not found yet.
    fn of_runs(t: &[Vec3; 3], runs: &[Run]) -> (bool, usize) {
        let [a, b, c] = t.map(coord);
        let mut sides = Sides::default();
        let mut tests = 0;
        for run in runs {
            let mut could = Sides::default();
            for corner in run.corners() {
                could.add(robust::orient3d(a, b, c, coord(corner)));
            }
            tests += 8;
            if sides.covers(could) {
                continue;
            }
            for p in run.vertices() {
                sides.add(robust::orient3d(a, b, c, coord(p)));
                tests += 1;
                if sides.split() {
                    return (true, tests);
                }
                if sides.covers(could) {
                    break;
                }
            }
        }
        (false, tests)
    }
}

/// Consecutive triangles whose vertices count as the scene's (the usable ones), and their box.
struct Run<'a> {
    triangles: &'a [[Vec3; 3]],
    usable: &'a [bool],
    lo: Vec3,
    hi: Vec3,
}

impl<'a> Run<'a> {
    fn split(
        triangles: &'a [[Vec3; 3]],
        usable: &'a [bool],
    ) -> impl Iterator<Item = (&'a [[Vec3; 3]], &'a [bool])> {
        triangles
            .chunks(RUN_TRIANGLES)
            .zip(usable.chunks(RUN_TRIANGLES))
    }

    /// The run over `triangles`, or None if none of them is usable.
    fn new(triangles: &'a [[Vec3; 3]], usable: &'a [bool]) -> Option<Run<'a>> {
        let mut run = Run {
            triangles,
            usable,
            lo: Vec3::INFINITY,
            hi: Vec3::NEG_INFINITY,
        };
        let (lo, hi) = run
            .vertices()
            .fold((run.lo, run.hi), |(lo, hi), p| (lo.min(p), hi.max(p)));
        (run.lo, run.hi) = (lo, hi);
        (lo.x <= hi.x).then_some(run)
    }

    fn vertices(&self) -> impl Iterator<Item = Vec3> + '_ {
        self.triangles
            .iter()
            .zip(self.usable)
            .filter(|&(_, &u)| u)
            .flat_map(|(t, _)| *t)
    }

    fn vertex_count(&self) -> usize {
        3 * self.usable.iter().filter(|&&u| u).count()
    }

    /// The box's eight corners (coordinates of the run's vertices, so exact).
    fn corners(&self) -> impl Iterator<Item = Vec3> + '_ {
        (0..8).map(|k| {
            let pick = |bit: usize, axis: usize| {
                if k & bit == 0 {
                    self.lo[axis]
                } else {
                    self.hi[axis]
                }
            };
            Vec3::new(pick(1, 0), pick(2, 1), pick(4, 2))
        })
    }
}

/// The scene's smallest and largest vertex along each axis, each the first of equal ones in
/// the runs' order (so the same on any thread count), without repeats.
fn extremes(runs: &[Run]) -> Vec<Vec3> {
    // Per extreme: its key (the coordinate, negated for the smallest), its place, the vertex.
    type Best = [(f32, usize, Vec3); EXTREMES];
    let none: Best = [(f32::NEG_INFINITY, usize::MAX, Vec3::ZERO); EXTREMES];
    let better = |a: (f32, usize, Vec3), b: (f32, usize, Vec3)| {
        if b.0 > a.0 || (b.0 == a.0 && b.1 < a.1) {
            b
        } else {
            a
        }
    };
    let best = runs
        .par_iter()
        .enumerate()
        .map(|(r, run)| {
            let mut best = none;
            for (k, p) in run.vertices().enumerate() {
                let place = r * 3 * RUN_TRIANGLES + k;
                for (rank, slot) in best.iter_mut().enumerate() {
                    let key = if rank % 2 == 0 {
                        -p[rank / 2]
                    } else {
                        p[rank / 2]
                    };
                    *slot = better(*slot, (key, place, p));
                }
            }
            best
        })
        .reduce(|| none, |a, b| std::array::from_fn(|k| better(a[k], b[k])));
    let mut front: Vec<(usize, Vec3)> = best
        .iter()
        .filter(|b| b.1 != usize::MAX)
        .map(|b| (b.1, b.2))
        .collect();
    front.sort_by_key(|b| b.0);
    front.dedup_by_key(|b| b.0);
    front.into_iter().map(|b| b.1).collect()
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
        let scene = shuffled_strip();
        let hull = hull_faces(&scene);
        let vertices = 3 * scene.len();
        let runs = scene.len().div_ceil(RUN_TRIANGLES);
        // No extreme vertex settles a hull face, and every run's box straddles every plane: each
        // batch of triangles tests each run's corners and every vertex while budget is left
        // before it; the triangles of the batches after are left occluders.
        let per_batch = BATCH * (8 * runs + vertices);
        let budget = TESTS_FIXED + TESTS_PER_VERTEX * vertices;
        let complete = budget.div_ceil(per_batch) * BATCH;
        assert!(
            complete >= 2 * BATCH && complete < scene.len() / 2,
            "{complete}"
        );
        assert!(hull[..complete].iter().all(|&h| h));
        assert!(hull[complete..].iter().all(|&h| !h));
    }

    /// A fine convex mesh is all hull faces: a strip over the parabola z = x^2 at integer x
    /// (exact in f32), 2^12 triangles, in an order that puts triangles from all along the
    /// strip in every run of [`RUN_TRIANGLES`], so that no run's box settles a face.
    fn shuffled_strip() -> Vec<[Vec3; 3]> {
        let n = 1usize << 11;
        let p = |k: usize, y: f32| Vec3::new(k as f32, y, (k * k) as f32);
        let strip: Vec<[Vec3; 3]> = (0..n)
            .flat_map(|k| quad([p(k, 0.0), p(k + 1, 0.0), p(k + 1, 1.0), p(k, 1.0)]))
            .collect();
        // 1031 is prime, so coprime with the count, a power of two: a permutation.
        (0..strip.len())
            .map(|j| strip[j * 1031 % strip.len()])
            .collect()
    }

    /// A plane with whole runs on each side and none across it: the search visits a run for
    /// the side still missing (here the runs below, after the runs above), even though no
    /// run's box straddles the plane.
    #[test]
    fn runs_each_wholly_on_one_side_still_split_a_plane() {
        let flat = [
            Vec3::new(-9.0, -9.0, 0.0),
            Vec3::new(9.0, -9.0, 0.0),
            Vec3::new(0.0, 9.0, 0.0),
        ];
        let layer = |z: f32| -> Vec<[Vec3; 3]> {
            (0..2 * RUN_TRIANGLES)
                .map(|k| {
                    let x = k as f32 / RUN_TRIANGLES as f32;
                    [
                        Vec3::new(x, 0.0, z),
                        Vec3::new(x, 1.0, z + 0.5),
                        Vec3::new(x + 1.0, 0.0, z),
                    ]
                })
                .collect()
        };
        let mut scene = layer(1.0);
        scene.extend(layer(-2.0));
        let usable = vec![true; scene.len()];
        let runs: Vec<Run> = Run::split(&scene, &usable)
            .filter_map(|(t, u)| Run::new(t, u))
            .collect();
        assert_eq!(runs.len(), 4);
        let (split, tests) = Sides::of_runs(&flat, &runs);
        assert!(split);
        // Two runs' corners, one vertex of the first run above, then the next run's corners
        // and one of its vertices below.
        assert_eq!(tests, 8 + 1 + 8 + 8 + 1, "{tests}");
        // Everything above: no split, every run's corners and nothing else tested.
        let above: Vec<Run> = runs.into_iter().take(2).collect();
        assert_eq!(Sides::of_runs(&flat, &above), (false, 8 + 1 + 8));
    }

    /// The runs' boxes only skip tests: on rooms holding random triangles (some poking through
    /// the walls) and point lights (some outside), the hull faces are those of the definition,
    /// every usable vertex and light tested against every triangle.
    #[test]
    fn hull_faces_are_those_no_two_scene_points_straddle() {
        let mut seed = 7u64;
        let mut next = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 40) as f32 / (1u64 << 24) as f32
        };
        for case in 0..6 {
            let mut scene = cube(Vec3::ZERO, Vec3::splat(10.0));
            // Inside the walls, or some through them.
            let (from, spread) = [(1.0, 8.0), (-0.25, 10.5)][case % 2];
            for _ in 0..(700 + 300 * case) {
                let c = Vec3::new(next(), next(), next()) * spread + Vec3::splat(from);
                let mut corner = || c + (Vec3::new(next(), next(), next()) - 0.5) * 0.8;
                scene.push([corner(), corner(), corner()]);
            }
            // In slabs along x, as meshes keep neighbours together: runs' boxes that lie on one
            // side of most planes, which the search must still visit for the side it lacks.
            scene[12..].sort_by(|a, b| a[0].x.total_cmp(&b[0].x));
            if case == 3 {
                // Degenerate triangles far away: their vertices count for nothing.
                scene.push([Vec3::splat(-50.0); 3]);
            }
            let lights: Vec<Vec3> = (0..case)
                .map(|k| Vec3::new(next(), next(), next()) * 10.0 + Vec3::splat(k as f32 * 2.0))
                .collect();
            let points: Vec<Vec3> = scene
                .iter()
                .filter(|t| !is_degenerate(t))
                .flatten()
                .copied()
                .chain(lights.iter().copied())
                .collect();
            let expected: Vec<bool> = scene
                .iter()
                .map(|t| !is_degenerate(t) && !Sides::of_points(t, &points).split())
                .collect();
            // The runs' search alone, for every triangle (most are settled before it).
            let usable: Vec<bool> = scene.iter().map(|t| !is_degenerate(t)).collect();
            let light_triangles: Vec<[Vec3; 3]> = lights.iter().map(|&p| [p; 3]).collect();
            let everywhere = vec![true; lights.len()];
            let runs: Vec<Run> = Run::split(&scene, &usable)
                .chain(Run::split(&light_triangles, &everywhere))
                .filter_map(|(t, u)| Run::new(t, u))
                .collect();
            for (t, &hull) in scene.iter().zip(&expected) {
                if !is_degenerate(t) {
                    assert_eq!(Sides::of_runs(t, &runs).0, !hull, "case {case}: {t:?}");
                }
            }
            let hull = hull_faces_with(&scene, &lights);
            assert_eq!(hull, expected, "case {case}");
            if case == 0 {
                // Nothing pokes through the walls: they are the hull.
                assert!(hull[..12].iter().all(|&h| h) && !hull[12..].contains(&true));
            }
        }
    }

    #[test]
    fn the_answer_is_the_same_on_one_thread_and_on_several() {
        // Chunks with budgets of their own: where the budget runs out does not depend on which
        // thread tests what. A room with a box, and the strip past its budget.
        let mut room = cube(Vec3::ZERO, Vec3::splat(10.0));
        room.extend(cube(Vec3::splat(3.0), Vec3::splat(5.0)));
        for scene in [room, shuffled_strip()] {
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
