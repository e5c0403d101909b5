//! Partial files: the accumulation of one sample range (`passgraph render --samples A..B
//! --partial PART.exr`), kept exactly so that `passgraph merge` can combine ranges into the
//! render of their union (docs/distributed.md, "Partial files").
//!
//! # Format (version 1)
//!
//! A single-part, scan-line OpenEXR file (ZIP, lossless) of the image's size. For each channel
//! `C` of the accumulation, in the result buffer's plane order `l0`, `direct`, `indirect`,
//! `ambient`, `sum`, seven channels:
//!
//! | EXR channel | type | holds |
//! | --- | --- | --- |
//! | `C.R`, `C.G`, `C.B` | f32 | the running mean as the accumulate pass left it (`result`) |
//! | `C.compensation.R`, `.G`, `.B` | f32 | the rounding error it carries (`compensation`) |
//! | `C.count` | u32 | the pixel's sample count: the range's length less the samples it dropped |
//!
//! so an EXR viewer shows each channel as a layer. Pixel (x, y) is at row y from the top, as
//! in the `result` buffer. The exact mean of a pixel's samples is `mean + compensation` to
//! within a few ulps of `compensation` (src/render/accumulate.rs). The GPU counts in f32,
//! exact below 2^24, so a range is at most 2^24 samples long; merged counts are u32 sums.
//!
//! The header's text attribute `passgraph.partial` holds the fields, one `key: value` line
//! each, in this order (one attribute, not nine: the `exr` crate writes custom attributes in a
//! random order, and `merge` must write the same bytes every time):
//!
//! | key | value |
//! | --- | --- |
//! | `format` | `passgraph partial 2` |
//! | `samples` | the sample range `A..B` (frame indices A to B-1) |
//! | `size` | `WxH`, which must equal the data window's size |
//! | `dropped` | samples dropped (non-finite) in the range, over all pixels |
//! | `fingerprint` | 32 hex digits: graph, scene and settings in one hash |
//! | `fingerprint.graph`, `fingerprint.scene` | 32 hex digits each |
//! | `settings` | `size WxH, seed K, max_depth D` |
//! | `tiles` | only in a checkpoint of a tiled render stopped inside its range: `WxH done D next N`, the tile size, the tiles finished (in rendering order: [`Tiling::in_rendering_order`]) and the samples the next one holds; the tiles after it hold none |
//! | `source` | informative: graph and scene as given, the adapter; never compared |
//! | `checksum` | 32 hex digits: XXH3-128 of every line above but `source`, then each channel's means, compensations and counts (little-endian, channel order as above) |
//!
//! (see [`super::fingerprint`] for what the hashes cover). Reading checks all of it and names
//! the file in every error: unreadable or truncated EXR, not a partial, an unknown version, a
//! missing or mistyped channel, a size that disagrees, a fingerprint that does not add up, a
//! checksum that does not match (an edited header or data, flipped bits), counts above the
//! samples their pixel holds (the range's length, or the tile's progress) or differing between
//! channels, a `dropped` that is not what the counts leave out, non-finite values.
//!
//! A partial without a `tiles` line holds the whole range in every pixel, whether it was
//! rendered whole or in tiles: the two files are the same bytes. One with a `tiles` line is
//! only a checkpoint to resume (`merge` refuses it). The checksum catches edits and damage, not a
//! forger who recomputes it: no check without a secret can.

use super::channels::Channel;
use super::fingerprint::{Fingerprint, hash_text, parse_hash};
pub use super::planes::Plane;
use super::planes::{planes_from_buffers, planes_to_result, tile_rows};
pub use super::sample_range::SampleRange;
use super::tiling::{Tile, Tiling};
use crate::atomic_write::write_atomic;
use exr::prelude::{
    AnyChannel, AnyChannels, AttributeValue, Encoding, FlatSamples, Image, Layer, LayerAttributes,
    ReadChannels, ReadLayers, SmallVec, Text, WritableImage,
};
use std::fmt;
use std::path::Path;

/// The value of `passgraph.format`.
pub const FORMAT: &str = "passgraph partial 2";
/// The longest range one render may have: the GPU's f32 sample count is exact below this.
pub const MAX_RANGE: u32 = 1 << 24;

