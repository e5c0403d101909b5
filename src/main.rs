//! The `passgraph` command line: parse, call the library, print.

use clap::{Parser, Subcommand};
use passgraph::bench::metrics::image_error;
use passgraph::bench::variant::Variant;
use passgraph::render::camera_path::{Segment, load_camera_path};
use passgraph::render::channels::{Channel, ChannelSelection};
use passgraph::render::checkpoint::{Checkpoints, resume};
use passgraph::render::fingerprint::Fingerprint;
use passgraph::render::image::{RgbImage, check_output_path};
use passgraph::render::partial::{MAX_RANGE, Packing, Partial, SampleRange};
use passgraph::render::session::{Keep, RenderSettings, Session, check_render_contract};
use passgraph::render::tiles::ImageRender;
use passgraph::{GraphError, compile_file, to_dot};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

/// Built-in defaults, so `cargo run --release` alone renders the Cornell box.
const DEFAULT_GRAPH: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/graphs/pathtracer.ron");
const DEFAULT_SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/cornell/scene.ron");

#[derive(Parser)]
#[command(
    name = "passgraph",
    version,
    about = "A render graph of WGSL compute passes described in RON",
    args_conflicts_with_subcommands = true
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Without a command: `render` with these options (the Cornell box by default).
    #[command(flatten)]
    render: RenderArgs,
}

#[derive(Subcommand)]
enum Command {
    /// Load and compile a graph, and check it has what `render` reads back; report the first
    /// error.
    Check {
        #[command(flatten)]
        graph: GraphArgs,
        /// Check only the framework's rules, not what `render` needs (`result`, `dropped`,
        /// ray counts): for graphs run through the library.
        #[arg(long)]
        generic: bool,
    },
    /// Print the compiled plan: stages, barriers, culled passes, lifetimes and reuse.
    Plan {
        #[command(flatten)]
        graph: GraphArgs,
        /// Print a pass x resource chart instead: who writes and reads each resource, where it
        /// is alive, and which memory object holds it.
        #[arg(long)]
        chart: bool,
    },
    /// Render a scene progressively with a graph and write images.
    Render(RenderArgs),
    /// Combine partial files of consecutive sample ranges of one render (written by `render
    /// --samples A..B --partial`) into its image and, optionally, one partial of the union.
    Merge(MergeArgs),
    /// Speed against error: render graph variants, measure the error against a reference at
    /// log-spaced checkpoints, write CSVs, a log-log chart and a markdown report.
    Bench(BenchArgs),
    /// Open a window showing the image as it accumulates: fly camera, channel keys, hot reload.
    View(ViewArgs),
    /// Run graph test files (RON): per case, build the graph, render the scene for its
    /// frames and seeds, check the plan's shape and image statistics; one line per case.
    Test {
        /// Test files, e.g. tests/graphs/*.ron.
        #[arg(required = true)]
        files: Vec<PathBuf>,
        /// Print every expectation's measured value, passed or not (to derive a new case's
        /// bounds, e.g. over many seeds).
        #[arg(long)]
        measure: bool,
        #[arg(long)]
        adapter: Option<String>,
    },
    /// Write the scene for Mitsuba 3: DIR/scene.xml (parameters $spp, $sampler_type,
    /// $max_depth, $seed with defaults) and one OBJ per material.
    MitsubaScene {
        /// The scene file (RON naming a mesh and a camera, or a Mitsuba XML scene).
        scene: PathBuf,
        /// A Mitsuba XML scene's parameter, as `mitsuba -D`.
        #[arg(short = 'D', long = "define", value_name = "NAME=VALUE", value_parser = parse_define)]
        define: Vec<(String, String)>,
        /// A glTF scene's camera, by its name or its node's (default: the first).
        #[arg(long, value_name = "NAME")]
        camera: Option<String>,
        /// Output directory.
        #[arg(long)]
        out: PathBuf,
        /// Image size, WxH.
        #[arg(long, default_value = "256x256", value_parser = parse_size)]
        size: [u32; 2],
        /// Longest path in segments (replaces the scene file's).
        #[arg(long, value_parser = parse_max_depth)]
        max_depth: Option<u32>,
    },
    /// Print the graph in Graphviz dot format.
    Dot {
        #[command(flatten)]
        graph: GraphArgs,
        /// Write to this file instead of standard output.
        #[arg(long)]
        out: Option<PathBuf>,
    },
}

#[derive(clap::Args)]
struct GraphArgs {
    /// The graph file, e.g. graphs/pathtracer.ron.
    graph: PathBuf,
    /// Output size the plan is made for, WxH.
    #[arg(long, default_value = "256x256", value_parser = parse_size)]
    size: [u32; 2],
}

