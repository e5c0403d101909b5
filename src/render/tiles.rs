//! Big images: rendering an image in tiles when the graph's resources for the whole image
//! exceed the device's limits (on lavapipe `result`, 80 bytes per pixel, passes the 128 MiB
//! storage-binding limit above 1,677,721 pixels), or when asked (`render --tile WxH`).
//!
//! Each tile is rendered by a session whose graph is compiled for the tile's size and whose
//! `frame` uniform carries the tile's origin in the image and the image's size; camera rays and
//! sampler seeds follow the pixel's place in the image (shaders/lib/camera_ray.wgsl,
//! shaders/lib/sampler.wgsl), so a tiled image equals the whole render bit for bit. Only graphs
//! whose passes all declare `footprint: Pixel` (crates/graph/src/decl.rs) are tiled: a filter or a
//! reprojection reads other pixels, which a tile's edge would lack. Tiles are rendered one after
//! another, all frames of one tile, then the next, so only one tile's resources are alive; a
//! session is reused for the next tile of its size (pipelines are built once per tile size).
//! A tile is also a unit of work a render farm could hand out.

use super::channels::ChannelSelection;
use super::fingerprint::Fingerprint;
use super::image::RgbImage;
use super::partial::{Partial, SampleRange, TileProgress};
use super::planes::{
    Plane, cut_tile, paste_tile, planes_from_buffers, planes_to_result, zero_planes,
};
use super::session::{
    RenderError, RenderSettings, Session, compile_for, load_scene_for, prepare_graph,
};
use super::tile_order::TILE;
use super::tiling::{Tile, Tiling};
use crate::gpu::GpuContext;
use crate::gpu::limits::check_limits;
use crate::graph::decl::{Footprint, ResourceDecl, TextureSize};
use crate::graph::load::{LoadedGraph, load_graph};
use crate::graph::plan::Plan;
use crate::scene::{Scene, SceneGpu};

/// Why the graph cannot be rendered in tiles, naming the pass or resource; `None` if it can.
pub fn untileable(graph: &LoadedGraph, plan: &Plan) -> Option<String> {
    if let Some(pass) = plan.passes.iter().find(|p| p.footprint != Footprint::Pixel) {
        return Some(format!(
            "pass '{}' ({}) does not declare `footprint: Pixel`: it may read other pixels than its own (a filter, a reprojection) or draw the frame's projection (a raster pass), which a tile's edge would change",
            pass.name,
            pass.pass_file.display()
        ));
    }
    graph.decl.resources.iter().find_map(|(name, r)| match r {
        ResourceDecl::Texture {
            size: TextureSize::Scaled(f),
            ..
        } if *f != 1.0 => Some(format!(
            "resource '{name}' is Scaled({f}): its texels are not the tile's pixels"
        )),
        _ => None,
    })
}

/// GPU memory of a plan's resources (after transient reuse), per pixel of its frame.
pub fn bytes_per_pixel(plan: &Plan) -> f64 {
    let [w, h] = plan.output_size;
    plan.bytes_allocated() as f64 / (f64::from(w) * f64::from(h))
}

/// A render of the whole image at once, or in tiles: what `passgraph render` runs.
pub enum ImageRender {
    Whole(Box<Session>),
    Tiled(Box<TiledRender>),
}

