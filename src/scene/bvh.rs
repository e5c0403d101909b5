//! The threaded BVH (docs/design.md §5): a binned SAH build on the CPU, flattened depth-first so that a
//! node's first child is the next node and only the miss link (`skip`) is stored.

use super::bvh_grid::{BvhGrid, MAX_ENCODED_LEAF};
use super::gpu::BvhNode;
use glam::Vec3;
use rayon::prelude::*;
use std::time::{Duration, Instant};

/// A node with more triangles than this is always split (unless the depth limit is reached).
pub const MAX_LEAF_TRIANGLES: usize = 4;
/// Beyond this depth every node that fits a leaf ([`MAX_ENCODED_LEAF`] triangles) is one, and
/// larger ones are halved, so the build terminates on any input.
pub const MAX_DEPTH: usize = 64;
/// SAH bins per axis.
const BINS: usize = 16;
/// SAH cost of visiting a node, relative to intersecting one triangle. 2 rather than 1: leaves
/// of about 2.7 triangles instead of 1.85, 0.73 nodes per triangle instead of 1.08 (a third less
/// memory for the node copies) at the same loop iterations per ray within 2 % and the same
/// frames/s within noise on a 1M-triangle mesh (docs/benchmark-history.md, 2026-12-04).
const TRAVERSAL_COST: f32 = 2.0;
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

/// What the build needs of one triangle: its box, its box's centre and its input index. The
/// build partitions these records themselves (not indices into them), so each pass over a
/// node reads memory in order.
#[derive(Clone, Copy)]
struct Item {
    lo: Vec3,
    hi: Vec3,
    centroid: Vec3,
    index: u32,
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
        // Each triangle's record in parallel (exact: no sums), the degenerate ones apart.
        let records: Vec<Option<Item>> = triangles
            .par_iter()
            .enumerate()
            .map(|(i, v)| {
                if is_degenerate(v) {
                    return None;
                }
                let lo = v[0].min(v[1]).min(v[2]);
                let hi = v[0].max(v[1]).max(v[2]);
                Some(Item {
                    lo,
                    hi,
                    centroid: (lo + hi) * 0.5,
                    index: i as u32,
                })
            })
            .collect();
        let mut items = Vec::with_capacity(triangles.len());
        let mut degenerate = Vec::new();
        for (i, record) in records.into_iter().enumerate() {
            match record {
                Some(item) => items.push(item),
                None => degenerate.push(i as u32),
            }
        }
        let others = partition_in_place(&mut items, |t| !occluder[t.index as usize]);

        let (tree, occluder_root) = if others == 0 || others == items.len() {
            let tree = if items.is_empty() {
                Subtree::default()
            } else {
                subtree(&mut items, 0, 0)
            };
            let root = if others == 0 {
                0
            } else {
                tree.nodes.len() as u32
            };
            (tree, root)
        } else {
            let bounds = bounds_of(&items).0;
            let (left, right) = items.split_at_mut(others);
            let (left, right) = rayon::join(|| subtree(left, 0, 1), || subtree(right, others, 1));
            let root = 1 + left.nodes.len() as u32;
            (Subtree::join(&bounds, left, right), root)
        };
        let mut order: Vec<u32> = items.par_iter().map(|t| t.index).collect();
        order.extend(degenerate);

        // Snapping grows every box, so children stay inside their parents.
        let mut nodes = tree.nodes;
        let grid = nodes.first().map_or_else(BvhGrid::default, |root| {
            BvhGrid::covering(root.lo.into(), root.hi.into())
        });
        nodes.par_iter_mut().for_each(|node| {
            let (lo, hi) = grid.snap(node.lo.into(), node.hi.into());
            (node.lo, node.hi) = (lo.into(), hi.into());
        });
        let stats = BvhStats {
            build_time: start.elapsed(),
            node_count: nodes.len(),
            leaf_count: tree.leaf_count,
            max_depth: tree.max_depth,
            max_leaf_triangles: tree.max_leaf_triangles,
            triangle_count: triangles.len(),
            degenerate_count: order.len() - items.len(),
        };
        Bvh {
            nodes,
            grid,
            order,
            occluder_root,
            stats,
        }
    }
}

/// Subtrees over at least this many triangles build their two children in parallel (rayon):
/// each child then gets a node list of its own, copied into the parent's once, so small
/// subtrees, where that copy would cost more than the thread saves, build in place.
const PARALLEL_MIN_TRIANGLES: usize = 16 * 1024;