#[derive(clap::Args)]
struct RenderArgs {
    /// The graph to run.
    #[arg(long, default_value = DEFAULT_GRAPH)]
    graph: PathBuf,
    /// The scene file: RON naming a mesh and a camera, or a Mitsuba 3 scene (.xml).
    #[arg(long, default_value = DEFAULT_SCENE)]
    scene: PathBuf,
    /// A Mitsuba XML scene's parameter, as `mitsuba -D`: replaces its <default name="NAME">.
    #[arg(short = 'D', long = "define", value_name = "NAME=VALUE", value_parser = parse_define)]
    define: Vec<(String, String)>,
    /// A glTF scene's camera, by its name or its node's (default: the first).
    #[arg(long, value_name = "NAME")]
    camera: Option<String>,
    /// Longest path in segments, as Mitsuba's max_depth (replaces the scene file's; default 3).
    #[arg(long, value_parser = parse_max_depth)]
    max_depth: Option<u32>,
    /// Frames to accumulate (one sample per pixel each); default: a Mitsuba scene's sampler
    /// sample_count, else 1000.
    #[arg(long, value_parser = parse_frames)]
    frames: Option<u32>,
    /// Render only the samples (frame indices) A to B-1 of the accumulation `--frames B` would
    /// render, e.g. 64..128: same seeds and sampler dimensions, so partials of ranges merge
    /// into the whole render (`passgraph merge`).
    #[arg(long, value_name = "A..B", conflicts_with_all = ["frames", "camera_path"])]
    samples: Option<SampleRange>,
    /// Write the accumulation as a partial file (EXR: per channel mean, compensation and
    /// sample count; the range and a fingerprint of graph, scene and settings) for `passgraph
    /// merge`: of --samples A..B, or of 0..N with --frames N. No image unless --out is given.
    #[arg(long, value_name = "PART.exr", conflicts_with = "camera_path")]
    partial: Option<PathBuf>,
    /// Write the accumulation so far to this partial file (a checkpoint) every
    /// --checkpoint-every seconds, when SIGTERM, SIGINT or SIGHUP arrives (then end as that
    /// signal would) and when done; --resume continues from it. A render in tiles checkpoints
    /// its finished tiles and the current one's frames.
    #[arg(long, value_name = "CKPT.exr", conflicts_with = "camera_path")]
    checkpoint: Option<PathBuf>,
    /// Seconds between checkpoints (default 300; 0: after every frame).
    #[arg(long, value_name = "SECONDS", requires = "checkpoint", value_parser = parse_interval)]
    checkpoint_every: Option<f64>,
    /// Continue the render a checkpoint (or partial file) of the same graph, scene and settings
    /// holds: the result is bit for bit that of the render never stopped. A checkpoint written
    /// inside a tiled render resumes in tiles of its size.
    #[arg(long, value_name = "CKPT.exr", conflicts_with = "camera_path")]
    resume: Option<PathBuf>,
    /// Image size, WxH; default: a Mitsuba scene's film size, else 256x256.
    #[arg(long, value_parser = parse_size)]
    size: Option<[u32; 2]>,
    /// Render in tiles of WxH (sides multiples of 8), one after another, bit for bit the
    /// whole image; without it, only an image over the device's limits is tiled.
    #[arg(long, value_parser = parse_size, conflicts_with = "camera_path")]
    tile: Option<[u32; 2]>,
    /// Random seed: the same seed gives the same image on the same adapter.
    #[arg(long, default_value_t = 0)]
    seed: u32,
    /// Channel(s) to write: sum, l0, direct, indirect, ambient, a '+'-joined list, or an output texture of the graph (e.g. denoised).
    #[arg(long, default_value = "sum")]
    channel: ChannelSelection,
    /// Override a graph param: INSTANCE.PARAM=VALUE (repeatable).
    #[arg(long = "set")]
    set: Vec<String>,
    /// Output image: .png (sRGB, clamped) or .exr (linear float32). Repeatable. Default
    /// render.png, or none with --partial.
    #[arg(long = "out")]
    out: Vec<PathBuf>,
    /// Use the first adapter whose printed line (name, backend, driver, e.g. "llvmpipe",
    /// "vulkan", "mesa 25") contains this, ignoring case (also env PASSGRAPH_ADAPTER).
    #[arg(long)]
    adapter: Option<String>,
    /// A linear EXR of the same size to report the error against (RMSE, relMSE, bias).
    #[arg(long)]
    reference: Option<PathBuf>,
    /// Render a scripted camera path (RON, see src/render/camera_path.rs) instead of --frames
    /// at the scene's camera; segments with a reference report their error after every frame.
    #[arg(long, conflicts_with = "frames")]
    camera_path: Option<PathBuf>,
    /// With --camera-path: write the per-frame errors as CSV.
    #[arg(long, requires = "camera_path")]
    error_csv: Option<PathBuf>,
    /// With --camera-path: render segment K (from 1) alone, as the whole path renders it (a
    /// unit a job system can distribute); K must start an accumulation (move the camera).
    #[arg(long, value_name = "K", requires = "camera_path", value_parser = parse_frames)]
    segment: Option<u32>,
}