impl ImageRender {
    /// Checks the graph against what `render` reads back for `channel` (before any GPU work),
    /// then renders the image whole if its plan fits the device and no `tile` is asked for, in
    /// tiles of `tile` if asked, else in the largest tiles that fit. A graph that does not fit
    /// whole and cannot be tiled is an error naming the pass and the largest untiled size.
    /// With `keep_accumulation` (a partial file, checkpoints, a resume) the graph must also
    /// have what [`super::session::partial_contract`] lists, and a tiled render keeps the
    /// finished tiles' accumulation on the host.
    pub fn for_render(
        settings: &RenderSettings,
        channel: &ChannelSelection,
        tile: Option<[u32; 2]>,
        keep_accumulation: bool,
    ) -> Result<ImageRender, RenderError> {
        let keep = keep_accumulation;
        let [w, h] = settings.size;
        if u64::from(w) * u64::from(h) > u64::from(u32::MAX) {
            // shaders/lib/sampler.wgsl names a pixel's sequence by its u32 index in the image.
            return Err(RenderError::Other(format!(
                "{w}x{h} is more than 2^32 pixels, which the sampler cannot tell apart (it names each pixel by a 32-bit index); use a smaller --size"
            )));
        }
        let shown = Some(channel);
        let graph = prepare_graph(load_graph(&settings.graph)?, settings, shown, keep)?;
        let plan = compile_for(&graph, settings.size, shown, keep)?;
        let requested = tile
            .map(|t| Tiling::new(settings.size, t))
            .transpose()
            .map_err(RenderError::Other)?;
        let scene = load_scene_for(settings)?;
        let ctx = GpuContext::new(settings.adapter.as_deref())?;
        let (limits, features) = (ctx.device().limits(), ctx.device().features());
        let fits = |size: [u32; 2]| -> Result<bool, RenderError> {
            let plan = compile_for(&graph, size, shown, keep)?;
            Ok(check_limits(&plan, &limits, features).is_ok())
        };
        let tiling = match (requested, check_limits(&plan, &limits, features)) {
            (Some(tiling), _) => tiling,
            (None, Ok(())) => {
                let whole = Tile::whole(settings.size);
                let session = Session::from_plan(ctx, &graph, plan, settings, whole, scene)?;
                return Ok(ImageRender::Whole(Box::new(session)));
            }
            (None, Err(over)) => {
                // Not a matter of size if even the smallest tile is over a limit.
                if !fits([TILE.min(settings.size[0]), TILE.min(settings.size[1])])? {
                    return Err(over.into());
                }
                if let Some(why) = untileable(&graph, &plan) {
                    let largest = largest_untiled(settings.size, &fits)?;
                    return Err(RenderError::Other(format!(
                        "{over}; {}x{} cannot be rendered in tiles instead: {why}. The largest image of this aspect ratio the graph renders untiled on this device is {}x{}",
                        settings.size[0], settings.size[1], largest[0], largest[1]
                    )));
                }
                largest_tiling(settings.size, &fits)?
            }
        };
        if let Some(why) = untileable(&graph, &plan) {
            return Err(RenderError::Other(format!(
                "{}: cannot render in tiles: {why}",
                settings.graph.display()
            )));
        }
        TiledRender::new(ctx, graph, settings, channel, tiling, scene, keep)
            .map(|t| ImageRender::Tiled(Box::new(t)))
    }

    /// The session rendering the whole image, if not tiled (camera paths need one).
    pub fn whole_mut(&mut self) -> Option<&mut Session> {
        match self {
            ImageRender::Whole(s) => Some(s),
            ImageRender::Tiled(_) => None,
        }
    }

    /// The session of the current tile (or of the whole image).
    pub fn session(&self) -> &Session {
        match self {
            ImageRender::Whole(s) => s,
            ImageRender::Tiled(t) => &t.session,
        }
    }

    /// Renders samples from `first` on (`--samples`; see [`Session::start_at_sample`]), in
    /// every tile; before the first frame.
    pub fn start_at_sample(&mut self, first: u32) {
        match self {
            ImageRender::Whole(s) => s.start_at_sample(first),
            ImageRender::Tiled(t) => {
                t.first_sample = first;
                t.session.start_at_sample(first);
            }
        }
    }

    /// Calls of [`Self::render_frame`] left until every pixel has its frames (after a resume,
    /// fewer than frames times tiles).
    pub fn steps_left(&self) -> u64 {
        match self {
            ImageRender::Whole(s) => u64::from(s.frames_left()),
            ImageRender::Tiled(t) => t.steps_left(),
        }
    }

