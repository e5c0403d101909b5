//! The XML document as a tree of plugins (Mitsuba's `src/core/xml.cpp` semantics for the
//! structure): `<default>` and `$name` substitution (the command line's defines win over a
//! file's defaults), `<include>` (the included scene's children join the including element),
//! `<path>` (a directory searched for files), `id` + `<ref>` (a plugin declared once and used
//! by reference), nested plugins, and properties parsed into typed values. Every plugin and
//! property keeps its file and line (roxmltree's `text_pos_at`) for messages.

use super::spectrum::{SpectrumValue, parse_spectrum};
use super::transform::{TransformOp, compose, is_affine, matrix_from_row_major};
use crate::scene::error::{Location, SceneError};
use glam::{DMat4, DVec3};
use std::cell::{Cell, RefCell};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::rc::Rc;

/// The tags that make plugins; `spectrum` is a property here (only `value` spectra are in the
/// subset).
const PLUGIN_TAGS: &[&str] = &[
    "shape",
    "bsdf",
    "texture",
    "emitter",
    "sensor",
    "film",
    "rfilter",
    "sampler",
    "integrator",
    "medium",
    "phase",
    "volume",
];

/// Includes nested deeper than this are taken for a cycle.
const MAX_INCLUDE_DEPTH: usize = 32;

/// A place in a scene file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct At {
    pub path: Rc<PathBuf>,
    pub line: usize,
}

impl At {
    pub fn location(&self) -> Location {
        Location::line(&self.path, self.line)
    }
}

/// A property's value, typed by its tag.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Integer(i64),
    Float(f64),
    String(String),
    Boolean(bool),
    Rgb([f64; 3]),
    Spectrum(SpectrumValue),
    Point(DVec3),
    Vector(DVec3),
    /// The matrix, and the lookat's (origin, target, up) as written when the transform ends
    /// in a `lookat` with only scales before it: a camera then takes them as they are, so
    /// that its frame is the one written, to the last bit.
    Transform(DMat4, Option<[DVec3; 3]>),
}

impl Value {
    /// The XML tag that writes this kind of value.
    pub fn tag(&self) -> &'static str {
        match self {
            Value::Integer(_) => "integer",
            Value::Float(_) => "float",
            Value::String(_) => "string",
            Value::Boolean(_) => "boolean",
            Value::Rgb(_) => "rgb",
            Value::Spectrum(_) => "spectrum",
            Value::Point(_) => "point",
            Value::Vector(_) => "vector",
            Value::Transform(..) => "transform",
        }
    }
}

#[derive(Debug)]
pub struct Property {
    pub name: String,
    pub value: Value,
    pub at: At,
    /// Set when the loader reads it: a property left unread is an error (never dropped).
    pub used: Cell<bool>,
}

/// A nested plugin, written inline or as a `<ref>`.
#[derive(Debug)]
pub struct Child {
    /// The `name` attribute (e.g. a texture's parameter), if any.
    pub name: Option<String>,
    pub plugin: Rc<Plugin>,
    /// Where it is nested (the `<ref>` for a reference).
    pub at: At,
    pub used: Cell<bool>,
}

/// A plugin element: `<shape type="sphere">` and what it holds.
#[derive(Debug)]
pub struct Plugin {
    /// The tag: `shape`, `bsdf`, `texture`, ... or `scene` for the root.
    pub class: String,
    /// The `type` attribute (the plugin's name; `scene` for the root).
    pub kind: String,
    pub id: Option<String>,
    pub at: At,
    pub properties: Vec<Property>,
    pub children: Vec<Child>,
    /// The parameter names the loader asked for, for the message about one it did not.
    pub asked: RefCell<Vec<String>>,
}

/// What the parser is given besides the file.
#[derive(Clone, Debug, Default)]
pub struct ParseOptions {
    /// `NAME=VALUE` from the command line: they replace the file's `<default>`s.
    pub defines: Vec<(String, String)>,
}

struct Parser {
    /// Substitution values: the command line's, then each `<default>` not already set.
    params: HashMap<String, String>,
    /// `<path>` directories, latest first.
    search: Vec<PathBuf>,
    ids: HashMap<String, Rc<Plugin>>,
}

fn error(at: &At, message: impl Into<String>) -> SceneError {
    SceneError::Syntax {
        at: at.location(),
        message: message.into(),
    }
}

/// A parsed scene: the root plugin (class `scene`) and the `<path>` directories, which the
/// plugins' file names are resolved against.
pub struct ParsedScene {
    pub root: Plugin,
    pub search: Vec<PathBuf>,
}

