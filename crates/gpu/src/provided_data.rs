//! The scene's side of the framework-provided resources: bytes for each provided buffer the
//! graph binds, and values for the scene overrides its shaders declare.

use std::collections::BTreeMap;

#[derive(Clone, Debug, Default, PartialEq)]
pub struct ProvidedData {
    /// Provided resource name (e.g. `scene.triangles`, `camera`) -> its initial bytes.
    pub buffers: BTreeMap<String, Vec<u8>>,
    /// Scene override name (e.g. `scene_light_count`) -> its value as a pipeline constant.
    pub overrides: BTreeMap<String, f64>,
}

impl ProvidedData {
    pub fn with_buffer(mut self, name: impl Into<String>, bytes: impl Into<Vec<u8>>) -> Self {
        self.buffers.insert(name.into(), bytes.into());
        self
    }

    pub fn with_override(mut self, name: impl Into<String>, value: f64) -> Self {
        self.overrides.insert(name.into(), value);
        self
    }
}
