//! Hot reload: notice that a file the graph was built from changed, rebuild the session, and
//! keep the last good one when the rebuild fails.
//!
//! Detection compares file contents on each [`Reloader::poll`] rather than waiting for OS
//! events: a graph reads a few dozen small files, so reading them once per frame costs far less
//! than a frame, works on every filesystem (mtimes can be coarser than two quick saves), needs
//! no watcher thread or dependency, and lets tests drive it deterministically.

use crate::gpu::GpuContext;
use crate::graph::error::GraphError;
use crate::render::session::{RenderError, RenderSettings, Session};
use crate::scene::CameraDesc;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The contents of the watched files as last seen; `None` for a file that could not be read
/// (deleted, or mid-rename by an editor), so its return counts as a change.
#[derive(Debug, Default, PartialEq)]
struct Snapshot(BTreeMap<PathBuf, Option<Vec<u8>>>);

impl Snapshot {
    fn read(files: impl IntoIterator<Item = PathBuf>) -> Snapshot {
        Snapshot(
            files
                .into_iter()
                .map(|f| {
                    let content = std::fs::read(&f).ok();
                    (f, content)
                })
                .collect(),
        )
    }

    /// The files whose content differs from `self`, read now.
    fn changes(&self) -> (Vec<PathBuf>, Snapshot) {
        let now = Snapshot::read(self.0.keys().cloned());
        let changed = now
            .0
            .iter()
            .filter(|(path, content)| self.0.get(*path) != Some(content))
            .map(|(path, _)| path.clone())
            .collect();
        (changed, now)
    }
}

/// What a poll found.
pub enum ReloadOutcome {
    /// No watched file changed.
    Unchanged,
    /// Files changed and the graph rebuilt: the new session, with the camera carried over.
    Reloaded {
        session: Box<Session>,
        changed: Vec<PathBuf>,
    },
    /// Files changed but the rebuild failed; the caller keeps its session. The message names
    /// the file, line and pass as the loader reports them.
    Failed {
        message: String,
        changed: Vec<PathBuf>,
    },
}

/// Rebuilds sessions on one device when the graph's files change.
pub struct Reloader {
    ctx: GpuContext,
    settings: RenderSettings,
    watched: Snapshot,
}

impl Reloader {
    /// Builds the first session; failing here is an error for the caller (there is no last
    /// good graph to keep).
    pub fn new(ctx: GpuContext, settings: RenderSettings) -> Result<(Reloader, Session), String> {
        // Read before building, so an edit made while the graph compiles is seen next poll.
        let before = Snapshot::read(graph_file(&settings));
        let session = Session::builder(&settings)
            .on(ctx.clone())
            .build()
            .map_err(|e| e.to_string())?;
        let watched = watched_after(&before, &session);
        Ok((
            Reloader {
                ctx,
                settings,
                watched,
            },
            session,
        ))
    }

    pub fn settings(&self) -> &RenderSettings {
        &self.settings
    }

    /// The files being watched.
    pub fn watched_files(&self) -> impl Iterator<Item = &Path> {
        self.watched.0.keys().map(PathBuf::as_path)
    }

    /// Checks the watched files; on a change rebuilds the graph, putting `camera` on the new
    /// session so a reload does not move the view.
    pub fn poll(&mut self, camera: CameraDesc) -> ReloadOutcome {
        let (changed, now) = self.watched.changes();
        if changed.is_empty() {
            return ReloadOutcome::Unchanged;
        }
        let built = Session::builder(&self.settings)
            .on(self.ctx.clone())
            .build()
            .and_then(|mut s| s.set_camera(camera).map(|()| s));
        match built {
            Ok(session) => {
                self.watched = watched_after(&now, &session);
                ReloadOutcome::Reloaded {
                    session: Box::new(session),
                    changed,
                }
            }
            Err(e) => {
                // Remember the broken contents, so the error is reported once per edit, not
                // once per frame; the files of the last good build stay watched, and so does
                // the file at fault (it may be new, e.g. a just-included library).
                self.watched = now;
                if let Some(file) = file_at_fault(&e) {
                    let content = std::fs::read(&file).ok();
                    self.watched.0.entry(file).or_insert(content);
                }
                ReloadOutcome::Failed {
                    message: e.to_string(),
                    changed,
                }
            }
        }
    }
}

/// The file an error points at, when it names one.
fn file_at_fault(error: &RenderError) -> Option<PathBuf> {
    match error {
        RenderError::Graph(GraphError::Wgsl { file, .. } | GraphError::Include { file, .. }) => {
            Some(file.clone())
        }
        RenderError::Graph(GraphError::Ron { path, .. } | GraphError::Io { path, .. }) => {
            Some(path.clone())
        }
        _ => None,
    }
}

fn graph_file(settings: &RenderSettings) -> Vec<PathBuf> {
    vec![settings.graph.clone()]
}

/// The session's files, with the contents read before it was built where known (an edit during
/// the build then still differs), else as they are now.
fn watched_after(before: &Snapshot, session: &Session) -> Snapshot {
    let mut snapshot = BTreeMap::new();
    for file in session.source_files() {
        let content = match before.0.get(file) {
            Some(content) => content.clone(),
            None => std::fs::read(file).ok(),
        };
        snapshot.insert(file.clone(), content);
    }
    Snapshot(snapshot)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_changed_or_deleted_file_is_a_change_and_an_unchanged_one_is_not() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.wgsl");
        let b = dir.path().join("b.wgsl");
        std::fs::write(&a, "one").unwrap();
        std::fs::write(&b, "two").unwrap();
        let snapshot = Snapshot::read([a.clone(), b.clone()]);
        assert!(snapshot.changes().0.is_empty());
        // Same length, written at once: an mtime-and-size check could miss this.
        std::fs::write(&a, "ONE").unwrap();
        std::fs::remove_file(&b).unwrap();
        let (changed, now) = snapshot.changes();
        assert_eq!(changed, vec![a.clone(), b.clone()]);
        assert!(now.changes().0.is_empty());
        std::fs::write(&b, "two").unwrap();
        assert_eq!(now.changes().0, vec![b]);
    }
}
