//! The RON schema: what users write in `passes/*.ron` and `graphs/*.ron`.

use super::format::TextureFormat;
use super::id::{IdVec, PassIndex};
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
    /// The values a scalar param may take, `(min, max)` inclusive: a graph or `--set` value
    /// outside is an error naming the param, the value and the range (e.g. a sample count of 0
    /// that renders black, or of 2^32 - 1 that never finishes a frame).
    #[serde(default, deserialize_with = "unique_keys")]
    pub ranges: BTreeMap<String, (f64, f64)>,
    /// A raster pass: vertex and fragment entry points drawing into attachments (then
    /// `entry` and `dispatch` are unused).
    #[serde(default, deserialize_with = "plain_option")]
    pub raster: Option<RasterDecl>,
    /// Which pixels of the frame an invocation depends on: what decides whether an image can
    /// be rendered in tiles (src/render/tiles.rs).
    #[serde(default)]
    pub footprint: Footprint,
}

/// Which pixels of the frame a pass's invocation for one pixel depends on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
pub enum Footprint {
    /// Any (the default, as nothing else is safe to assume): a pass that reads neighbours (a
    /// filter), pixels elsewhere (reprojection) or draws the frame's projection (a raster
    /// pass). An image of a graph with such a pass is rendered whole, never in tiles.
    #[default]
    Image,
    /// Its own pixel only: it reads and writes image-sized resources at its own pixel (or
    /// within its own 8x8 block of pixels, as subgroups do), and takes rays and samples from
    /// the pixel's place in the whole image (`frame.image_origin`, `frame.image_size`). An
    /// image of a graph whose passes all declare it can be rendered in tiles, bit for bit as
    /// whole. Not for `Workgroups` or `Indirect` dispatches or raster passes.
    Pixel,
}

/// The draw of a raster pass: its entry points, attachments and vertex count. Attachments are
/// shader-side names like bindings: the graph binds each to a texture in the instance's `bind`.
#[derive(Clone, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename = "Raster", deny_unknown_fields)]
pub struct RasterDecl {
    pub vertex: String,
    pub fragment: String,
    /// Colour attachments: attachment `i` receives the fragment output at `@location(i)`.
    #[serde(default)]
    pub color: Vec<String>,
    /// A `Depth32Float` attachment, tested `Less` and written.
    #[serde(default, deserialize_with = "plain_option")]
    pub depth: Option<String>,
    /// What the attachments hold when the pass begins.
    #[serde(default)]
    pub load: LoadOp,
    /// The pipeline-overridable constant the application provides whose value is the number
    /// of triangles to draw (3 vertices each, no vertex buffers: the vertex shader reads its
    /// triangle `vertex_index / 3` from a provided resource).
    pub triangles: String,
}

/// How a raster pass begins with its attachments.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
pub enum LoadOp {
    /// Colours to zero, depth to 1 (the far plane).
    #[default]
    Clear,
    /// Keep what the attachments hold (they are then read as well as written).
    Load,
}

fn default_entry() -> String {
    "main".to_string()
}

/// How many workgroups a pass launches.
#[derive(Clone, Debug, Default, PartialEq, Eq, Deserialize)]
pub enum Dispatch {
    /// One invocation per output pixel: ceil(size / workgroup_size) workgroups.
    #[default]
    PerPixel,
    /// A fixed number of workgroups (x, y, z).
    Workgroups(u32, u32, u32),
    /// One invocation per output pixel, one workgroup per `(w, h)` tile of the output:
    /// ceil(size / (w, h)) workgroups of w * h invocations in any shape, the shader mapping
    /// them onto the tile. For shaders that need a one-dimensional workgroup over a 2D tile
    /// (subgroup builtins require one: shaders/path_reuse.wgsl).
    PerTile(u32, u32),
    /// As many workgroups as an earlier pass of the frame wrote: three u32 (x, y, z) in the
    /// buffer bound to the shader's read-only storage `binding`, at byte offset
    /// `stride * index` where `index` names a u32 param of the pass (offset 0 without one),
    /// so a pass runs only the work queued for it (the wavefront's levels:
    /// shaders/lib/wavefront.wgsl). The record must lie inside the buffer (checked when the
    /// graph compiles); limits past the device's per-dimension maximum launch nothing.
    Indirect {
        binding: String,
        #[serde(default, deserialize_with = "plain_option")]
        index: Option<String>,
        #[serde(default = "indirect_stride")]
        stride: u64,
    },
}

