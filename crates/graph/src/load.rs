//! Reading graph and pass files from disk: RON with positions, pass lookup, shaders and reflection.

use super::compose::{Flattened, IncludeTarget, Origins, PassOrigin, flatten};
use super::decl::{Dispatch, Footprint, GraphDecl, PassDecl};
use super::error::GraphError;
use super::interface::ShaderInterface;
use super::param::ParamValue;
use super::provided::ProvidedSet;
use super::reflect::{reflect, reflect_raster};
use super::ron_file::{clean, parse_ron, read_text};
use super::shader_source::ShaderSource;
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

impl LoadedPass {
    /// The pass's params with their defaults: its file's `params`, then each `override` of its
    /// shader with a literal default that the file leaves out and the application does not
    /// set. A default is written once, in the WGSL; the pass file lists only what has none
    /// (or is a `params` uniform field).
    pub fn params(&self, provided: &ProvidedSet) -> BTreeMap<String, ParamValue> {
        let mut params = self.decl.params.clone();
        for o in &self.interface.overrides {
            if let Some(default) = &o.default
                && provided.get_override(&o.name).is_none()
            {
                params
                    .entry(o.name.clone())
                    .or_insert_with(|| default.clone());
            }
        }
        params
    }
}

/// A graph file, flattened (crates/graph/src/compose.rs), with every pass it names.
#[derive(Clone, Debug)]
pub struct LoadedGraph {
    pub file: PathBuf,
    /// The flattened graph: no `extends`, `include` or changes left.
    pub decl: GraphDecl,
    /// The file each pass, resource and output came from.
    pub origins: Origins,
    /// Every graph file it was composed from, `file` first.
    pub graph_files: Vec<PathBuf>,
    /// Keyed by the `pass` name used in the graph.
    pub passes: BTreeMap<String, LoadedPass>,
    /// Include inputs bound to names only a `ProvidedSet` can resolve.
    pub include_targets: Vec<IncludeTarget>,
    /// Makes every colour texture of the graph that a kept pass uses an output (kept whole,
    /// readable), without changing which passes are kept: a viewer can show any of them.
    pub keep_used_textures: bool,
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
    check_footprint(file, &decl)?;
    let shader = ShaderSource::load(&shader_path, &shader_root)?;
    let interface = match &decl.raster {
        Some(raster) => reflect_raster(&shader, &raster.vertex, &raster.fragment),
        None => reflect(&shader, &decl.entry),
    }
    .map_err(|e| e.in_pass_file(file))?;
    Ok(LoadedPass {
        file: file.to_path_buf(),
        decl,
        shader,
        interface,
    })
}

/// `footprint: Pixel` promises that one pixel's invocation depends on that pixel alone, which
/// only a pass dispatched per pixel (or per tile of pixels) can keep.
fn check_footprint(file: &Path, decl: &PassDecl) -> Result<(), GraphError> {
    if decl.footprint != Footprint::Pixel {
        return Ok(());
    }
    let reason = if decl.raster.is_some() {
        "a raster pass draws the whole frame's projection, so it cannot declare `footprint: Pixel` (its image is never rendered in tiles); remove the field"
    } else if let Dispatch::Workgroups(..) = decl.dispatch {
        "a `Workgroups` dispatch is not one invocation per pixel, so it cannot declare `footprint: Pixel`; dispatch PerPixel or PerTile, or remove the field"
    } else if let Dispatch::Indirect { .. } = decl.dispatch {
        "an `Indirect` dispatch runs the work an earlier pass queued, not one invocation per pixel, so it cannot declare `footprint: Pixel`; remove the field"
    } else {
        return Ok(());
    };
    Err(GraphError::Footprint {
        pass_file: file.to_path_buf(),
        reason: reason.to_string(),
    })
}

/// Loads a graph file, flattens its composition, and loads every pass it instantiates (each
/// pass file once; a pass is looked up beside the graph file that introduced it).
pub fn load_graph(file: &Path) -> Result<LoadedGraph, GraphError> {
    load_flattened(file, flatten(file)?)
}

/// Loads the passes of a flattened graph. A pass is looked up beside the graph file that
/// introduced it, then beside the other files of the composition (so changes written inline in
/// a graph test find the passes of the graph they extend).
pub fn load_flattened(file: &Path, flat: Flattened) -> Result<LoadedGraph, GraphError> {
    let mut passes: BTreeMap<String, LoadedPass> = BTreeMap::new();
    for instance in &flat.decl.passes {
        let introduced_by = flat
            .origins
            .passes
            .get(&instance.name)
            .map_or(file, |o| o.file.as_path());
        let mut candidates = pass_candidates(introduced_by, &instance.pass);
        for other in &flat.files {
            for c in pass_candidates(other, &instance.pass) {
                if !candidates.contains(&c) {
                    candidates.push(c);
                }
            }
        }
        let Some(found) = candidates.iter().find(|p| p.is_file()).map(|p| clean(p)) else {
            return Err(GraphError::UnknownPass {
                graph: introduced_by.to_path_buf(),
                pass: instance.name.clone(),
                pass_name: instance.pass.clone(),
                searched: candidates,
            });
        };
        match passes.get(&instance.pass) {
            Some(loaded) if loaded.file != found => {
                return Err(GraphError::Compose {
                    file: introduced_by.to_path_buf(),
                    line: None,
                    message: format!(
                        "pass '{}' uses pass '{}', which is {} here but {} for another file of this graph; rename one of the pass files",
                        instance.name,
                        instance.pass,
                        found.display(),
                        loaded.file.display()
                    ),
                });
            }
            Some(_) => {}
            None => {
                passes.insert(instance.pass.clone(), load_pass(&found)?);
            }
        }
    }
    Ok(LoadedGraph {
        file: file.to_path_buf(),
        decl: flat.decl,
        origins: flat.origins,
        graph_files: flat.files,
        passes,
        include_targets: flat.include_targets,
        keep_used_textures: false,
    })
}

impl LoadedGraph {
    /// The file that introduced a pass instance (the top file for one added after loading).
    pub fn pass_origin(&self, instance: &str) -> PassOrigin {
        self.origins
            .passes
            .get(instance)
            .cloned()
            .unwrap_or_else(|| PassOrigin::new(&self.file))
    }

    /// The file that introduced a resource or output.
    pub fn resource_origin(&self, name: &str) -> &Path {
        self.origins.resources.get(name).unwrap_or(&self.file)
    }

    pub fn output_origin(&self, name: &str) -> &Path {
        self.origins.outputs.get(name).unwrap_or(&self.file)
    }
}