#[derive(clap::Args)]
struct MergeArgs {
    /// Partial files of one render whose sample ranges join without gaps or overlaps, in any
    /// order.
    #[arg(required = true, value_name = "PART.exr")]
    partials: Vec<PathBuf>,
    /// Output image: .png (sRGB, clamped) or .exr (linear float32). Repeatable.
    #[arg(long = "out")]
    out: Vec<PathBuf>,
    /// Also write the merged partial (of the union of the ranges), itself mergeable.
    #[arg(long, value_name = "OUT.exr")]
    partial: Option<PathBuf>,
    /// Channel(s) to write: sum, l0, direct, indirect, ambient, or a '+'-joined list.
    #[arg(long, default_value = "sum")]
    channel: ChannelSelection,
}

#[derive(clap::Args)]
struct ViewArgs {
    #[arg(long, default_value = DEFAULT_GRAPH)]
    graph: PathBuf,
    #[arg(long, default_value = DEFAULT_SCENE)]
    scene: PathBuf,
    /// A Mitsuba XML scene's parameter, as `mitsuba -D`: replaces its <default name="NAME">.
    #[arg(short = 'D', long = "define", value_name = "NAME=VALUE", value_parser = parse_define)]
    define: Vec<(String, String)>,
    /// A glTF scene's camera, by its name or its node's (default: the first).
    #[arg(long, value_name = "NAME")]
    camera: Option<String>,
    /// Longest path in segments, as Mitsuba's max_depth (replaces the scene file's; default 3).
    #[arg(long, value_parser = parse_max_depth)]
    max_depth: Option<u32>,
    /// Image size, WxH; the window starts at twice this.
    #[arg(long, default_value = "256x256", value_parser = parse_size)]
    size: [u32; 2],
    #[arg(long, default_value_t = 0)]
    seed: u32,
    /// Override a graph param: INSTANCE.PARAM=VALUE (repeatable).
    #[arg(long = "set")]
    set: Vec<String>,
    #[arg(long)]
    adapter: Option<String>,
    /// Scripted input, one event per line: wait N, key K, hold K N, drag DX DY, scroll N, screenshot PATH.png, quit.
    #[arg(long)]
    script: Option<PathBuf>,
    /// Quit after this many frames.
    #[arg(long)]
    frames: Option<u32>,
}

#[derive(clap::Args)]
struct BenchArgs {
    #[arg(long, default_value = DEFAULT_SCENE)]
    scene: PathBuf,
    /// A Mitsuba XML scene's parameter, as `mitsuba -D`: replaces its <default name="NAME">.
    #[arg(short = 'D', long = "define", value_name = "NAME=VALUE", value_parser = parse_define)]
    define: Vec<(String, String)>,
    /// A glTF scene's camera, by its name or its node's (default: the first).
    #[arg(long, value_name = "NAME")]
    camera: Option<String>,
    /// Longest path in segments, as Mitsuba's max_depth (replaces the scene file's; default 3).
    #[arg(long, value_parser = parse_max_depth)]
    max_depth: Option<u32>,
    /// A graph variant (repeatable): [LABEL=]GRAPH[@CHANNEL][:INSTANCE.PARAM=VALUE,...];
    /// @CHANNEL compares CHANNEL instead of --channel (e.g. graphs/pathtracer-denoise.ron@denoised),
    /// :SETs override params for this variant only (see src/bench/variant.rs).
    #[arg(long = "graph", default_value = DEFAULT_GRAPH)]
    graphs: Vec<Variant>,
    /// Linear EXR reference of the scene at --size.
    #[arg(long, required_unless_present = "combine")]
    reference: Option<PathBuf>,
    /// Stop each variant after this much rendering time...
    #[arg(long, conflicts_with = "frames", value_parser = parse_seconds)]
    seconds: Option<f64>,
    /// ...or after this many frames (default 256).
    #[arg(long, value_parser = parse_frames)]
    frames: Option<u32>,
    #[arg(long, default_value = "256x256", value_parser = parse_size)]
    size: [u32; 2],
    #[arg(long, default_value_t = 0)]
    seed: u32,
    /// Channels compared with the reference (the physical image by default).
    #[arg(long, default_value = "l0+direct+indirect")]
    channel: ChannelSelection,
    /// Override a graph param in every variant: INSTANCE.PARAM=VALUE (repeatable).
    #[arg(long = "set")]
    set: Vec<String>,
    /// [LABEL=]CSV from scripts/mitsuba-reference to put on the same chart and tables
    /// (repeatable: one curve per label; a label given several CSVs, one per round, gets the
    /// median per sample count).
    #[arg(long)]
    mitsuba: Vec<String>,
    /// Render nothing: report the median per checkpoint of the runs earlier `bench --out DIR`
    /// runs wrote (repeatable: one DIR per round).
    #[arg(long, conflicts_with_all = ["reference", "seconds", "frames"])]
    combine: Vec<PathBuf>,
    /// Output directory.
    #[arg(long, default_value = "bench-out")]
    out: PathBuf,
    #[arg(long)]
    adapter: Option<String>,
}

/// The default label of a bare `--mitsuba CSV`.
const MITSUBA_LABEL: &str = "Mitsuba 3 (llvm_ad_rgb, CPU)";

