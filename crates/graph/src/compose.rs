//! Composition: a graph that `extends` another and changes it, and subgraphs joined with
//! `include`, flattened into one plain graph that remembers which file introduced each pass,
//! param, resource and output (so `plan` can show it and errors can name it).

use super::decl::{GraphDecl, IncludeDecl, PassInstanceDecl};
use super::error::{GraphError, list};
use super::id::{Id, IdVec, PassIndex};
use super::provided::ProvidedSet;
use super::ron_file::{clean, parse_ron, read_text};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The file that introduced a pass instance, and the files that changed its params since.
#[derive(Clone, Debug, PartialEq)]
pub struct PassOrigin {
    pub file: PathBuf,
    /// Params set by a later file's `params` change.
    pub params: BTreeMap<String, PathBuf>,
}

impl PassOrigin {
    pub fn new(file: &Path) -> PassOrigin {
        PassOrigin {
            file: file.to_path_buf(),
            params: BTreeMap::new(),
        }
    }

    /// The file that set `param`'s value.
    pub fn param_file(&self, param: &str) -> &Path {
        self.params.get(param).unwrap_or(&self.file)
    }
}

/// Which file each element of a flattened graph came from, by its final name.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Origins {
    pub passes: BTreeMap<String, PassOrigin>,
    pub resources: BTreeMap<String, PathBuf>,
    pub outputs: BTreeMap<String, PathBuf>,
    /// The file that set each of `shared_params`.
    pub shared_params: BTreeMap<String, PathBuf>,
}

/// A graph with every `extends`, `include` and change applied.
#[derive(Clone, Debug)]
pub struct Flattened {
    /// Only `inputs`, `resources`, `passes`, `outputs` and `shared_params` are set.
    pub decl: GraphDecl,
    pub origins: Origins,
    /// Every graph file read, the top file first.
    pub files: Vec<PathBuf>,
    /// Include inputs bound to names no graph file declares: they must be provided, which only
    /// the application's `ProvidedSet` can tell (see [`check_include_targets`]).
    pub include_targets: Vec<IncludeTarget>,
}

/// An include input bound to a name that is not a resource of the including graph, and the
/// error to report if the application does not provide it either.
#[derive(Clone, Debug, PartialEq)]
pub struct IncludeTarget {
    pub name: String,
    pub file: PathBuf,
    pub line: Option<usize>,
    pub message: String,
}

/// The first include input bound to a name neither declared nor in `provided`.
pub fn check_include_targets(
    targets: &[IncludeTarget],
    provided: &ProvidedSet,
) -> Result<(), GraphError> {
    match targets.iter().find(|t| provided.get(&t.name).is_none()) {
        Some(t) => Err(GraphError::Compose {
            file: t.file.clone(),
            line: t.line,
            message: t.message.clone(),
        }),
        None => Ok(()),
    }
}

/// Reads `file` and everything it extends or includes, and flattens it.
pub fn flatten(file: &Path) -> Result<Flattened, GraphError> {
    flatten_within(file, &mut Vec::new())
}

/// Flattens a graph written inside another file (a graph test's inline `changes`): its paths
/// are relative to `file`, and errors and origins name `file` (lines found in `text`).
pub fn flatten_inline(file: &Path, text: &str, decl: &GraphDecl) -> Result<Flattened, GraphError> {
    let mut chain = vec![Link {
        canonical: std::fs::canonicalize(file).unwrap_or_else(|_| file.to_path_buf()),
        shown: file.to_path_buf(),
    }];
    apply(&Source { file, text }, decl, &mut chain)
}

/// A graph file on the chain of files being flattened: its canonical path (to find cycles) and
/// the path as the user wrote it (to show them).
struct Link {
    canonical: PathBuf,
    shown: PathBuf,
}

fn flatten_within(file: &Path, chain: &mut Vec<Link>) -> Result<Flattened, GraphError> {
    let text = read_text(file)?;
    let decl: GraphDecl = parse_ron(file, &text)?;
    chain.push(Link {
        canonical: std::fs::canonicalize(file).unwrap_or_else(|_| file.to_path_buf()),
        shown: file.to_path_buf(),
    });
    let source = Source { file, text: &text };
    let result = apply(&source, &decl, chain);
    chain.pop();
    result
}

