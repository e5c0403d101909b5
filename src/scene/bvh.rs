//! The threaded BVH (docs/design.md §5): a binned SAH build on the CPU, flattened depth-first so that a
//! node's first child is the next node and only the miss link (`skip`) is stored.

use super::bvh_grid::{BvhGrid, MAX_ENCODED_LEAF};
use super::gpu_layout::BvhNode;
use glam::{Vec3, Vec3A, Vec4};
use rayon::prelude::*;
use std::time::{Duration, Instant};

/// A node with more triangles than this is always split (unless the depth limit is reached).
pub const MAX_LEAF_TRIANGLES: usize = 4;
/// Beyond this depth every node that fits a leaf ([`MAX_ENCODED_LEAF`] triangles) is one, and
/// larger ones are halved, so the build terminates on any input.
pub const MAX_DEPTH: usize = 64;
/// SAH bins per axis.
const BINS: usize = 16;
const LAST_BIN: f32 = (BINS - 1) as f32;
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

/// What the build needs of one triangle: its box and its input index, in 32 bytes. The build
/// partitions these records themselves (not indices into them), so each pass over a node reads
/// memory in order. Boxes are SIMD vectors: growing one is two instructions rather than six,
/// and the build is mostly growing boxes. The index rides in the fourth lane of the lower
/// corner (a 48-byte record with a field of its own cost a third more memory traffic and page
/// faults); box arithmetic ignores that lane. The arithmetic is the same lane by lane, so the
/// tree is the same as with scalar vectors.
#[derive(Clone, Copy)]
struct Item {
    lo: Vec4,
    hi: Vec4,
}

impl Item {
    /// The index's bits flipped so that the lane holds a normal float (exponent ≥ 128) for
    /// indices below 2^30: box arithmetic also runs on it, and subnormals can be slow.
    const INDEX_MARK: u32 = 1 << 30;

    fn new(lo: Vec3A, hi: Vec3A, index: u32) -> Item {
        Item {
            lo: lo.extend(f32::from_bits(index ^ Item::INDEX_MARK)),
            hi: hi.extend(0.0),
        }
    }

    fn lo(&self) -> Vec3A {
        Vec3A::from_vec4(self.lo)
    }

    fn hi(&self) -> Vec3A {
        Vec3A::from_vec4(self.hi)
    }

    fn index(&self) -> u32 {
        self.lo.w.to_bits() ^ Item::INDEX_MARK
    }

    /// The box's centre, computed where it is used: two instructions, cheaper than reading 16
    /// more bytes per triangle in every pass.
    fn centroid(&self) -> Vec3A {
        (self.lo() + self.hi()) * 0.5
    }
}

#[derive(Clone, Copy)]
struct Bounds {
    lo: Vec3A,
    hi: Vec3A,
}

impl Bounds {
    const EMPTY: Bounds = Bounds {
        lo: Vec3A::INFINITY,
        hi: Vec3A::NEG_INFINITY,
    };

    fn grow(&mut self, lo: Vec3A, hi: Vec3A) {
        self.lo = self.lo.min(lo);
        self.hi = self.hi.max(hi);
    }

