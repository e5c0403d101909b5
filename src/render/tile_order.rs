//! The order in which an image pass's workgroups take the image's 8x8 tiles
//! (`shaders/lib/tile_order.wgsl`): workgroup (x, y) of the dispatch shades the tile in column x
//! and row ((x + y) * stride) mod rows.
//!
//! lavapipe gives each CPU thread one contiguous run of a dispatch's workgroups (their count
//! divided by the threads), so in row order one thread shades the top of the image and another
//! the bottom, and where the two differ in cost (the bunny on the floor, the light on the
//! ceiling) one waits for the other at every dispatch's end. With a stride coprime to the row
//! count each column's rows are permuted, and a stride near rows / golden ratio, sheared by the
//! column, spreads any run of consecutive workgroups over the whole image. Measured
//! (docs/benchmark-history.md): the fused path pass gains 8 % wall time on the bunny; the seed's
//! short separate passes did not gain, so they keep row order. The stride is computed here, once per frame, because lavapipe
//! runs a shader's integer divisions lane by lane: a Euclid loop in every invocation cost more
//! than it saved in the cheap passes.

/// The side of the square tiles an image pass's workgroups cover.
pub const TILE: u32 = 8;

/// The stride for an image `height` pixels high: coprime to its tile row count, so that each
/// column's k -> (k * stride) mod rows is a permutation of the rows.
pub fn tile_row_stride(height: u32) -> u32 {
    let rows = height.div_ceil(TILE).max(1);
    let mut stride = ((f64::from(rows) * 0.618_034) as u32).max(1);
    while gcd(stride, rows) != 1 {
        stride += 1;
    }
    stride
}

/// The tile (column, row) that workgroup (x, y) shades, as tile_order.wgsl computes it.
pub fn scattered_tile(group: [u32; 2], rows: u32, stride: u32) -> [u32; 2] {
    [group[0], ((group[0] + group[1]) * stride) % rows]
}

fn gcd(mut a: u32, mut b: u32) -> u32 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tiles in dispatch order (x fastest, as lavapipe numbers workgroups).
    fn order(width: u32, height: u32) -> Vec<[u32; 2]> {
        let (columns, rows) = (width.div_ceil(TILE), height.div_ceil(TILE));
        let stride = tile_row_stride(height);
        (0..rows)
            .flat_map(|y| (0..columns).map(move |x| scattered_tile([x, y], rows, stride)))
            .collect()
    }

    #[test]
    fn every_tile_is_taken_exactly_once_for_every_size() {
        for height in 1..=600 {
            for width in [1, 8, 9, 100, 256] {
                let mut tiles = order(width, height);
                tiles.sort_unstable();
                let mut expected: Vec<[u32; 2]> = (0..width.div_ceil(TILE))
                    .flat_map(|x| (0..height.div_ceil(TILE)).map(move |y| [x, y]))
                    .collect();
                expected.sort_unstable();
                assert_eq!(tiles, expected, "{width}x{height}");
            }
        }
    }

    #[test]
    fn the_largest_texture_keeps_the_product_in_u32() {
        // 16384 tiles a side: (columns + rows - 2) * stride must not wrap in the shader's u32.
        let side = 131_072;
        let tiles = side / TILE;
        let product = u64::from(2 * tiles - 2) * u64::from(tile_row_stride(side));
        assert!(product < u64::from(u32::MAX), "{product}");
    }

    #[test]
    fn each_half_of_the_dispatch_shades_half_of_each_quarter_of_the_image() {
        // The failure this prevents: one CPU thread shading the whole top of the image.
        for (width, height) in [
            (128, 128),
            (256, 256),
            (1280, 720),
            (1920, 1080),
            (512, 128),
        ] {
            let tiles = order(width, height);
            let (columns, rows) = (width.div_ceil(TILE), height.div_ceil(TILE));
            let first = &tiles[..tiles.len() / 2];
            for (qx, qy) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                let in_quarter =
                    |t: &[u32; 2]| (t[0] * 2 / columns == qx) && (t[1] * 2 / rows == qy);
                let all = tiles.iter().filter(|t| in_quarter(t)).count();
                let taken = first.iter().filter(|t| in_quarter(t)).count();
                let share = taken as f64 / all as f64;
                assert!(
                    (0.4..=0.6).contains(&share),
                    "{width}x{height}, quarter ({qx}, {qy}): {share}"
                );
            }
        }
    }
}
