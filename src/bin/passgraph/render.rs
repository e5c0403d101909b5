//! `passgraph render`: the main job. Everything that can be checked is checked before the
//! first frame; checkpoints, partial files and outputs are written whole or not at all.

use crate::args::*;
use crate::camera_path::*;
use crate::output::*;
use passgraph::bench::metrics::image_error;
use passgraph::render::camera_path::load_camera_path;
use passgraph::render::channels::ChannelSelection;
use passgraph::render::checkpoint::{Checkpoints, resume};
use passgraph::render::fingerprint::Fingerprint;
use passgraph::render::image::{RgbImage, check_output_path};
use passgraph::render::partial::{MAX_RANGE, Packing, Partial, SampleRange};
use passgraph::render::session::{Keep, RenderSettings};
use passgraph::render::tiles::ImageRender;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

#[derive(clap::Args)]
pub(crate) struct RenderArgs {
    /// The graph to run.
    #[arg(long, default_value = DEFAULT_GRAPH)]
    pub(crate) graph: PathBuf,
    #[command(flatten)]
    pub(crate) scene: SceneArgs,
    /// Frames to accumulate (one sample per pixel each); default: a Mitsuba scene's sampler
    /// sample_count, else 1000.
    #[arg(long, value_parser = parse_frames)]
    pub(crate) frames: Option<u32>,
    /// Render only the samples (frame indices) A to B-1 of the accumulation `--frames B` would
    /// render, e.g. 64..128: same seeds and sampler dimensions, so partials of ranges merge
    /// into the whole render (`passgraph merge`).
    #[arg(long, value_name = "A..B", conflicts_with_all = ["frames", "camera_path"])]
    pub(crate) samples: Option<SampleRange>,
    /// Write the accumulation as a partial file (EXR: per channel mean, compensation and
    /// sample count; the range and a fingerprint of graph, scene and settings) for `passgraph
    /// merge`: of --samples A..B, or of 0..N with --frames N. No image unless --out is given.
    #[arg(long, value_name = "PART.exr", conflicts_with = "camera_path")]
    pub(crate) partial: Option<PathBuf>,
    /// Write the accumulation so far to this partial file (a checkpoint) every
    /// --checkpoint-every seconds, when SIGTERM, SIGINT or SIGHUP arrives (then end as that
    /// signal would) and when done; --resume continues from it. A render in tiles checkpoints
    /// its finished tiles and the current one's frames.
    #[arg(long, value_name = "CKPT.exr", conflicts_with = "camera_path")]
    pub(crate) checkpoint: Option<PathBuf>,
    /// Seconds between checkpoints (default 300; 0: after every frame).
    #[arg(long, value_name = "SECONDS", requires = "checkpoint", value_parser = parse_interval)]
    pub(crate) checkpoint_every: Option<f64>,
    /// Continue the render a checkpoint (or partial file) of the same graph, scene and settings
    /// holds: the result is bit for bit that of the render never stopped. A checkpoint written
    /// inside a tiled render resumes in tiles of its size.
    #[arg(long, value_name = "CKPT.exr", conflicts_with = "camera_path")]
    pub(crate) resume: Option<PathBuf>,
    /// Image size, WxH; default: a Mitsuba scene's film size, else 256x256.
    #[arg(long, value_parser = parse_size)]
    pub(crate) size: Option<[u32; 2]>,
    /// Render in tiles of WxH (sides multiples of 8), one after another, bit for bit the
    /// whole image; without it, only an image over the device's limits is tiled.
    #[arg(long, value_parser = parse_size, conflicts_with = "camera_path")]
    pub(crate) tile: Option<[u32; 2]>,
    /// Random seed: the same seed gives the same image on the same adapter.
    #[arg(long, default_value_t = 0)]
    pub(crate) seed: u32,
    /// Channel(s) to write: sum, l0, direct, indirect, ambient, a '+'-joined list, or an output texture of the graph (e.g. denoised).
    #[arg(long, default_value = "sum")]
    pub(crate) channel: ChannelSelection,
    /// Override a graph param: INSTANCE.PARAM=VALUE (repeatable).
    #[arg(long = "set")]
    pub(crate) set: Vec<String>,
    /// Output image: .png (sRGB, clamped) or .exr (linear float32). Repeatable. Default
    /// render.png, or none with --partial.
    #[arg(long = "out")]
    pub(crate) out: Vec<PathBuf>,
    /// Use the first adapter whose printed line (name, backend, driver, e.g. "llvmpipe",
    /// "vulkan", "mesa 25") contains this, ignoring case (also env PASSGRAPH_ADAPTER).
    #[arg(long)]
    pub(crate) adapter: Option<String>,
    /// A linear EXR of the same size to report the error against (RMSE, relMSE, bias).
    #[arg(long)]
    pub(crate) reference: Option<PathBuf>,
    /// Render a scripted camera path (RON, see src/render/camera_path.rs) instead of --frames
    /// at the scene's camera; segments with a reference report their error after every frame.
    #[arg(long, conflicts_with = "frames")]
    pub(crate) camera_path: Option<PathBuf>,
    /// With --camera-path: write the per-frame errors as CSV.
    #[arg(long, requires = "camera_path")]
    pub(crate) error_csv: Option<PathBuf>,
    /// With --camera-path: render segment K (from 1) alone, as the whole path renders it (a
    /// unit a job system can distribute); K must start an accumulation (move the camera).
    #[arg(long, value_name = "K", requires = "camera_path", value_parser = parse_frames)]
    pub(crate) segment: Option<u32>,
}

