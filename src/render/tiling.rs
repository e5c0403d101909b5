//! The geometry of tiles: the part of the image a session renders, and an image cut into
//! tiles in the order a tiled render (src/render/tiles.rs) takes them.

use super::tile_order::TILE;

/// The part of the image a session renders: a tile, or the whole image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tile {
    /// Its top-left pixel in the image.
    pub origin: [u32; 2],
    pub size: [u32; 2],
    /// The whole image's size.
    pub image: [u32; 2],
}

impl Tile {
    pub fn whole(size: [u32; 2]) -> Tile {
        Tile {
            origin: [0, 0],
            size,
            image: size,
        }
    }
}

/// An image cut into tiles of `tile` pixels, row by row; the last column and row are narrower
/// where the tile does not divide the image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tiling {
    pub image: [u32; 2],
    pub tile: [u32; 2],
}

impl Tiling {
    /// Tile sides must be multiples of 8, so that the passes' 8x8 workgroups (and the subgroups
    /// within them that shaders/path_reuse.wgsl shares work across) cover the same pixels as in
    /// the whole image; a side at least the image's is the image's.
    pub fn new(image: [u32; 2], tile: [u32; 2]) -> Result<Tiling, String> {
        let tile = [tile[0].min(image[0]), tile[1].min(image[1])];
        for k in 0..2 {
            if !tile[k].is_multiple_of(TILE) && tile[k] != image[k] {
                return Err(format!(
                    "tile {}x{}: each side must be a multiple of {TILE} (the passes' workgroups are {TILE}x{TILE} pixels) or the image's ({}x{})",
                    tile[0], tile[1], image[0], image[1]
                ));
            }
        }
        Ok(Tiling { image, tile })
    }

    /// Every tile, row by row.
    pub fn tiles(&self) -> Vec<Tile> {
        let [w, h] = self.image;
        let [tw, th] = self.tile;
        (0..h.div_ceil(th))
            .flat_map(|row| {
                (0..w.div_ceil(tw)).map(move |column| {
                    let origin = [column * tw, row * th];
                    Tile {
                        origin,
                        size: [tw.min(w - origin[0]), th.min(h - origin[1])],
                        image: self.image,
                    }
                })
            })
            .collect()
    }

    /// Every tile in the order a render takes them: grouped by size, largest first, so that
    /// one session serves each run of equal tiles; row by row within a size.
    pub fn in_rendering_order(&self) -> Vec<Tile> {
        let mut tiles = self.tiles();
        // Stable: row order within each size.
        tiles.sort_by_key(|t| std::cmp::Reverse(t.size));
        tiles
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_cover_the_image_once_with_narrower_last_ones() {
        let tiling = Tiling::new([48, 40], [32, 24]).unwrap();
        let tiles = tiling.tiles();
        let sizes: Vec<_> = tiles.iter().map(|t| (t.origin, t.size)).collect();
        assert_eq!(
            sizes,
            [
                ([0, 0], [32, 24]),
                ([32, 0], [16, 24]),
                ([0, 24], [32, 16]),
                ([32, 24], [16, 16])
            ]
        );
        let area: u32 = tiles.iter().map(|t| t.size[0] * t.size[1]).sum();
        assert_eq!(area, 48 * 40);
    }

    #[test]
    fn tile_sides_are_multiples_of_8_or_the_image() {
        assert!(Tiling::new([48, 40], [20, 16]).is_err());
        assert_eq!(Tiling::new([50, 40], [64, 16]).unwrap().tile, [50, 16]);
        assert!(Tiling::new([50, 44], [50, 44]).is_ok());
    }
}
