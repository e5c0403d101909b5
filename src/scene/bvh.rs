//! The threaded BVH (docs/design.md §5): a binned SAH build on the CPU, flattened depth-first so that a
//! node's first child is the next node and only the miss link (`skip`) is stored.

use super::bvh_grid::{BvhGrid, MAX_ENCODED_LEAF};
use super::gpu::BvhNode;
use glam::Vec3;
use std::time::{Duration, Instant};

/// A node with more triangles than this is always split (unless the depth limit is reached).
pub const MAX_LEAF_TRIANGLES: usize = 4;
/// Beyond this depth every node that fits a leaf ([`MAX_ENCODED_LEAF`] triangles) is one, and
/// larger ones are halved, so the build terminates on any input.
pub const MAX_DEPTH: usize = 64;
/// SAH bins per axis.
const BINS: usize = 16;
/// SAH cost of visiting a node, relative to intersecting one triangle.
const TRAVERSAL_COST: f32 = 1.0;
/// How much node boxes are grown, relative to their largest coordinate (about 4 ulps). The
/// triangle test rounds vertex coordinates, so a hit it reports can lie a few ulps outside the
/// exact bounds; the grown box keeps traversal from culling it.
const BOX_PAD: f32 = 1.0 / (1u32 << 21) as f32;

/// The flattened BVH and the order it puts the triangles in.
#[derive(Clone, Debug)]
pub struct Bvh {
    /// Boxes on `grid`.
    pub nodes: Vec<BvhNode>,
    pub grid: BvhGrid,
    /// `order[i]` is the input index of the triangle at position `i` in BVH order. Leaves hold
    /// ranges of positions; degenerate triangles are placed last, in no leaf.
    pub order: Vec<u32>,
    /// The first node of the subtree over the triangles that can block a shadow ray (see
    /// [`Bvh::build_with_occluders`]): traversal from it to the end visits only them. 0 when
    /// every triangle can; `nodes.len()` when none can.
    pub occluder_root: u32,
    pub stats: BvhStats,
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct BvhStats {
    pub build_time: Duration,
    pub node_count: usize,
    pub leaf_count: usize,
    /// The root has depth 0.
    pub max_depth: usize,
    pub max_leaf_triangles: usize,
    /// All triangles, degenerate ones included.
    pub triangle_count: usize,
    /// Degenerate triangles ([`is_degenerate`]: zero area, a normal too small or too large to
    /// normalise in f32), kept in the buffer but in no leaf.
    pub degenerate_count: usize,
}

/// Whether a triangle has no area the renderer can use: a non-finite vertex, or a normal
/// `n = cross(p1 - p0, p2 - p0)` that a GPU cannot normalise. That is: coincident or collinear
/// vertices (`|n|² = 0`); `|n|²` below [`MIN_NORMAL_LENGTH_SQUARED`], where every squared
/// component may be subnormal and a GPU that flushes subnormals (WGSL allows it) computes
/// `|n| = 0` and a NaN normal; or `|n|²` overflowing f32 (edges longer than about 4e9), where
/// `normalize` gives NaN too. Such triangles are never returned as hits and never emit.
pub fn is_degenerate(v: &[Vec3; 3]) -> bool {
    if !v.iter().all(|p| p.is_finite()) {
        return true;
    }
    let normal = (v[1] - v[0]).cross(v[2] - v[0]);
    let length_squared = normal.length_squared();
    // NaN is in no range, so it counts as degenerate too.
    !(MIN_NORMAL_LENGTH_SQUARED..=f32::MAX).contains(&length_squared)
}

/// The smallest `|n|²` a usable triangle may have: 4 × the smallest normal f32. Three squared
/// components each below `f32::MIN_POSITIVE` (each flushable to 0) sum to less than 3 × it,
/// so at least one component's square is a normal number, with room for the GPU rounding the
/// cross product differently.
pub const MIN_NORMAL_LENGTH_SQUARED: f32 = 4.0 * f32::MIN_POSITIVE;

/// What the build needs of one triangle.
#[derive(Clone, Copy)]
struct Primitive {
    lo: Vec3,
    hi: Vec3,
    centroid: Vec3,
}

#[derive(Clone, Copy)]
struct Bounds {
    lo: Vec3,
    hi: Vec3,
}

impl Bounds {
    const EMPTY: Bounds = Bounds {
        lo: Vec3::INFINITY,
        hi: Vec3::NEG_INFINITY,
    };

    fn grow(&mut self, lo: Vec3, hi: Vec3) {
        self.lo = self.lo.min(lo);
        self.hi = self.hi.max(hi);
    }