    /// Tiles in the image (1 if whole): a frame of the image is this many steps.
    pub fn tile_count(&self) -> usize {
        match self {
            ImageRender::Whole(_) => 1,
            ImageRender::Tiled(t) => t.tiles.len(),
        }
    }

    /// Continues from a checkpoint (`render --resume`) whose fingerprint the caller checked: a
    /// whole render from a checkpoint of any frame, a tiled one also from a checkpoint of its
    /// tiling stopped inside a tile (its finished tiles are not rendered again).
    pub fn resume_from(&mut self, checkpoint: &Partial) -> Result<(), RenderError> {
        match self {
            ImageRender::Whole(s) => match checkpoint.progress {
                Some(p) => Err(RenderError::Other(format!(
                    "the checkpoint is of a render in tiles of {}x{} stopped inside a tile: resume it in tiles of that size (--tile {}x{})",
                    p.tile[0], p.tile[1], p.tile[0], p.tile[1]
                ))),
                None if checkpoint.size != s.tile().size => Err(RenderError::Other(format!(
                    "the checkpoint is {}x{}, this render {}x{}",
                    checkpoint.size[0],
                    checkpoint.size[1],
                    s.tile().size[0],
                    s.tile().size[1]
                ))),
                None => s.restore(checkpoint.samples, checkpoint.dropped, &checkpoint.planes),
            },
            ImageRender::Tiled(t) => t.resume_from(checkpoint),
        }
    }

    /// The accumulation so far as a partial file of samples from `start` on (a checkpoint; at
    /// the end, the `--partial` file). A tiled render's accumulation is the finished tiles'
    /// and the current one's; stopped inside its range it has a [`TileProgress`].
    pub fn accumulation(
        &self,
        start: u32,
        fingerprint: &Fingerprint,
        source: &str,
    ) -> Result<Partial, String> {
        match self {
            ImageRender::Whole(s) => whole_accumulation(s, start, fingerprint, source),
            ImageRender::Tiled(t) => t.accumulation(start, fingerprint, source),
        }
    }

    /// One frame of the current tile (or of the whole image); a tile that has its frames is
    /// read back and the next one started.
    pub fn render_frame(&mut self) -> Result<(), RenderError> {
        match self {
            ImageRender::Whole(s) => s.render_frame().map(|_| ()),
            ImageRender::Tiled(t) => t.render_frame(),
        }
    }

    /// The image: tiles not rendered yet are black.
    pub fn image(&self, channel: &ChannelSelection) -> Result<RgbImage, RenderError> {
        match self {
            ImageRender::Whole(s) => s.image(channel),
            ImageRender::Tiled(t) => Ok(t.image.clone()),
        }
    }

    pub fn dropped(&self) -> Result<u32, RenderError> {
        match self {
            ImageRender::Whole(s) => s.dropped(),
            ImageRender::Tiled(t) => Ok(t.dropped),
        }
    }

    pub fn rays_counted(&self) -> Result<Option<u64>, RenderError> {
        match self {
            ImageRender::Whole(s) => s.rays_counted(),
            ImageRender::Tiled(t) => Ok(t.rays),
        }
    }

    /// Frames accumulated in every pixel (of the finished tiles).
    pub fn accumulated(&self) -> u32 {
        match self {
            ImageRender::Whole(s) => s.accumulated(),
            ImageRender::Tiled(t) => t.accumulated,
        }
    }

    /// The tiling, if tiled.
    pub fn tiling(&self) -> Option<Tiling> {
        match self {
            ImageRender::Whole(_) => None,
            ImageRender::Tiled(t) => Some(t.tiling),
        }
    }