/// The file being applied, for errors that point into it.
struct Source<'a> {
    file: &'a Path,
    text: &'a str,
}

impl Source<'_> {
    /// An error at the line where `name` (quoted) first appears after `key`.
    fn error(&self, key: &str, name: &str, message: String) -> GraphError {
        GraphError::Compose {
            file: self.file.to_path_buf(),
            line: line_of(self.text, key, name),
            message,
        }
    }
}

/// The line of the first `"name"` after the field `key`, else of `key` itself; RON values
/// carry no positions, so this finds the text the user wrote.
fn line_of(text: &str, key: &str, name: &str) -> Option<usize> {
    let start = text.find(&format!("{key}:")).unwrap_or(0);
    let quoted = format!("\"{name}\"");
    let at = text[start..]
        .find(&quoted)
        .map(|i| start + i)
        .or_else(|| text.find(&quoted))
        .or_else(|| text.find(&format!("{key}:")))?;
    Some(text[..at].matches('\n').count() + 1)
}

fn names<'a>(items: impl IntoIterator<Item = &'a String>) -> String {
    list(&items.into_iter().cloned().collect::<Vec<_>>())
}

/// The longest chain of graphs extending or including one another: far beyond any real
/// composition, far below a stack overflow (as shader includes: MAX_INCLUDE_DEPTH).
pub const MAX_COMPOSITION_DEPTH: usize = 64;

/// Reads the file a graph `extends` or `include`s, refusing a cycle and a chain too deep.
fn follow(
    source: &Source,
    key: &str,
    reference: &str,
    chain: &mut Vec<Link>,
) -> Result<Flattened, GraphError> {
    let dir = source.file.parent().unwrap_or(Path::new("."));
    let path = clean(&dir.join(reference));
    if !path.is_file() {
        return Err(source.error(
            key,
            reference,
            format!(
                "{key} \"{reference}\": no such graph file ({})",
                path.display()
            ),
        ));
    }
    // Each link recurses: a bounded chain ends in this error, not a stack overflow.
    if chain.len() >= MAX_COMPOSITION_DEPTH {
        return Err(source.error(
            key,
            reference,
            format!(
                "{key} \"{reference}\": graphs extend or include one another more than {MAX_COMPOSITION_DEPTH} deep (from {}); a chain this long is a mistake (or a generated file): join the files",
                chain[0].shown.display()
            ),
        ));
    }
    let canonical = std::fs::canonicalize(&path).unwrap_or_else(|_| path.clone());
    if let Some(i) = chain.iter().position(|l| l.canonical == canonical) {
        let cycle: Vec<String> = chain[i..]
            .iter()
            .map(|l| l.shown.display().to_string())
            .chain([path.display().to_string()])
            .collect();
        return Err(source.error(
            key,
            reference,
            format!(
                "{key} \"{reference}\" makes a cycle of extends/include: {}",
                cycle.join(" -> ")
            ),
        ));
    }
    flatten_within(&path, chain)
}