/// `--size` and `--frames`, or where not given a Mitsuba scene's film size and sample count,
/// else 256x256 and 1000 frames.
pub(crate) fn render_size_and_frames(args: &RenderArgs) -> Result<([u32; 2], u32), Failure> {
    let film = if (args.size.is_none() || args.frames.is_none())
        && passgraph::scene::is_mitsuba_xml(&args.scene.path)
    {
        Some(
            passgraph::scene::mitsuba_xml::film_defaults(&args.scene.path, &args.scene.define)
                .map_err(|e| e.to_string())?,
        )
    } else {
        None
    };
    let size = args
        .size
        .or(film.map(|f| f.0))
        .unwrap_or(RenderSettings::DEFAULT_SIZE);
    let frames = args
        .frames
        .or(film.map(|f| f.1))
        .unwrap_or(RenderSettings::DEFAULT_MAX_FRAMES);
    Ok((size, frames))
}

pub(crate) fn render(mut args: RenderArgs) -> Result<(), Failure> {
    let (size, frames) = render_size_and_frames(&args)?;
    let range = check_before_rendering(&mut args, size, frames)?;
    let reference = match &args.reference {
        Some(path) => {
            let reference = RgbImage::read_exr(path)?;
            if [reference.width, reference.height] != size {
                return Err(format!(
                    "{}: the reference is {}x{} but --size is {}x{}",
                    path.display(),
                    reference.width,
                    reference.height,
                    size[0],
                    size[1]
                )
                .into());
            }
            Some((path, reference))
        }
        None => None,
    };
    let settings = RenderSettings {
        graph: args.graph,
        scene: args.scene.path,
        size,
        seed: args.seed,
        set: args.set,
        adapter: args.adapter.clone(),
        // A camera path restarts the accumulation at each move: no cap. A range of samples
        // counts its own frames (past the default 1000 too).
        max_frames: if args.camera_path.is_some() {
            u32::MAX
        } else {
            range.len()
        },
        keep: Keep::Outputs,
        max_depth: args.scene.max_depth,
        defines: args.scene.define.clone(),
        camera: args.scene.camera.clone(),
    };
    // A checkpoint written inside a tiled render resumes in tiles of its size: read first.
    let checkpoint_in = match &args.resume {
        Some(path) => Some((path.as_path(), Partial::read(path)?)),
        None => None,
    };
    let mut tile = args.tile;
    if let Some(progress) = checkpoint_in.as_ref().and_then(|(_, c)| c.progress) {
        let asked = tile
            .map(|t| passgraph::render::tiling::Tiling::new(size, t).map(|t| t.tile))
            .transpose()
            .map_err(Failure::Usage)?;
        if asked.is_some_and(|t| t != progress.tile) {
            return Err(Failure::Usage(format!(
                "{}: the checkpoint is of a render in tiles of {}x{}, stopped inside a tile; it resumes in tiles of that size only (leave out --tile, or give --tile {}x{})",
                args.resume.as_deref().unwrap_or(Path::new("")).display(),
                progress.tile[0],
                progress.tile[1],
                progress.tile[0],
                progress.tile[1]
            )));
        }
        tile = Some(progress.tile);
    }
    // A partial file, a checkpoint or a resumed render reads or writes the whole accumulation.
    let keep_accumulation =
        args.partial.is_some() || args.checkpoint.is_some() || args.resume.is_some();
    let mut render = ImageRender::for_render(&settings, &args.channel, tile, keep_accumulation)
        .map_err(|e| e.to_string())?;
    let fingerprint = if keep_accumulation {
        Some(Fingerprint::of(&settings, render.session())?)
    } else {
        None
    };
    render.start_at_sample(range.start);
    if args.checkpoint.is_some()
        && let Some(name) = render.session().state_beyond_accumulation()
    {
        return Err(format!(
            "{}: keeps state in '{name}' from frame to frame, which a checkpoint does not hold: checkpoint a graph whose only history is its accumulation (e.g. graphs/pathtracer-fast.ron)",
            settings.graph.display()
        )
        .into());
    }
    let source = format!(
        "graph {}, scene {}, adapter {}",
        settings.graph.display(),
        settings.scene.display(),
        passgraph::gpu::context::describe(render.session().context().adapter_info())
    );
    let resumed = match (&checkpoint_in, &fingerprint) {
        (Some((path, checkpoint)), Some(fingerprint)) => Some(resume(
            path,
            checkpoint,
            &mut render,
            fingerprint,
            range.end,
        )?),
        _ => None,
    };
    let mut checkpoints = args.checkpoint.clone().map(|path| {
        // The first signal now asks for a checkpoint; a second still ends the process at once.
        passgraph::atomic_write::defer_signals();
        Checkpoints::new(
            path,
            Duration::from_secs_f64(args.checkpoint_every.unwrap_or(300.0)),
        )
    });
    if range.start > 0 && !range.is_power_of_two_aligned() {
        eprintln!(
            "note: samples {range} are not a power-of-two block aligned to its length (e.g. 64..128); with the Sobol sampler this range alone is less evenly stratified than such a block, though a merge of ranges is the same as the whole render"
        );
    }
    let session = render.session();
    let segments = match &args.camera_path {
        Some(path) => Some(load_camera_path(path, session.scene_description().camera)?),
        None => None,
    };
    describe(&render);
    let start = Instant::now();
    // The frames of the camera path's segments rendered, all of them (not only the last's).
    let mut path_frames = None;
    if let Some(segments) = &segments {
        let session = render.whole_mut().ok_or_else(|| {
            "--camera-path renders whole images only: use a smaller --size".to_string()
        })?;
        let (segments, first) = match args.segment {
            Some(k) => {
                let path = args.camera_path.as_deref().unwrap_or(Path::new(""));
                let (segment, frames_before) = one_segment(path, segments, k)?;
                session.skip_frames(frames_before);
                (std::slice::from_ref(segment), (k, frames_before))
            }
            None => (segments.as_slice(), (1, 0)),
        };
        path_frames = Some(segments.iter().map(|s| u64::from(s.frames)).sum::<u64>());
        let rows = render_camera_path(session, segments, first, &args.channel)?;
        if let Some(csv) = &args.error_csv {
            let mut text = String::from("frame,segment,accumulated,rmse,relmse,bias\n");
            for r in &rows {
                text += &format!(
                    "{},{},{},{},{},{}\n",
                    r.frame, r.segment, r.accumulated, r.error.rmse, r.error.relmse, r.error.bias
                );
            }
            passgraph::atomic_write::write_text(csv, &text)?;
        }
    }
    if let (Some((path, _)), Some(held)) = (&checkpoint_in, &resumed) {
        eprintln!("resumed from {}, which holds {held}", path.display());
    }
    // Tiles are rendered one after another: the bar counts frames of tiles. A camera path
    // renders its own frames above.
    let steps = if segments.is_some() {
        0
    } else {
        render.steps_left()
    };
    let bar = indicatif::ProgressBar::new(steps);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} frames {per_sec} eta {eta}")
            .map_err(|e| e.to_string())?,
    );
    for _ in 0..steps {
        render.render_frame().map_err(|e| e.to_string())?;
        bar.inc(1);
        if let (Some(checkpoints), Some(fingerprint)) = (&mut checkpoints, &fingerprint) {
            let signal = passgraph::atomic_write::pending_signal();
            if signal.is_some() || checkpoints.due() {
                let held = checkpoints.write(&render, range.start, fingerprint, &source)?;
                // A line each, for a farm's log (and for tests to act on).
                bar.suspend(|| {
                    eprintln!(
                        "checkpoint: {held} in {} ({:.1} ms)",
                        checkpoints.path.display(),
                        checkpoints
                            .costs
                            .last()
                            .map_or(0.0, |c| c.as_secs_f64() * 1e3)
                    )
                });
            }
            if let Some(signal) = signal {
                bar.finish_and_clear();
                eprintln!(
                    "signal {signal}: the checkpoint is written; continue with --resume {}",
                    checkpoints.path.display()
                );
                passgraph::atomic_write::die_of(signal);
            }
        }
    }
    // Reading the result waits for the GPU, so the time below includes every frame's work.
    let image = render.image(&args.channel).map_err(|e| e.to_string())?;
    let seconds = start.elapsed().as_secs_f64();
    bar.finish_and_clear();
    let dropped = render.dropped().map_err(|e| e.to_string())?;
    // All outputs as a set: each is encoded and written beside its target before any replaces
    // an older file, so a failure leaves no new PNG beside an old EXR.
    let mut encoded = args
        .out
        .iter()
        .map(|path| Ok((path.as_path(), image.encode_for(path)?)))
        .collect::<Result<Vec<_>, String>>()?;
    // The partial file and the last checkpoint: the accumulation of the whole range.
    let accumulation_outputs: Vec<&PathBuf> = args
        .partial
        .iter()
        .chain(checkpoints.as_ref().map(|c| &c.path))
        .collect();
    if let (Some(first), Some(fingerprint)) = (accumulation_outputs.first(), &fingerprint) {
        let bytes = render
            .accumulation(range.start, fingerprint, &source)
            .and_then(|partial| partial.encode(Packing::Small))
            .map_err(|e| format!("{}: {e}", first.display()))?;
        for path in accumulation_outputs {
            encoded.push((path.as_path(), bytes.clone()));
        }
    }
    write_files(&encoded)?;
    if let Some(cost) = checkpoints.as_ref().and_then(|c| c.median_cost()) {
        eprintln!(
            "checkpoints: {} written during the render, {:.1} ms each (median)",
            checkpoints.as_ref().map_or(0, |c| c.costs.len()),
            cost.as_secs_f64() * 1e3
        );
    }
    if let Some((path, reference)) = &reference {
        let e = image_error(&image, reference).map_err(|e| format!("{}: {e}", path.display()))?;
        say_line(&format!(
            "error of {} against {}: RMSE {:.5}, relMSE {:.3e}, bias {:+.5}",
            args.channel,
            path.display(),
            e.rmse,
            e.relmse,
            e.bias
        ))?;
    }
    // The frames this process rendered (not those a checkpoint brought; a camera path's in
    // every segment); in tiles, steps over tiles (a fraction after a resume inside a tile).
    let frames = path_frames.map_or(steps as f64 / render.tile_count() as f64, |f| f as f64);
    let fps = frames / seconds;
    let samples = match (args.samples, &resumed) {
        (_, Some(held)) => format!(" (samples {range}, after {held} resumed)"),
        (Some(range), None) => format!(" (samples {range})"),
        (None, None) => String::new(),
    };
    let rays = match render.rays_counted().map_err(|e| e.to_string())? {
        Some(counted) => format!("{:.2} Mrays/s", counted as f64 / seconds / 1e6),
        None => "rays not counted (no pass binds ray_count)".to_string(),
    };
    say_line(&format!(
        "{frames} frames{samples} in {seconds:.2} s: {fps:.1} frames/s, {rays}, {dropped} dropped samples; wrote {}",
        args.out
            .iter()
            .chain(&args.partial)
            .chain(&args.checkpoint)
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    ))?;
    Ok(())
}