    /// What `render` prints about GPU memory: bytes per pixel of the graph's resources and
    /// what the whole image or each tile holds.
    pub fn memory_line(&self) -> String {
        let plan = self.session().plan();
        let per_pixel = bytes_per_pixel(plan);
        let bytes = crate::graph::plan_text::human_bytes(plan.bytes_allocated());
        match self.tiling() {
            None => format!(
                "memory: {per_pixel:.1} GPU bytes per pixel (graph resources after reuse), {bytes} for {}x{}",
                plan.output_size[0], plan.output_size[1]
            ),
            Some(t) => format!(
                "memory: {per_pixel:.1} GPU bytes per pixel (graph resources after reuse), {bytes} per {}x{} tile; {} tiles of the {}x{} image, rendered one after another",
                t.tile[0],
                t.tile[1],
                t.tiles().len(),
                t.image[0],
                t.image[1]
            ),
        }
    }
}

/// The largest tiling that fits: tiles as wide as the image if a strip 8 rows high fits (else
/// the fewest columns that do), as many rows as fit, then evened out so that the tiles are
/// nearly equal (no thin last strip).
fn largest_tiling(
    image: [u32; 2],
    fits: &dyn Fn([u32; 2]) -> Result<bool, RenderError>,
) -> Result<Tiling, RenderError> {
    let [w, h] = image;
    let side = |extent: u32, parts: u32| extent.div_ceil(parts).next_multiple_of(TILE).min(extent);
    let mut columns = 1;
    while !fits([side(w, columns), TILE.min(h)])? {
        columns += 1;
    }
    let width = side(w, columns);
    // The largest multiple of 8 rows that fits, by bisection (fits is monotonic in rows).
    let (mut lo, mut hi) = (1, h.div_ceil(TILE));
    while lo < hi {
        let mid = (lo + hi).div_ceil(2);
        if fits([width, (mid * TILE).min(h)])? {
            lo = mid;
        } else {
            hi = mid - 1;
        }
    }
    let rows = h.div_ceil((lo * TILE).min(h));
    Tiling::new(image, [width, side(h, rows)]).map_err(RenderError::Other)
}

/// The largest image with `image`'s aspect ratio that fits untiled.
fn largest_untiled(
    image: [u32; 2],
    fits: &dyn Fn([u32; 2]) -> Result<bool, RenderError>,
) -> Result<[u32; 2], RenderError> {
    let [w, h] = image;
    let at = |height: u32| {
        let width = (u64::from(w) * u64::from(height)).div_ceil(u64::from(h)) as u32;
        [width.max(1), height]
    };
    let (mut lo, mut hi) = (1, h);
    while lo < hi {
        let mid = (lo + hi).div_ceil(2);
        if fits(at(mid))? {
            lo = mid;
        } else {
            hi = mid - 1;
        }
    }
    Ok(at(lo))
}

/// Tiles rendered one after another: the current tile's session, and the image and counters
/// of the tiles done.
pub struct TiledRender {
    graph: LoadedGraph,
    settings: RenderSettings,
    channel: ChannelSelection,
    scene: (Scene, SceneGpu),
    tiling: Tiling,
    /// In rendering order: grouped by size, so a session serves each run of equal tiles.
    tiles: Vec<Tile>,
    /// Index into `tiles` of the tile `session` renders.
    current: usize,
    session: Session,
    image: RgbImage,
    dropped: u32,
    rays: Option<u64>,
    /// Frames per pixel of the tiles done.
    accumulated: u32,
    /// The sample index every tile starts at.
    first_sample: u32,
    /// The accumulation of the whole image, finished tiles filled in, when a partial file, a
    /// checkpoint or a resume needs it (5 planes, 28 bytes a pixel each, on the host).
    kept: Option<Vec<Plane>>,
    /// Frames each tile (in `tiles`' order) held when the render started: all 0, unless
    /// resumed from a checkpoint.
    held: Vec<u32>,
    /// Compiled with the partial contract: the session keeps `result` and `compensation`.
    keep: bool,
}

