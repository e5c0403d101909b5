//! The threaded BVH re-threaded for four octants of ray directions (docs/design.md §5): a
//! stackless traversal visits a node's children in the order they are stored, so a closest-hit
//! query finds the near hit first, and then culls the far subtree, only if the near child comes
//! first. Copy `c` stores, at every interior node, first the child nearer for directions with
//! the signs of octant [`COPY_OCTANTS`]`[c]` (bit k set: negative along axis k). The copies are
//! the four octants with an even number of negative signs; a ray of another octant traverses
//! the copy that differs from its own only in the sign of its smallest component, the axis
//! along which the order matters least. Same boxes, same leaves, same triangles: only the order
//! differs, so the answers do not (ties resolve by triangle index). Measured in
//! docs/benchmark-history.md: eight copies (one per octant) took 0.90x the CPU time of one on
//! the bunny; four cost 1-2 % more node visits than eight for half the memory.

use super::gpu_layout::BvhNode;
use glam::Vec3;
use rayon::prelude::*;

/// How many copies of the nodes the GPU holds.
pub const COPIES: usize = 4;

/// The octant each copy is ordered for: the even ones, so that copy `c` is octant `2c` or
/// `2c + 1` (the one of the pair with an even number of bits).
pub const COPY_OCTANTS: [usize; COPIES] = [0, 3, 5, 6];

/// The octant of direction `dir`: bit k set when its component k is negative (-0 counts as
/// positive, as the shader's `dir.x < 0.0` does).
pub fn octant(dir: Vec3) -> usize {
    (0..3).filter(|&k| dir[k] < 0.0).map(|k| 1 << k).sum()
}

/// The copy a ray along `dir` traverses: its octant's, or for an octant with an odd number of
/// negative signs the one with the sign of its smallest component (the first of equal ones)
/// flipped. bvh.wgsl's `bvh_copy` is the same function.
pub fn copy_of(dir: Vec3) -> usize {
    let mut o = octant(dir);
    if o.count_ones() % 2 == 1 {
        let a = dir.abs();
        let k = if a.x <= a.y && a.x <= a.z {
            0
        } else if a.y <= a.z {
            1
        } else {
            2
        };
        o ^= 1 << k;
    }
    o >> 1
}

/// The [`COPIES`] copies of `nodes` (a threaded tree, root at 0), one after the other, each
/// with links local to its copy. With `keep_root` the root's children keep their order in
/// every copy: the occluders' subtree (`Bvh::build_with_occluders`) must stay last, at the
/// same `occluder_root`, for shadow rays to start there.
pub fn octant_copies(nodes: &[BvhNode], keep_root: bool) -> Vec<BvhNode> {
    // Every copy has the tree's node count and links local to it: the copies fill disjoint
    // slices of one buffer, in parallel.
    let mut out = vec![BvhNode::default(); COPIES * nodes.len()];
    if !nodes.is_empty() {
        out.par_chunks_mut(nodes.len())
            .enumerate()
            .for_each(|(c, copy)| {
                rethread(nodes, 0, COPY_OCTANTS[c], keep_root, copy, &mut 0);
            });
    }
    out
}

/// Writes the subtree at `i` as octant `o` orders it into `copy` from `*len` on (advancing it),
/// its miss links counted from the copy's first node.
fn rethread(
    nodes: &[BvhNode],
    i: usize,
    o: usize,
    keep_order: bool,
    copy: &mut [BvhNode],
    len: &mut usize,
) {
    let node = nodes[i];
    if node.count > 0 {
        copy[*len] = node;
        *len += 1;
        return;
    }
    let left = i + 1;
    let right = subtree_end(nodes, left);
    let (first, second) = if keep_order || nearer_first(&nodes[left], &nodes[right], o) {
        (left, right)
    } else {
        (right, left)
    };
    let index = *len;
    copy[index] = node;
    *len += 1;
    rethread(nodes, first, o, false, copy, len);
    rethread(nodes, second, o, false, copy, len);
    copy[index].a = *len as u32;
}

/// The index after the subtree at `i`: a leaf's successor, an interior node's miss link.
fn subtree_end(nodes: &[BvhNode], i: usize) -> usize {
    if nodes[i].count > 0 {
        i + 1
    } else {
        nodes[i].a as usize
    }
}

