//! The `passgraph` command line: parse, call the library, print.

use clap::{Parser, Subcommand};
use passgraph::{GraphError, compile_file, to_dot};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "passgraph",
    version,
    about = "A render graph of WGSL compute passes described in RON"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Load and compile a graph; report the first error.
    Check(GraphArgs),
    /// Print the compiled plan: stages, barriers, culled passes, lifetimes and reuse.
    Plan(GraphArgs),
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

fn run(cli: Cli) -> Result<(), String> {
    let plan =
        |g: &GraphArgs| compile_file(&g.graph, g.size).map_err(|e: GraphError| e.to_string());
    match cli.command {
        Command::Check(g) => {
            let p = plan(&g)?;
            println!(
                "{}: ok ({} passes in {} stages, {} culled)",
                g.graph.display(),
                p.passes.len(),
                p.stages.len(),
                p.culled.len()
            );
        }
        Command::Plan(g) => print!("{}", plan(&g)?),
        Command::Dot { graph, out } => {
            let dot = to_dot(&plan(&graph)?);
            match out {
                Some(path) => passgraph::atomic_write::write_atomic(&path, dot.as_bytes())
                    .map_err(|e| format!("{}: cannot write: {e}", path.display()))?,
                None => print!("{dot}"),
            }
        }
    }
    Ok(())
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}
