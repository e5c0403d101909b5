//! `passgraph bench`: speed against error, graph variants against a reference.

use crate::args::*;
use crate::output::*;
use passgraph::bench::variant::Variant;
use passgraph::render::channels::ChannelSelection;
use passgraph::render::image::RgbImage;
use passgraph::render::session::{Keep, RenderSettings, check_render_contract};
use std::path::PathBuf;

#[derive(clap::Args)]
pub(crate) struct BenchArgs {
    #[command(flatten)]
    pub(crate) scene: SceneArgs,
    /// A graph variant (repeatable): [LABEL=]GRAPH[@CHANNEL][:INSTANCE.PARAM=VALUE,...];
    /// @CHANNEL compares CHANNEL instead of --channel (e.g. graphs/pathtracer-denoise.ron@denoised),
    /// :SETs override params for this variant only (see src/bench/variant.rs).
    #[arg(long = "graph", default_value = DEFAULT_GRAPH)]
    pub(crate) graphs: Vec<Variant>,
    /// Linear EXR reference of the scene at --size.
    #[arg(long, required_unless_present = "combine")]
    pub(crate) reference: Option<PathBuf>,
    /// Stop each variant after this much rendering time...
    #[arg(long, conflicts_with = "frames", value_parser = parse_seconds)]
    pub(crate) seconds: Option<f64>,
    /// ...or after this many frames (default 256).
    #[arg(long, value_parser = parse_frames)]
    pub(crate) frames: Option<u32>,
    #[arg(long, default_value = "256x256", value_parser = parse_size)]
    pub(crate) size: [u32; 2],
    #[arg(long, default_value_t = 0)]
    pub(crate) seed: u32,
    /// Channels compared with the reference (the physical image by default).
    #[arg(long, default_value = "l0+direct+indirect")]
    pub(crate) channel: ChannelSelection,
    /// Override a graph param in every variant: INSTANCE.PARAM=VALUE (repeatable).
    #[arg(long = "set")]
    pub(crate) set: Vec<String>,
    /// [LABEL=]CSV from scripts/mitsuba-reference to put on the same chart and tables
    /// (repeatable: one curve per label; a label given several CSVs, one per round, gets the
    /// median per sample count).
    #[arg(long)]
    pub(crate) mitsuba: Vec<String>,
    /// Render nothing: report the median per checkpoint of the runs earlier `bench --out DIR`
    /// runs wrote (repeatable: one DIR per round).
    #[arg(long, conflicts_with_all = ["reference", "seconds", "frames"])]
    pub(crate) combine: Vec<PathBuf>,
    /// Output directory.
    #[arg(long, default_value = "bench-out")]
    pub(crate) out: PathBuf,
    #[arg(long)]
    pub(crate) adapter: Option<String>,
}

/// The default label of a bare `--mitsuba CSV`.
pub(crate) const MITSUBA_LABEL: &str = "Mitsuba 3 (llvm_ad_rgb, CPU)";

/// `--mitsuba` arguments grouped by label, in the order given: LABEL=CSV, or CSV alone (a path
/// that exists as given is never split).
pub(crate) fn mitsuba_curves(args: &[String]) -> Vec<(String, Vec<PathBuf>)> {
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

pub(crate) fn bench(args: BenchArgs) -> Result<(), Failure> {
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
            passgraph::atomic_write::write_text(
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
    let scene_name = args.scene.path.display().to_string();
    plot::write_plot(
        &chart,
        &format!("relMSE against time: {scene_name}"),
        &ours,
        &extra,
    )?;
    let md = report::markdown(&runs, &extra);
    passgraph::atomic_write::write_text(&args.out.join("report.md"), &md)?;
    say(&md)?;
    eprintln!("wrote {}", args.out.display());
    Ok(())
}

/// Renders every variant to the budget, writing each one's CSV as it finishes.
pub(crate) fn bench_render(args: &BenchArgs) -> Result<Vec<passgraph::bench::run::Run>, String> {
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
        defines: args.scene.define.clone(),
        max_depth: None,
        camera: args.scene.camera.clone(),
    };
    let scene = passgraph::scene::load_scene_with(&args.scene.path, &scene_options)
        .map_err(|e| e.to_string())?
        .scene;
    for warning in &scene.mesh.warnings {
        eprintln!("warning: {warning}");
    }
    for variant in &args.graphs {
        let channel = variant.channel.as_ref().unwrap_or(&args.channel);
        let mut graph = passgraph::load_graph(&variant.graph).map_err(|e| e.to_string())?;
        for set in args.set.iter().chain(&variant.set) {
            passgraph::graph::set_param::set_param(
                &mut graph,
                set,
                passgraph::render::provided::path_tracer(),
            )
            .map_err(|e| e.to_string())?;
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
            scene: args.scene.path.clone(),
            size: args.size,
            seed: args.seed,
            set: args.set.iter().chain(&variant.set).cloned().collect(),
            adapter: args.adapter.clone(),
            max_frames: u32::MAX,
            keep: Keep::Outputs,
            max_depth: args.scene.max_depth,
            defines: args.scene.define.clone(),
            camera: args.scene.camera.clone(),
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
        passgraph::atomic_write::write_text(
            &args.out.join(format!("{label}.csv")),
            &report::run_csv(&r),
        )?;
        runs.push(r);
    }
    Ok(runs)
}