/// A subtree's nodes, depth-first, with miss links relative to its first node (a leaf's `a`,
/// a triangle position, is absolute), and its shape.
#[derive(Default)]
struct Subtree {
    nodes: Vec<BvhNode>,
    leaf_count: usize,
    /// The deepest leaf's depth in the whole tree.
    max_depth: usize,
    max_leaf_triangles: usize,
}

impl Subtree {
    /// An empty subtree with room for the nodes over `triangles` (at most 2 n - 1: only
    /// the pages written are backed by memory).
    fn with_capacity(triangles: usize) -> Subtree {
        Subtree {
            nodes: Vec::with_capacity(2 * triangles),
            ..Subtree::default()
        }
    }

    /// A node over `bounds` whose children are `left` and `right`.
    fn join(bounds: &Bounds, left: Subtree, right: Subtree) -> Subtree {
        let mut nodes = Vec::with_capacity(1 + left.nodes.len() + right.nodes.len());
        nodes.push(BvhNode::default());
        append(&mut nodes, &left.nodes);
        append(&mut nodes, &right.nodes);
        nodes[0] = node(bounds, nodes.len() as u32, 0);
        Subtree {
            nodes,
            leaf_count: left.leaf_count + right.leaf_count,
            max_depth: left.max_depth.max(right.max_depth),
            max_leaf_triangles: left.max_leaf_triangles.max(right.max_leaf_triangles),
        }
    }
}

/// Appends a subtree's nodes, moving its miss links to where it now starts.
fn append(nodes: &mut Vec<BvhNode>, subtree: &[BvhNode]) {
    let offset = nodes.len() as u32;
    nodes.extend(subtree.iter().map(|n| {
        let mut n = *n;
        if n.count == 0 {
            n.a += offset;
        }
        n
    }));
}

/// The subtree over `items` (the triangles at BVH positions `first..`) at `depth`.
fn subtree(items: &mut [Item], first: usize, depth: usize) -> Subtree {
    let (bounds, centroids) = bounds_of(items);
    let mut tree = Subtree::with_capacity(items.len());
    build(&mut tree, items, &bounds, &centroids, first, depth);
    tree
}

/// The box around the triangles of `items`, and the box around their centroids.
fn bounds_of(items: &[Item]) -> (Bounds, Bounds) {
    let mut bounds = Bounds::EMPTY;
    let mut centroids = Bounds::EMPTY;
    for t in items {
        bounds.grow(t.lo, t.hi);
        centroids.grow(t.centroid, t.centroid);
    }
    (bounds, centroids)
}

/// Emits the subtree over `items` into `tree` depth-first (miss links relative to its start).
fn build(
    tree: &mut Subtree,
    items: &mut [Item],
    bounds: &Bounds,
    centroids: &Bounds,
    first: usize,
    depth: usize,
) {
    let index = tree.nodes.len();
    tree.nodes.push(BvhNode::default());
    tree.max_depth = tree.max_depth.max(depth);
    let Some(split) = partition(items, bounds, centroids, depth) else {
        tree.nodes[index] = node(bounds, first as u32, items.len() as u32);
        tree.leaf_count += 1;
        tree.max_leaf_triangles = tree.max_leaf_triangles.max(items.len());
        return;
    };
    let mid = split.mid;
    let (left, right) = items.split_at_mut(mid);
    if left.len().min(right.len()) >= PARALLEL_MIN_TRIANGLES {
        let (l, r) = rayon::join(
            || {
                let mut t = Subtree::with_capacity(left.len());
                build(&mut t, left, &split.left.0, &split.left.1, first, depth + 1);
                t
            },
            || {
                let mut t = Subtree::with_capacity(right.len());
                build(
                    &mut t,
                    right,
                    &split.right.0,
                    &split.right.1,
                    first + mid,
                    depth + 1,
                );
                t
            },
        );
        for child in [l, r] {
            append(&mut tree.nodes, &child.nodes);
            tree.leaf_count += child.leaf_count;
            tree.max_depth = tree.max_depth.max(child.max_depth);
            tree.max_leaf_triangles = tree.max_leaf_triangles.max(child.max_leaf_triangles);
        }
        tree.nodes[index] = node(bounds, tree.nodes.len() as u32, 0);
        return;
    }
    build(tree, left, &split.left.0, &split.left.1, first, depth + 1);
    build(
        tree,
        right,
        &split.right.0,
        &split.right.1,
        first + mid,
        depth + 1,
    );
    // The miss link: the node after this whole subtree.
    tree.nodes[index] = node(bounds, tree.nodes.len() as u32, 0);
}

/// A node's split: its first `mid` items (after `partition` reordered them) form the left
/// child; each side's box and centroid box.
struct Partition {
    mid: usize,
    left: (Bounds, Bounds),
    right: (Bounds, Bounds),
}