/// Three u32 (x, y, z): records packed one after another.
fn indirect_stride() -> u64 {
    12
}

/// `graphs/<name>.ron`: resources, pass instances in program order, and outputs — or, with
/// `extends`, the changes to another graph, and subgraphs joined with `include`
/// (crates/graph/src/compose.rs applies them; after that only the first three fields are set).
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(rename = "Graph", deny_unknown_fields)]
pub struct GraphDecl {
    /// The base graph, relative to this file: its resources, passes and outputs are inherited.
    #[serde(default, deserialize_with = "plain_option")]
    pub extends: Option<String>,
    /// Names the passes bind that an including graph supplies: this file is a subgraph.
    #[serde(default)]
    pub inputs: Vec<String>,
    /// Resources added (a name the base already declares is an error: use `replace_resources`).
    #[serde(default, deserialize_with = "unique_keys")]
    pub resources: BTreeMap<String, ResourceDecl>,
    #[serde(default, deserialize_with = "unique_keys")]
    pub replace_resources: BTreeMap<String, ResourceDecl>,
    /// Also drops them from `outputs`.
    #[serde(default)]
    pub remove_resources: Vec<String>,
    /// Passes added, in program order: at the end, or at `before`/`after` an existing pass.
    #[serde(default)]
    pub passes: IdVec<PassIndex, PassInstanceDecl>,
    /// Whole new instances for inherited passes of the same name, in the same place.
    #[serde(default)]
    pub replace_passes: Vec<PassInstanceDecl>,
    #[serde(default)]
    pub remove_passes: Vec<String>,
    /// Param values for inherited passes: instance -> param -> value.
    #[serde(default, deserialize_with = "unique_keys")]
    pub params: BTreeMap<String, ParamChanges>,
    /// Graph-level params: param -> value for every instance whose pass has that param (an
    /// instance's own value wins). Inherited through `extends`, a later file's value winning;
    /// not allowed in a subgraph.
    #[serde(default, deserialize_with = "unique_keys")]
    pub shared_params: BTreeMap<String, ParamValue>,
    #[serde(default)]
    pub include: Vec<IncludeDecl>,
    /// Resources the host reads back (added to the base's).
    #[serde(default)]
    pub outputs: Vec<String>,
    #[serde(default)]
    pub remove_outputs: Vec<String>,
}

/// One instance's param changes: param -> value.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(transparent)]
pub struct ParamChanges(
    #[serde(deserialize_with = "unique_keys")] pub BTreeMap<String, ParamValue>,
);

/// A subgraph joined as a unit: its passes and resources get `prefix/` in front of their names,
/// except its inputs (bound to this graph's resources) and the outputs renamed here.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(rename = "Include", deny_unknown_fields)]
pub struct IncludeDecl {
    /// The subgraph file, relative to this file.
    pub file: String,
    /// Default: the subgraph file's stem.
    #[serde(default, deserialize_with = "plain_option")]
    pub prefix: Option<String>,
    /// Subgraph input -> resource of this graph.
    #[serde(default, deserialize_with = "unique_keys")]
    pub inputs: BTreeMap<String, String>,
    /// Subgraph output -> its name here (unprefixed). Every subgraph output is an output here.
    #[serde(default, deserialize_with = "unique_keys")]
    pub outputs: BTreeMap<String, String>,
    #[serde(default, deserialize_with = "plain_option")]
    pub before: Option<String>,
    #[serde(default, deserialize_with = "plain_option")]
    pub after: Option<String>,
}

/// `key: value` for an optional value, without RON's `Some(...)`.
pub fn plain_option<'de, D, T>(deserializer: D) -> Result<Option<T>, D::Error>
where
    D: Deserializer<'de>,
    T: Deserialize<'de>,
{
    T::deserialize(deserializer).map(Some)
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
#[derive(Clone, Debug, PartialEq, Deserialize)]
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
    /// Where an added pass goes in program order (default: the end); used by composition only.
    #[serde(default, deserialize_with = "plain_option")]
    pub before: Option<String>,
    #[serde(default, deserialize_with = "plain_option")]
    pub after: Option<String>,
}

/// A map whose every key appears once: serde's own maps keep the last of two equal keys
/// silently, which hides a typo'd copy-paste. The error is positioned at the repeated key.
pub fn unique_keys<'de, D, V>(deserializer: D) -> Result<BTreeMap<String, V>, D::Error>
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