/// Parses `path` (a Mitsuba 3 or 2 scene) into its plugin tree.
pub fn parse_scene(path: &Path, options: &ParseOptions) -> Result<ParsedScene, SceneError> {
    let mut parser = Parser {
        params: options.defines.iter().cloned().collect(),
        search: Vec::new(),
        ids: HashMap::new(),
    };
    let at = At {
        path: Rc::new(path.to_path_buf()),
        line: 1,
    };
    let mut root = Plugin {
        class: "scene".into(),
        kind: "scene".into(),
        id: None,
        at: at.clone(),
        properties: Vec::new(),
        children: Vec::new(),
        asked: RefCell::new(Vec::new()),
    };
    parser.parse_file(path, &mut root, 0)?;
    let mut search = parser.search;
    // Files named inside an included file may be relative to the main scene's directory too.
    search.push(path.parent().unwrap_or(Path::new("")).to_path_buf());
    Ok(ParsedScene { root, search })
}

impl Parser {
    fn parse_file(
        &mut self,
        path: &Path,
        into: &mut Plugin,
        depth: usize,
    ) -> Result<(), SceneError> {
        let text = crate::text_file::read_utf8(path).map_err(|source| SceneError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let file = Rc::new(path.to_path_buf());
        let doc = roxmltree::Document::parse(&text).map_err(|e| {
            let pos = e.pos();
            SceneError::Syntax {
                at: Location::line(path, pos.row as usize),
                message: format!("XML: {e}"),
            }
        })?;
        let root = doc.root_element();
        let at = At {
            path: file.clone(),
            line: doc.text_pos_at(root.range().start).row as usize,
        };
        if root.tag_name().name() != "scene" {
            return Err(error(
                &at,
                format!(
                    "the root element is <{}>; a Mitsuba scene file's is <scene>",
                    root.tag_name().name()
                ),
            ));
        }
        let version = root
            .attribute("version")
            .ok_or_else(|| error(&at, "<scene> needs a version attribute (2.x or 3.x)"))?;
        let major = version.split('.').next().unwrap_or("");
        if major != "2" && major != "3" {
            return Err(error(
                &at,
                format!(
                    "scene version {version}: only versions 2.x and 3.x are supported (Mitsuba 0.x scenes use other parameter names: convert them with Mitsuba 3 first)"
                ),
            ));
        }
        for a in root.attributes() {
            if a.name() != "version" {
                return Err(error(
                    &at,
                    format!("<scene> has an unknown attribute '{}'", a.name()),
                ));
            }
        }
        let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
        self.parse_children(&doc, root, &file, &dir, into, depth)
    }

    fn at(&self, doc: &roxmltree::Document, node: roxmltree::Node, file: &Rc<PathBuf>) -> At {
        At {
            path: file.clone(),
            line: doc.text_pos_at(node.range().start).row as usize,
        }
    }

    /// An attribute with `$name`s replaced.
    fn attr(
        &self,
        node: roxmltree::Node,
        name: &str,
        at: &At,
    ) -> Result<Option<String>, SceneError> {
        node.attribute(name)
            .map(|v| self.substitute(v, at))
            .transpose()
    }

    fn required(&self, node: roxmltree::Node, name: &str, at: &At) -> Result<String, SceneError> {
        self.attr(node, name, at)?.ok_or_else(|| {
            error(
                at,
                format!("<{}> needs a '{name}' attribute", node.tag_name().name()),
            )
        })
    }

    /// Replaces `$name` (letters, digits, `_`) by its value; an unknown name is an error.
    fn substitute(&self, text: &str, at: &At) -> Result<String, SceneError> {
        let mut out = String::with_capacity(text.len());
        let mut rest = text;
        while let Some(i) = rest.find('$') {
            out.push_str(&rest[..i]);
            let after = &rest[i + 1..];
            let len = after
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .unwrap_or(after.len());
            let name = &after[..len];
            if name.is_empty() {
                out.push('$');
            } else {
                let value = self.params.get(name).ok_or_else(|| {
                    error(
                        at,
                        format!(
                            "${name} is not defined: add <default name=\"{name}\" value=\"...\"/> or give --define {name}=VALUE"
                        ),
                    )
                })?;
                out.push_str(value);
            }
            rest = &after[len..];
        }
        out.push_str(rest);
        Ok(out)
    }

    /// Checks that an element has only the attributes `allowed`.
    fn only_attributes(
        &self,
        node: roxmltree::Node,
        allowed: &[&str],
        at: &At,
    ) -> Result<(), SceneError> {
        for a in node.attributes() {
            if !allowed.contains(&a.name()) {
                return Err(error(
                    at,
                    format!(
                        "<{}> has an unknown attribute '{}' (it takes: {})",
                        node.tag_name().name(),
                        a.name(),
                        allowed.join(", ")
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Finds a file as Mitsuba's file resolver does: absolute as is, else relative to the
    /// `<path>` directories (latest first), then to the directory of the file naming it.
    pub fn resolve(&self, name: &str, dir: &Path) -> Option<PathBuf> {
        let p = Path::new(name);
        if p.is_absolute() {
            return p.exists().then(|| p.to_path_buf());
        }
        self.search
            .iter()
            .map(|d| d.join(p))
            .chain(std::iter::once(dir.join(p)))
            .find(|c| c.exists())
    }

    fn parse_children(
        &mut self,
        doc: &roxmltree::Document,
        node: roxmltree::Node,
        file: &Rc<PathBuf>,
        dir: &Path,
        into: &mut Plugin,
        depth: usize,
    ) -> Result<(), SceneError> {
        for child in node.children().filter(|n| n.is_element()) {
            let at = self.at(doc, child, file);
            let tag = child.tag_name().name();
            match tag {
                "default" => {
                    self.only_attributes(child, &["name", "value"], &at)?;
                    let name = self.required(child, "name", &at)?;
                    let value = self.required(child, "value", &at)?;
                    // The command line's value (or an earlier default) wins.
                    self.params.entry(name).or_insert(value);
                }
                "path" => {
                    self.only_attributes(child, &["value"], &at)?;
                    let value = self.required(child, "value", &at)?;
                    let p = dir.join(&value);
                    if !p.is_dir() {
                        return Err(error(
                            &at,
                            format!(
                                "<path value=\"{value}\">: {} is not a directory",
                                p.display()
                            ),
                        ));
                    }
                    self.search.insert(0, p);
                }
                "include" => {
                    self.only_attributes(child, &["filename"], &at)?;
                    let name = self.required(child, "filename", &at)?;
                    if depth >= MAX_INCLUDE_DEPTH {
                        return Err(error(
                            &at,
                            format!(
                                "<include filename=\"{name}\">: includes nest deeper than {MAX_INCLUDE_DEPTH} (a cycle?)"
                            ),
                        ));
                    }
                    let path = self.resolve(&name, dir).ok_or_else(|| {
                        error(
                            &at,
                            format!("<include filename=\"{name}\">: file not found"),
                        )
                    })?;
                    self.parse_file(&path, into, depth + 1)?;
                }
                "ref" => {
                    self.only_attributes(child, &["id", "name"], &at)?;
                    let id = self.required(child, "id", &at)?;
                    let plugin = self.ids.get(&id).cloned().ok_or_else(|| {
                        error(
                            &at,
                            format!("<ref id=\"{id}\">: no plugin with this id is declared above"),
                        )
                    })?;
                    into.children.push(Child {
                        name: self.attr(child, "name", &at)?,
                        plugin,
                        at,
                        used: Cell::new(false),
                    });
                }
                "alias" => {
                    return Err(error(
                        &at,
                        "<alias> is not supported: give the plugin a second id by referencing it with <ref>",
                    ));
                }
                t if PLUGIN_TAGS.contains(&t)
                    || (t == "spectrum" && child.attribute("type").is_some()) =>
                {
                    self.only_attributes(child, &["type", "id", "name"], &at)?;
                    let kind = self.required(child, "type", &at)?;
                    let id = self.attr(child, "id", &at)?;
                    let name = self.attr(child, "name", &at)?;
                    let mut plugin = Plugin {
                        class: tag.to_string(),
                        kind,
                        id: id.clone(),
                        at: at.clone(),
                        properties: Vec::new(),
                        children: Vec::new(),
                        asked: RefCell::new(Vec::new()),
                    };
                    self.parse_children(doc, child, file, dir, &mut plugin, depth)?;
                    let plugin = Rc::new(plugin);
                    if let Some(id) = id {
                        if self.ids.insert(id.clone(), plugin.clone()).is_some() {
                            return Err(error(&at, format!("id '{id}' is declared twice")));
                        }
                    }
                    into.children.push(Child {
                        name,
                        plugin,
                        at,
                        used: Cell::new(false),
                    });
                }
                "integer" | "float" | "string" | "boolean" | "rgb" | "spectrum" | "point"
                | "vector" | "transform" => {
                    let name = self.required(child, "name", &at)?;
                    let value = self.value(doc, child, file, dir, &at)?;
                    if into.properties.iter().any(|p| p.name == name) {
                        return Err(error(&at, format!("parameter '{name}' is given twice")));
                    }
                    into.properties.push(Property {
                        name,
                        value,
                        at,
                        used: Cell::new(false),
                    });
                }
                other => {
                    return Err(error(
                        &at,
                        format!(
                            "<{other}> is not a Mitsuba 3 scene element (supported: {}, integer, float, string, boolean, rgb, spectrum, point, vector, transform, ref, default, include, path)",
                            PLUGIN_TAGS.join(", ")
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    fn value(
        &self,
        doc: &roxmltree::Document,
        node: roxmltree::Node,
        file: &Rc<PathBuf>,
        _dir: &Path,
        at: &At,
    ) -> Result<Value, SceneError> {
        let tag = node.tag_name().name();
        let value = |p: &Self| -> Result<String, SceneError> { p.required(node, "value", at) };
        Ok(match tag {
            "integer" => {
                self.only_attributes(node, &["name", "value"], at)?;
                let v = value(self)?;
                Value::Integer(
                    v.trim()
                        .parse()
                        .map_err(|_| error(at, format!("<integer>: '{v}' is not an integer")))?,
                )
            }
            "float" => {
                self.only_attributes(node, &["name", "value"], at)?;
                let v = value(self)?;
                Value::Float(
                    parse_float(&v).ok_or_else(|| {
                        error(at, format!("<float>: '{v}' is not a finite number"))
                    })?,
                )
            }
            "string" => {
                self.only_attributes(node, &["name", "value"], at)?;
                Value::String(value(self)?)
            }
            "boolean" => {
                self.only_attributes(node, &["name", "value"], at)?;
                let v = value(self)?;
                Value::Boolean(match v.trim().to_ascii_lowercase().as_str() {
                    "true" => true,
                    "false" => false,
                    _ => {
                        return Err(error(
                            at,
                            format!("<boolean>: '{v}' is neither true nor false"),
                        ));
                    }
                })
            }
            "rgb" => {
                self.only_attributes(node, &["name", "value"], at)?;
                let v = value(self)?;
                let numbers = parse_list(&v)
                    .ok_or_else(|| error(at, format!("<rgb>: '{v}' is not a list of numbers")))?;
                Value::Rgb(match numbers[..] {
                    [g] => [g; 3],
                    [r, g, b] => [r, g, b],
                    _ => {
                        return Err(error(
                            at,
                            format!(
                                "<rgb>: '{v}' has {} numbers; give 3 (or 1 for a grey)",
                                numbers.len()
                            ),
                        ));
                    }
                })
            }
            "spectrum" => {
                self.only_attributes(node, &["name", "value"], at)?;
                if node.attribute("filename").is_some() {
                    return Err(error(
                        at,
                        "<spectrum filename>: spectra from files are not supported",
                    ));
                }
                let v = value(self)?;
                Value::Spectrum(
                    parse_spectrum(&v).map_err(|m| error(at, format!("<spectrum>: {m}")))?,
                )
            }
            "point" | "vector" => {
                self.only_attributes(node, &["name", "value", "x", "y", "z"], at)?;
                let v = self.vector3(node, at, 0.0)?;
                if tag == "point" {
                    Value::Point(v)
                } else {
                    Value::Vector(v)
                }
            }
            "transform" => {
                self.only_attributes(node, &["name"], at)?;
                let mut ops = Vec::new();
                for op in node.children().filter(|n| n.is_element()) {
                    let op_at = self.at(doc, op, file);
                    ops.push(self.transform_op(op, &op_at)?);
                }
                let m = compose(&ops).map_err(|m| error(at, m))?;
                if !is_affine(&m) {
                    return Err(error(
                        at,
                        "<transform>: the matrix's last row must be 0 0 0 1 (projective transforms are not supported)",
                    ));
                }
                let lookat = match ops.split_last() {
                    Some((TransformOp::LookAt { origin, target, up }, before))
                        if before.iter().all(|op| matches!(op, TransformOp::Scale(_))) =>
                    {
                        Some([*origin, *target, *up])
                    }
                    _ => None,
                };
                Value::Transform(m, lookat)
            }
            _ => unreachable!("value() is called for property tags only"),
        })
    }

    /// `x`, `y`, `z` attributes (each `default` when absent) or `value="x, y, z"`.
    fn vector3(&self, node: roxmltree::Node, at: &At, default: f64) -> Result<DVec3, SceneError> {
        let tag = node.tag_name().name();
        if let Some(v) = self.attr(node, "value", at)? {
            if ["x", "y", "z"].iter().any(|a| node.attribute(*a).is_some()) {
                return Err(error(
                    at,
                    format!("<{tag}>: give value or x, y, z, not both"),
                ));
            }
            let numbers = parse_list(&v)
                .ok_or_else(|| error(at, format!("<{tag}>: '{v}' is not a list of numbers")))?;
            return match numbers[..] {
                [x, y, z] => Ok(DVec3::new(x, y, z)),
                // `<scale value="2"/>` scales uniformly.
                [s] if tag == "scale" => Ok(DVec3::splat(s)),
                _ => Err(error(at, format!("<{tag}>: '{v}' needs 3 numbers"))),
            };
        }
        let c = |name: &str| -> Result<f64, SceneError> {
            match self.attr(node, name, at)? {
                None => Ok(default),
                Some(v) => parse_float(&v).ok_or_else(|| {
                    error(at, format!("<{tag}>: {name}='{v}' is not a finite number"))
                }),
            }
        };
        Ok(DVec3::new(c("x")?, c("y")?, c("z")?))
    }

    fn transform_op(&self, node: roxmltree::Node, at: &At) -> Result<TransformOp, SceneError> {
        let tag = node.tag_name().name();
        Ok(match tag {
            "translate" => {
                self.only_attributes(node, &["x", "y", "z", "value"], at)?;
                TransformOp::Translate(self.vector3(node, at, 0.0)?)
            }
            "scale" => {
                self.only_attributes(node, &["x", "y", "z", "value"], at)?;
                TransformOp::Scale(self.vector3(node, at, 1.0)?)
            }
            "rotate" => {
                self.only_attributes(node, &["x", "y", "z", "value", "angle"], at)?;
                let angle = self.required(node, "angle", at)?;
                let degrees = parse_float(&angle).ok_or_else(|| {
                    error(
                        at,
                        format!("<rotate>: angle '{angle}' is not a finite number"),
                    )
                })?;
                TransformOp::Rotate {
                    axis: self.vector3(node, at, 0.0)?,
                    degrees,
                }
            }
            "matrix" => {
                self.only_attributes(node, &["value"], at)?;
                let v = self.required(node, "value", at)?;
                let numbers = parse_list(&v).ok_or_else(|| {
                    error(at, format!("<matrix>: '{v}' is not a list of numbers"))
                })?;
                TransformOp::Matrix(matrix_from_row_major(&numbers).ok_or_else(|| {
                    error(
                        at,
                        format!(
                            "<matrix>: {} numbers; give 16 (4x4, row by row) or 9 (3x3)",
                            numbers.len()
                        ),
                    )
                })?)
            }
            "lookat" => {
                self.only_attributes(node, &["origin", "target", "up"], at)?;
                let point = |name: &str| -> Result<DVec3, SceneError> {
                    let v = self.required(node, name, at)?;
                    match parse_list(&v).as_deref() {
                        Some(&[x, y, z]) => Ok(DVec3::new(x, y, z)),
                        _ => Err(error(at, format!("<lookat>: {name}='{v}' needs 3 numbers"))),
                    }
                };
                TransformOp::LookAt {
                    origin: point("origin")?,
                    target: point("target")?,
                    up: point("up")?,
                }
            }
            other => {
                return Err(error(
                    at,
                    format!(
                        "<{other}> is not a transform element (supported: translate, rotate, scale, matrix, lookat)"
                    ),
                ));
            }
        })
    }
}

/// A finite number (Mitsuba's parser reads doubles).
pub fn parse_float(text: &str) -> Option<f64> {
    text.trim().parse::<f64>().ok().filter(|v| v.is_finite())
}

/// Numbers separated by commas and/or white space, each finite.
pub fn parse_list(text: &str) -> Option<Vec<f64>> {
    let numbers: Option<Vec<f64>> = text
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter(|w| !w.is_empty())
        .map(parse_float)
        .collect();
    numbers.filter(|n| !n.is_empty())
}

/// Resolves a file a plugin names: `<path>` directories first, then the naming file's own.
pub fn resolve_file(root_search: &[PathBuf], name: &str, at: &At) -> Option<PathBuf> {
    let p = Path::new(name);
    if p.is_absolute() {
        return p.exists().then(|| p.to_path_buf());
    }
    let dir = at.path.parent().unwrap_or(Path::new(""));
    root_search
        .iter()
        .map(|d| d.join(p))
        .chain(std::iter::once(dir.join(p)))
        .find(|c| c.exists())
}