/// Where to split a node: triangles whose centroid falls in a bin `<= bin` along `axis` go
/// left.
#[derive(Clone, Copy)]
struct Split {
    axis: usize,
    bin: usize,
    cost: f32,
}

/// One SAH bin: the box of its triangles and how many there are.
#[derive(Clone, Copy)]
struct Bin {
    bounds: Bounds,
    count: usize,
}

impl Bin {
    const EMPTY: Bin = Bin {
        bounds: Bounds::EMPTY,
        count: 0,
    };
}

/// Maps centroids to bins along each axis: `(c - lo) * scale`, the scale computed once per
/// node (the same product as dividing by the extent in each call, so the same bins).
struct Binning {
    lo: Vec3,
    scale: Vec3,
    /// Axes along which the centroids have an extent (the others have no split).
    axes: [bool; 3],
}

impl Binning {
    fn new(centroids: &Bounds) -> Binning {
        let extent = centroids.hi - centroids.lo;
        Binning {
            lo: centroids.lo,
            scale: Vec3::splat(BINS as f32) / extent,
            axes: [0, 1, 2].map(|a| !extent[a].is_nan() && extent[a] > 0.0),
        }
    }

    fn bin(&self, centroid: Vec3, axis: usize) -> usize {
        let scaled = (centroid[axis] - self.lo[axis]) * self.scale[axis];
        // `as` saturates (NaN → 0), so this is always a valid bin.
        (scaled as usize).min(BINS - 1)
    }
}

/// Reorders `items` into the node's two children and says where they split, or None if the
/// node should be a leaf.
fn partition(
    items: &mut [Item],
    bounds: &Bounds,
    centroids: &Bounds,
    depth: usize,
) -> Option<Partition> {
    let count = items.len();
    if count <= 1 || (depth >= MAX_DEPTH && count <= MAX_ENCODED_LEAF) {
        return None;
    }
    if depth < MAX_DEPTH {
        let binning = Binning::new(centroids);
        let chosen = if count <= SMALL_NODE {
            best_split_small(items, &binning)
        } else {
            best_split_binned(items, &binning)
        };
        if let Some((split, left_bounds, right_bounds)) = chosen {
            // SAH, in units of one triangle test: a leaf tests all `count` triangles; a split
            // pays a traversal step plus each side's triangles weighted by the chance of
            // entering it. (A zero or infinite area gives a non-finite ratio: then split.)
            let split_cost = TRAVERSAL_COST + split.cost / bounds.half_area();
            if count <= MAX_LEAF_TRIANGLES && split_cost >= count as f32 {
                return None;
            }
            // One pass moves the left side's items to the front and boxes both sides'
            // centroids; the sides' boxes are their bins'.
            let (mut mid, mut left_c, mut right_c) = (0, Bounds::EMPTY, Bounds::EMPTY);
            for i in 0..count {
                let c = items[i].centroid;
                if binning.bin(c, split.axis) <= split.bin {
                    left_c.grow(c, c);
                    items.swap(mid, i);
                    mid += 1;
                } else {
                    right_c.grow(c, c);
                }
            }
            if mid > 0 && mid < count {
                return Some(Partition {
                    mid,
                    left: (left_bounds, left_c),
                    right: (right_bounds, right_c),
                });
            }
        }
        if count <= MAX_LEAF_TRIANGLES {
            return None;
        }
    }
    // Past the depth limit, or all centroids (nearly) coincide: no plane separates them, and
    // any halving is as good as another. Halving by count bounds the depth by log2(count).
    let mid = count / 2;
    Some(Partition {
        mid,
        left: bounds_of(&items[..mid]),
        right: bounds_of(&items[mid..]),
    })
}

/// Nodes of at most this many triangles find their binned split by sorting the triangles by
/// bin ([`best_split_small`]) rather than sweeping all 3 x [`BINS`] bins, whose fixed cost
/// made up most of the build (a million nodes of a few triangles each in a 1M-triangle mesh).
const SMALL_NODE: usize = 32;

/// The binned split ([`best_split`]) with each side's box (the box of its bins).
fn best_split_binned(items: &[Item], binning: &Binning) -> Option<(Split, Bounds, Bounds)> {
    let bins = bin(items, binning);
    let split = best_split(&bins, binning)?;
    let side = |range: std::ops::Range<usize>| {
        let mut b = Bounds::EMPTY;
        for bin in &bins[split.axis][range] {
            b.grow(bin.bounds.lo, bin.bounds.hi);
        }
        b
    };
    Some((split, side(0..split.bin + 1), side(split.bin + 1..BINS)))
}

