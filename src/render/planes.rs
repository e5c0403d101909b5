//! The accumulation's planes on the host: per channel the running means, the rounding errors
//! they carry and the sample counts, read from a session's buffers and written back, cut into
//! tiles and pasted together. A partial file (src/render/partial.rs) holds them; a session
//! restores them (`Session::restore`).

use super::channels::Channel;
use super::tiling::Tile;

/// One channel's running means over a range: `width * height` pixels each.
#[derive(Clone, Debug, PartialEq)]
pub struct Plane {
    pub mean: Vec<[f32; 3]>,
    pub compensation: Vec<[f32; 3]>,
    pub count: Vec<u32>,
}

/// Planes from a session's `result` and `compensation` buffers (planes of `pixels` vec4:
/// xyz, then the count in `result`'s w); the buffers hold at least 5 planes.
pub fn planes_from_buffers(
    pixels: usize,
    result: &[[f32; 4]],
    compensation: &[[f32; 4]],
) -> Vec<Plane> {
    Channel::ALL
        .iter()
        .map(|c| {
            let r = &result[c.layer() * pixels..][..pixels];
            let e = &compensation[c.layer() * pixels..][..pixels];
            Plane {
                mean: r.iter().map(|v| [v[0], v[1], v[2]]).collect(),
                compensation: e.iter().map(|v| [v[0], v[1], v[2]]).collect(),
                // The shader adds 1.0 per sample: a whole number, exact below 2^24.
                count: r.iter().map(|v| v[3] as u32).collect(),
            }
        })
        .collect()
}

/// The planes as the `result` buffer holds them (mean, count as f32).
pub fn planes_to_result(planes: &[Plane]) -> Vec<[f32; 4]> {
    planes
        .iter()
        .flat_map(|p| {
            p.mean
                .iter()
                .zip(&p.count)
                .map(|(m, &n)| [m[0], m[1], m[2], n as f32])
        })
        .collect()
}

/// Five zero planes of `pixels` pixels, or an error if the host cannot hold them.
pub fn zero_planes(pixels: usize) -> Result<Vec<Plane>, String> {
    let bytes = pixels as u64 * 28 * Channel::ALL.len() as u64;
    let too_big = || {
        format!(
            "the accumulation of {pixels} pixels does not fit in this machine's memory ({bytes} bytes)"
        )
    };
    let zeros = |n: usize| -> Result<Vec<[f32; 3]>, String> {
        let mut v = Vec::new();
        v.try_reserve_exact(n).map_err(|_| too_big())?;
        v.resize(n, [0.0; 3]);
        Ok(v)
    };
    Channel::ALL
        .iter()
        .map(|_| {
            let mut count = Vec::new();
            count.try_reserve_exact(pixels).map_err(|_| too_big())?;
            count.resize(pixels, 0);
            Ok(Plane {
                mean: zeros(pixels)?,
                compensation: zeros(pixels)?,
                count,
            })
        })
        .collect()
}

/// The part of `planes` (of an image `width` pixels wide) inside `tile`.
pub fn cut_tile(planes: &[Plane], width: u32, tile: Tile) -> Vec<Plane> {
    let cut = |v: &[[f32; 3]]| -> Vec<[f32; 3]> {
        tile_rows(tile, width)
            .flat_map(|row| v[row].iter().copied())
            .collect()
    };
    planes
        .iter()
        .map(|p| Plane {
            mean: cut(&p.mean),
            compensation: cut(&p.compensation),
            count: tile_rows(tile, width)
                .flat_map(|row| p.count[row].iter().copied())
                .collect(),
        })
        .collect()
}

/// Copies `part` (planes of `tile`'s size) into `planes` (of an image `width` pixels wide) at
/// the tile's place.
pub fn paste_tile(planes: &mut [Plane], width: u32, tile: Tile, part: &[Plane]) {
    let tw = tile.size[0] as usize;
    for (p, q) in planes.iter_mut().zip(part) {
        for (k, row) in tile_rows(tile, width).enumerate() {
            let from = k * tw..(k + 1) * tw;
            p.mean[row.clone()].copy_from_slice(&q.mean[from.clone()]);
            p.compensation[row.clone()].copy_from_slice(&q.compensation[from.clone()]);
            p.count[row].copy_from_slice(&q.count[from]);
        }
    }
}

/// The index ranges of `tile`'s rows in planes of an image `width` pixels wide.
pub(crate) fn tile_rows(tile: Tile, width: u32) -> impl Iterator<Item = std::ops::Range<usize>> {
    let (width, tw) = (width as usize, tile.size[0] as usize);
    (0..tile.size[1] as usize).map(move |row| {
        let start = (tile.origin[1] as usize + row) * width + tile.origin[0] as usize;
        start..start + tw
    })
}