    /// Half the surface area (the factor 2 cancels in SAH ratios); 0 when empty.
    fn half_area(&self) -> f32 {
        let d = (self.hi - self.lo).max(Vec3A::ZERO);
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
        // Each triangle's record in parallel (exact: no sums); a degenerate one gets the empty
        // box, which no real triangle has (its corners are ordered), and is taken out after.
        let mut items: Vec<Item> = triangles
            .par_iter()
            .enumerate()
            .map(|(i, v)| {
                let (lo, hi) = if is_degenerate(v) {
                    (Bounds::EMPTY.lo, Bounds::EMPTY.hi)
                } else {
                    let v = v.map(Vec3A::from);
                    (v[0].min(v[1]).min(v[2]), v[0].max(v[1]).max(v[2]))
                };
                Item::new(lo, hi, i as u32)
            })
            .collect();
        let is_empty = |t: &Item| t.lo.x > t.hi.x;
        let degenerate: Vec<u32> = items
            .par_iter()
            .filter(|t| is_empty(t))
            .map(|t| t.index())
            .collect();
        if !degenerate.is_empty() {
            items.retain(|t| !is_empty(t));
        }
        let others = partition_in_place(&mut items, |t| !occluder[t.index() as usize]);

        let (tree, occluder_root) = if others == 0 || others == items.len() {
            let tree = if items.is_empty() {
                Subtree::default()
            } else {
                subtree(&mut items, 0, 0)
            };
            let root = if others == 0 { 0 } else { tree.node_count };
            (tree, root as u32)
        } else {
            let bounds = bounds_of(&items).0;
            let (left, right) = items.split_at_mut(others);
            let (left, right) = rayon::join(|| subtree(left, 0, 1), || subtree(right, others, 1));
            let mut tree = Subtree::with_capacity(0);
            let root = tree.push();
            tree.adopt(left);
            let occluder_root = tree.node_count as u32;
            tree.adopt(right);
            tree.set(root, node(&bounds, tree.link(root), 0));
            (tree, occluder_root)
        };
        let mut order: Vec<u32> = items.par_iter().map(|t| t.index()).collect();
        order.extend(degenerate);

        let (leaf_count, max_depth, max_leaf_triangles) =
            (tree.leaf_count, tree.max_depth, tree.max_leaf_triangles);
        // Snapping grows every box, so children stay inside their parents.
        let grid = tree.root().map_or_else(BvhGrid::default, |root| {
            BvhGrid::covering(root.lo.into(), root.hi.into())
        });
        let nodes = tree.into_nodes(|node| {
            let (lo, hi) = grid.snap(node.lo.into(), node.hi.into());
            (node.lo, node.hi) = (lo.into(), hi.into());
        });
        let stats = BvhStats {
            build_time: start.elapsed(),
            node_count: nodes.len(),
            leaf_count,
            max_depth,
            max_leaf_triangles,
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

/// Subtrees over at least this many triangles build their two children in parallel (rayon);
/// smaller ones build on the thread that reached them.
const PARALLEL_MIN_TRIANGLES: usize = 16 * 1024;

/// A subtree's nodes, depth-first, as segments that concatenate to the node list, and its
/// shape. A miss link is relative to the first node of its node's segment (it may point past
/// the segment's end); a leaf's `a`, a triangle position, is absolute. Children built in
/// parallel hand over their segments rather than nodes, so a node is copied at most once, into
/// the final list (copying the children's nodes into the parent's list at each parallel level
/// cost a tenth of the build).
#[derive(Default)]
struct Subtree {
    segments: Vec<Vec<BvhNode>>,
    node_count: usize,
    leaf_count: usize,
    /// The deepest leaf's depth in the whole tree.
    max_depth: usize,
    max_leaf_triangles: usize,
}

/// Where a node is: its segment, its place in it, and its place in the subtree.
#[derive(Clone, Copy)]
struct At {
    segment: usize,
    place: usize,
    node: usize,
}

impl Subtree {
    /// An empty subtree with room for the nodes over `triangles` (at most 2 n - 1: only
    /// the pages written are backed by memory).
    fn with_capacity(triangles: usize) -> Subtree {
        Subtree {
            segments: vec![Vec::with_capacity(2 * triangles)],
            ..Subtree::default()
        }
    }

    /// Appends a node to be set later.
    fn push(&mut self) -> At {
        let segment = self.segments.len() - 1;
        let nodes = &mut self.segments[segment];
        nodes.push(BvhNode::default());
        self.node_count += 1;
        At {
            segment,
            place: nodes.len() - 1,
            node: self.node_count - 1,
        }
    }

    fn set(&mut self, at: At, node: BvhNode) {
        self.segments[at.segment][at.place] = node;
    }

    /// The miss link of the node `at`, whose subtree ends here: the next node, relative to its
    /// segment's start.
    fn link(&self, at: At) -> u32 {
        (at.place + self.node_count - at.node) as u32
    }

    /// Appends `child`'s nodes (the segments, not a copy), and opens a new segment for the
    /// nodes after them.
    fn adopt(&mut self, child: Subtree) {
        self.segments.extend(child.segments);
        self.segments.push(Vec::new());
        self.node_count += child.node_count;
        self.leaf_count += child.leaf_count;
        self.max_depth = self.max_depth.max(child.max_depth);
        self.max_leaf_triangles = self.max_leaf_triangles.max(child.max_leaf_triangles);
    }

    /// The root node, once set.
    fn root(&self) -> Option<&BvhNode> {
        self.segments.first().and_then(|s| s.first())
    }

    /// The node list, miss links made absolute and `finish` applied to each node, in parallel:
    /// the first segment, which has room for every node of the tree (it is the root's), with
    /// the others copied after it. A fresh list would cost a page fault per 4 KB written (as
    /// much as the copy on this machine); built on one thread, the tree is one segment and
    /// nothing is copied.
    fn into_nodes(self, finish: impl Fn(&mut BvhNode) + Sync) -> Vec<BvhNode> {
        let mut segments = self.segments.into_iter();
        let mut nodes = segments.next().unwrap_or_default();
        nodes.par_iter_mut().for_each(&finish);
        let first = nodes.len();
        nodes.reserve(self.node_count - first);
        // Each later segment's destination: disjoint slices of the spare capacity, in order.
        let mut spare = &mut nodes.spare_capacity_mut()[..self.node_count - first];
        let mut copies = Vec::new();
        let mut offset = first;
        for segment in segments {
            let (to, rest) = spare.split_at_mut(segment.len());
            let at = offset as u32;
            offset += segment.len();
            copies.push((segment, to, at));
            spare = rest;
        }
        assert!(spare.is_empty() && offset == self.node_count);
        const CHUNK: usize = 4096;
        copies.into_par_iter().for_each(|(segment, to, offset)| {
            segment
                .par_chunks(CHUNK)
                .zip(to.par_chunks_mut(CHUNK))
                .for_each(|(from, to)| {
                    for (n, slot) in from.iter().zip(to) {
                        let mut n = *n;
                        if n.count == 0 {
                            n.a += offset;
                        }
                        finish(&mut n);
                        slot.write(n);
                    }
                });
        });
        // SAFETY: the segments' lengths sum to `node_count - first` (asserted above), and each
        // slot of those was written once, by the copy of the segment it was split off for.
        unsafe { nodes.set_len(self.node_count) };
        nodes
    }
}

/// The subtree over `items` (the triangles at BVH positions `first..`) at `depth`.
fn subtree(items: &mut [Item], first: usize, depth: usize) -> Subtree {
    let (bounds, centroids) = bounds_of(items);
    let mut tree = Subtree::with_capacity(items.len());
    build(
        &mut tree,
        &mut Scratch::new(),
        items,
        &bounds,
        &centroids,
        first,
        depth,
    );
    tree
}

/// The box around the triangles of `items`, and the box around their centroids.
fn bounds_of(items: &[Item]) -> (Bounds, Bounds) {
    let mut bounds = Bounds::EMPTY;
    let mut centroids = Bounds::EMPTY;
    for t in items {
        bounds.grow(t.lo(), t.hi());
        let c = t.centroid();
        centroids.grow(c, c);
    }
    (bounds, centroids)
}

/// Emits the subtree over `items` into `tree` depth-first.
fn build(
    tree: &mut Subtree,
    scratch: &mut Scratch,
    items: &mut [Item],
    bounds: &Bounds,
    centroids: &Bounds,
    first: usize,
    depth: usize,
) {
    let at = tree.push();
    tree.max_depth = tree.max_depth.max(depth);
    let Some(split) = partition(scratch, items, bounds, centroids, depth) else {
        tree.set(at, node(bounds, first as u32, items.len() as u32));
        tree.leaf_count += 1;
        tree.max_leaf_triangles = tree.max_leaf_triangles.max(items.len());
        return;
    };
    let mid = split.mid;
    let (left, right) = items.split_at_mut(mid);
    let (l, r) = (&split.left, &split.right);
    if left.len().min(right.len()) >= PARALLEL_MIN_TRIANGLES {
        let child = |items: &mut [Item], (bounds, centroids): &(Bounds, Bounds), first| {
            let mut t = Subtree::with_capacity(items.len());
            build(
                &mut t,
                &mut Scratch::new(),
                items,
                bounds,
                centroids,
                first,
                depth + 1,
            );
            t
        };
        let (l, r) = rayon::join(|| child(left, l, first), || child(right, r, first + mid));
        tree.adopt(l);
        tree.adopt(r);
    } else {
        build(tree, scratch, left, &l.0, &l.1, first, depth + 1);
        build(tree, scratch, right, &r.0, &r.1, first + mid, depth + 1);
    }
    // The miss link: the node after this whole subtree.
    tree.set(at, node(bounds, tree.link(at), 0));
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

/// A node's triangles binned along each axis: per bin the box of its triangles and how many
/// there are, and which bins hold any (bit `b` of `occupied[axis]`), so that the sweep for the
/// best split visits only those: most nodes hold a few triangles, and a sweep over all
/// 3 x [`BINS`] bins would cost more than binning them.
#[derive(Clone, Copy)]
struct Bins {
    bounds: [[Bounds; BINS]; 3],
    counts: [[u32; BINS]; 3],
    occupied: [u16; 3],
}

impl Bins {
    const EMPTY: Bins = Bins {
        bounds: [[Bounds::EMPTY; BINS]; 3],
        counts: [[0; BINS]; 3],
        occupied: [0; 3],
    };

    /// Empties the occupied bins (the others are empty already).
    fn clear(&mut self) {
        for axis in 0..3 {
            for b in occupied_bins(self.occupied[axis]) {
                self.bounds[axis][b] = Bounds::EMPTY;
                self.counts[axis][b] = 0;
            }
            self.occupied[axis] = 0;
        }
    }

    /// Adds a triangle to its bin along each axis with extent.
    fn add(&mut self, t: &Item, binning: &Binning) {
        let index = binning.bins(t.centroid());
        for (axis, &b) in index.iter().enumerate() {
            if binning.axes[axis] {
                self.bounds[axis][b].grow(t.lo(), t.hi());
                self.counts[axis][b] += 1;
                self.occupied[axis] |= 1 << b;
            }
        }
    }

    /// Moves `other`'s occupied bins into these (boxes merge by min and max, counts by sum:
    /// exact), leaving it empty.
    fn drain(&mut self, other: &mut Bins) {
        for axis in 0..3 {
            for b in occupied_bins(other.occupied[axis]) {
                let o = other.bounds[axis][b];
                self.bounds[axis][b].grow(o.lo, o.hi);
                self.counts[axis][b] += other.counts[axis][b];
            }
            self.occupied[axis] |= other.occupied[axis];
        }
        other.clear();
    }
}

/// A thread's working memory for the split search, empty between nodes: a node's binning
/// touches only the bins its triangles fall in and empties just those after, so a node of a
/// few triangles costs a few bins, not the 2 KB that a fresh set of bins and sweep would clear
/// (most nodes are small: clearing was a fifth of the build).
struct Scratch {
    bins: Bins,
    /// The second set of bins of large nodes ([`bin_into`]).
    spare: Bins,
    /// The sweep's suffix sums; [`best_split`] writes each before reading it.
    right: [(Bounds, f32); BINS],
}

impl Scratch {
    fn new() -> Scratch {
        Scratch {
            bins: Bins::EMPTY,
            spare: Bins::EMPTY,
            right: [(Bounds::EMPTY, 0.0); BINS],
        }
    }
}

/// The occupied bins of a mask, lowest first.
fn occupied_bins(mask: u16) -> OccupiedBins {
    OccupiedBins(mask)
}

/// The set bits of a bin mask, found by counting zeros rather than testing all 16.
struct OccupiedBins(u16);

impl Iterator for OccupiedBins {
    type Item = usize;

    fn next(&mut self) -> Option<usize> {
        let b = self.0.trailing_zeros();
        if b == u16::BITS {
            return None;
        }
        self.0 &= self.0 - 1;
        Some(b as usize)
    }
}

impl DoubleEndedIterator for OccupiedBins {
    fn next_back(&mut self) -> Option<usize> {
        let zeros = self.0.leading_zeros();
        if zeros == u16::BITS {
            return None;
        }
        let b = u16::BITS - 1 - zeros;
        self.0 &= !(1 << b);
        Some(b as usize)
    }
}

/// Maps centroids to bins along each axis: `(c - lo) * scale`, the scale computed once per
/// node (the same product as dividing by the extent in each call, so the same bins).
struct Binning {
    lo: Vec3A,
    scale: Vec3A,
    /// Axes along which the centroids have an extent (the others have no split).
    axes: [bool; 3],
}

impl Binning {
    fn new(centroids: &Bounds) -> Binning {
        let extent = centroids.hi - centroids.lo;
        Binning {
            lo: centroids.lo,
            scale: Vec3A::splat(BINS as f32) / extent,
            axes: [0, 1, 2].map(|a| !extent[a].is_nan() && extent[a] > 0.0),
        }
    }

    /// Each centroid's bin along the three axes: `(c - lo) * scale` clamped to the bins, NaN
    /// (from an infinite centroid times a zero scale) to bin 0. A vector `max` treats NaN as
    /// the SIMD unit does (SSE returns the second operand, NEON NaN), so NaN is caught by a
    /// comparison instead, false for it everywhere. Clamped before the conversion, so the
    /// conversion needs no saturation of its own.
    fn bins(&self, centroid: Vec3A) -> [usize; 3] {
        let scaled = (centroid - self.lo) * self.scale;
        let positive = Vec3A::select(scaled.cmpge(Vec3A::ZERO), scaled, Vec3A::ZERO);
        let clamped = positive.min(Vec3A::splat(LAST_BIN));
        clamped.to_array().map(to_bin)
    }
}

/// Whether a centroid's bin along one axis is at most a given bin, without computing the bin
/// (see [`Binning::side_test`]).
struct SideTest {
    lo: Vec3A,
    scale: Vec3A,
    /// The bin after the last one on the left side, on every lane.
    first_right: Vec3A,
    axis_bit: u32,
}

impl SideTest {
    fn goes_left(&self, centroid: Vec3A) -> bool {
        let scaled = (centroid - self.lo) * self.scale;
        scaled.cmpge(self.first_right).bitmask() & self.axis_bit == 0
    }
}

impl Binning {
    /// The test `bin(centroid, axis) <= bin` for `bin` below the last: a bin coordinate (the
    /// same product as [`Binning::bins`]) truncates to at most `bin` exactly when it is below
    /// `bin + 1`, and NaN and negative ones, bin 0, fail the comparison too. One comparison of
    /// the three lanes replaces the clamp, the conversion and picking the axis's lane, which
    /// went through memory: the partition's loop is the build's second-hottest.
    fn side_test(&self, axis: usize, bin: usize) -> SideTest {
        debug_assert!(bin < BINS - 1);
        SideTest {
            lo: self.lo,
            scale: self.scale,
            first_right: Vec3A::splat((bin + 1) as f32),
            axis_bit: 1 << axis,
        }
    }
}

/// A clamped bin coordinate's bin. `as usize` would saturate (a dozen instructions per
/// conversion: tests for NaN, negative and large values), a fifth of the binning's time; the
/// value is known to be in range, so one truncating conversion does.
fn to_bin(clamped: f32) -> usize {
    debug_assert!((0.0..=LAST_BIN).contains(&clamped));
    // SAFETY: the callers map NaN and negative values to 0 and clamp to LAST_BIN, so the
    // value is finite and fits a u32.
    unsafe { clamped.to_int_unchecked::<u32>() as usize }
}

/// Reorders `items` into the node's two children and says where they split, or None if the
/// node should be a leaf.
fn partition(
    scratch: &mut Scratch,
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
        // A split pays a traversal step and a share (never negative) of each side's tests:
        // with no more triangles than that step costs, a leaf is cheaper and binning would
        // only confirm it. (A box with zero or infinite area gives non-finite ratios, which
        // split: left to the SAH below.)
        let area = bounds.half_area();
        if count <= MAX_LEAF_TRIANGLES
            && count as f32 <= TRAVERSAL_COST
            && area.is_finite()
            && area > 0.0
        {
            return None;
        }
        let binning = Binning::new(centroids);
        if let Some((split, left_bounds, right_bounds)) =
            best_split_binned(scratch, items, &binning)
        {
            // SAH, in units of one triangle test: a leaf tests all `count` triangles; a split
            // pays a traversal step plus each side's triangles weighted by the chance of
            // entering it. (A zero or infinite area gives a non-finite ratio: then split.)
            let split_cost = TRAVERSAL_COST + split.cost / area;
            if count <= MAX_LEAF_TRIANGLES && split_cost >= count as f32 {
                return None;
            }
            // One pass moves the left side's items to the front and boxes both sides'
            // centroids; the sides' boxes are their bins'.
            let (mut mid, mut left_c, mut right_c) = (0, Bounds::EMPTY, Bounds::EMPTY);
            let side = binning.side_test(split.axis, split.bin);
            for i in 0..count {
                let c = items[i].centroid();
                if side.goes_left(c) {
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

/// The cheapest binned SAH split of `items` (the sum of child area x count) with each side's
/// box (the box of its bins), or None when the centroids have no extent on any axis or no
/// candidate has a finite cost.
fn best_split_binned(
    scratch: &mut Scratch,
    items: &[Item],
    binning: &Binning,
) -> Option<(Split, Bounds, Bounds)> {
    if items.len() > PARALLEL_BIN_CHUNK {
        return best_split(&bin(items, binning), binning, &mut scratch.right);
    }
    bin_into(&mut scratch.bins, &mut scratch.spare, items, binning);
    let best = best_split(&scratch.bins, binning, &mut scratch.right);
    scratch.bins.clear();
    best
}

/// Nodes over this many triangles bin them in parallel chunks of this size, merged after (the
/// same bins: boxes merge by min and max, counts by sum). The top nodes' binning otherwise
/// runs on one thread while the other waits.
const PARALLEL_BIN_CHUNK: usize = 64 * 1024;

/// The triangles of `items` binned along each axis with extent.
fn bin(items: &[Item], binning: &Binning) -> Bins {
    items
        .par_chunks(PARALLEL_BIN_CHUNK)
        .map(|chunk| {
            let (mut bins, mut spare) = (Bins::EMPTY, Bins::EMPTY);
            bin_into(&mut bins, &mut spare, chunk, binning);
            bins
        })
        .reduce(
            || Bins::EMPTY,
            |mut a, mut b| {
                a.drain(&mut b);
                a
            },
        )
}

/// Adds the triangles of `items` to `bins`, on one thread, in one pass. `spare` is an empty set
/// of bins, and is left empty.
fn bin_into(bins: &mut Bins, spare: &mut Bins, items: &[Item], binning: &Binning) {
    if items.len() < TWO_BIN_SETS_MIN {
        for t in items {
            bins.add(t, binning);
        }
        return;
    }
    // Neighbouring triangles mostly fall in the same bins, so each update waits for the one
    // before it (a load of what was just stored); alternating between two sets of bins halves
    // those chains. Merging is exact, so the bins are the same.
    let mut pairs = items.chunks_exact(2);
    for pair in &mut pairs {
        bins.add(&pair[0], binning);
        spare.add(&pair[1], binning);
    }
    for t in pairs.remainder() {
        bins.add(t, binning);
    }
    bins.drain(spare);
}

/// Nodes over this many triangles bin them into two sets of bins (see [`bin_into`]); below
/// it merging would cost more than it saves. (Binning a 1M-triangle mesh: nodes of 257 to 64k
/// triangles 28 % faster, those of 17 to 256 11 %; measured per node size with the CPU's
/// cycle counter, docs/benchmark-history.md, 2026-12-06.)
const TWO_BIN_SETS_MIN: usize = 64;

/// The cheapest split over the three axes. Only boundaries between two occupied bins are
/// candidates: a split at an empty bin has the same two sides as the split at the occupied
/// bin before it, so a sweep over every bin would meet each cost first there and then repeat
/// it (the first of equal costs wins). The tree is the one that sweep would build, bit for bit
/// (tested).
fn best_split(
    bins: &Bins,
    binning: &Binning,
    right: &mut [(Bounds, f32); BINS],
) -> Option<(Split, Bounds, Bounds)> {
    let mut best: Option<(Split, Bounds, Bounds)> = None;
    for axis in 0..3 {
        if !binning.axes[axis] {
            continue;
        }
        let (boxes, counts, mask) = (&bins.bounds[axis], &bins.counts[axis], bins.occupied[axis]);
        // right[b]: the box, area x count of the occupied bins from b on (at occupied b only).
        let mut acc = Bounds::EMPTY;
        let mut n = 0u32;
        for b in occupied_bins(mask).rev() {
            acc.grow(boxes[b].lo, boxes[b].hi);
            n += counts[b];
            right[b] = (acc, acc.half_area() * n as f32);
        }
        let mut acc = Bounds::EMPTY;
        let mut n = 0u32;
        let mut bins = occupied_bins(mask).peekable();
        while let Some(b) = bins.next() {
            let Some(&next) = bins.peek() else { break };
            acc.grow(boxes[b].lo, boxes[b].hi);
            n += counts[b];
            let (right_bounds, right_cost) = right[next];
            let cost = acc.half_area() * n as f32 + right_cost;
            // NaN only comes from overflowing coordinates (inf * 0); such a cost says nothing.
            if cost.is_nan() {
                continue;
            }
            if best.is_none_or(|(s, _, _)| cost < s.cost) {
                best = Some((Split { axis, bin: b, cost }, acc, right_bounds));
            }
        }
    }
    best
}

/// A node whose box is `bounds`, grown by [`BOX_PAD`].
fn node(bounds: &Bounds, a: u32, count: u32) -> BvhNode {
    let magnitude = bounds.lo.abs().max(bounds.hi.abs()).max_element();
    let pad = Vec3A::splat(magnitude * BOX_PAD);
    BvhNode {
        lo: (bounds.lo - pad).into(),
        a,
        hi: (bounds.hi + pad).into(),
        count,
    }
}

/// The tree's SAH cost in units of one triangle test: over every node, the chance that a ray
/// through the root's box enters its box (area over the root's area) times the node's cost
/// (a box test at [`TRAVERSAL_COST`], and a leaf's triangle tests). The build minimises this
/// greedily, so it compares the quality of two builds of one mesh without tracing a ray.
pub fn sah_cost(bvh: &Bvh) -> f64 {
    let half_area = |n: &BvhNode| {
        let d = Vec3::from(n.hi) - Vec3::from(n.lo);
        f64::from(d.x) * f64::from(d.y)
            + f64::from(d.y) * f64::from(d.z)
            + f64::from(d.z) * f64::from(d.x)
    };
    let Some(root) = bvh.nodes.first() else {
        return 0.0;
    };
    let root = half_area(root);
    bvh.nodes
        .iter()
        .map(|n| half_area(n) / root * (f64::from(TRAVERSAL_COST) + f64::from(n.count)))
        .sum()
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
                let v = v.map(Vec3A::from);
                Item::new(v[0].min(v[1]).min(v[2]), v[0].max(v[1]).max(v[2]), i as u32)
            })
            .collect()
    }

    /// The split with every bin swept, as a textbook binned builder does: the reference the
    /// sweep over occupied bins must match.
    fn best_split_every_bin(bins: &Bins, binning: &Binning) -> Option<(Split, Bounds, Bounds)> {
        let mut best: Option<(Split, Bounds, Bounds)> = None;
        for axis in (0..3).filter(|&a| binning.axes[a]) {
            let side = |range: std::ops::Range<usize>| {
                let mut acc = Bounds::EMPTY;
                let mut n = 0;
                for b in range {
                    acc.grow(bins.bounds[axis][b].lo, bins.bounds[axis][b].hi);
                    n += bins.counts[axis][b];
                }
                (acc, n)
            };
            for b in 0..BINS - 1 {
                let ((left, nl), (right, nr)) = (side(0..b + 1), side(b + 1..BINS));
                if nl == 0 || nr == 0 {
                    continue;
                }
                let cost = left.half_area() * nl as f32 + right.half_area() * nr as f32;
                if !cost.is_nan() && best.is_none_or(|(s, _, _)| cost < s.cost) {
                    best = Some((Split { axis, bin: b, cost }, left, right));
                }
            }
        }
        best
    }

    /// Fresh bins holding `items`.
    fn bin_serial(items: &[Item], binning: &Binning) -> Bins {
        let (mut bins, mut spare) = (Bins::EMPTY, Bins::EMPTY);
        bin_into(&mut bins, &mut spare, items, binning);
        bins
    }

    /// Bin coordinates convert without saturation, so each must be a number in range first:
    /// The index kept in the box's fourth lane comes back whole for any u32 (the lane's bit
    /// pattern is only moved, never computed), and the box beside it is the one given.
    #[test]
    fn every_triangle_index_round_trips_through_the_item() {
        let (lo, hi) = (Vec3A::new(-1.0, 2.0, -3.0), Vec3A::new(4.0, 5.0, 6.0));
        for index in [
            0,
            1,
            (1 << 23) + 5,
            (1 << 30) - 1,
            1 << 30,
            0x7f80_0001,
            u32::MAX,
        ] {
            let item = Item::new(lo, hi, index);
            let moved = [item; 3][1];
            assert_eq!(moved.index(), index);
            assert_eq!((moved.lo(), moved.hi()), (lo, hi));
        }
    }

    /// NaN (an overflowing centroid times a zero scale), infinities and values beyond the grid
    /// go to the end bins, and the partition's side test agrees with the bins, at and
    /// beside every bin boundary too.
    #[test]
    fn nan_and_out_of_grid_centroids_bin_into_the_end_bins() {
        let binning = Binning {
            lo: Vec3A::new(0.0, -1.0, 2.0),
            scale: Vec3A::new(0.0, 4.0, f32::INFINITY),
            axes: [true; 3],
        };
        let cases = [
            (
                Vec3A::splat(f32::INFINITY),
                [0, LAST_BIN as usize, LAST_BIN as usize],
            ),
            (Vec3A::splat(f32::NEG_INFINITY), [0, 0, 0]),
            (Vec3A::new(f32::NAN, 1e30, -1e30), [0, LAST_BIN as usize, 0]),
            (Vec3A::new(5.0, 0.0, 2.0), [0, 4, 0]),
        ];
        for (centroid, expected) in cases {
            assert_eq!(binning.bins(centroid), expected, "{centroid}");
        }
        let mut centroids: Vec<Vec3A> = cases.iter().map(|c| c.0).collect();
        // Coordinates whose bin coordinate (y: (c + 1) * 4) is at, just below and just above
        // each boundary, and random ones.
        for b in 0..=BINS {
            let at = b as f32 / 4.0 - 1.0;
            for y in [at, at.next_down(), at.next_up()] {
                centroids.push(Vec3A::new(0.0, y, 2.0));
            }
        }
        let mut rng = Lcg(3);
        centroids.extend((0..1000).map(|_| Vec3A::new(rng.next(), rng.next(), rng.next()) * 5.0));
        for c in centroids {
            let bins = binning.bins(c);
            for (axis, &at) in bins.iter().enumerate() {
                for bin in 0..BINS - 1 {
                    let side = binning.side_test(axis, bin);
                    assert_eq!(side.goes_left(c), at <= bin, "{c} axis {axis} bin {bin}");
                }
            }
        }
    }

    /// `partition` makes a node of two triangles a leaf without binning; the SAH it skips
    /// must have made it one too, or trees would change where a split was cheaper.
    #[test]
    fn two_triangle_nodes_skip_binning_only_where_the_sah_makes_them_leaves() {
        let mut rng = Lcg(5);
        let mut scratch = Scratch::new();
        let mut shortcuts = 0;
        for case in 0..5000 {
            let mut triangles = random_triangles(&mut rng, 2, [0.01, 0.5, 1.0, 30.0][case % 4]);
            if case % 7 == 0 {
                // Coincident centroids: no axis to bin on.
                triangles[1] = triangles[0];
            }
            if case % 11 == 0 {
                // Flat in z: boxes of zero height.
                for v in triangles.iter_mut().flatten() {
                    v.z = 0.25;
                }
            }
            let mut items = items_of(&triangles);
            let (bounds, centroids) = bounds_of(&items);
            let area = bounds.half_area();
            let shortcut = 2.0 <= TRAVERSAL_COST && area.is_finite() && area > 0.0;
            if !shortcut {
                continue;
            }
            shortcuts += 1;
            assert!(partition(&mut scratch, &mut items, &bounds, &centroids, 1).is_none());
            let binning = Binning::new(&centroids);
            if let Some((split, _, _)) = best_split_binned(&mut scratch, &items, &binning) {
                let split_cost = TRAVERSAL_COST + split.cost / area;
                assert!(
                    split_cost >= 2.0,
                    "case {case}: a split costs {split_cost} < 2"
                );
            }
        }
        assert!(shortcuts > 4000, "only {shortcuts} cases took the shortcut");
    }

    /// Large nodes bin into two sets merged after; their bins must be those of one set, bit
    /// for bit, and the spare set must be left empty for the next node.
    #[test]
    fn binning_into_two_sets_gives_the_bins_of_one() {
        let mut rng = Lcg(11);
        let mut spare = Bins::EMPTY;
        for case in 0..200 {
            let n = TWO_BIN_SETS_MIN + case % 97;
            let items = items_of(&random_triangles(&mut rng, n, [0.5, 30.0][case % 2]));
            let binning = Binning::new(&bounds_of(&items).1);
            let mut one = Bins::EMPTY;
            for t in &items {
                one.add(t, &binning);
            }
            let mut two = Bins::EMPTY;
            bin_into(&mut two, &mut spare, &items, &binning);
            let bits = |bins: &Bins| -> Vec<u32> {
                let boxes = bins.bounds.iter().flatten();
                boxes
                    .flat_map(|b| b.lo.to_array().into_iter().chain(b.hi.to_array()))
                    .map(f32::to_bits)
                    .chain(bins.counts.iter().flatten().copied())
                    .chain(bins.occupied.map(u32::from))
                    .collect()
            };
            assert_eq!(bits(&one), bits(&two), "case {case}, {n} triangles");
            assert_eq!(
                bits(&spare),
                bits(&Bins::EMPTY),
                "case {case}: spare not emptied"
            );
        }
    }

    /// Sweeping only the occupied bins, in scratch bins that earlier nodes used, must choose
    /// what the sweep over every bin of fresh bins chooses, bit for bit, or the tree (and every
    /// image) would change.
    #[test]
    fn the_sweep_over_occupied_bins_is_the_sweep_over_every_bin() {
        let mut rng = Lcg(7);
        let mut scratch = Scratch::new();
        for case in 0..3000 {
            let n = 2 + case % 200;
            let spread = [0.5, 1.0, 30.0][case % 3];
            let items = items_of(&random_triangles(&mut rng, n, spread));
            let (_, centroids) = bounds_of(&items);
            let binning = Binning::new(&centroids);
            let key = |c: Option<(Split, Bounds, Bounds)>| {
                c.map(|(s, l, r)| (s.axis, s.bin, s.cost.to_bits(), l.lo, l.hi, r.lo, r.hi))
            };
            assert_eq!(
                key(best_split_binned(&mut scratch, &items, &binning)),
                key(best_split_every_bin(
                    &bin_serial(&items, &binning),
                    &binning
                )),
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
        let key = |bins: Bins| {
            let boxes = bins.bounds.iter().flatten();
            let counts = bins.counts.iter().flatten();
            let boxes = boxes.zip(counts).map(|(b, &c)| {
                let bits = |v: Vec3A| v.to_array().map(f32::to_bits);
                (c, bits(b.lo), bits(b.hi))
            });
            (bins.occupied, boxes.collect::<Vec<_>>())
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