/// The one header attribute holding the partial's fields, a line `key: value` each. One
/// attribute, because the `exr` crate writes custom attributes in its HashMap's (random) order,
/// and a merge must write the same bytes every time.
pub const HEADER: &str = "passgraph.partial";
const ATTR_FORMAT: &str = "format";
const ATTR_SAMPLES: &str = "samples";
const ATTR_SIZE: &str = "size";
const ATTR_DROPPED: &str = "dropped";
const ATTR_FINGERPRINT: &str = "fingerprint";
const ATTR_GRAPH: &str = "fingerprint.graph";
const ATTR_SCENE: &str = "fingerprint.scene";
const ATTR_SETTINGS: &str = "settings";
const ATTR_TILES: &str = "tiles";
const ATTR_SOURCE: &str = "source";
const ATTR_CHECKSUM: &str = "checksum";

/// How far a tiled render got, in a checkpoint written before its last tile was done.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TileProgress {
    /// The tile size of the render's [`Tiling`].
    pub tile: [u32; 2],
    /// Tiles finished, in rendering order: they hold the whole range.
    pub done: u32,
    /// Samples the next tile holds (fewer than the range's); the tiles after it hold none.
    pub next: u32,
}

impl fmt::Display for TileProgress {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(
            f,
            "{}x{} done {} next {}",
            self.tile[0], self.tile[1], self.done, self.next
        )
    }
}

impl std::str::FromStr for TileProgress {
    type Err = String;

    fn from_str(s: &str) -> Result<TileProgress, String> {
        let bad = || format!("'{s}' is not 'WxH done D next N'");
        let words: Vec<&str> = s.split_whitespace().collect();
        let [size, "done", done, "next", next] = words.as_slice() else {
            return Err(bad());
        };
        let (w, h) = size.split_once('x').ok_or_else(bad)?;
        let number = |t: &str| t.parse::<u32>().map_err(|_| bad());
        Ok(TileProgress {
            tile: [number(w)?, number(h)?],
            done: number(done)?,
            next: number(next)?,
        })
    }
}

/// A partial file in memory (see the module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct Partial {
    pub size: [u32; 2],
    pub samples: SampleRange,
    pub dropped: u64,
    pub fingerprint: Fingerprint,
    /// Informative only (graph, scene, adapter): never compared.
    pub source: String,
    /// In [`Channel::ALL`] order.
    pub planes: Vec<Plane>,
    /// Set only in a checkpoint of a tiled render stopped before its last tile was done.
    pub progress: Option<TileProgress>,
}

/// How a partial file's data is compressed; either reads back the same. ZIP for files sent to
/// a merge, RLE for checkpoints, written often and read once if ever: at 1280x720 a checkpoint
/// took 6.0 s with ZIP (20.6 MB) and 2.7 s with RLE (38 MB) in one run (debug build; exr is
/// built without its threads).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Packing {
    Small,
    Fast,
}

impl Partial {
    /// A partial from the session's `result` and `compensation` buffers (planes of
    /// `width * height` vec4: xyz, then the count in `result`'s w).
    pub fn from_buffers(
        size: [u32; 2],
        samples: SampleRange,
        dropped: u64,
        fingerprint: Fingerprint,
        source: String,
        result: &[[f32; 4]],
        compensation: &[[f32; 4]],
    ) -> Result<Partial, String> {
        let pixels = size[0] as usize * size[1] as usize;
        let needed = Channel::ALL.len() * pixels;
        if result.len() < needed || compensation.len() < needed {
            return Err(format!(
                "the result and compensation buffers hold {} and {} pixels of planes; a partial of {}x{} needs {needed}",
                result.len(),
                compensation.len(),
                size[0],
                size[1]
            ));
        }
        let planes = planes_from_buffers(pixels, result, compensation);
        let partial = Partial {
            size,
            samples,
            dropped,
            fingerprint,
            source,
            planes,
            progress: None,
        };
        partial.check().map_err(|e| format!("the render's {e}"))?;
        Ok(partial)
    }