impl TiledRender {
    fn new(
        ctx: GpuContext,
        graph: LoadedGraph,
        settings: &RenderSettings,
        channel: &ChannelSelection,
        tiling: Tiling,
        scene: (Scene, SceneGpu),
        keep: bool,
    ) -> Result<TiledRender, RenderError> {
        let tiles = tiling.in_rendering_order();
        let [w, h] = tiling.image;
        // The whole image is assembled on the host: a clear error rather than an abort when it
        // cannot be held.
        let mut pixels = Vec::new();
        let count = w as usize * h as usize;
        pixels.try_reserve_exact(count).map_err(|_| {
            RenderError::Other(format!(
                "a {w}x{h} image does not fit in this machine's memory ({} for its pixels); use a smaller --size",
                crate::graph::plan_text::human_bytes(count as u64 * 12)
            ))
        })?;
        pixels.resize(count, [0.0; 3]);
        let kept = keep
            .then(|| zero_planes(count))
            .transpose()
            .map_err(|e| RenderError::Other(format!("{w}x{h}: {e}; use a smaller --size")))?;
        let session = tile_session(ctx, &graph, settings, channel, tiles[0], &scene, keep)?;
        // Zero, not "not counted", when no tile is rendered here (a finished resume).
        let rays = session.counts_rays().then_some(0);
        Ok(TiledRender {
            graph,
            settings: settings.clone(),
            channel: channel.clone(),
            scene,
            tiling,
            held: vec![0; tiles.len()],
            tiles,
            current: 0,
            session,
            image: RgbImage {
                width: w,
                height: h,
                pixels,
            },
            dropped: 0,
            rays,
            accumulated: 0,
            first_sample: 0,
            kept,
            keep,
        })
    }

    fn render_frame(&mut self) -> Result<(), RenderError> {
        if self.current >= self.tiles.len() {
            return Ok(());
        }
        self.session.render_frame()?;
        if self.session.accumulated() < self.settings.max_frames {
            return Ok(());
        }
        self.finish_tile()?;
        self.current += 1;
        self.enter_tile()
    }

    /// Moves to the tile at `current`, past those a checkpoint brought finished: its session
    /// (this one if of its size) starts there, from the frames the checkpoint holds of it.
    fn enter_tile(&mut self) -> Result<(), RenderError> {
        while self.current < self.tiles.len() && self.held[self.current] >= self.settings.max_frames
        {
            self.finish_held_tile()?;
            self.current += 1;
        }
        let Some(&tile) = self.tiles.get(self.current) else {
            return Ok(());
        };
        if tile != self.session.tile() {
            if tile.size == self.session.tile().size {
                self.session.start_tile(tile)?;
            } else {
                // The next size's session is built before this one is dropped: at a change of
                // size (at most three per image, each to smaller tiles) two tiles' resources
                // are alive for a moment.
                let ctx = self.session.context().clone();
                self.session = tile_session(
                    ctx,
                    &self.graph,
                    &self.settings,
                    &self.channel,
                    tile,
                    &self.scene,
                    self.keep,
                )?;
                self.session.start_at_sample(self.first_sample);
            }
        }
        let held = self.held[self.current];
        if let (true, Some(kept)) = (held > 0, &self.kept) {
            let planes = cut_tile(kept, self.tiling.image[0], tile);
            let samples = SampleRange {
                start: self.first_sample,
                end: self.first_sample + held,
            };
            self.session
                .restore(samples, dropped_of(&planes, held), &planes)?;
        }
        Ok(())
    }

    /// Copies the current tile into the image (and the kept accumulation) and adds its
    /// counters.
    fn finish_tile(&mut self) -> Result<(), RenderError> {
        let tile = self.session.tile();
        let part = self.session.image(&self.channel)?;
        self.paste_image(tile, &part);
        if let Some(kept) = &mut self.kept {
            let planes = session_planes(&self.session)?;
            paste_tile(kept, self.tiling.image[0], tile, &planes);
        }
        self.dropped += self.session.dropped()?;
        if let Some(rays) = self.session.rays_counted()? {
            *self.rays.get_or_insert(0) += rays;
        }
        self.accumulated = self.session.accumulated();
        Ok(())
    }

