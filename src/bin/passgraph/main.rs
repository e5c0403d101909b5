//! The `passgraph` command line: parse, dispatch to a command's module, report how it ended.

mod args;
mod bench;
mod camera_path;
mod merge;
mod output;
mod render;
mod runtime_dir;

use args::*;
use bench::{BenchArgs, bench};
use clap::{Parser, Subcommand};
use merge::{MergeArgs, merge};
use output::*;
use passgraph::render::channels::{Channel, ChannelSelection};
use passgraph::render::session::{Keep, RenderSettings, check_render_contract};
use passgraph::{GraphError, compile_file, to_dot};
use render::{RenderArgs, render};
use runtime_dir::*;
use std::path::PathBuf;
use std::process::ExitCode;

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
                scene: a.scene.path,
                size: a.size,
                seed: a.seed,
                set: a.set,
                adapter: a.adapter,
                max_frames: RenderSettings::DEFAULT_MAX_FRAMES,
                // Any texture the graph computes can be shown.
                keep: Keep::EveryTexture,
                max_depth: a.scene.max_depth,
                defines: a.scene.define,
                camera: a.scene.camera,
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
        None => paths.extend([&mut cli.render.graph, &mut cli.render.scene.path]),
        Some(Command::Render(a)) => paths.extend([&mut a.graph, &mut a.scene.path]),
        Some(Command::View(a)) => paths.extend([&mut a.graph, &mut a.scene.path]),
        Some(Command::Bench(a)) => {
            paths.push(&mut a.scene.path);
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