/// The same split as [`best_split_binned`] for at most [`SMALL_NODE`] triangles: along each
/// axis the triangles sorted by bin, each boundary between two occupied bins a candidate. The
/// bins between are empty, so the sweep over all bins meets each candidate's cost (the same
/// boxes, counts and arithmetic) first at the candidate's own bin, then repeats it; the first
/// of equal costs wins in both. So the tree is the same, bit for bit.
fn best_split_small(items: &[Item], binning: &Binning) -> Option<(Split, Bounds, Bounds)> {
    let n = items.len();
    let mut best: Option<(Split, Bounds, Bounds)> = None;
    let mut keys = [(0u8, 0u8); SMALL_NODE];
    let mut right = [Bounds::EMPTY; SMALL_NODE + 1];
    for axis in 0..3 {
        if !binning.axes[axis] {
            continue;
        }
        let keys = &mut keys[..n];
        for (i, t) in items.iter().enumerate() {
            keys[i] = (binning.bin(t.centroid, axis) as u8, i as u8);
        }
        keys.sort_unstable();
        // right[i]: the box of the triangles keys[i..].
        for i in (0..n).rev() {
            let t = &items[keys[i].1 as usize];
            right[i] = right[i + 1];
            right[i].grow(t.lo, t.hi);
        }
        let mut acc = Bounds::EMPTY;
        for i in 0..n - 1 {
            let t = &items[keys[i].1 as usize];
            acc.grow(t.lo, t.hi);
            if keys[i].0 == keys[i + 1].0 {
                continue;
            }
            let right_cost = right[i + 1].half_area() * (n - i - 1) as f32;
            let cost = acc.half_area() * (i + 1) as f32 + right_cost;
            if cost.is_nan() {
                continue;
            }
            if best.is_none_or(|(s, _, _)| cost < s.cost) {
                let bin = keys[i].0 as usize;
                best = Some((Split { axis, bin, cost }, acc, right[i + 1]));
            }
        }
    }
    best
}

/// Nodes over this many triangles bin them in parallel chunks of this size, merged after (the
/// same bins: boxes merge by min and max, counts by sum). The top nodes' binning otherwise
/// runs on one thread while the other waits.
const PARALLEL_BIN_CHUNK: usize = 64 * 1024;

/// The triangles of `items` binned along each axis with extent.
fn bin(items: &[Item], binning: &Binning) -> [[Bin; BINS]; 3] {
    if items.len() <= PARALLEL_BIN_CHUNK {
        return bin_serial(items, binning);
    }
    items
        .par_chunks(PARALLEL_BIN_CHUNK)
        .map(|chunk| bin_serial(chunk, binning))
        .reduce(
            || [[Bin::EMPTY; BINS]; 3],
            |mut a, b| {
                for (a, b) in a.iter_mut().flatten().zip(b.iter().flatten()) {
                    a.bounds.grow(b.bounds.lo, b.bounds.hi);
                    a.count += b.count;
                }
                a
            },
        )
}

/// [`bin`] on one thread, in one pass over the triangles.
fn bin_serial(items: &[Item], binning: &Binning) -> [[Bin; BINS]; 3] {
    let mut bins = [[Bin::EMPTY; BINS]; 3];
    for t in items {
        for (axis, bins) in bins.iter_mut().enumerate() {
            if binning.axes[axis] {
                let b = &mut bins[binning.bin(t.centroid, axis)];
                b.bounds.grow(t.lo, t.hi);
                b.count += 1;
            }
        }
    }
    bins
}