fn apply(
    source: &Source,
    decl: &GraphDecl,
    chain: &mut Vec<Link>,
) -> Result<Flattened, GraphError> {
    let file = source.file;
    let mut g = match &decl.extends {
        Some(base) => follow(source, "extends", base, chain)?,
        None => Flattened {
            decl: GraphDecl::default(),
            origins: Origins::default(),
            files: Vec::new(),
            include_targets: Vec::new(),
        },
    };
    g.files.insert(0, file.to_path_buf());
    let from =
        |path: Option<&PathBuf>| path.map_or(String::new(), |p| format!(" (from {})", p.display()));

    for input in &decl.inputs {
        if g.decl.inputs.contains(input) {
            return Err(source.error("inputs", input, format!("input '{input}' is listed twice")));
        }
        g.decl.inputs.push(input.clone());
    }
    for name in &decl.remove_outputs {
        let Some(i) = g.decl.outputs.iter().position(|o| o == name) else {
            return Err(source.error(
                "remove_outputs",
                name,
                format!(
                    "remove_outputs: '{name}' is not an output (outputs: {})",
                    names(&g.decl.outputs)
                ),
            ));
        };
        g.decl.outputs.remove(i);
        g.origins.outputs.remove(name);
    }
    for name in &decl.remove_passes {
        let i = find_pass(source, "remove_passes", &g.decl.passes, name)?;
        g.decl.passes.remove(i.index());
        g.origins.passes.remove(name);
    }
    for name in &decl.remove_resources {
        if g.decl.resources.remove(name).is_none() {
            return Err(source.error(
                "remove_resources",
                name,
                format!(
                    "remove_resources: no resource '{name}' to remove (resources: {})",
                    names(g.decl.resources.keys())
                ),
            ));
        }
        g.origins.resources.remove(name);
        g.decl.outputs.retain(|o| o != name);
        g.origins.outputs.remove(name);
    }
    for (name, resource) in &decl.replace_resources {
        if !g.decl.resources.contains_key(name) {
            return Err(source.error(
                "replace_resources",
                name,
                format!(
                    "replace_resources: no resource '{name}' to replace (resources: {})",
                    names(g.decl.resources.keys())
                ),
            ));
        }
        g.decl.resources.insert(name.clone(), resource.clone());
        g.origins.resources.insert(name.clone(), file.to_path_buf());
    }
    for (name, resource) in &decl.resources {
        if g.decl.resources.contains_key(name) {
            return Err(source.error(
                "resources",
                name,
                format!(
                    "resource '{name}' is already declared{}; change it with replace_resources",
                    from(g.origins.resources.get(name))
                ),
            ));
        }
        if g.decl.inputs.contains(name) {
            return Err(source.error(
                "resources",
                name,
                format!("resource '{name}' is also an input; a subgraph's input is supplied by the graph that includes it"),
            ));
        }
        g.decl.resources.insert(name.clone(), resource.clone());
        g.origins.resources.insert(name.clone(), file.to_path_buf());
    }
    for pass in &decl.replace_passes {
        let i = find_pass(source, "replace_passes", &g.decl.passes, &pass.name)?;
        if pass.before.is_some() || pass.after.is_some() {
            return Err(source.error(
                "replace_passes",
                &pass.name,
                format!("replace_passes: '{}' keeps the place of the pass it replaces; drop before/after (or remove the pass and add one)", pass.name),
            ));
        }
        g.decl.passes[i] = pass.clone();
        g.origins
            .passes
            .insert(pass.name.clone(), PassOrigin::new(file));
    }
    for (param, value) in &decl.shared_params {
        if !decl.inputs.is_empty() || !g.decl.inputs.is_empty() {
            return Err(source.error(
                "shared_params",
                param,
                format!(
                    "shared_params: a subgraph's passes take params one by one (params); set '{param}' in `params`, or in the including graph's shared_params"
                ),
            ));
        }
        g.decl.shared_params.insert(param.clone(), value.clone());
        g.origins
            .shared_params
            .insert(param.clone(), file.to_path_buf());
    }
    for (instance, changes) in &decl.params {
        let i = find_pass(source, "params", &g.decl.passes, instance)?;
        let origin = g
            .origins
            .passes
            .entry(instance.clone())
            .or_insert_with(|| PassOrigin::new(file));
        for (param, value) in &changes.0 {
            g.decl.passes[i].params.insert(param.clone(), value.clone());
            origin.params.insert(param.clone(), file.to_path_buf());
        }
    }
    for pass in &decl.passes {
        if g.decl.passes.iter().any(|p| p.name == pass.name) {
            let origin = g.origins.passes.get(&pass.name).map(|o| &o.file);
            if origin.is_none_or(|o| o == file) {
                return Err(GraphError::DuplicatePassName {
                    graph: file.to_path_buf(),
                    name: pass.name.clone(),
                });
            }
            return Err(source.error(
                "passes",
                &pass.name,
                format!(
                    "a pass named '{}' already exists{}; pass names must be unique (to change it, use replace_passes or params)",
                    pass.name,
                    from(origin)
                ),
            ));
        }
        let at = anchor(
            source,
            "passes",
            &g.decl.passes,
            &pass.name,
            &pass.before,
            &pass.after,
        )?;
        let mut instance = pass.clone();
        instance.before = None;
        instance.after = None;
        g.decl.passes.insert(at, instance);
        g.origins
            .passes
            .insert(pass.name.clone(), PassOrigin::new(file));
    }
    for include in &decl.include {
        join(source, include, &mut g, chain)?;
    }
    for output in &decl.outputs {
        if g.decl.outputs.contains(output) {
            if let Some(origin) = g.origins.outputs.get(output).filter(|o| *o != file) {
                return Err(source.error(
                    "outputs",
                    output,
                    format!(
                        "'{output}' is already an output (from {})",
                        origin.display()
                    ),
                ));
            }
        }
        g.decl.outputs.push(output.clone());
        g.origins.outputs.insert(output.clone(), file.to_path_buf());
    }
    for name in &decl.remove_resources {
        if let Some(p) = g
            .decl
            .passes
            .iter()
            .find(|p| p.bind.values().any(|r| r == name))
        {
            return Err(source.error(
                "remove_resources",
                name,
                format!(
                    "remove_resources: '{name}' is still bound by pass '{}'{}; remove or replace that pass too",
                    p.name,
                    from(g.origins.passes.get(&p.name).map(|o| &o.file))
                ),
            ));
        }
    }
    Ok(g)
}

