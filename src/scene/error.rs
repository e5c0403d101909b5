//! Every way loading a scene can fail, each naming the file and, where the format has lines, the
//! line at fault.

use super::camera::CameraError;
use std::fmt;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// A place in an input file: `path:line`, or just `path` (with a note such as "face 12") where the
/// format has no lines (binary PLY) or the loader could not tell.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Location {
    pub path: PathBuf,
    pub line: Option<usize>,
    /// What is at fault when there is no line, e.g. "face 12".
    pub item: Option<String>,
}

impl Location {
    pub fn line(path: &Path, line: usize) -> Location {
        Location {
            path: path.to_path_buf(),
            line: Some(line),
            item: None,
        }
    }

    pub fn item(path: &Path, item: String) -> Location {
        Location {
            path: path.to_path_buf(),
            line: None,
            item: Some(item),
        }
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.path.display())?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        if let Some(item) = &self.item {
            write!(f, " ({item})")?;
        }
        Ok(())
    }
}

#[derive(Debug, Error)]
pub enum SceneError {
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

    #[error("{at}: invalid camera: {source}")]
    Camera { at: Location, source: CameraError },

    #[error("{}: unsupported mesh format (expected a .obj or .ply file)", path.display())]
    UnsupportedMeshFormat { path: PathBuf },

    #[error("{at}: {message}")]
    Syntax { at: Location, message: String },

    #[error(
        "{at}: vertex has a non-finite coordinate ({value}); every coordinate must be a finite number"
    )]
    NonFiniteVertex { at: Location, value: String },

    #[error(
        "{at}: face refers to vertex {index}, but {vertex_count} vertices are defined (valid: {valid})"
    )]
    FaceIndexOutOfRange {
        at: Location,
        /// The index as written in the file.
        index: i64,
        vertex_count: usize,
        /// The valid range in the file's convention, e.g. "1..=8 or -8..=-1".
        valid: String,
    },

    #[error("{at}: `usemtl {name}` names a material that no material library defines (defined: {})",
        if defined.is_empty() { "none".to_string() } else { defined.join(", ") })]
    UnknownMaterial {
        at: Location,
        name: String,
        defined: Vec<String>,
    },

    #[error("{at}: material library {} not found", mtl.display())]
    MissingMaterialLibrary { at: Location, mtl: PathBuf },

    #[error("{}: {message}", path.display())]
    Mesh { path: PathBuf, message: String },

    #[error("{}: the mesh has no triangles", path.display())]
    NoTriangles { path: PathBuf },

    /// A Mitsuba XML plugin or parameter outside the supported subset, or a bad value: the
    /// message says what is supported.
    #[error("{at}: {plugin}: {message}")]
    Mitsuba {
        at: Location,
        /// e.g. "bsdf 'roughconductor'".
        plugin: String,
        message: String,
    },
}
