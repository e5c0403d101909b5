//! Reading the framework's files: UTF-8 text, RON whose errors carry file:line:column, and
//! paths shown as their users wrote them.

use super::error::GraphError;
use serde::de::DeserializeOwned;
use std::path::{Path, PathBuf};

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

/// Drops `dir/..` pairs lexically so messages show `passes/x.ron`, not `graphs/../passes/x.ron`.
pub fn clean(path: &Path) -> PathBuf {
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