/// `--mitsuba` arguments grouped by label, in the order given: LABEL=CSV, or CSV alone (a path
/// that exists as given is never split).
fn mitsuba_curves(args: &[String]) -> Vec<(String, Vec<PathBuf>)> {
    let mut curves: Vec<(String, Vec<PathBuf>)> = Vec::new();
    for arg in args {
        let (label, csv) = match arg.split_once('=') {
            Some((label, csv)) if !label.is_empty() && !std::path::Path::new(arg).exists() => {
                (label.to_string(), PathBuf::from(csv))
            }
            _ => (MITSUBA_LABEL.to_string(), PathBuf::from(arg)),
        };
        match curves.iter_mut().find(|(l, _)| *l == label) {
            Some((_, csvs)) => csvs.push(csv),
            None => curves.push((label, vec![csv])),
        }
    }
    curves
}

fn bench(args: BenchArgs) -> Result<(), Failure> {
    use passgraph::bench::{plot, report, rounds, series::Series};
    // Each variant writes <label>.csv: two variants with one label would overwrite each other.
    let mut labels = std::collections::BTreeMap::new();
    for variant in &args.graphs {
        if let Some(other) = labels.insert(&variant.label, &variant.graph) {
            return Err(Failure::Usage(format!(
                "--graph {} and --graph {} are both named '{}' in the report; bench each variant once",
                other.display(),
                variant.graph.display(),
                variant.label
            )));
        }
    }
    std::fs::create_dir_all(&args.out)
        .map_err(|e| format!("{}: cannot create: {e}", args.out.display()))?;
    let runs = if args.combine.is_empty() {
        let runs = bench_render(&args)?;
        rounds::write_runs(&args.out, &runs)?;
        runs
    } else {
        let read: Vec<_> = args
            .combine
            .iter()
            .map(|dir| rounds::read_runs(dir))
            .collect::<Result<_, _>>()?;
        let runs = rounds::combine(&read);
        for r in &runs {
            report::write_text(
                &args.out.join(format!("{}.csv", r.label)),
                &report::run_csv(r),
            )?;
        }
        runs
    };
    let mut extra = Vec::new();
    for (label, csvs) in mitsuba_curves(&args.mitsuba) {
        let paths: Vec<&std::path::Path> = csvs.iter().map(PathBuf::as_path).collect();
        extra.push(Series::from_mitsuba_csvs(&paths, &label)?);
    }
    let ours: Vec<Series> = runs.iter().map(Series::from_run).collect();
    let chart = args.out.join("error-vs-time.png");
    let scene_name = args.scene.display().to_string();
    plot::write_plot(
        &chart,
        &format!("relMSE against time: {scene_name}"),
        &ours,
        &extra,
    )?;
    let md = report::markdown(&runs, &extra);
    report::write_text(&args.out.join("report.md"), &md)?;
    say(&md)?;
    eprintln!("wrote {}", args.out.display());
    Ok(())
}

/// Renders every variant to the budget, writing each one's CSV as it finishes.
fn bench_render(args: &BenchArgs) -> Result<Vec<passgraph::bench::run::Run>, String> {
    use passgraph::bench::{report, run};
    let reference_path = args.reference.as_ref().ok_or("--reference is required")?;
    let reference = RgbImage::read_exr(reference_path)?;
    if [reference.width, reference.height] != args.size {
        return Err(format!(
            "{}: the reference is {}x{} but --size is {}x{}",
            reference_path.display(),
            reference.width,
            reference.height,
            args.size[0],
            args.size[1]
        ));
    }
    let budget = match (args.seconds, args.frames) {
        (Some(s), _) => run::Budget::Seconds(s),
        (None, f) => run::Budget::Frames(f.unwrap_or(256)),
    };
    // The scene, and every variant's graph, params and channel, are checked before the first
    // variant renders.
    let scene_options = passgraph::scene::SceneOptions {
        defines: args.define.clone(),
        max_depth: None,
        camera: args.camera.clone(),
    };
    let scene = passgraph::scene::load_scene_with(&args.scene, &scene_options)
        .map_err(|e| e.to_string())?
        .scene;
    for warning in &scene.mesh.warnings {
        eprintln!("warning: {warning}");
    }
    for variant in &args.graphs {
        let channel = variant.channel.as_ref().unwrap_or(&args.channel);
        let mut graph = passgraph::load_graph(&variant.graph).map_err(|e| e.to_string())?;
        for set in args.set.iter().chain(&variant.set) {
            passgraph::graph::set_param::set_param(&mut graph, set).map_err(|e| e.to_string())?;
        }
        let plan = passgraph::compile(&graph, args.size).map_err(|e| e.to_string())?;
        check_render_contract(&plan, channel).map_err(|e| format!("{}: {e}", variant.label))?;
    }
    let mut runs = Vec::new();
    for variant in &args.graphs {
        let label = &variant.label;
        let channel = variant.channel.as_ref().unwrap_or(&args.channel);
        let settings = RenderSettings {
            graph: variant.graph.clone(),
            scene: args.scene.clone(),
            size: args.size,
            seed: args.seed,
            set: args.set.iter().chain(&variant.set).cloned().collect(),
            adapter: args.adapter.clone(),
            max_frames: u32::MAX,
            keep: Keep::Outputs,
            max_depth: args.max_depth,
            defines: args.define.clone(),
            camera: args.camera.clone(),
        };
        eprintln!("bench {label} ...");
        let r =
            run::run(label, &settings, channel, &reference, budget).map_err(|e| e.to_string())?;
        if runs
            .last()
            .is_none_or(|p: &run::Run| p.adapter != r.adapter)
        {
            eprintln!("adapter: {}", r.adapter);
        }
        report::write_text(&args.out.join(format!("{label}.csv")), &report::run_csv(&r))?;
        runs.push(r);
    }
    Ok(runs)
}