/// Whether `a` comes before `b` for directions of octant `o`: along the axis that separates
/// their centres most, `a` lies on the side the ray comes from.
fn nearer_first(a: &BvhNode, b: &BvhNode, o: usize) -> bool {
    let centre = |n: &BvhNode| (Vec3::from(n.lo) + Vec3::from(n.hi)) * 0.5;
    let d = centre(b) - centre(a);
    let axis = d.abs().max_position();
    (d[axis] >= 0.0) == (o >> axis & 1 == 0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Bvh;

    fn grid_of_triangles() -> Vec<[Vec3; 3]> {
        let mut triangles = Vec::new();
        for x in 0..6 {
            for y in 0..5 {
                for z in 0..4 {
                    let p = Vec3::new(x as f32, y as f32 * 1.5, z as f32 * 2.0);
                    triangles.push([p, p + Vec3::X * 0.5, p + Vec3::Y * 0.5]);
                }
            }
        }
        triangles
    }

    /// The leaves a traversal that enters every box meets, in order.
    fn leaves(copy: &[BvhNode]) -> Vec<(u32, u32)> {
        copy.iter()
            .filter(|n| n.count > 0)
            .map(|n| (n.a, n.count))
            .collect()
    }

    #[test]
    fn every_copy_holds_the_same_nodes_with_links_inside_itself() {
        let bvh = Bvh::build(&grid_of_triangles());
        let n = bvh.nodes.len();
        let copies = octant_copies(&bvh.nodes, false);
        assert_eq!(copies.len(), COPIES * n);
        let mut expected = leaves(&bvh.nodes);
        expected.sort_unstable();
        for copy in copies.chunks(n) {
            let mut got = leaves(copy);
            got.sort_unstable();
            assert_eq!(got, expected);
            for (i, node) in copy.iter().enumerate() {
                if node.count == 0 {
                    // An interior node's miss link lies past its two children, within the copy.
                    assert!(
                        node.a as usize > i + 2 && node.a as usize <= n,
                        "{i}: {node:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn each_copy_visits_the_leaves_nearest_first_along_its_octant() {
        // The failure this prevents: a copy ordered against its octant, whose closest-hit
        // traversal would meet the far leaves first and cull nothing. Measured over all pairs
        // of leaves, not successive ones: leaves of a few triangles overlap along the diagonal.
        let bvh = Bvh::build(&grid_of_triangles());
        let n = bvh.nodes.len();
        let copies = octant_copies(&bvh.nodes, false);
        for (c, copy) in copies.chunks(n).enumerate() {
            let o = COPY_OCTANTS[c];
            let sign = Vec3::new(
                if o & 1 == 0 { 1.0 } else { -1.0 },
                if o & 2 == 0 { 1.0 } else { -1.0 },
                if o & 4 == 0 { 1.0 } else { -1.0 },
            );
            let depth: Vec<f32> = copy
                .iter()
                .filter(|n| n.count > 0)
                .map(|n| ((Vec3::from(n.lo) + Vec3::from(n.hi)) * 0.5).dot(sign))
                .collect();
            // Kendall's tau of the stored order against the depth along the octant: pairs in
            // order minus pairs out of order (here 0.68 of all pairs; a copy stored for the
            // opposite octant has the negative).
            let pairs = depth.len() * (depth.len() - 1) / 2;
            let tau: i64 = (0..depth.len())
                .flat_map(|i| (i + 1..depth.len()).map(move |j| (i, j)))
                .map(|(i, j)| match depth[i].partial_cmp(&depth[j]) {
                    Some(std::cmp::Ordering::Less) => 1,
                    Some(std::cmp::Ordering::Greater) => -1,
                    _ => 0,
                })
                .sum();
            assert!(
                tau * 2 >= pairs as i64,
                "octant {o}: Kendall's tau {tau} of {pairs} pairs of leaves along {sign}"
            );
        }
    }

    #[test]
    fn the_root_keeps_its_order_where_the_occluders_subtree_must_stay_last() {
        let triangles = grid_of_triangles();
        let occluder: Vec<bool> = (0..triangles.len()).map(|i| i % 3 != 0).collect();
        let bvh = Bvh::build_with_occluders(&triangles, &occluder);
        let n = bvh.nodes.len();
        let root = bvh.occluder_root as usize;
        assert!(root > 0 && root < n);
        let copies = octant_copies(&bvh.nodes, true);
        let mut expected = leaves(&bvh.nodes[root..]);
        expected.sort_unstable();
        for copy in copies.chunks(n) {
            let mut got = leaves(&copy[root..]);
            got.sort_unstable();
            assert_eq!(got, expected);
        }
    }

    #[test]
    fn a_ray_traverses_the_copy_of_its_octant_or_of_the_one_across_its_smallest_axis() {
        for (c, &o) in COPY_OCTANTS.iter().enumerate() {
            assert_eq!(o.count_ones() % 2, 0);
            assert_eq!(o >> 1, c);
        }
        // Even octants: their own copy.
        assert_eq!(copy_of(Vec3::new(1.0, 2.0, 3.0)), 0);
        assert_eq!(copy_of(Vec3::new(-1.0, -2.0, 3.0)), 1);
        // Octant 1 (x negative): x is the smallest, so octant 0; y the smallest, octant 3.
        assert_eq!(copy_of(Vec3::new(-0.1, 2.0, 3.0)), 0);
        assert_eq!(copy_of(Vec3::new(-1.0, 0.2, 3.0)), 1);
        // Octant 7: z the smallest, octant 3; ties take the first axis: octant 6.
        assert_eq!(copy_of(Vec3::new(-1.0, -2.0, -0.5)), 1);
        assert_eq!(copy_of(Vec3::new(-1.0, -1.0, -1.0)), 3);
    }

    #[test]
    fn the_octant_is_the_sign_bits_with_negative_zero_positive() {
        assert_eq!(octant(Vec3::new(1.0, 2.0, 3.0)), 0);
        assert_eq!(octant(Vec3::new(-1.0, 2.0, -3.0)), 5);
        assert_eq!(octant(Vec3::new(-0.0, -1.0, 0.0)), 2);
    }
}