fn find_pass(
    source: &Source,
    key: &str,
    passes: &IdVec<PassIndex, PassInstanceDecl>,
    name: &str,
) -> Result<PassIndex, GraphError> {
    passes.position(|p| p.name == name).ok_or_else(|| {
        source.error(
            key,
            name,
            format!(
                "{key}: no pass '{name}' (passes: {})",
                names(passes.iter().map(|p| &p.name))
            ),
        )
    })
}

/// Where in program order an added pass or subgraph goes: before or after a named pass, or last.
fn anchor(
    source: &Source,
    key: &str,
    passes: &[PassInstanceDecl],
    what: &str,
    before: &Option<String>,
    after: &Option<String>,
) -> Result<usize, GraphError> {
    let find = |anchor: &str, side: &str| {
        passes.iter().position(|p| p.name == anchor).ok_or_else(|| {
            source.error(
                key,
                anchor,
                format!(
                    "'{what}' goes {side} '{anchor}', but there is no such pass (passes: {})",
                    names(passes.iter().map(|p| &p.name))
                ),
            )
        })
    };
    match (before, after) {
        (Some(_), Some(_)) => Err(source.error(
            key,
            what,
            format!("'{what}' has both before and after; give one"),
        )),
        (Some(b), None) => find(b, "before"),
        (None, Some(a)) => find(a, "after").map(|i| i + 1),
        (None, None) => Ok(passes.len()),
    }
}

