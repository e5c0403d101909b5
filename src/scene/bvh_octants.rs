//! The threaded BVH re-threaded once per octant of ray directions (docs/design.md §5): a
//! stackless traversal visits a node's children in the order they are stored, so a closest-hit
//! query finds the near hit first, and then culls the far subtree, only if the near child comes
//! first. Copy `o` stores, at every interior node, first the child nearer for directions with
//! the signs of octant `o` (bit k set: negative along axis k); a ray traverses the copy of its
//! direction's octant. Same boxes, same leaves, same triangles: only the order differs, so the
//! answers do not (ties resolve by triangle index). Measured in docs/benchmark-history.md:
//! 0.90x the CPU time on the bunny, 0.975x on the Cornell box, for 8 node texels instead of 1.

use super::gpu::BvhNode;
use glam::Vec3;
use rayon::prelude::*;

/// How many copies: one per octant of directions.
pub const OCTANTS: usize = 8;

/// The octant of direction `dir`: bit k set when its component k is negative (-0 counts as
/// positive, as the shader's `dir.x < 0.0` does).
pub fn octant(dir: Vec3) -> usize {
    (0..3).filter(|&k| dir[k] < 0.0).map(|k| 1 << k).sum()
}

/// The [`OCTANTS`] copies of `nodes` (a threaded tree, root at 0), one after the other, each
/// with links local to its copy. With `keep_root` the root's children keep their order in
/// every copy: the occluders' subtree (`Bvh::build_with_occluders`) must stay last, at the
/// same `occluder_root`, for shadow rays to start there.
pub fn octant_copies(nodes: &[BvhNode], keep_root: bool) -> Vec<BvhNode> {
    // Every copy has the tree's node count and links local to it: the copies fill disjoint
    // slices of one buffer, in parallel.
    let mut out = vec![BvhNode::default(); OCTANTS * nodes.len()];
    if !nodes.is_empty() {
        out.par_chunks_mut(nodes.len())
            .enumerate()
            .for_each(|(o, copy)| {
                rethread(nodes, 0, o, keep_root, copy, &mut 0);
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
        assert_eq!(copies.len(), OCTANTS * n);
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
        // traversal would meet the far leaves first and cull nothing.
        let bvh = Bvh::build(&grid_of_triangles());
        let n = bvh.nodes.len();
        let copies = octant_copies(&bvh.nodes, false);
        for (o, copy) in copies.chunks(n).enumerate() {
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
            let ordered = depth.windows(2).filter(|w| w[0] <= w[1]).count();
            assert!(
                ordered * 10 >= (depth.len() - 1) * 7,
                "octant {o}: only {ordered} of {} successive leaves farther along {sign}",
                depth.len() - 1
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
    fn the_octant_is_the_sign_bits_with_negative_zero_positive() {
        assert_eq!(octant(Vec3::new(1.0, 2.0, 3.0)), 0);
        assert_eq!(octant(Vec3::new(-1.0, 2.0, -3.0)), 5);
        assert_eq!(octant(Vec3::new(-0.0, -1.0, 0.0)), 2);
    }
}