    /// The current tile, all of whose frames a checkpoint brought: its image from the kept
    /// accumulation.
    fn finish_held_tile(&mut self) -> Result<(), RenderError> {
        let tile = self.tiles[self.current];
        let ChannelSelection::Planes(channels) = &self.channel else {
            return Err(RenderError::Other(format!(
                "--channel {}: tiles a checkpoint brought finished can show only channels of the accumulation (sum, l0, direct, indirect, ambient)",
                self.channel
            )));
        };
        let kept = self.kept.as_ref().ok_or_else(|| {
            RenderError::Other("a resumed tiled render keeps its accumulation".into())
        })?;
        let planes = cut_tile(kept, self.tiling.image[0], tile);
        let part = RgbImage::from_result(
            &planes_to_result(&planes),
            tile.size[0],
            tile.size[1],
            channels,
        );
        self.paste_image(tile, &part);
        let frames = self.settings.max_frames;
        self.dropped += u32::try_from(dropped_of(&planes, frames)).unwrap_or(u32::MAX);
        self.accumulated = frames;
        Ok(())
    }

    fn paste_image(&mut self, tile: Tile, part: &RgbImage) {
        let width = self.image.width as usize;
        for (y, row) in part.pixels.chunks_exact(tile.size[0] as usize).enumerate() {
            let start = (tile.origin[1] as usize + y) * width + tile.origin[0] as usize;
            self.image.pixels[start..start + row.len()].copy_from_slice(row);
        }
    }

    fn steps_left(&self) -> u64 {
        let frames = self.settings.max_frames;
        (self.current..self.tiles.len())
            .map(|i| {
                let done = if i == self.current {
                    self.session.accumulated().max(self.held[i])
                } else {
                    self.held[i]
                };
                u64::from(frames.saturating_sub(done))
            })
            .sum()
    }

    fn resume_from(&mut self, checkpoint: &Partial) -> Result<(), RenderError> {
        let fail = |why: String| Err(RenderError::Other(why));
        if self.current != 0 || self.session.accumulated() != 0 {
            return fail("a render resumes before its first frame".into());
        }
        if checkpoint.size != self.tiling.image {
            return fail(format!(
                "the checkpoint is {}x{}, this render {}x{}",
                checkpoint.size[0], checkpoint.size[1], self.tiling.image[0], self.tiling.image[1]
            ));
        }
        if checkpoint.samples.start != self.first_sample {
            return fail(format!(
                "the checkpoint holds samples {}, but this render starts at sample {}",
                checkpoint.samples, self.first_sample
            ));
        }
        let frames = self.settings.max_frames;
        let held: Vec<u32> = match checkpoint.progress {
            None => vec![checkpoint.samples.len(); self.tiles.len()],
            Some(p) if p.tile != self.tiling.tile => {
                return fail(format!(
                    "the checkpoint is of a render in tiles of {}x{}, this one in tiles of {}x{}: resume it with --tile {}x{}",
                    p.tile[0],
                    p.tile[1],
                    self.tiling.tile[0],
                    self.tiling.tile[1],
                    p.tile[0],
                    p.tile[1]
                ));
            }
            Some(p) if checkpoint.samples.len() != frames => {
                return fail(format!(
                    "the checkpoint's finished tiles hold samples {} ({p}); a render of another number of frames ({}) cannot continue it: give --frames {} (or --samples {})",
                    checkpoint.samples, frames, checkpoint.samples.end, checkpoint.samples
                ));
            }
            Some(_) => checkpoint
                .tiles_held()
                .map_err(RenderError::Other)?
                .into_iter()
                .map(|(_, n)| n)
                .collect(),
        };
        if let Some(&most) = held.iter().max()
            && most > frames
        {
            return fail(format!(
                "the checkpoint holds {most} frames, more than the {frames} this render has"
            ));
        }
        self.held = held;
        self.kept = Some(checkpoint.planes.clone());
        self.enter_tile()
    }