/// A partial file's path: an `.exr` that can be written, and not also an image output (one
/// would silently replace the other).
pub(crate) fn check_partial_path(path: &std::path::Path, images: &[PathBuf]) -> Result<(), String> {
    if images.iter().any(|image| image == path) {
        return Err(format!(
            "{}: given as both --partial and --out; a partial file is not an image",
            path.display()
        ));
    }
    let is_exr = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    if !is_exr {
        return Err(format!(
            "{}: a partial file is an OpenEXR file: name it .exr",
            path.display()
        ));
    }
    passgraph::atomic_write::check_target(path)
        .map_err(|e| format!("{}: cannot write: {e}", path.display()))
}

/// Everything that can be checked before rendering is: a mistake should not cost the frames.
/// Returns the samples to render; fills in the default output.
fn check_before_rendering(
    args: &mut RenderArgs,
    size: [u32; 2],
    frames: u32,
) -> Result<SampleRange, Failure> {
    if args.error_csv.is_some() && args.camera_path.is_none() {
        return Err(Failure::Usage(
            "--error-csv needs --camera-path (the errors it writes are a camera path's)".into(),
        ));
    }
    // The frames to render: a range of samples, or 0..--frames.
    let range = args.samples.unwrap_or(SampleRange {
        start: 0,
        end: frames,
    });
    if range.len() > MAX_RANGE {
        return Err(Failure::Usage(format!(
            "--samples {range} is {} samples long; one render holds at most {MAX_RANGE} (the GPU counts samples in f32): split it into shorter ranges and merge them",
            range.len()
        )));
    }
    if args.samples.is_some() && args.partial.is_none() && args.out.is_empty() {
        return Err(Failure::Usage(format!(
            "--samples {range} writes nothing: add --partial PART.exr (for `passgraph merge`) or --out IMAGE"
        )));
    }
    if args.out.is_empty() && args.partial.is_none() {
        args.out.push(PathBuf::from("render.png"));
    }
    for path in &args.out {
        check_output_path(path).map_err(Failure::Usage)?;
    }
    if let Some(tile) = args.tile {
        passgraph::render::tiling::Tiling::new(size, tile).map_err(Failure::Usage)?;
    }
    if let Some(path) = &args.partial {
        check_partial_path(path, &args.out).map_err(Failure::Usage)?;
    }
    if let Some(path) = &args.checkpoint {
        check_partial_path(path, &args.out).map_err(Failure::Usage)?;
        if args.partial.as_ref() == Some(path) {
            return Err(Failure::Usage(format!(
                "{}: given as both --partial and --checkpoint; the final checkpoint is the partial of the whole range already",
                path.display()
            )));
        }
    }
    if let Some(csv) = &args.error_csv {
        passgraph::atomic_write::check_target(csv)
            .map_err(|e| Failure::Usage(format!("{}: cannot write: {e}", csv.display())))?;
    }
    // No output may replace an input, but a checkpoint may replace the one it resumes from
    // (with more samples).
    let mut inputs: Vec<(&str, &Path)> = Vec::new();
    if let Some(path) = &args.reference {
        inputs.push(("the --reference", path));
    }
    if let Some(path) = &args.camera_path {
        inputs.push(("the --camera-path", path));
    }
    let checkpoint: Vec<&Path> = args.checkpoint.iter().map(PathBuf::as_path).collect();
    passgraph::atomic_write::refuse_outputs_that_are_inputs(&checkpoint, &inputs)
        .map_err(Failure::Usage)?;
    if let Some(path) = &args.resume {
        inputs.push(("the --resume checkpoint", path));
    }
    let outputs: Vec<&Path> = args
        .out
        .iter()
        .chain(&args.partial)
        .chain(&args.error_csv)
        .map(PathBuf::as_path)
        .collect();
    passgraph::atomic_write::refuse_outputs_that_are_inputs(&outputs, &inputs)
        .map_err(Failure::Usage)?;
    Ok(range)
}