    /// Half the surface area (the factor 2 cancels in SAH ratios); 0 when empty.
    fn half_area(&self) -> f32 {
        let d = (self.hi - self.lo).max(Vec3::ZERO);
        d.x * d.y + d.y * d.z + d.z * d.x
    }
}

impl Bvh {
    /// Builds the BVH over `triangles`. Never fails: degenerate triangles are left out of the
    /// tree, and with none left the BVH has no nodes.
    pub fn build(triangles: &[[Vec3; 3]]) -> Bvh {
        Bvh::build_with_occluders(triangles, &vec![true; triangles.len()])
    }

    /// As [`Bvh::build`], with the triangles that can block a shadow ray (`occluder[i]`; see
    /// `hull.rs`) in a subtree of their own, the root's second child: depth first, its nodes
    /// are the last ones and their miss links end the traversal, so shadow rays start at
    /// `occluder_root` and never visit the others. When both kinds exist the root's split is
    /// this one rather than the SAH's; below it, each side is an SAH tree.
    pub fn build_with_occluders(triangles: &[[Vec3; 3]], occluder: &[bool]) -> Bvh {
        let start = Instant::now();
        let mut order = Vec::with_capacity(triangles.len());
        let mut degenerate = Vec::new();
        let mut primitives = Vec::with_capacity(triangles.len());
        for (i, v) in triangles.iter().enumerate() {
            let lo = v[0].min(v[1]).min(v[2]);
            let hi = v[0].max(v[1]).max(v[2]);
            primitives.push(Primitive {
                lo,
                hi,
                centroid: (lo + hi) * 0.5,
            });
            if is_degenerate(v) {
                degenerate.push(i as u32);
            } else {
                order.push(i as u32);
            }
        }
        let others = partition_in_place(&mut order, |i| !occluder[i as usize]);

        let mut builder = Builder {
            primitives,
            nodes: Vec::with_capacity(2 * order.len() / MAX_LEAF_TRIANGLES + 2),
            stats: BvhStats {
                triangle_count: triangles.len(),
                degenerate_count: degenerate.len(),
                ..BvhStats::default()
            },
        };
        let occluder_root = if others == 0 || others == order.len() {
            if !order.is_empty() {
                builder.build(&mut order, 0, 0);
            }
            if others == 0 {
                0
            } else {
                builder.nodes.len() as u32
            }
        } else {
            let bounds = builder.bounds(&order);
            builder.nodes.push(BvhNode::default());
            let (left, right) = order.split_at_mut(others);
            builder.build(left, 0, 1);
            let root = builder.nodes.len() as u32;
            builder.build(right, others, 1);
            builder.nodes[0] = node(&bounds, builder.nodes.len() as u32, 0);
            root
        };
        order.extend(degenerate);

        // Snapping grows every box, so children stay inside their parents.
        let mut nodes = builder.nodes;
        let grid = nodes.first().map_or_else(BvhGrid::default, |root| {
            BvhGrid::covering(root.lo.into(), root.hi.into())
        });
        for node in &mut nodes {
            let (lo, hi) = grid.snap(node.lo.into(), node.hi.into());
            (node.lo, node.hi) = (lo.into(), hi.into());
        }
        let mut stats = builder.stats;
        stats.node_count = nodes.len();
        stats.build_time = start.elapsed();
        Bvh {
            nodes,
            grid,
            order,
            occluder_root,
            stats,
        }
    }
}

struct Builder {
    primitives: Vec<Primitive>,
    nodes: Vec<BvhNode>,
    stats: BvhStats,
}

/// Where to split a node: primitives whose centroid falls in a bin `<= bin` along `axis` go
/// left.
#[derive(Clone, Copy)]
struct Split {
    axis: usize,
    bin: usize,
    cost: f32,
}

impl Builder {
    /// Emits the subtree over `order` (the triangles at BVH positions `first..`) depth-first.
    fn build(&mut self, order: &mut [u32], first: usize, depth: usize) {
        let bounds = self.bounds(order);
        let mut centroids = Bounds::EMPTY;
        for &i in order.iter() {
            let p = &self.primitives[i as usize];
            centroids.grow(p.centroid, p.centroid);
        }

        let index = self.nodes.len();
        self.nodes.push(BvhNode::default());
        self.stats.max_depth = self.stats.max_depth.max(depth);

        match self.partition(order, &bounds, &centroids, depth) {
            Some(mid) => {
                let (left, right) = order.split_at_mut(mid);
                self.build(left, first, depth + 1);
                self.build(right, first + mid, depth + 1);
                // The miss link: the node after this whole subtree.
                self.nodes[index] = node(&bounds, self.nodes.len() as u32, 0);
            }
            None => {
                self.nodes[index] = node(&bounds, first as u32, order.len() as u32);
                self.stats.leaf_count += 1;
                self.stats.max_leaf_triangles = self.stats.max_leaf_triangles.max(order.len());
            }
        }
    }

