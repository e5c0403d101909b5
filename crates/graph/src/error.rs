//! Every way loading or compiling a graph can fail, each naming the file, pass and binding at fault.

use std::path::PathBuf;
use thiserror::Error;

/// `'a', 'b'` or `none`: how messages list names.
pub fn list(items: &[String]) -> String {
    if items.is_empty() {
        "none".to_string()
    } else {
        items
            .iter()
            .map(|s| format!("'{s}'"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

#[derive(Debug, Error)]
pub enum GraphError {
    #[error("{}: cannot read: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },

    #[error("{}:{line}:{col}: {message}", path.display())]
    Ron {
        path: PathBuf,
        line: usize,
        col: usize,
        message: String,
    },

    #[error("{}: pass '{pass}' uses pass '{pass_name}', but no pass file exists (looked for {})",
        graph.display(), searched.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", "))]
    UnknownPass {
        graph: PathBuf,
        pass: String,
        pass_name: String,
        searched: Vec<PathBuf>,
    },

    /// A bad `extends`, `include` or change, at the file (and, where found, line) that made it.
    #[error("{}{}: {message}", file.display(), line.map_or(String::new(), |l| format!(":{l}")))]
    Compose {
        file: PathBuf,
        line: Option<usize>,
        message: String,
    },

    #[error("{}: is a subgraph (inputs {}): it cannot run on its own; include it from a graph with include: [(file: \"...\", inputs: {{...}})]",
        graph.display(), list(inputs))]
    Subgraph { graph: PathBuf, inputs: Vec<String> },

    #[error("{}: shader file {} not found", pass_file.display(), shader.display())]
    MissingShader { pass_file: PathBuf, shader: PathBuf },

    #[error("{}:{line}: cannot include \"{include}\": {reason}", file.display())]
    Include {
        file: PathBuf,
        line: usize,
        include: String,
        reason: String,
    },

    #[error("{}:{line}:{col}: {message}", file.display())]
    Wgsl {
        file: PathBuf,
        line: usize,
        col: usize,
        message: String,
    },

    #[error("{}{}: no {stage} entry point '{entry}' ({stage} entry points: {})",
        match pass_file { Some(p) => format!("{}: pass's shader ", p.display()), None => String::new() },
        shader.display(), list(available))]
    NoEntryPoint {
        /// The pass file naming the entry point, once known (see [`GraphError::in_pass_file`]).
        pass_file: Option<PathBuf>,
        shader: PathBuf,
        /// `compute`, `vertex` or `fragment`.
        stage: String,
        entry: String,
        available: Vec<String>,
    },

    #[error("{}: binding '{binding}': {reason}", shader.display())]
    UnsupportedBinding {
        shader: PathBuf,
        binding: String,
        reason: String,
    },

    #[error("{}: two passes are named '{name}'; pass names must be unique", graph.display())]
    DuplicatePassName { graph: PathBuf, name: String },

    #[error("{}: pass '{pass}' binds '{binding}' to resource '{resource}', which is neither declared in `resources` nor provided by the framework (declared: {})",
        graph.display(), list(known))]
    UnknownResource {
        graph: PathBuf,
        pass: String,
        binding: String,
        resource: String,
        known: Vec<String>,
    },

    #[error("{}: pass '{pass}' sets param '{param}', which {} does not declare (declared: {})",
        graph.display(), pass_file.display(), list(known))]
    UnknownParam {
        graph: PathBuf,
        pass: String,
        pass_file: PathBuf,
        param: String,
        known: Vec<String>,
    },

    #[error("{}: shared_params: '{param}' is a param of none of the graph's passes ({})",
        graph.display(), list(passes))]
    UnusedSharedParam {
        graph: PathBuf,
        param: String,
        /// The graph's instances.
        passes: Vec<String>,
    },

    #[error("{}: pass '{pass}': param '{param}' is {found}, but {expected_where} expects {expected}", file.display())]
    ParamType {
        file: PathBuf,
        pass: String,
        param: String,
        expected: String,
        found: String,
        expected_where: String,
    },

    #[error("{}: pass '{pass}' leaves shader binding '{binding}' ({kind}, {}) unbound; add \"{binding}\": \"<resource>\" to its `bind`",
        graph.display(), shader.display())]
    Unbound {
        graph: PathBuf,
        pass: String,
        binding: String,
        kind: String,
        shader: PathBuf,
    },

    #[error("{}: pass '{pass}' binds '{binding}', but {} has no such binding in its entry point (bindings: {})",
        graph.display(), shader.display(), list(available))]
    NoSuchBinding {
        graph: PathBuf,
        pass: String,
        binding: String,
        shader: PathBuf,
        available: Vec<String>,
    },

    #[error("{}: pass '{pass}': attachment '{attachment}' -> resource '{resource}': {reason}", graph.display())]
    Attachment {
        graph: PathBuf,
        pass: String,
        attachment: String,
        resource: String,
        reason: String,
    },

    #[error("{}: raster pass: {reason}", pass_file.display())]
    Raster { pass_file: PathBuf, reason: String },

    #[error("{}: footprint: {reason}", pass_file.display())]
    Footprint { pass_file: PathBuf, reason: String },

    #[error("{}: pass '{pass}', binding '{binding}' -> resource '{resource}': {reason}", graph.display())]
    BindingMismatch {
        graph: PathBuf,
        pass: String,
        binding: String,
        resource: String,
        reason: String,
    },

    #[error("{}: pass '{pass}' binds resource '{resource}' to {} with a write among them; a pass may write a resource through one binding only",
        graph.display(), list(bindings))]
    ConflictingUsage {
        graph: PathBuf,
        pass: String,
        resource: String,
        bindings: Vec<String>,
    },

    #[error("{}: field '{field}' of the `params` uniform in {} is not a param of this pass; declare it in `params`",
        pass_file.display(), shader.display())]
    UndeclaredUniformField {
        pass_file: PathBuf,
        shader: PathBuf,
        field: String,
    },

    #[error("{}: param '{param}' is neither a field of the shader's `params` uniform nor an `override` in {}",
        pass_file.display(), shader.display())]
    UnusedParam {
        pass_file: PathBuf,
        shader: PathBuf,
        param: String,
    },

    #[error("{}: `override {name}` has no default and is not a param of {}; give it a default or declare the param",
        shader.display(), pass_file.display())]
    OverrideWithoutValue {
        pass_file: PathBuf,
        shader: PathBuf,
        name: String,
    },

    #[error("{}: param '{name}' defaults to {ron} here, but its `override {name}` in {}:{line} defaults to {wgsl}; one value, two places that disagree: make them agree (the pass file's is the one used)",
        pass_file.display(), shader.display())]
    OverrideDefaultDisagrees {
        pass_file: PathBuf,
        /// The file (the shader or one it includes) and line of the override.
        shader: PathBuf,
        line: usize,
        name: String,
        ron: String,
        wgsl: String,
    },

    #[error("{}: resource '{resource}': {reason}", graph.display())]
    InvalidResource {
        graph: PathBuf,
        resource: String,
        reason: String,
    },

    #[error("{}: pass '{pass}' reads '{resource}' ({through}) before any pass writes it{}",
        graph.display(),
        match later_writer {
            Some(w) => format!("; pass '{w}' writes it later: list '{w}' before '{pass}', or declare '{resource}' persistent: true to read the previous frame's value"),
            None => format!("; no pass writes it: declare '{resource}' persistent: true if it holds data from earlier frames"),
        })]
    ReadBeforeWrite {
        graph: PathBuf,
        pass: String,
        resource: String,
        /// What reads it: "binding 'src'" or "attachment 'depth', loaded".
        through: String,
        later_writer: Option<String>,
    },

    #[error("{}: cycle detected: {}; make one of these resources persistent: true to read the previous frame's value instead",
        graph.display(), cycle_text(passes, via))]
    Cycle {
        graph: PathBuf,
        /// The passes in order; the first one is repeated implicitly at the end.
        passes: Vec<String>,
        /// `via[i]` is the resource that carries the dependency from `passes[i]` to the next.
        via: Vec<String>,
    },

    #[error("{}: output '{output}' is not a declared resource (declared: {})", graph.display(), list(known))]
    UnknownOutput {
        graph: PathBuf,
        output: String,
        known: Vec<String>,
    },

    #[error("{}: --set {setting}: {reason}", graph.display())]
    InvalidSetting {
        graph: PathBuf,
        setting: String,
        reason: String,
    },

    #[error("{}: no pass writes output '{output}'", graph.display())]
    OutputNotWritten { graph: PathBuf, output: String },

    #[error("{}: pass '{pass}': param '{param}' is {value}, outside its range {min} to {max} (declared in {})", file.display(), pass_file.display())]
    ParamOutOfRange {
        file: PathBuf,
        pass: String,
        pass_file: PathBuf,
        param: String,
        value: String,
        min: f64,
        max: f64,
    },

    #[error("{}: `ranges`: {reason}", file.display())]
    BadParamRange { file: PathBuf, reason: String },

    #[error("{}: pass '{pass}': param '{param}' is {value}, which is not finite; a param must be a finite number", file.display())]
    NonFiniteParam {
        file: PathBuf,
        pass: String,
        param: String,
        value: String,
    },

    #[error("{}: {reason}", graph.display())]
    EmptyGraph { graph: PathBuf, reason: String },

    #[error("{}: resource '{resource}': {reason}", graph.display())]
    Contract {
        graph: PathBuf,
        /// The application whose needs the graph does not meet (e.g. "render").
        user: String,
        resource: String,
        reason: String,
    },

    #[error("{}: pass '{pass}' ({}): {reason}", graph.display(), shader.display())]
    Dispatch {
        graph: PathBuf,
        pass: String,
        shader: PathBuf,
        reason: String,
    },

    #[error("{}: pass '{pass}', binding '{binding}' -> resource '{resource}': {reason}", graph.display())]
    OutOfBounds {
        graph: PathBuf,
        pass: String,
        binding: String,
        resource: String,
        reason: String,
    },
}

impl GraphError {
    /// The error as seen from the pass file that uses the shader: a missing entry point then
    /// names the pass file that asked for it.
    pub fn in_pass_file(self, file: &std::path::Path) -> GraphError {
        match self {
            GraphError::NoEntryPoint {
                pass_file: None,
                shader,
                stage,
                entry,
                available,
            } => GraphError::NoEntryPoint {
                pass_file: Some(file.to_path_buf()),
                shader,
                stage,
                entry,
                available,
            },
            other => other,
        }
    }
}

fn cycle_text(passes: &[String], via: &[String]) -> String {
    let mut s = String::new();
    for (i, p) in passes.iter().enumerate() {
        s.push_str(&format!(
            "'{p}' -[{}]-> ",
            via.get(i).map_or("?", |v| v.as_str())
        ));
    }
    if let Some(first) = passes.first() {
        s.push_str(&format!("'{first}'"));
    }
    s
}