/// What the render runs on and with, on stderr: adapter, scene, BVH, specialised values,
/// culled and unspecialised passes, memory.
fn describe(render: &ImageRender) {
    let session = render.session();
    for warning in &session.scene_description().mesh.warnings {
        eprintln!("warning: {warning}");
    }
    let info = session.context().adapter_info();
    let scene = session.scene();
    let bvh = &scene.bvh;
    let scene_bytes = scene.byte_len();
    eprintln!("adapter: {}", passgraph::gpu::context::describe(info));
    // The reuse pass groups lanes of a subgroup (shaders/path_reuse.wgsl): its width matters.
    if info.subgroup_max_size > 0 {
        eprintln!(
            "subgroups: {}..{} lanes",
            info.subgroup_min_size, info.subgroup_max_size
        );
    }
    eprintln!(
        "scene: {} triangles ({} degenerate), {} lights; BVH {} nodes, depth {}, built in {:.1} ms; {} bytes on the GPU ({:.1} per triangle)",
        bvh.triangle_count,
        bvh.degenerate_count,
        scene.light_count,
        bvh.node_count,
        bvh.max_depth,
        bvh.build_time.as_secs_f64() * 1e3,
        scene_bytes,
        scene_bytes as f64 / bvh.triangle_count.max(1) as f64
    );
    eprintln!(
        "specialised: scene_light_count={}, scene_has_specular={}, scene_max_depth={}",
        scene.light_count, scene.has_specular, scene.max_depth
    );
    for c in &session.plan().culled {
        eprintln!("culled {}: {}", c.name, c.reason);
    }
    // Never silent: the image is the same, but such a pipeline takes longer to create.
    for (pass, why) in session.unspecialised() {
        eprintln!(
            "warning: pass '{pass}' is not specialised to its override values ({why}); its pipeline was built from the WGSL as written"
        );
    }
    eprintln!("{}", render.memory_line());
}
