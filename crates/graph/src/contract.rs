//! What an application needs from a graph beyond the framework's own rules: the resources it
//! reads back, their kinds and least sizes. Checked on the compiled plan, so `passgraph check`
//! rejects a graph `render` could not run instead of `render` failing (or panicking) later.

use super::error::GraphError;
use super::id::ResourceId;
use super::plan::{Plan, ResourceKind};

/// The least size of a required buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MinSize {
    Bytes(u64),
    /// So many bytes per output pixel, as `Buffer(size: PerPixel(n))` declares.
    PerPixel(u64),
}

/// A buffer the application reads back after the frames: it must be declared with at least
/// `min` bytes and listed in `outputs` (only outputs keep their content after a frame).
#[derive(Clone, Debug)]
pub struct RequiredBuffer {
    /// The resource's name, or, when `by_binding`, the shader binding whose resource it is.
    pub name: String,
    /// Every resource bound to a shader binding of this name (e.g. `ray_count`), not a resource
    /// of this name; none bound is fine.
    pub by_binding: bool,
    pub min: MinSize,
    /// What the application reads it for, for the message.
    pub why: String,
}

/// Everything `user` (e.g. "render") needs from a graph.
#[derive(Clone, Debug, Default)]
pub struct Contract {
    pub user: String,
    pub buffers: Vec<RequiredBuffer>,
}

impl Contract {
    /// Checks a compiled plan against the contract; the error names the graph file, the
    /// resource and what is missing.
    pub fn check(&self, plan: &Plan) -> Result<(), GraphError> {
        let [w, h] = plan.output_size;
        let error = |resource: &str, reason: String| GraphError::Contract {
            graph: plan.graph.clone(),
            user: self.user.clone(),
            resource: resource.to_string(),
            reason,
        };
        for need in &self.buffers {
            let resources: Vec<ResourceId> = if need.by_binding {
                let mut ids: Vec<ResourceId> = plan
                    .passes
                    .iter()
                    .flat_map(|p| &p.bindings)
                    .filter(|b| b.name == need.name)
                    .map(|b| b.resource)
                    .collect();
                ids.sort_unstable();
                ids.dedup();
                ids
            } else {
                match plan.resource_id(&need.name) {
                    Some(id) => vec![id],
                    None => {
                        return Err(error(
                            &need.name,
                            format!(
                                "not declared; {} needs it ({}): declare \"{}\": Buffer(size: {}) and list it in `outputs`",
                                self.user,
                                need.why,
                                need.name,
                                need.min.declaration()
                            ),
                        ));
                    }
                }
            };
            let least = match need.min {
                MinSize::Bytes(b) => b,
                MinSize::PerPixel(b) => b.saturating_mul(u64::from(w) * u64::from(h)),
            };
            for id in resources {
                let r = &plan.resources[id];
                let what = if need.by_binding {
                    format!("it is bound to '{}' ({})", need.name, need.why)
                } else {
                    need.why.clone()
                };
                let ResourceKind::Buffer { size } = r.kind else {
                    return Err(error(
                        &r.name,
                        format!(
                            "{} reads it back as a buffer ({what}), but it is not a graph-owned buffer",
                            self.user
                        ),
                    ));
                };
                if size < least {
                    return Err(error(
                        &r.name,
                        format!(
                            "{size} bytes at {w}x{h}, but {} needs at least {least} ({what}): declare it Buffer(size: {})",
                            self.user,
                            need.min.declaration()
                        ),
                    ));
                }
                if !r.output {
                    return Err(error(
                        &r.name,
                        format!(
                            "{} reads it back ({what}), so it must be listed in `outputs`",
                            self.user
                        ),
                    ));
                }
            }
        }
        Ok(())
    }
}

impl MinSize {
    /// How a graph would declare this size.
    fn declaration(self) -> String {
        match self {
            MinSize::Bytes(b) => format!("Bytes({b})"),
            MinSize::PerPixel(b) => format!("PerPixel({b})"),
        }
    }
}