/// The error after one frame of a camera path segment that has a reference.
struct PathError {
    frame: u32,
    segment: usize,
    accumulated: u32,
    error: passgraph::bench::metrics::ImageError,
}

/// Segment `k` (from 1) of a camera path, and the frames of the segments before it. A segment
/// that keeps the previous one's camera continues its accumulation, so it cannot be rendered
/// alone.
fn one_segment<'a>(
    path: &Path,
    segments: &'a [Segment],
    k: u32,
) -> Result<(&'a Segment, u32), String> {
    let i = k as usize - 1;
    let Some(segment) = segments.get(i) else {
        return Err(format!(
            "{}: --segment {k}: the path has {} segments",
            path.display(),
            segments.len()
        ));
    };
    if i > 0 && segments[i - 1].camera == segment.camera {
        return Err(format!(
            "{}: --segment {k}: segment {k} keeps segment {i}'s camera, so it continues that accumulation and cannot be rendered alone (render from the segment that moves the camera)",
            path.display()
        ));
    }
    let before = segments[..i]
        .iter()
        .try_fold(0u32, |sum, s| sum.checked_add(s.frames))
        .ok_or_else(|| {
            format!(
                "{}: more than 2^32 frames before segment {k}",
                path.display()
            )
        })?;
    Ok((segment, before))
}

/// Renders each segment at its camera (a move restarts the accumulation; a reprojecting graph
/// keeps what it can) and measures `channel` after every frame of segments with a reference.
fn render_camera_path(
    session: &mut Session,
    segments: &[Segment],
    (first_segment, frames_before): (u32, u32),
    channel: &ChannelSelection,
) -> Result<Vec<PathError>, String> {
    // Every reference is read and checked before the first frame.
    let [w, h] = session.plan().output_size;
    let mut references = Vec::with_capacity(segments.len());
    for segment in segments {
        references.push(match &segment.reference {
            Some(path) => {
                let image = RgbImage::read_exr(path)?;
                if [image.width, image.height] != [w, h] {
                    return Err(format!(
                        "{}: the reference is {}x{} but --size is {w}x{h}",
                        path.display(),
                        image.width,
                        image.height
                    ));
                }
                Some((path, image))
            }
            None => None,
        });
    }
    let mut rows = Vec::new();
    let mut frame = frames_before;
    for (i, (segment, reference)) in segments.iter().zip(&references).enumerate() {
        let number = first_segment as usize + i;
        if segment.camera != session.scene_description().camera {
            session
                .set_camera(segment.camera)
                .map_err(|e| e.to_string())?;
        }
        for _ in 0..segment.frames {
            session.render_frame().map_err(|e| e.to_string())?;
            frame += 1;
            let Some((path, reference)) = &reference else {
                continue;
            };
            let image = session.image(channel).map_err(|e| e.to_string())?;
            let error =
                image_error(&image, reference).map_err(|e| format!("{}: {e}", path.display()))?;
            say_line(&format!(
                "frame {frame} (segment {number}, {} accumulated): RMSE {:.5}, relMSE {:.3e}",
                session.accumulated(),
                error.rmse,
                error.relmse
            ))?;
            rows.push(PathError {
                frame,
                segment: number,
                accumulated: session.accumulated(),
                error,
            });
        }
    }
    Ok(rows)
}

