//! Reading graph and pass files from disk: RON with positions, pass lookup, shaders and reflection.

use super::decl::{GraphDecl, PassDecl};
use super::error::GraphError;
use super::interface::ShaderInterface;
use super::reflect::reflect;
use super::shader_source::ShaderSource;
use serde::de::DeserializeOwned;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A pass file with its shader loaded and reflected.
#[derive(Clone, Debug)]
pub struct LoadedPass {
    pub file: PathBuf,
    pub decl: PassDecl,
    pub shader: ShaderSource,
    pub interface: ShaderInterface,
}

/// A graph file with every pass it names.
#[derive(Clone, Debug)]
pub struct LoadedGraph {
    pub file: PathBuf,
    pub decl: GraphDecl,
    /// Keyed by the `pass` name used in the graph.
    pub passes: BTreeMap<String, LoadedPass>,
}

pub fn read_text(path: &Path) -> Result<String, GraphError> {
    crate::text_file::read_utf8(path).map_err(|source| GraphError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Parses RON, turning a syntax or schema error into file:line:column.
pub fn parse_ron<T: DeserializeOwned>(path: &Path, text: &str) -> Result<T, GraphError> {
    ron::from_str(text).map_err(|e| GraphError::Ron {
        path: path.to_path_buf(),
        line: e.span.start.line,
        col: e.span.start.col,
        message: e.code.to_string(),
    })
}

/// Where a graph looks for `passes/<name>.ron`: beside the graph, then beside its directory
/// (so both `graphs/x.ron` with `passes/` next to `graphs/`, and a self-contained folder work).
pub fn pass_candidates(graph_file: &Path, pass: &str) -> Vec<PathBuf> {
    let dir = graph_file.parent().unwrap_or(Path::new("."));
    let file = format!("{pass}.ron");
    vec![
        dir.join("passes").join(&file),
        dir.join("..").join("passes").join(&file),
    ]
}

/// Loads a pass file, its shader (from `shaders/` beside `passes/`) and the shader's interface.
pub fn load_pass(file: &Path) -> Result<LoadedPass, GraphError> {
    let decl: PassDecl = parse_ron(file, &read_text(file)?)?;
    let shader_root = clean(&file.parent().unwrap_or(Path::new(".")).join("../shaders"));
    let shader_path = shader_root.join(&decl.shader);
    if !shader_path.is_file() {
        return Err(GraphError::MissingShader {
            pass_file: file.to_path_buf(),
            shader: shader_path,
        });
    }
    let shader = ShaderSource::load(&shader_path, &shader_root)?;
    let interface = reflect(&shader, &decl.entry)?;
    Ok(LoadedPass {
        file: file.to_path_buf(),
        decl,
        shader,
        interface,
    })
}

/// Loads a graph file and every pass it instantiates (each pass file once).
pub fn load_graph(file: &Path) -> Result<LoadedGraph, GraphError> {
    let decl: GraphDecl = parse_ron(file, &read_text(file)?)?;
    let mut passes = BTreeMap::new();
    for instance in &decl.passes {
        if passes.contains_key(&instance.pass) {
            continue;
        }
        let candidates = pass_candidates(file, &instance.pass);
        let Some(found) = candidates.iter().find(|p| p.is_file()) else {
            return Err(GraphError::UnknownPass {
                graph: file.to_path_buf(),
                pass: instance.name.clone(),
                pass_name: instance.pass.clone(),
                searched: candidates,
            });
        };
        passes.insert(instance.pass.clone(), load_pass(&clean(found))?);
    }
    Ok(LoadedGraph {
        file: file.to_path_buf(),
        decl,
        passes,
    })
}

/// Drops `dir/..` pairs lexically so messages show `passes/x.ron`, not `graphs/../passes/x.ron`.
fn clean(path: &Path) -> PathBuf {
    use std::path::Component;
    let mut out: Vec<Component> = Vec::new();
    for c in path.components() {
        match c {
            Component::ParentDir if matches!(out.last(), Some(Component::Normal(_))) => {
                out.pop();
            }
            Component::CurDir => {}
            other => out.push(other),
        }
    }
    if out.is_empty() {
        PathBuf::from(".")
    } else {
        out.iter().collect()
    }
}