    /// The planes as the `result` buffer holds them (mean, count as f32), for
    /// [`super::image::RgbImage::from_result`].
    pub fn to_result(&self) -> Vec<[f32; 4]> {
        planes_to_result(&self.planes)
    }

    /// The header's fields the checksum covers, in file order.
    fn checked_fields(&self) -> Vec<(&'static str, String)> {
        let fp = &self.fingerprint;
        let mut fields = vec![
            (ATTR_FORMAT, FORMAT.to_string()),
            (ATTR_SAMPLES, self.samples.to_string()),
            (ATTR_SIZE, format!("{}x{}", self.size[0], self.size[1])),
            (ATTR_DROPPED, self.dropped.to_string()),
            (ATTR_FINGERPRINT, fp.combined()),
            (ATTR_GRAPH, hash_text(fp.graph)),
            (ATTR_SCENE, hash_text(fp.scene)),
            (ATTR_SETTINGS, fp.settings.replace(['\n', '\r'], " ")),
        ];
        fields.extend(self.progress.map(|p| (ATTR_TILES, p.to_string())));
        fields
    }

    /// XXH3-128 of the checked header fields and every plane's data (module documentation).
    pub fn checksum(&self) -> u128 {
        let mut h = xxhash_rust::xxh3::Xxh3::new();
        for (name, value) in self.checked_fields() {
            h.update(format!("{name}: {value}\n").as_bytes());
        }
        for plane in &self.planes {
            h.update(bytemuck::cast_slice(&plane.mean));
            h.update(bytemuck::cast_slice(&plane.compensation));
            h.update(bytemuck::cast_slice(&plane.count));
        }
        h.digest128()
    }

    /// The file's bytes.
    pub fn encode(&self, packing: Packing) -> Result<Vec<u8>, String> {
        let [w, h] = self.size;
        let mut channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = SmallVec::new();
        for (c, plane) in Channel::ALL.iter().zip(&self.planes) {
            for (k, rgb) in ["R", "G", "B"].iter().enumerate() {
                channels.push(AnyChannel::new(
                    format!("{}.{rgb}", c.name()).as_str(),
                    FlatSamples::F32(plane.mean.iter().map(|v| v[k]).collect()),
                ));
                channels.push(AnyChannel::new(
                    format!("{}.compensation.{rgb}", c.name()).as_str(),
                    FlatSamples::F32(plane.compensation.iter().map(|v| v[k]).collect()),
                ));
            }
            channels.push(AnyChannel::new(
                format!("{}.count", c.name()).as_str(),
                FlatSamples::U32(plane.count.clone()),
            ));
        }
        let mut attributes = LayerAttributes::default();
        let mut header = String::new();
        for (name, value) in self.checked_fields().into_iter().chain([
            (ATTR_SOURCE, self.source.clone()),
            (ATTR_CHECKSUM, hash_text(self.checksum())),
        ]) {
            // A line each: a value never spans two.
            header += &format!("{name}: {}\n", value.replace(['\n', '\r'], " "));
        }
        attributes
            .other
            .insert(Text::from(HEADER), AttributeValue::Text(exr_text(&header)));
        let layer = Layer::new(
            (w as usize, h as usize),
            attributes,
            match packing {
                Packing::Small => Encoding::SMALL_LOSSLESS,
                Packing::Fast => Encoding::FAST_LOSSLESS,
            },
            AnyChannels::sort(channels),
        );
        let mut out = std::io::Cursor::new(Vec::new());
        Image::from_layer(layer)
            .write()
            .to_buffered(&mut out)
            .map_err(|e| format!("cannot encode the partial file: {e}"))?;
        Ok(out.into_inner())
    }

    /// Writes the file whole or not at all (temporary file, then rename).
    pub fn write(&self, path: &Path, packing: Packing) -> Result<(), String> {
        let bytes = self
            .encode(packing)
            .map_err(|e| format!("{}: {e}", path.display()))?;
        write_atomic(path, &bytes).map_err(|e| format!("{}: cannot write: {e}", path.display()))
    }