/// The cheapest binned SAH split over the three axes (sum of child area × count), or None
/// when the centroids have no extent on any axis.
fn best_split(bins: &[[Bin; BINS]; 3], binning: &Binning) -> Option<Split> {
    let mut best: Option<Split> = None;
    for (axis, bins) in bins.iter().enumerate() {
        if !binning.axes[axis] {
            continue;
        }
        // Sweep from the right, storing each suffix's cost and count, then from the left.
        let mut right = [(0.0f32, 0usize); BINS];
        let mut acc = Bounds::EMPTY;
        let mut n = 0;
        for b in (1..BINS).rev() {
            acc.grow(bins[b].bounds.lo, bins[b].bounds.hi);
            n += bins[b].count;
            right[b] = (acc.half_area() * n as f32, n);
        }
        let mut acc = Bounds::EMPTY;
        let mut n = 0;
        for b in 0..BINS - 1 {
            acc.grow(bins[b].bounds.lo, bins[b].bounds.hi);
            n += bins[b].count;
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
fn partition_in_place<T>(items: &mut [T], left: impl Fn(&T) -> bool) -> usize {
    let mut mid = 0;
    for i in 0..items.len() {
        if left(&items[i]) {
            items.swap(mid, i);
            mid += 1;
        }
    }
    mid
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Uniform numbers in [0, 1) from a fixed seed (an LCG: the tests need no quality).
    struct Lcg(u64);

    impl Lcg {
        fn next(&mut self) -> f32 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    fn random_triangles(rng: &mut Lcg, n: usize, spread: f32) -> Vec<[Vec3; 3]> {
        (0..n)
            .map(|_| {
                // Centroids on a coarse lattice sometimes, so that several share a bin.
                let snap = |x: f32| {
                    if spread < 1.0 {
                        (x * 4.0).floor() / 4.0
                    } else {
                        x
                    }
                };
                let c = Vec3::new(snap(rng.next()), snap(rng.next()), snap(rng.next())) * spread;
                let mut corner = || Vec3::new(rng.next(), rng.next(), rng.next()) * 0.05;
                [c + corner(), c + corner(), c + corner()]
            })
            .collect()
    }

    fn items_of(triangles: &[[Vec3; 3]]) -> Vec<Item> {
        triangles
            .iter()
            .enumerate()
            .map(|(i, v)| {
                let lo = v[0].min(v[1]).min(v[2]);
                let hi = v[0].max(v[1]).max(v[2]);
                Item {
                    lo,
                    hi,
                    centroid: (lo + hi) * 0.5,
                    index: i as u32,
                }
            })
            .collect()
    }

    /// The sorted search for small nodes must choose what the sweep over every bin chooses, or
    /// the tree (and every image) would change with the node size where it takes over.
    #[test]
    fn the_small_node_split_is_the_binned_split() {
        let mut rng = Lcg(7);
        for case in 0..2000 {
            let n = 2 + case % (SMALL_NODE - 1);
            let spread = [0.5, 1.0, 30.0][case % 3];
            let items = items_of(&random_triangles(&mut rng, n, spread));
            let (_, centroids) = bounds_of(&items);
            let binning = Binning::new(&centroids);
            let key = |c: Option<(Split, Bounds, Bounds)>| {
                c.map(|(s, l, r)| (s.axis, s.bin, s.cost.to_bits(), l.lo, l.hi, r.lo, r.hi))
            };
            assert_eq!(
                key(best_split_small(&items, &binning)),
                key(best_split_binned(&items, &binning)),
                "case {case}: {n} triangles"
            );
        }
    }

    /// A big node's bins, merged from parallel chunks, are the one pass's bins exactly: the
    /// tree must not depend on where the parallel binning takes over.
    #[test]
    fn parallel_binning_equals_the_serial_pass() {
        let mut rng = Lcg(13);
        let items = items_of(&random_triangles(
            &mut rng,
            3 * PARALLEL_BIN_CHUNK + 17,
            20.0,
        ));
        let (_, centroids) = bounds_of(&items);
        let binning = Binning::new(&centroids);
        let key = |bins: [[Bin; BINS]; 3]| {
            bins.iter()
                .flatten()
                .map(|b| (b.count, b.bounds.lo.to_array(), b.bounds.hi.to_array()))
                .map(|(c, lo, hi)| (c, lo.map(f32::to_bits), hi.map(f32::to_bits)))
                .collect::<Vec<_>>()
        };
        assert_eq!(
            key(bin(&items, &binning)),
            key(bin_serial(&items, &binning))
        );
    }

    /// Built on one thread or on several, the BVH is the same: rayon only changes who builds
    /// which subtree, never a split.
    #[test]
    fn the_parallel_build_equals_the_one_thread_build() {
        let mut rng = Lcg(11);
        let triangles = random_triangles(&mut rng, 8 * PARALLEL_MIN_TRIANGLES, 10.0);
        let occluder: Vec<bool> = (0..triangles.len()).map(|i| i % 3 != 0).collect();
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| Bvh::build_with_occluders(&triangles, &occluder));
        let many = rayon::ThreadPoolBuilder::new()
            .num_threads(4)
            .build()
            .unwrap()
            .install(|| Bvh::build_with_occluders(&triangles, &occluder));
        assert!(one.stats.node_count > 1000);
        assert_eq!(one.order, many.order);
        assert_eq!(one.occluder_root, many.occluder_root);
        assert!(one.nodes == many.nodes, "the node lists differ");
        assert_eq!(
            (one.stats.leaf_count, one.stats.max_depth),
            (many.stats.leaf_count, many.stats.max_depth)
        );
    }
}