/// `--size` and `--frames`, or where not given a Mitsuba scene's film size and sample count,
/// else 256x256 and 1000 frames.
fn render_size_and_frames(args: &RenderArgs) -> Result<([u32; 2], u32), Failure> {
    let film = if (args.size.is_none() || args.frames.is_none())
        && passgraph::scene::is_mitsuba_xml(&args.scene)
    {
        Some(
            passgraph::scene::mitsuba_xml::film_defaults(&args.scene, &args.define)
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

fn render(mut args: RenderArgs) -> Result<(), Failure> {
    let (size, frames) = render_size_and_frames(&args)?;
    // Everything that can be checked before rendering is: a mistake should not cost the frames.
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
        passgraph::render::tiles::Tiling::new(size, tile).map_err(Failure::Usage)?;
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
        scene: args.scene,
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
        max_depth: args.max_depth,
        defines: args.define.clone(),
        camera: args.camera.clone(),
    };
    // A checkpoint written inside a tiled render resumes in tiles of its size: read first.
    let checkpoint_in = match &args.resume {
        Some(path) => Some((path.as_path(), Partial::read(path)?)),
        None => None,
    };
    let mut tile = args.tile;
    if let Some(progress) = checkpoint_in.as_ref().and_then(|(_, c)| c.progress) {
        let asked = tile
            .map(|t| passgraph::render::tiles::Tiling::new(size, t).map(|t| t.tile))
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
    for warning in &session.scene_description().mesh.warnings {
        eprintln!("warning: {warning}");
    }
    let info = session.context().adapter_info();
    let scene = session.scene();
    let bvh = &scene.bvh;
    let scene_bytes = size_of_val(scene.triangles.as_slice())
        + size_of_val(scene.materials.as_slice())
        + size_of_val(scene.lights.as_slice())
        + scene.bvh_bytes().len()
        + scene.shading_bytes().len()
        + scene.textures_bytes().len();
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
            passgraph::bench::report::write_text(csv, &text)?;
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
fn check_partial_path(path: &std::path::Path, images: &[PathBuf]) -> Result<(), String> {
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

/// `passgraph merge`: reads every partial (each checked, errors naming the file), merges them
/// in range order and writes the image(s) and the merged partial as one set.
fn merge(args: MergeArgs) -> Result<(), Failure> {
    if args.out.is_empty() && args.partial.is_none() {
        return Err(Failure::Usage(
            "merge writes nothing: give --out IMAGE (.png or .exr) and/or --partial OUT.exr".into(),
        ));
    }
    let ChannelSelection::Planes(planes) = &args.channel else {
        return Err(Failure::Usage(format!(
            "--channel {}: a partial holds the accumulation's channels only (sum, l0, direct, indirect, ambient)",
            args.channel
        )));
    };
    for path in &args.out {
        check_output_path(path).map_err(Failure::Usage)?;
    }
    if let Some(path) = &args.partial {
        check_partial_path(path, &args.out).map_err(Failure::Usage)?;
    }
    let outputs: Vec<&Path> = args
        .out
        .iter()
        .chain(&args.partial)
        .map(PathBuf::as_path)
        .collect();
    let inputs: Vec<(&str, &Path)> = args
        .partials
        .iter()
        .map(|p| ("the partial", p.as_path()))
        .collect();
    passgraph::atomic_write::refuse_outputs_that_are_inputs(&outputs, &inputs)
        .map_err(Failure::Usage)?;
    let merged = passgraph::render::merge::merge_files(&args.partials)?;
    let [w, h] = merged.size;
    let image = RgbImage::from_result(&merged.to_result(), w, h, planes);
    let mut encoded = args
        .out
        .iter()
        .map(|path| Ok((path.as_path(), image.encode_for(path)?)))
        .collect::<Result<Vec<_>, String>>()?;
    if let Some(path) = &args.partial {
        encoded.push((
            path.as_path(),
            merged
                .encode(Packing::Small)
                .map_err(|e| format!("{}: {e}", path.display()))?,
        ));
    }
    write_files(&encoded)?;
    say_line(&format!(
        "merged {} partials: samples {}, {w}x{h}, {} dropped samples; wrote {}",
        args.partials.len(),
        merged.samples,
        merged.dropped,
        encoded
            .iter()
            .map(|(p, _)| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    ))?;
    Ok(())
}

/// Writes encoded files as a set (all or none, see `write_atomic_set`); errors name the file.
fn write_files(encoded: &[(&std::path::Path, Vec<u8>)]) -> Result<(), String> {
    let files: Vec<(&std::path::Path, &[u8])> =
        encoded.iter().map(|(p, b)| (*p, b.as_slice())).collect();
    passgraph::atomic_write::write_atomic_set(&files)
        .map_err(|(path, e)| format!("{}: cannot write: {e}", path.display()))
}

/// A positive frame count: zero frames would write a black image (or, for bench, render one).
/// Seconds between checkpoints: finite and not negative (0: after every frame).
fn parse_interval(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && (0.0..=1e9).contains(&v) => Ok(v),
        _ => Err(format!(
            "'{s}' is not a number of seconds from 0 to 1e9 (0: a checkpoint after every frame)"
        )),
    }
}

fn parse_frames(s: &str) -> Result<u32, String> {
    match s.trim().parse::<u32>() {
        Ok(n) if n > 0 => Ok(n),
        _ => Err(format!("'{s}' is not a positive number of frames")),
    }
}

/// A path length of at least one segment (Mitsuba's max_depth).
fn parse_max_depth(s: &str) -> Result<u32, String> {
    let depth: i64 = s
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not a whole number"))?;
    passgraph::scene::check_max_depth(depth)
}

/// A finite, positive time budget: NaN or infinity would never be reached.
fn parse_seconds(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(t) if t.is_finite() && t > 0.0 => Ok(t),
        _ => Err(format!("'{s}' is not a finite, positive number of seconds")),
    }
}

/// `NAME=VALUE` (a Mitsuba XML define).
fn parse_define(s: &str) -> Result<(String, String), String> {
    let (name, value) = s
        .split_once('=')
        .ok_or_else(|| format!("'{s}' is not NAME=VALUE"))?;
    if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
        return Err(format!(
            "'{name}' is not a parameter name (letters, digits, _)"
        ));
    }
    Ok((name.to_string(), value.to_string()))
}

fn parse_size(s: &str) -> Result<[u32; 2], String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("'{s}' is not WxH"))?;
    let dim = |v: &str| match v.trim().parse::<u32>() {
        Ok(n) if n > 0 => Ok(n),
        _ => Err(format!("'{v}' in '{s}' is not a positive integer")),
    };
    Ok([dim(w)?, dim(h)?])
}

/// Why a command failed: invalid input (exit 1) or a command-line usage error (exit 2, like
/// clap's own).
enum Failure {
    Invalid(String),
    Usage(String),
}

impl From<String> for Failure {
    fn from(message: String) -> Failure {
        Failure::Invalid(message)
    }
}

fn run(cli: Cli) -> Result<(), Failure> {
    let plan =
        |g: &GraphArgs| compile_file(&g.graph, g.size).map_err(|e: GraphError| e.to_string());
    match cli.command.unwrap_or(Command::Render(cli.render)) {
        Command::Render(args) => render(args)?,
        Command::Merge(args) => merge(args)?,
        Command::Bench(args) => bench(args)?,
        Command::View(a) => passgraph::view::run(passgraph::view::ViewOptions {
            settings: RenderSettings {
                graph: a.graph,
                scene: a.scene,
                size: a.size,
                seed: a.seed,
                set: a.set,
                adapter: a.adapter,
                max_frames: RenderSettings::DEFAULT_MAX_FRAMES,
                // Any texture the graph computes can be shown.
                keep: Keep::EveryTexture,
                max_depth: a.max_depth,
                defines: a.define,
                camera: a.camera,
            },
            window_scale: 2,
            script: a.script,
            frames: a.frames,
        })?,
        Command::Check { graph: g, generic } => {
            let p = plan(&g)?;
            if !generic {
                check_render_contract(&p, &ChannelSelection::Planes(vec![Channel::Sum]))
                    .map_err(|e| e.to_string())?;
            }
            say_line(&format!(
                "{}: ok ({} passes in {} stages, {} culled)",
                g.graph.display(),
                p.passes.len(),
                p.stages.len(),
                p.culled.len()
            ))?;
        }
        Command::Plan { graph, chart } => {
            let p = plan(&graph)?;
            if chart {
                say(&passgraph::graph::plan_chart::lifetime_chart(&p))?;
            } else {
                say(&p.to_string())?;
            }
        }
        Command::Test {
            files,
            measure,
            adapter,
        } => {
            let summary = passgraph::graphtest::run_files(
                &files,
                adapter.as_deref(),
                measure,
                &mut std::io::stdout(),
            );
            if !summary.success() {
                return Err(Failure::Invalid(format!(
                    "{} of {} cases failed{}",
                    summary.failed,
                    summary.passed + summary.failed,
                    match summary.bad_files {
                        0 => String::new(),
                        n => format!(", {n} test file(s) could not be run"),
                    }
                )));
            }
        }
        Command::MitsubaScene {
            scene,
            define,
            camera,
            out,
            size,
            max_depth,
        } => {
            let options = passgraph::scene::SceneOptions {
                defines: define,
                max_depth: None,
                camera,
            };
            let scene = passgraph::scene::load_scene_with(&scene, &options)
                .map_err(|e| e.to_string())?
                .scene;
            for warning in &scene.mesh.warnings {
                eprintln!("warning: {warning}");
            }
            let options = passgraph::scene::mitsuba::ExportOptions { size, max_depth };
            let written = passgraph::scene::mitsuba::export(&scene, &out, &options)?;
            say_line(&format!(
                "wrote {} ({} meshes)",
                out.join("scene.xml").display(),
                written.len() - 1
            ))?;
        }
        Command::Dot { graph, out } => {
            let dot = to_dot(&plan(&graph)?);
            match out {
                Some(path) => passgraph::atomic_write::write_atomic(&path, dot.as_bytes())
                    .map_err(|e| format!("{}: cannot write: {e}", path.display()))?,
                None => say(&dot)?,
            }
        }
    }
    Ok(())
}

/// Mesa's Vulkan drivers print "XDG_RUNTIME_DIR is invalid or not set" when probing window
/// systems, which reads like an error of ours on a headless machine. Give them a private,
/// valid directory when the session has none; the guard removes it when dropped (also when a
/// panic unwinds), and a signal's cleanup removes it too.
fn quiet_mesa_without_a_session() -> Option<RuntimeDir> {
    if std::env::var_os("XDG_RUNTIME_DIR").is_some() {
        return None;
    }
    let dir = std::env::temp_dir().join(format!("{RUNTIME_DIR_PREFIX}{}", std::process::id()));
    #[cfg(unix)]
    let made = {
        use std::os::unix::fs::DirBuilderExt;
        std::fs::DirBuilder::new().mode(0o700).create(&dir).is_ok()
    };
    #[cfg(not(unix))]
    let made = false;
    if !made {
        return None;
    }
    passgraph::atomic_write::remove_on_signal(dir.clone());
    // SAFETY: called in main before any other thread exists.
    unsafe { std::env::set_var("XDG_RUNTIME_DIR", &dir) };
    Some(RuntimeDir(dir))
}

const RUNTIME_DIR_PREFIX: &str = "passgraph-runtime-";
/// The built-in defaults of a binary outside its build tree (see [`builtin_defaults`]).
const BUILTIN_DIR_PREFIX: &str = "passgraph-builtin-";

/// SIGKILL (or SIGQUIT, or a crash) ends a process without its guard: the runtime and built-in
/// directories of this user's passgraph processes that no longer run are removed at the next
/// start.
fn remove_runtime_dirs_of_dead_processes() {
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::fs::MetadataExt;
        let Ok(entries) = std::fs::read_dir(std::env::temp_dir()) else {
            return;
        };
        // SAFETY: getuid has no preconditions and cannot fail.
        let uid = unsafe { libc::getuid() };
        for entry in entries.flatten() {
            let name = entry.file_name();
            let Some(pid) = name
                .to_str()
                .and_then(|n| {
                    n.strip_prefix(RUNTIME_DIR_PREFIX)
                        .or_else(|| n.strip_prefix(BUILTIN_DIR_PREFIX))
                })
                .and_then(|p| p.parse::<u32>().ok())
            else {
                continue;
            };
            let ours = entry.metadata().is_ok_and(|m| m.is_dir() && m.uid() == uid);
            let alive = Path::new(&format!("/proc/{pid}")).exists();
            if ours && !alive {
                let _ = std::fs::remove_dir_all(entry.path());
            }
        }
    }
}