    /// Reads and checks a partial file; every error names it.
    pub fn read(path: &Path) -> Result<Partial, String> {
        let bytes =
            std::fs::read(path).map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
        Partial::decode(&bytes).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Parses and checks a partial file's bytes.
    pub fn decode(bytes: &[u8]) -> Result<Partial, String> {
        let image = exr::prelude::read()
            .no_deep_data()
            .largest_resolution_level()
            .all_channels()
            .all_layers()
            .all_attributes()
            // Pedantic: a missing or damaged chunk is an error, never silently zero.
            .pedantic()
            .non_parallel()
            .from_buffered(std::io::Cursor::new(bytes))
            .map_err(|e| format!("not a readable OpenEXR file (truncated or damaged?): {e}"))?;
        let not_partial = || {
            format!(
                "not a passgraph partial file (no '{HEADER}' attribute; partial files are written by `passgraph render --partial` and `passgraph merge --partial`)"
            )
        };
        let [layer] = image.layer_data.as_slice() else {
            return match image.layer_data.first() {
                Some(first) if text_attr(&first.attributes.other, HEADER).is_some() => {
                    Err(format!(
                        "holds {} parts; a partial file has one",
                        image.layer_data.len()
                    ))
                }
                _ => Err(not_partial()),
            };
        };
        let header = text_attr(&layer.attributes.other, HEADER).ok_or_else(not_partial)?;
        let mut fields = std::collections::BTreeMap::new();
        for line in header.lines() {
            let (key, value) = line.split_once(": ").ok_or_else(|| {
                format!("the '{HEADER}' attribute has a line that is not 'key: value': '{line}'")
            })?;
            if fields.insert(key, value).is_some() {
                return Err(format!("the '{HEADER}' attribute has two '{key}' lines"));
            }
        }
        let need = |name: &str| {
            fields
                .get(name)
                .map(|v| v.to_string())
                .ok_or_else(|| format!("the '{HEADER}' attribute has no '{name}' line"))
        };
        let format = need(ATTR_FORMAT)?;
        if format != FORMAT {
            return Err(format!(
                "'{ATTR_FORMAT}' is '{format}'; this passgraph reads '{FORMAT}'"
            ));
        }
        let samples: SampleRange = need(ATTR_SAMPLES)?
            .parse()
            .map_err(|e| format!("'{ATTR_SAMPLES}': {e}"))?;
        let size_text = need(ATTR_SIZE)?;
        let size = [layer.size.0, layer.size.1].map(|v| v as u32);
        if size_text != format!("{}x{}", size[0], size[1]) {
            return Err(format!(
                "'{ATTR_SIZE}' says {size_text} but the image is {}x{}",
                size[0], size[1]
            ));
        }
        let dropped: u64 = need(ATTR_DROPPED)?
            .parse()
            .map_err(|_| format!("'{ATTR_DROPPED}' is not a whole number"))?;
        let hash = |name: &str| {
            need(name).and_then(|t| {
                parse_hash(&t).ok_or_else(|| format!("'{name}' is '{t}', not 32 hex digits"))
            })
        };
        let fingerprint = Fingerprint {
            graph: hash(ATTR_GRAPH)?,
            scene: hash(ATTR_SCENE)?,
            settings: need(ATTR_SETTINGS)?,
        };
        let combined = need(ATTR_FINGERPRINT)?;
        if combined != fingerprint.combined() {
            return Err(format!(
                "'{ATTR_FINGERPRINT}' ({combined}) does not match its parts ({}): the header is damaged",
                fingerprint.combined()
            ));
        }
        let source = need(ATTR_SOURCE).unwrap_or_default();
        let progress = fields
            .get(ATTR_TILES)
            .map(|t| t.parse::<TileProgress>())
            .transpose()
            .map_err(|e| format!("'{ATTR_TILES}': {e}"))?;
        let channels = &layer.channel_data.list;
        let find = |name: &str| {
            channels
                .iter()
                .find(|c| c.name == *name)
                .map(|c| &c.sample_data)
                .ok_or_else(|| format!("missing channel '{name}'"))
        };
        let f32s = |name: &str| match find(name)? {
            FlatSamples::F32(v) => Ok(v),
            other => Err(format!(
                "channel '{name}' holds {}; a partial stores it as f32",
                sample_type(other)
            )),
        };
        let mut planes = Vec::new();
        for c in Channel::ALL {
            let n = c.name();
            let [r, g, b] = [
                f32s(&format!("{n}.R"))?,
                f32s(&format!("{n}.G"))?,
                f32s(&format!("{n}.B"))?,
            ];
            let [cr, cg, cb] = [
                f32s(&format!("{n}.compensation.R"))?,
                f32s(&format!("{n}.compensation.G"))?,
                f32s(&format!("{n}.compensation.B"))?,
            ];
            let count = match find(&format!("{n}.count"))? {
                FlatSamples::U32(v) => v.clone(),
                other => {
                    return Err(format!(
                        "channel '{n}.count' holds {}; a partial stores it as u32",
                        sample_type(other)
                    ));
                }
            };
            planes.push(Plane {
                mean: (0..r.len()).map(|i| [r[i], g[i], b[i]]).collect(),
                compensation: (0..cr.len()).map(|i| [cr[i], cg[i], cb[i]]).collect(),
                count,
            });
        }
        let partial = Partial {
            size,
            samples,
            dropped,
            fingerprint,
            source,
            planes,
            progress,
        };
        // The planes' sizes first: the checksum of planes of the wrong size means nothing.
        partial.check_sizes()?;
        let stored = hash(ATTR_CHECKSUM)?;
        if stored != partial.checksum() {
            return Err(format!(
                "the checksum does not match the header and data ({} stored, {} computed): the file was changed after it was written, or damaged",
                hash_text(stored),
                hash_text(partial.checksum())
            ));
        }
        partial.check()?;
        Ok(partial)
    }

    /// Five planes of the image's size.
    fn check_sizes(&self) -> Result<(), String> {
        let pixels = self.size[0] as usize * self.size[1] as usize;
        if self.planes.len() != Channel::ALL.len() {
            return Err(format!("{} planes; a partial has 5", self.planes.len()));
        }
        for (c, p) in Channel::ALL.iter().zip(&self.planes) {
            if p.mean.len() != pixels || p.compensation.len() != pixels || p.count.len() != pixels {
                return Err(format!(
                    "channel '{}' does not hold {pixels} pixels",
                    c.name()
                ));
            }
        }
        Ok(())
    }

    /// What every partial satisfies: planes of the image's size, finite values, counts no
    /// larger than the samples their pixel holds and the same in every channel (a dropped
    /// sample is dropped for the whole pixel: shaders/accumulate.wgsl), `dropped` what the
    /// counts leave out.
    pub(crate) fn check(&self) -> Result<(), String> {
        self.check_sizes()?;
        let held = self.samples_held()?;
        let pixels = self.size[0] as usize * self.size[1] as usize;
        for (c, p) in Channel::ALL.iter().zip(&self.planes) {
            let name = c.name();
            let bad = p
                .mean
                .iter()
                .chain(&p.compensation)
                .position(|v| !v.iter().all(|x| x.is_finite()));
            if let Some(i) = bad {
                return Err(format!(
                    "channel '{name}' has a non-finite value at pixel {}",
                    pixel_name(i % pixels, self.size[0])
                ));
            }
            if let Some(i) = (0..pixels).find(|&i| p.count[i] > held[i]) {
                let holds = match self.progress {
                    None => format!("the range {} holds", self.samples),
                    Some(progress) => format!(
                        "its tile holds ({} of range {}: {progress})",
                        held[i], self.samples
                    ),
                };
                return Err(format!(
                    "channel '{name}' counts {} samples at pixel {}, more than {holds}",
                    p.count[i],
                    pixel_name(i, self.size[0]),
                ));
            }
            let first = &self.planes[0];
            if let Some(i) = (0..pixels).find(|&i| p.count[i] != first.count[i]) {
                return Err(format!(
                    "channel '{name}' counts {} samples at pixel {} but channel '{}' {}: a dropped sample is dropped in every channel",
                    p.count[i],
                    pixel_name(i, self.size[0]),
                    Channel::ALL[0].name(),
                    first.count[i]
                ));
            }
        }
        let missing: u64 = self.planes[0]
            .count
            .iter()
            .zip(&held)
            .map(|(&n, &h)| u64::from(h - n))
            .sum();
        if missing != self.dropped {
            let of = match self.progress {
                None => format!(
                    "the {} x {pixels} samples of range {}",
                    self.samples.len(),
                    self.samples
                ),
                Some(progress) => format!(
                    "the samples its tiles hold ({progress}) of range {}",
                    self.samples
                ),
            };
            return Err(format!(
                "'{ATTR_DROPPED}' is {} but the counts leave {missing} of {of} out",
                self.dropped
            ));
        }
        Ok(())
    }

    /// The tiles of a checkpoint with [`TileProgress`], in rendering order, each with the
    /// samples it holds; an error if the progress does not fit the image and range.
    pub fn tiles_held(&self) -> Result<Vec<(Tile, u32)>, String> {
        let Some(progress) = self.progress else {
            return Ok(vec![(Tile::whole(self.size), self.samples.len())]);
        };
        let tiling = Tiling::new(self.size, progress.tile)
            .map_err(|e| format!("'{ATTR_TILES}' ({progress}): {e}"))?;
        let tiles = tiling.in_rendering_order();
        if tiling.tile != progress.tile || progress.done as usize >= tiles.len() {
            return Err(format!(
                "'{ATTR_TILES}' ({progress}) is not the progress of a {}x{} image in {} tiles of {}x{}",
                self.size[0],
                self.size[1],
                tiles.len(),
                tiling.tile[0],
                tiling.tile[1]
            ));
        }
        if progress.next >= self.samples.len() {
            return Err(format!(
                "'{ATTR_TILES}' ({progress}): the next tile holds {} samples, but a tile in progress holds fewer than the range's {}",
                progress.next,
                self.samples.len()
            ));
        }
        Ok(tiles
            .into_iter()
            .enumerate()
            .map(|(i, tile)| {
                let held = match (i as u32).cmp(&progress.done) {
                    std::cmp::Ordering::Less => self.samples.len(),
                    std::cmp::Ordering::Equal => progress.next,
                    std::cmp::Ordering::Greater => 0,
                };
                (tile, held)
            })
            .collect())
    }

    /// What it holds, for a log line: `samples 0..64`, or for a tiled render in progress
    /// `samples 0..64 in 2 of 5 tiles of 1920x224, 0..17 in the next`.
    pub fn holds(&self) -> String {
        match (self.progress, self.tiles_held()) {
            (Some(p), Ok(tiles)) => {
                let next = match p.next {
                    0 => String::new(),
                    n => format!(
                        ", {} in the next",
                        SampleRange {
                            start: self.samples.start,
                            end: self.samples.start + n
                        }
                    ),
                };
                format!(
                    "samples {} in {} of {} tiles of {}x{}{next}",
                    self.samples,
                    p.done,
                    tiles.len(),
                    p.tile[0],
                    p.tile[1]
                )
            }
            _ => format!("samples {}", self.samples),
        }
    }

    /// The samples each pixel holds, before any was dropped.
    fn samples_held(&self) -> Result<Vec<u32>, String> {
        let mut held = vec![0; self.size[0] as usize * self.size[1] as usize];
        for (tile, n) in self.tiles_held()? {
            for row in tile_rows(tile, self.size[0]) {
                held[row].fill(n);
            }
        }
        Ok(held)
    }
}

fn pixel_name(i: usize, width: u32) -> String {
    let w = width as usize;
    format!("({}, {})", i % w, i / w)
}

fn sample_type(s: &FlatSamples) -> &'static str {
    match s {
        FlatSamples::F16(_) => "f16",
        FlatSamples::F32(_) => "f32",
        FlatSamples::U32(_) => "u32",
    }
}

fn text_attr(
    attrs: &std::collections::HashMap<Text, AttributeValue>,
    name: &str,
) -> Option<String> {
    match attrs.get(&Text::from(name))? {
        AttributeValue::Text(t) => Some(t.to_string()),
        _ => None,
    }
}

/// EXR text is one byte per character: anything else (a path in another script) becomes '?'.
fn exr_text(s: &str) -> Text {
    let ascii: String = s
        .chars()
        .map(|c| if c.is_ascii() { c } else { '?' })
        .collect();
    Text::from(ascii.as_str())
}