    /// The box around the triangles of `order`.
    fn bounds(&self, order: &[u32]) -> Bounds {
        let mut bounds = Bounds::EMPTY;
        for &i in order {
            let p = &self.primitives[i as usize];
            bounds.grow(p.lo, p.hi);
        }
        bounds
    }

    /// Reorders `order` so that its first `mid` triangles form the left child and returns `mid`,
    /// or None if this node should be a leaf.
    fn partition(
        &self,
        order: &mut [u32],
        bounds: &Bounds,
        centroids: &Bounds,
        depth: usize,
    ) -> Option<usize> {
        let count = order.len();
        if count <= 1 || (depth >= MAX_DEPTH && count <= MAX_ENCODED_LEAF) {
            return None;
        }
        if depth >= MAX_DEPTH {
            return Some(count / 2);
        }
        if let Some(split) = self.best_split(order, centroids) {
            // SAH, in units of one triangle test: a leaf tests all `count` triangles; a split
            // pays a traversal step plus each side's triangles weighted by the chance of
            // entering it. (A zero or infinite area gives a non-finite ratio: then split.)
            let split_cost = TRAVERSAL_COST + split.cost / bounds.half_area();
            if count <= MAX_LEAF_TRIANGLES && split_cost >= count as f32 {
                return None;
            }
            let mid = partition_in_place(order, |i| {
                self.bin_of(self.primitives[i as usize].centroid, centroids, split.axis)
                    <= split.bin
            });
            if mid > 0 && mid < count {
                return Some(mid);
            }
        }
        if count <= MAX_LEAF_TRIANGLES {
            return None;
        }
        // All centroids (nearly) coincide: no plane separates them, and any halving is as good
        // as another. Halving by count bounds the depth by log2(count).
        Some(count / 2)
    }

    /// The cheapest binned SAH split over the three axes (sum of child area × count), or None
    /// when the centroids have no extent on any axis.
    fn best_split(&self, order: &[u32], centroids: &Bounds) -> Option<Split> {
        let mut best: Option<Split> = None;
        for axis in 0..3 {
            let extent = centroids.hi[axis] - centroids.lo[axis];
            if extent.is_nan() || extent <= 0.0 {
                continue;
            }
            let mut bins = [(Bounds::EMPTY, 0usize); BINS];
            for &i in order {
                let p = &self.primitives[i as usize];
                let bin = &mut bins[self.bin_of(p.centroid, centroids, axis)];
                bin.0.grow(p.lo, p.hi);
                bin.1 += 1;
            }
            // Sweep from the right, storing each suffix's cost and count, then from the left.
            let mut right = [(0.0f32, 0usize); BINS];
            let mut acc = Bounds::EMPTY;
            let mut n = 0;
            for b in (1..BINS).rev() {
                acc.grow(bins[b].0.lo, bins[b].0.hi);
                n += bins[b].1;
                right[b] = (acc.half_area() * n as f32, n);
            }
            let mut acc = Bounds::EMPTY;
            let mut n = 0;
            for b in 0..BINS - 1 {
                acc.grow(bins[b].0.lo, bins[b].0.hi);
                n += bins[b].1;
                let (right_cost, right_count) = right[b + 1];
                if n == 0 || right_count == 0 {
                    continue;
                }
                let cost = acc.half_area() * n as f32 + right_cost;
                // NaN only comes from overflowing coordinates (inf * 0); such a cost says nothing.
                if cost.is_nan() {
                    continue;
                }
                if best.is_none_or(|s| cost < s.cost) {
                    best = Some(Split { axis, bin: b, cost });
                }
            }
        }
        best
    }

    fn bin_of(&self, centroid: Vec3, centroids: &Bounds, axis: usize) -> usize {
        let extent = centroids.hi[axis] - centroids.lo[axis];
        let scaled = (centroid[axis] - centroids.lo[axis]) * (BINS as f32 / extent);
        // `as` saturates (NaN → 0), so this is always a valid bin.
        (scaled as usize).min(BINS - 1)
    }
}

/// A node whose box is `bounds`, grown by [`BOX_PAD`].
fn node(bounds: &Bounds, a: u32, count: u32) -> BvhNode {
    let magnitude = bounds.lo.abs().max(bounds.hi.abs()).max_element();
    let pad = Vec3::splat(magnitude * BOX_PAD);
    BvhNode {
        lo: (bounds.lo - pad).into(),
        a,
        hi: (bounds.hi + pad).into(),
        count,
    }
}

/// Moves the elements satisfying `left` to the front and returns how many there are.
fn partition_in_place(items: &mut [u32], left: impl Fn(u32) -> bool) -> usize {
    let mut mid = 0;
    for i in 0..items.len() {
        if left(items[i]) {
            items.swap(mid, i);
            mid += 1;
        }
    }
    mid
}