    fn accumulation(
        &self,
        start: u32,
        fingerprint: &Fingerprint,
        source: &str,
    ) -> Result<Partial, String> {
        let mut planes = self
            .kept
            .clone()
            .ok_or("this tiled render does not keep its accumulation")?;
        let mut dropped = u64::from(self.dropped);
        let progress = match self.tiles.get(self.current) {
            None => None,
            Some(&tile) => {
                let next = self.session.accumulated();
                if next > 0 {
                    let part = session_planes(&self.session).map_err(|e| e.to_string())?;
                    paste_tile(&mut planes, self.tiling.image[0], tile, &part);
                    dropped += u64::from(self.session.dropped().map_err(|e| e.to_string())?);
                } else if self.current == 0 {
                    return Err("no frame is rendered yet: nothing to write".into());
                }
                Some(TileProgress {
                    tile: self.tiling.tile,
                    done: self.current as u32,
                    next,
                })
            }
        };
        let partial = Partial {
            size: self.tiling.image,
            samples: SampleRange {
                start,
                end: start + self.settings.max_frames,
            },
            dropped,
            fingerprint: fingerprint.clone(),
            source: source.to_string(),
            planes,
            progress,
        };
        partial.check().map_err(|e| format!("the render's {e}"))?;
        Ok(partial)
    }
}

/// The accumulation of `session` so far as a partial file of samples `start..start + n`.
fn whole_accumulation(
    session: &Session,
    start: u32,
    fingerprint: &Fingerprint,
    source: &str,
) -> Result<Partial, String> {
    let samples = SampleRange {
        start,
        end: start + session.accumulated(),
    };
    if samples.is_empty() {
        return Err("no frame is rendered yet: nothing to write".into());
    }
    Partial::from_buffers(
        session.tile().image,
        samples,
        u64::from(session.dropped().map_err(|e| e.to_string())?),
        fingerprint.clone(),
        source.to_string(),
        &session.result().map_err(|e| e.to_string())?,
        &session.compensation().map_err(|e| e.to_string())?,
    )
}

/// The accumulation of `session`'s tile, read back.
fn session_planes(session: &Session) -> Result<Vec<Plane>, RenderError> {
    let [w, h] = session.tile().size;
    Ok(planes_from_buffers(
        w as usize * h as usize,
        &session.result()?,
        &session.compensation()?,
    ))
}

/// Samples of `frames` per pixel that the counts of `planes` leave out.
fn dropped_of(planes: &[Plane], frames: u32) -> u64 {
    planes.first().map_or(0, |p| {
        p.count
            .iter()
            .map(|&n| u64::from(frames.saturating_sub(n)))
            .sum()
    })
}

fn tile_session(
    ctx: GpuContext,
    graph: &LoadedGraph,
    settings: &RenderSettings,
    channel: &ChannelSelection,
    tile: Tile,
    scene: &(Scene, SceneGpu),
    keep: bool,
) -> Result<Session, RenderError> {
    let plan = compile_for(graph, tile.size, Some(channel), keep)?;
    Session::from_plan(ctx, graph, plan, settings, tile, scene.clone())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_largest_tiling_is_even_and_fits() {
        // The limit of lavapipe's result buffer: 1,677,721 pixels.
        let fits = |s: [u32; 2]| Ok(u64::from(s[0]) * u64::from(s[1]) <= 134_217_728 / 80);
        let t = largest_tiling([1920, 1080], &fits).unwrap();
        assert_eq!(t.tile, [1920, 544]);
        let t = largest_tiling([3840, 2160], &fits).unwrap();
        assert_eq!(t.tile, [3840, 432]);
        assert_eq!(t.tiles().len(), 5);
        // Wider than any strip of 8 rows: columns too.
        let t = largest_tiling([300_000, 64], &fits).unwrap();
        assert!(
            t.tile[0] * 8 <= 1_677_721 && t.tile[0].is_multiple_of(8),
            "{t:?}"
        );
        let untiled = largest_untiled([1920, 1080], &fits).unwrap();
        assert_eq!(untiled, [1727, 971]);
    }
}