/// Joins a subgraph: its passes and own resources under `prefix/`, its inputs bound to this
/// graph's resources, its outputs (renamed where asked) added to this graph's outputs.
fn join(
    source: &Source,
    include: &IncludeDecl,
    g: &mut Flattened,
    chain: &mut Vec<Link>,
) -> Result<(), GraphError> {
    let key = "include";
    let file = &include.file;
    let sub = follow(source, key, file, chain)?;
    let fail =
        |message: String| Err(source.error(key, file, format!("include \"{file}\": {message}")));
    if let Some(param) = sub.decl.shared_params.keys().next() {
        return fail(format!(
            "it sets shared_params ('{param}'), which an included graph's passes do not take; set them in this graph's shared_params"
        ));
    }
    let prefix = include.prefix.clone().unwrap_or_else(|| {
        Path::new(file)
            .file_stem()
            .map_or(String::new(), |s| s.to_string_lossy().into_owned())
    });
    if prefix.is_empty() || prefix.contains('.') {
        // `--set INSTANCE.PARAM=VALUE` splits at the first '.'.
        return fail(format!(
            "prefix '{prefix}' must be non-empty and contain no '.'"
        ));
    }
    for input in &sub.decl.inputs {
        if !include.inputs.contains_key(input) {
            return fail(format!(
                "its input '{input}' is not bound; add \"{input}\": \"<resource>\" to the include's inputs"
            ));
        }
    }
    for (input, target) in &include.inputs {
        if !sub.decl.inputs.contains(input) {
            return fail(format!(
                "it has no input '{input}' (inputs: {})",
                names(&sub.decl.inputs)
            ));
        }
        let declared = g.decl.resources.contains_key(target) || g.decl.inputs.contains(target);
        if !declared {
            // The same error `fail` would make, reported by compile unless provided.
            g.include_targets.push(IncludeTarget {
                name: target.clone(),
                file: source.file.to_path_buf(),
                line: line_of(source.text, key, file),
                message: format!(
                    "include \"{file}\": input '{input}' -> '{target}', which is neither a resource of this graph nor provided (resources: {})",
                    names(g.decl.resources.keys())
                ),
            });
        }
    }
    for output in include.outputs.keys() {
        if !sub.decl.outputs.contains(output) {
            return fail(format!(
                "it has no output '{output}' (outputs: {})",
                names(&sub.decl.outputs)
            ));
        }
    }
    let rename = |name: &str| -> String {
        if let Some(target) = include.inputs.get(name).or(include.outputs.get(name)) {
            target.clone()
        } else if sub.decl.resources.contains_key(name) {
            format!("{prefix}/{name}")
        } else {
            // Provided, or unknown (compile reports it at the subgraph's pass).
            name.to_string()
        }
    };
    for (name, resource) in &sub.decl.resources {
        let new = rename(name);
        if g.decl.resources.contains_key(&new) {
            return fail(format!(
                "its resource '{name}' becomes '{new}', which this graph already declares{}",
                g.origins
                    .resources
                    .get(&new)
                    .map_or(String::new(), |p| format!(" (from {})", p.display()))
            ));
        }
        g.decl.resources.insert(new.clone(), resource.clone());
        if let Some(origin) = sub.origins.resources.get(name) {
            g.origins.resources.insert(new, origin.clone());
        }
    }
    let at = anchor(
        source,
        key,
        &g.decl.passes,
        file,
        &include.before,
        &include.after,
    )?;
    let mut added = Vec::new();
    for pass in &sub.decl.passes {
        let name = format!("{prefix}/{}", pass.name);
        if g.decl.passes.iter().any(|p| p.name == name) {
            return fail(format!(
                "its pass '{}' becomes '{name}', which this graph already has; give the include another prefix",
                pass.name
            ));
        }
        let mut instance = pass.clone();
        instance.name = name.clone();
        instance.bind = pass
            .bind
            .iter()
            .map(|(binding, resource)| (binding.clone(), rename(resource)))
            .collect();
        if let Some(origin) = sub.origins.passes.get(&pass.name) {
            g.origins.passes.insert(name, origin.clone());
        }
        added.push(instance);
    }
    g.decl.passes.splice(at..at, added);
    for output in &sub.decl.outputs {
        let new = rename(output);
        if !g.decl.outputs.contains(&new) {
            g.decl.outputs.push(new.clone());
        }
        if let Some(origin) = sub.origins.outputs.get(output) {
            g.origins.outputs.insert(new, origin.clone());
        }
    }
    g.files.extend(sub.files);
    g.include_targets.extend(sub.include_targets);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::line_of;

    #[test]
    fn line_of_finds_the_name_after_its_key() {
        let text = "Graph(\n  passes: [\"a\"],\n  remove_passes: [\"a\"],\n)";
        assert_eq!(line_of(text, "remove_passes", "a"), Some(3));
        assert_eq!(line_of(text, "params", "a"), Some(2));
        assert_eq!(line_of(text, "params", "zz"), None);
    }
}
