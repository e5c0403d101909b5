//! The RON schema: what users write in `passes/*.ron` and `graphs/*.ron`.

use super::format::TextureFormat;
use super::param::ParamValue;
use serde::de::{self, MapAccess, Visitor};
use serde::{Deserialize, Deserializer};
use std::collections::BTreeMap;
use std::fmt;
use std::marker::PhantomData;

/// `passes/<name>.ron`: a shader entry point, how to dispatch it, and its params with defaults.
#[derive(Clone, Debug, Deserialize)]
#[serde(rename = "Pass", deny_unknown_fields)]
pub struct PassDecl {
    /// Path of the WGSL file, relative to the `shaders/` directory beside `passes/`.
    pub shader: String,
    #[serde(default = "default_entry")]
    pub entry: String,
    #[serde(default)]
    pub dispatch: Dispatch,
    #[serde(default, deserialize_with = "unique_keys")]
    pub params: BTreeMap<String, ParamValue>,
}

fn default_entry() -> String {
    "main".to_string()
}

/// How many workgroups a pass launches.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
pub enum Dispatch {
    /// One invocation per output pixel: ceil(size / workgroup_size) workgroups.
    #[default]
    PerPixel,
    /// A fixed number of workgroups (x, y, z).
    Workgroups(u32, u32, u32),
}

/// `graphs/<name>.ron`: resources, pass instances in program order, and outputs.
#[derive(Clone, Debug, Deserialize)]
#[serde(rename = "Graph", deny_unknown_fields)]
pub struct GraphDecl {
    #[serde(default, deserialize_with = "unique_keys")]
    pub resources: BTreeMap<String, ResourceDecl>,
    pub passes: Vec<PassInstanceDecl>,
    pub outputs: Vec<String>,
}

/// A resource the graph owns. Persistent resources keep their content across frames.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(rename = "Resource", deny_unknown_fields)]
pub enum ResourceDecl {
    Texture {
        format: TextureFormat,
        #[serde(default)]
        size: TextureSize,
        #[serde(default = "one")]
        layers: u32,
        #[serde(default)]
        persistent: bool,
    },
    Buffer {
        size: BufferSize,
        #[serde(default)]
        persistent: bool,
    },
}

fn one() -> u32 {
    1
}

impl ResourceDecl {
    pub fn persistent(&self) -> bool {
        match self {
            ResourceDecl::Texture { persistent, .. } | ResourceDecl::Buffer { persistent, .. } => {
                *persistent
            }
        }
    }
}

/// A texture's size: the output's, a fraction of it, or absolute.
#[derive(Clone, Copy, Debug, Default, PartialEq, Deserialize)]
pub enum TextureSize {
    #[default]
    Output,
    /// The output size times this factor, rounded, at least 1 texel.
    Scaled(f32),
    Absolute(u32, u32),
}

/// A buffer's size: absolute, or so many bytes per output pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
pub enum BufferSize {
    Bytes(u64),
    PerPixel(u64),
}

/// One use of a pass in a graph.
// Messages name the type as users know it, not the Rust type.
#[derive(Clone, Debug, Deserialize)]
#[serde(rename = "PassInstance", deny_unknown_fields)]
pub struct PassInstanceDecl {
    /// Unique within the graph; several instances may share one `pass`.
    pub name: String,
    /// The pass file: `passes/<pass>.ron`.
    pub pass: String,
    /// Shader binding name -> resource name.
    #[serde(default, deserialize_with = "unique_keys")]
    pub bind: BTreeMap<String, String>,
    /// Overrides of the pass's param defaults.
    #[serde(default, deserialize_with = "unique_keys")]
    pub params: BTreeMap<String, ParamValue>,
}

/// A map whose every key appears once: serde's own maps keep the last of two equal keys
/// silently, which hides a typo'd copy-paste. The error is positioned at the repeated key.
fn unique_keys<'de, D, V>(deserializer: D) -> Result<BTreeMap<String, V>, D::Error>
where
    D: Deserializer<'de>,
    V: Deserialize<'de>,
{
    struct Unique<V>(PhantomData<V>);
    impl<'de, V: Deserialize<'de>> Visitor<'de> for Unique<V> {
        type Value = BTreeMap<String, V>;
        fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
            f.write_str("a map of names")
        }
        fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
            let mut out = BTreeMap::new();
            while let Some(key) = map.next_key::<String>()? {
                if out.contains_key(&key) {
                    return Err(de::Error::custom(format!(
                        "duplicate key \"{key}\": each key may appear once in a map"
                    )));
                }
                let value = map.next_value()?;
                out.insert(key, value);
            }
            Ok(out)
        }
    }
    deserializer.deserialize_map(Unique(PhantomData))
}