struct RuntimeDir(PathBuf);

impl Drop for RuntimeDir {
    fn drop(&mut self) {
        // Best effort: nothing should have been written there.
        let _ = std::fs::remove_dir_all(&self.0);
        passgraph::atomic_write::forget(&self.0);
    }
}

/// Writes to standard output. A closed pipe (`passgraph plan G | head -1`) ends the output
/// quietly, as Unix tools do; any other write error (a full disk) is an error saying so.
fn say(text: &str) -> Result<(), String> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) => Err(format!("cannot write to standard output: {e}")),
    }
}

/// [`say`] with a line break.
fn say_line(text: &str) -> Result<(), String> {
    say(&format!("{text}\n"))
}

/// A binary outside its build tree (copied to a farm worker, installed) renders its built-in
/// defaults (src/builtin.rs): they are written to a private temporary folder, removed at exit,
/// and the default graph and scene paths point into it.
fn builtin_defaults(cli: &mut Cli) -> Result<Option<RuntimeDir>, String> {
    use passgraph::builtin;
    if builtin::in_build_tree() {
        return Ok(None);
    }
    let (graph, scene) = (builtin::build_tree_graph(), builtin::build_tree_scene());
    let mut paths: Vec<&mut PathBuf> = Vec::new();
    match &mut cli.command {
        None => paths.extend([&mut cli.render.graph, &mut cli.render.scene]),
        Some(Command::Render(a)) => paths.extend([&mut a.graph, &mut a.scene]),
        Some(Command::View(a)) => paths.extend([&mut a.graph, &mut a.scene]),
        Some(Command::Bench(a)) => {
            paths.push(&mut a.scene);
            paths.extend(a.graphs.iter_mut().map(|v| &mut v.graph));
        }
        _ => {}
    }
    paths.retain(|p| **p == graph || **p == scene);
    if paths.is_empty() {
        return Ok(None);
    }
    let dir = std::env::temp_dir().join(format!("{BUILTIN_DIR_PREFIX}{}", std::process::id()));
    passgraph::atomic_write::remove_on_signal(dir.clone());
    let guard = RuntimeDir(dir.clone());
    builtin::extract(&dir)
        .map_err(|e| format!("{}: cannot write the built-in defaults: {e}", dir.display()))?;
    for p in paths {
        *p = dir.join(if *p == graph {
            builtin::GRAPH
        } else {
            builtin::SCENE
        });
    }
    Ok(Some(guard))
}

fn main() -> ExitCode {
    // Parsing first: a usage error or --help exits here, before anything is created.
    let mut cli = Cli::parse();
    remove_runtime_dirs_of_dead_processes();
    let runtime_dir = quiet_mesa_without_a_session();
    if let Err(e) = passgraph::atomic_write::install_signal_cleanup() {
        eprintln!("warning: temporary files will not be removed on Ctrl-C: {e}");
    }
    let builtin_dir = match builtin_defaults(&mut cli) {
        Ok(dir) => dir,
        Err(message) => {
            eprintln!("error: {message}");
            drop(runtime_dir);
            return ExitCode::FAILURE;
        }
    };
    let code = match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Usage(message)) => {
            eprintln!("error: {message}");
            ExitCode::from(2)
        }
        Err(Failure::Invalid(message)) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    };
    drop(builtin_dir);
    drop(runtime_dir);
    code
}
