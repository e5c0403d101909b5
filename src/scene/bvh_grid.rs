//! The grid BVH node boxes are snapped to, so that a node fits one 16-byte texel
//! (docs/design.md §5): each box coordinate is `origin + q * step` with `q` a 16-bit integer, and
//! `step` a power of two per axis. Decoding is exact in f32 (the products are exact and every
//! sum is a multiple of `step` below 2^24 steps), so the GPU's decoded boxes are bit for bit the
//! f32 boxes of [`SceneGpu::nodes`](super::SceneGpu), which the CPU twin traverses.

use super::gpu_layout::{BvhNode, GpuBvhGrid, PackedBvhNode};
use glam::Vec3;

/// Grid cells per axis: q runs over 0..=QUANTA.
const QUANTA: u32 = u16::MAX as u32;
/// Bits of a node's link (miss link or first triangle); the count takes the rest.
pub const LINK_BITS: u32 = 28;
/// The most triangles one leaf may hold (the count's 4 bits).
pub const MAX_ENCODED_LEAF: usize = (1 << (32 - LINK_BITS)) - 1;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BvhGrid {
    pub origin: Vec3,
    pub step: Vec3,
}

impl Default for BvhGrid {
    fn default() -> BvhGrid {
        BvhGrid {
            origin: Vec3::ZERO,
            step: Vec3::ONE,
        }
    }
}

impl BvhGrid {
    /// The grid covering the box `[lo, hi]` (the root's): per axis the smallest power-of-two step
    /// that spans it in QUANTA - 1 cells (one spare for the origin rounding down) and keeps
    /// its coordinates within 2^22 steps of 0, so that every grid value is a multiple of the
    /// step below 2^24 steps: exact in f32.
    pub fn covering(lo: Vec3, hi: Vec3) -> BvhGrid {
        let mut grid = BvhGrid::default();
        for k in 0..3 {
            let (lo, hi) = (f64::from(lo[k]), f64::from(hi[k]));
            let needed = ((hi - lo) / f64::from(QUANTA - 1))
                .max(lo.abs().max(hi.abs()) / f64::from(1u32 << 22))
                .max(f64::from(f32::MIN_POSITIVE));
            let step = 2f64.powi(needed.log2().ceil() as i32);
            grid.step[k] = step as f32;
            grid.origin[k] = ((lo / step).floor() * step) as f32;
        }
        grid
    }

    /// The grid cells of `[lo, hi]`, rounded outward (clamped to the grid). A cell coordinate
    /// is exact in f64 (a difference of two f32 times a power of two, the step's inverse: a
    /// product, cheaper than the division). Clamping to the integer
    /// ends first lets a truncation round it (floor and ceil commute with that clamp): x86-64's
    /// baseline has no rounding instruction, and the libm calls were most of a snap.
    fn cells(&self, lo: Vec3, hi: Vec3) -> ([u32; 3], [u32; 3]) {
        let mut q = ([0u32; 3], [0u32; 3]);
        for k in 0..3 {
            let per_step = 1.0 / f64::from(self.step[k]);
            let cell = |v: f32| {
                ((f64::from(v) - f64::from(self.origin[k])) * per_step)
                    .clamp(0.0, f64::from(QUANTA))
            };
            // `as` maps NaN to 0, as the clamp and rounding of NaN did.
            let low = cell(lo[k]);
            q.0[k] = low as u32;
            let high = cell(hi[k]);
            let truncated = high as u32;
            q.1[k] = truncated + u32::from(f64::from(truncated) < high);
        }
        q
    }

    fn value(&self, k: usize, q: u32) -> f32 {
        q as f32 * self.step[k] + self.origin[k]
    }

    /// `[lo, hi]` grown to the nearest grid values: what the GPU decodes.
    pub fn snap(&self, lo: Vec3, hi: Vec3) -> (Vec3, Vec3) {
        let (ql, qh) = self.cells(lo, hi);
        let (mut lo, mut hi) = (Vec3::ZERO, Vec3::ZERO);
        for k in 0..3 {
            lo[k] = self.value(k, ql[k]);
            hi[k] = self.value(k, qh[k]);
        }
        (lo, hi)
    }

    /// `node` as one texel: per axis the low cell in the low 16 bits and the high cell in the
    /// high ones, then the link with the count in the top bits. Boxes off the grid are grown
    /// to it.
    pub fn encode(&self, node: &BvhNode) -> PackedBvhNode {
        assert!(
            node.a < 1 << LINK_BITS && node.count as usize <= MAX_ENCODED_LEAF,
            "BVH node link {} or count {} does not fit a texel",
            node.a,
            node.count
        );
        let (ql, qh) = self.cells(node.lo.into(), node.hi.into());
        PackedBvhNode {
            bounds: [0, 1, 2].map(|k| ql[k] | (qh[k] << 16)),
            link: node.a | (node.count << LINK_BITS),
        }
    }

    pub fn to_gpu(self) -> GpuBvhGrid {
        GpuBvhGrid {
            origin: self.origin.into(),
            pad0: 0,
            step: self.step.into(),
            pad1: 0,
        }
    }
}
