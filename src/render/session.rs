//! A progressive rendering session: a compiled graph, a scene on the GPU, the frame counter.

use super::channels::ChannelSelection;
use super::image::RgbImage;
use super::output_texture::{output_texture_format, texture_channel, texture_image};
use super::planes::{Plane, planes_to_result};
use super::provided::{
    CAMERA, CAMERA_PREVIOUS, FRAME, ProvidedInputs, path_tracer, provided_data, tile_frame,
};
use super::sample_range::SampleRange;
use super::tiling::Tile;
use crate::gpu::{Executor, GpuContext, GpuError};
use crate::graph::compile::compile;
use crate::graph::contract::{Contract, MinSize, RequiredBuffer};
use crate::graph::error::GraphError;
use crate::graph::load::LoadedGraph;
use crate::graph::plan::Plan;
use crate::graph::set_param::set_param;
use crate::scene::gpu_layout::{Frame, GpuCamera};
use crate::scene::{CameraDesc, Scene, SceneError, SceneGpu, SceneOptions, load_scene_with};
use bytemuck::Zeroable;
use std::path::PathBuf;
use thiserror::Error;

#[derive(Debug, Error)]
pub enum RenderError {
    #[error(transparent)]
    Graph(#[from] GraphError),
    #[error(transparent)]
    Scene(#[from] SceneError),
    #[error(transparent)]
    Gpu(#[from] GpuError),
    #[error("{0}")]
    Other(String),
}

/// What to render.
#[derive(Clone, Debug)]
pub struct RenderSettings {
    pub graph: PathBuf,
    pub scene: PathBuf,
    pub size: [u32; 2],
    pub seed: u32,
    /// `INSTANCE.PARAM=VALUE` overrides of graph params.
    pub set: Vec<String>,
    /// Adapter name filter; `None` takes the default adapter.
    pub adapter: Option<String>,
    /// The accumulation stops here (the lab report's 1000); later frames cost nothing.
    pub max_frames: u32,
    /// Which graph textures keep their content after each frame, to be read back and shown.
    pub keep: Keep,
    /// Replaces the scene file's `max_depth` (the command line's `--max-depth`).
    pub max_depth: Option<u32>,
    /// A Mitsuba XML scene's `NAME=VALUE` defines (the command line's `--define`).
    pub defines: Vec<(String, String)>,
    /// A glTF scene's camera by its name or its node's (the command line's `--camera`).
    pub camera: Option<String>,
}

/// Graph textures a session keeps besides the graph's outputs (which it always keeps). A kept
/// texture is an output: never shared with another, readable after the frames.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Keep {
    /// The outputs only (and the texture a `render` channel shows).
    #[default]
    Outputs,
    /// Every texture a kept pass uses: what a viewer may show (the compiler marks them
    /// once it knows the kept passes: `LoadedGraph::keep_used_textures`).
    EveryTexture,
}

impl RenderSettings {
    /// The lab report's accumulation limit.
    pub const DEFAULT_MAX_FRAMES: u32 = 1000;
    /// The CLI's default image size.
    pub const DEFAULT_SIZE: [u32; 2] = [256, 256];

    /// `graph` on `scene` with the CLI's defaults: 256x256, seed 0, no `--set`, the default
    /// adapter, [`Self::DEFAULT_MAX_FRAMES`]. Change fields with struct update syntax.
    pub fn new(graph: impl Into<PathBuf>, scene: impl Into<PathBuf>) -> RenderSettings {
        RenderSettings {
            graph: graph.into(),
            scene: scene.into(),
            size: Self::DEFAULT_SIZE,
            seed: 0,
            set: Vec::new(),
            adapter: None,
            max_frames: Self::DEFAULT_MAX_FRAMES,
            keep: Keep::Outputs,
            max_depth: None,
            defines: Vec::new(),
            camera: None,
        }
    }
}

/// The result buffer's name and the dropped-sample counter's, as the path tracer graph
/// declares them.
pub const RESULT: &str = "result";
pub const DROPPED: &str = "dropped";
/// The rounding errors of `result`'s means (the accumulate pass's `compensation` binding).
pub const COMPENSATION: &str = "compensation";
/// The shader binding through which a pass counts its rays.
pub const RAY_COUNT: &str = "ray_count";
/// Five planes of vec4<f32>.
pub const RESULT_BYTES_PER_PIXEL: u64 = 5 * 16;

pub struct Session {
    ctx: GpuContext,
    plan: Plan,
    executor: Executor,
    scene: Scene,
    gpu_scene: SceneGpu,
    /// The frame's size: the image's, or one tile's (`tile.size`).
    size: [u32; 2],
    /// What of the image the session renders: all of it unless the image is rendered in tiles.
    tile: Tile,
    seed: u32,
    /// Frames submitted since the session started.
    index: u32,
    /// Frames in the current accumulation (0 after a reset).
    accumulated: u32,
    /// The sample index of the accumulation's first frame (see [`Session::start_at_sample`]).
    first_sample: u32,
    max_frames: u32,
    source_files: Vec<PathBuf>,
    /// The camera the last frame was rendered with; `None` before the first frame and after a
    /// reset, when there is no history a pass could reproject.
    previous_camera: Option<GpuCamera>,
}

impl Session {
    /// A session of a graph made by [`prepare_graph`] and compiled for `tile.size` by
    /// [`compile_for`], on a scene from [`load_scene_for`] (a tiled render loads it once for all
    /// its tiles).
    pub(crate) fn from_plan(
        ctx: GpuContext,
        graph: &LoadedGraph,
        plan: Plan,
        settings: &RenderSettings,
        tile: Tile,
        (scene, gpu_scene): (Scene, SceneGpu),
    ) -> Result<Session, RenderError> {
        check_history_camera(&plan, &scene)?;
        let provided = provided_data(&ProvidedInputs {
            scene: &scene,
            gpu: &gpu_scene,
            tile,
            seed: settings.seed,
        });
        let executor = Executor::new(&ctx, &plan, &provided)?;
        Ok(Session {
            ctx,
            plan,
            executor,
            scene,
            gpu_scene,
            size: tile.size,
            tile,
            seed: settings.seed,
            index: 0,
            accumulated: 0,
            first_sample: 0,
            max_frames: settings.max_frames,
            source_files: graph_files(graph),
            previous_camera: None,
        })
    }

    /// Moves the session to another tile of its size, as a new session there would start:
    /// frame 0, no history, every persistent resource zero (dropped samples and ray counts
    /// too: read them before).
    pub(crate) fn start_tile(&mut self, tile: Tile) -> Result<(), RenderError> {
        if tile.size != self.size || tile.image != self.tile.image {
            return Err(RenderError::Other(format!(
                "a session of {}x{} tiles cannot render a {}x{} tile",
                self.size[0], self.size[1], tile.size[0], tile.size[1]
            )));
        }
        for r in self.plan.resources.iter() {
            if r.persistent && r.physical.is_some() {
                let zeros = vec![0u8; r.kind.bytes() as usize];
                self.executor.write_resource(&r.name, &zeros)?;
            }
        }
        self.tile = tile;
        self.index = 0;
        self.accumulated = 0;
        self.previous_camera = None;
        Ok(())
    }

    /// The part of the image this session renders.
    pub fn tile(&self) -> Tile {
        self.tile
    }

    /// Every file the graph was built from: the graph, its pass files, their shaders and the
    /// shaders' includes (what a hot reload watches).
    pub fn source_files(&self) -> &[PathBuf] {
        &self.source_files
    }

    pub fn plan(&self) -> &Plan {
        &self.plan
    }

    pub fn scene(&self) -> &SceneGpu {
        &self.gpu_scene
    }

    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }

    pub fn accumulated(&self) -> u32 {
        self.accumulated
    }

    pub fn seed(&self) -> u32 {
        self.seed
    }

    /// Restarts the accumulation at sample index `first`: its k-th frame then draws the
    /// samples frame `first + k` of an accumulation from 0 draws (same seeds, same sampler
    /// dimensions), so a render of samples A..B holds exactly those of a whole render's frames
    /// A..B (`--samples`). `max_frames` still counts the frames of this accumulation.
    pub fn start_at_sample(&mut self, first: u32) {
        self.reset();
        self.first_sample = first;
    }

    /// Moves the frame index on by `frames` without rendering them, as if they had been rendered
    /// into an accumulation since restarted: a camera path's later segment, rendered alone
    /// (`--segment`), then draws the samples it draws in the whole path, also in graphs whose
    /// sample index runs on over restarts (`sample_index_restarts` false).
    pub fn skip_frames(&mut self, frames: u32) {
        self.index = self.index.saturating_add(frames);
    }

    /// The sample index of the accumulation's first frame (0 unless
    /// [`Session::start_at_sample`] moved it).
    pub fn first_sample(&self) -> u32 {
        self.first_sample
    }

    /// Renders one frame and adds it to the accumulation; once `max_frames` are accumulated
    /// it does nothing and returns false.
    pub fn render_frame(&mut self) -> Result<bool, RenderError> {
        if self.accumulated >= self.max_frames {
            return Ok(false);
        }
        let frame = Frame {
            first_sample: self.first_sample,
            ..tile_frame(self.tile, self.seed, self.index, self.accumulated)
        };
        self.executor
            .update_uniform(FRAME, bytemuck::bytes_of(&frame))?;
        let previous = self.previous_camera.unwrap_or_else(GpuCamera::zeroed);
        self.executor
            .update_uniform(CAMERA_PREVIOUS, bytemuck::bytes_of(&previous))?;
        self.executor.run_frame(&self.ctx)?;
        self.previous_camera = Some(self.gpu_camera());
        self.index += 1;
        self.accumulated += 1;
        Ok(true)
    }

    /// Blocks until the GPU has finished every submitted frame.
    pub fn wait(&self) -> Result<(), RenderError> {
        Ok(self.executor.wait()?)
    }

    /// GPU milliseconds per stage and per pass of the latest frame (blocking).
    pub fn last_frame_times(&self) -> Option<crate::gpu::FrameTimes> {
        self.executor.last_frame_times()
    }

    /// Starts the accumulation over (the next frame replaces the history).
    /// Restarts the accumulation; no history survives (see `camera_previous`).
    pub fn reset(&mut self) {
        self.accumulated = 0;
        self.previous_camera = None;
    }

    /// Moves the camera; the accumulation restarts, as any view change must.
    pub fn set_camera(&mut self, camera: CameraDesc) -> Result<(), RenderError> {
        // The whole image's camera: a tile is a window of it.
        let [w, h] = self.tile.image;
        let gpu = camera.to_gpu(w, h);
        self.executor
            .update_uniform(CAMERA, bytemuck::bytes_of(&gpu))?;
        self.scene.camera = camera;
        // A restart, but the last frame's camera stays `camera_previous`: a graph that
        // reprojects (graphs/pathtracer-reproject.ron) keeps what is still visible.
        self.accumulated = 0;
        Ok(())
    }

    fn gpu_camera(&self) -> GpuCamera {
        let [w, h] = self.tile.image;
        self.scene.camera.to_gpu(w, h)
    }

    /// The accumulation buffer: planes of width*height [mean r, g, b, sample count].
    pub fn result(&self) -> Result<Vec<[f32; 4]>, RenderError> {
        let bytes = self.executor.read_resource(RESULT)?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }

    /// The rounding error each mean of [`Session::result`] carries, in the same layout
    /// (xyz; w unused): what a partial file keeps beside the means.
    pub fn compensation(&self) -> Result<Vec<[f32; 4]>, RenderError> {
        let bytes = self.executor.read_resource(COMPENSATION)?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }

    pub fn image(&self, channels: &ChannelSelection) -> Result<RgbImage, RenderError> {
        let [w, h] = self.size;
        match channels {
            ChannelSelection::Planes(planes) => {
                let result = self.result()?;
                let needed = planes.iter().map(|c| c.layer() + 1).max().unwrap_or(0)
                    * (w as usize * h as usize);
                // Graphs are checked against render_contract; a session of another graph
                // gets an error here rather than an out-of-bounds panic.
                if result.len() < needed {
                    return Err(RenderError::Other(format!(
                        "{}: '{RESULT}' holds {} pixels of planes, but {channels} at {w}x{h} needs {needed}",
                        self.plan.graph.display(),
                        result.len()
                    )));
                }
                Ok(RgbImage::from_result(&result, w, h, planes))
            }
            ChannelSelection::Texture(name) => {
                let (format, layer) =
                    output_texture_format(&self.plan, name).map_err(RenderError::Other)?;
                let (texture, _) = texture_channel(name).map_err(RenderError::Other)?;
                Ok(texture_image(
                    &self.read_resource(texture)?,
                    format,
                    layer,
                    w,
                    h,
                ))
            }
        }
    }

    /// Any graph resource's content after every submitted frame, blocking (see
    /// [`Executor::read_resource`]): for graphs with outputs of their own, e.g. test counters.
    pub fn read_resource(&self, name: &str) -> Result<Vec<u8>, RenderError> {
        Ok(self.executor.read_resource(name)?)
    }

    /// Whether some pass counts the rays it traces (binds `ray_count`).
    pub fn counts_rays(&self) -> bool {
        self.plan
            .passes
            .iter()
            .any(|p| p.bindings.iter().any(|b| b.name == RAY_COUNT))
    }

    /// The persistent resources a checkpoint would not hold: a render can be resumed bit for
    /// bit only when the accumulation (`result`, `compensation`, `dropped`) is all the state
    /// its frames carry over (ray counts are reporting only). `None` when it is.
    pub fn state_beyond_accumulation(&self) -> Option<&str> {
        let counters: Vec<&str> = self
            .plan
            .passes
            .iter()
            .flat_map(|p| p.bindings.iter())
            .filter(|b| b.name == RAY_COUNT)
            .map(|b| self.plan.resources[b.resource].name.as_str())
            .collect();
        self.plan
            .resources
            .iter()
            .find(|r| {
                r.persistent
                    && r.physical.is_some()
                    && ![RESULT, COMPENSATION, DROPPED].contains(&r.name.as_str())
                    && !counters.contains(&r.name.as_str())
            })
            .map(|r| r.name.as_str())
    }

    /// Continues the accumulation a checkpoint holds: `planes` of this session's tile, holding
    /// this render's samples `first_sample..first_sample + n` (`samples`), of which `dropped`
    /// were dropped. The means, their rounding errors, counts and dropped samples go back into
    /// the buffers, and the next frame draws sample `first_sample + n`, so the render goes on bit
    /// for bit as if it had never stopped. The caller has checked the checkpoint's fingerprint
    /// against this render's (src/render/checkpoint.rs).
    pub fn restore(
        &mut self,
        samples: SampleRange,
        dropped: u64,
        planes: &[Plane],
    ) -> Result<(), RenderError> {
        let fail = |why: String| Err(RenderError::Other(why));
        if samples.start != self.first_sample {
            return fail(format!(
                "the checkpoint holds samples {samples}, but this render starts at sample {}",
                self.first_sample
            ));
        }
        if let Some(name) = self.state_beyond_accumulation() {
            return fail(format!(
                "graph {} keeps state in '{name}' from frame to frame, which a checkpoint does not hold",
                self.plan.graph.display()
            ));
        }
        let Ok(dropped) = u32::try_from(dropped) else {
            return fail(format!(
                "the checkpoint's {dropped} dropped samples exceed the u32 counter"
            ));
        };
        let done = samples.len();
        if done > self.max_frames {
            return fail(format!(
                "the checkpoint holds {done} frames, more than the {} this render has",
                self.max_frames
            ));
        }
        let compensation: Vec<[f32; 4]> = planes
            .iter()
            .flat_map(|p| p.compensation.iter().map(|c| [c[0], c[1], c[2], 0.0]))
            .collect();
        self.write_leading(RESULT, bytemuck::cast_slice(&planes_to_result(planes)))?;
        self.write_leading(COMPENSATION, bytemuck::cast_slice(&compensation))?;
        self.write_leading(DROPPED, &dropped.to_le_bytes())?;
        self.accumulated = done;
        self.index = done;
        self.previous_camera = Some(self.gpu_camera());
        Ok(())
    }

    /// Frames still to render before `max_frames` are accumulated.
    pub fn frames_left(&self) -> u32 {
        self.max_frames.saturating_sub(self.accumulated)
    }

    /// Writes `bytes` at the start of a graph buffer, zeros after them (a graph may declare
    /// its buffers larger than the contract's minimum).
    fn write_leading(&mut self, name: &str, bytes: &[u8]) -> Result<(), RenderError> {
        let size = self
            .plan
            .resources
            .iter()
            .find(|r| r.name == name)
            .map(|r| r.kind.bytes())
            .ok_or_else(|| RenderError::Other(format!("the graph has no '{name}' buffer")))?;
        if bytes.len() as u64 > size {
            return Err(RenderError::Other(format!(
                "'{name}' holds {size} bytes; the checkpoint has {} for it",
                bytes.len()
            )));
        }
        let mut all = bytes.to_vec();
        all.resize(size as usize, 0);
        Ok(self.executor.write_resource(name, &all)?)
    }

    /// The passes whose pipelines are not specialised to their override values, with why
    /// (see [`Executor::unspecialised`]): they render the same, but took longer to create.
    pub fn unspecialised(&self) -> Vec<(&str, &str)> {
        self.executor.unspecialised()
    }

    /// Samples dropped so far because a channel was NaN or infinite.
    pub fn dropped(&self) -> Result<u32, RenderError> {
        let bytes = self.executor.read_resource(DROPPED)?;
        bytes
            .get(0..4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .ok_or_else(|| RenderError::Other("the dropped counter is empty".into()))
    }

    /// Rays traced so far, as counted by the passes that bind a `ray_count` buffer (see
    /// shaders/lib/ray_count.wgsl); `None` if no pass counts. Blocks until the GPU is done.
    pub fn rays_counted(&self) -> Result<Option<u64>, RenderError> {
        let mut total = None;
        // Passes may share one count (the wavefront's levels): each buffer counts once.
        let mut buffers: Vec<_> = self
            .plan
            .passes
            .iter()
            .filter_map(|pass| pass.bindings.iter().find(|b| b.name == RAY_COUNT))
            .map(|binding| binding.resource)
            .collect();
        buffers.sort_unstable();
        buffers.dedup();
        for resource in buffers {
            let name = &self.plan.resources[resource].name;
            let bytes = self.executor.read_resource(name)?;
            let word = |i: usize| {
                bytes.get(4 * i..4 * i + 4).map_or(0, |b| {
                    u64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                })
            };
            *total.get_or_insert(0) += word(0) | (word(1) << 32);
        }
        Ok(total)
    }

    pub fn scene_description(&self) -> &Scene {
        &self.scene
    }
}

/// What `render` (and `bench`) read back from a graph showing `channel`: the accumulation
/// buffer (for a channel of it), the dropped-sample counter and every `ray_count` buffer.
pub fn render_contract(channel: &ChannelSelection) -> Contract {
    let mut buffers = Vec::new();
    if let ChannelSelection::Planes(_) = channel {
        buffers.push(RequiredBuffer {
            name: RESULT.to_string(),
            by_binding: false,
            min: MinSize::PerPixel(RESULT_BYTES_PER_PIXEL),
            why: "the image: 5 planes (l0, direct, indirect, ambient, sum) of vec4<f32> per pixel"
                .to_string(),
        });
    }
    buffers.push(RequiredBuffer {
        name: DROPPED.to_string(),
        by_binding: false,
        min: MinSize::Bytes(4),
        why: "the count of dropped samples, a u32".to_string(),
    });
    buffers.push(RequiredBuffer {
        name: RAY_COUNT.to_string(),
        by_binding: true,
        min: MinSize::Bytes(8),
        why: "the rays counted, a 64-bit count as two u32".to_string(),
    });
    Contract {
        user: "render".to_string(),
        buffers,
    }
}

/// What a partial file (`render --partial`) reads back besides [`render_contract`]'s: the
/// accumulation and the rounding errors its means carry.
pub fn partial_contract() -> Contract {
    let per_pixel = |name: &str, why: &str| RequiredBuffer {
        name: name.to_string(),
        by_binding: false,
        min: MinSize::PerPixel(RESULT_BYTES_PER_PIXEL),
        why: why.to_string(),
    };
    Contract {
        user: "render --partial".to_string(),
        buffers: vec![
            per_pixel(
                RESULT,
                "the means and counts: 5 planes (l0, direct, indirect, ambient, sum) of vec4<f32> per pixel",
            ),
            per_pixel(
                COMPENSATION,
                "the rounding error of each mean, the accumulate pass's compensation (same layout)",
            ),
        ],
    }
}

/// Checks a compiled plan against [`render_contract`], and that a texture channel names an
/// output texture that can be shown.
pub fn check_render_contract(plan: &Plan, channel: &ChannelSelection) -> Result<(), RenderError> {
    render_contract(channel).check(plan)?;
    if let ChannelSelection::Texture(name) = channel {
        output_texture_format(plan, name).map_err(RenderError::Other)?;
    }
    Ok(())
}

/// A graph that binds `camera_previous` reprojects its history through it as a pinhole does
/// (shaders/reproject.wgsl): a point seen through a thin lens lands on a blur of pixels and an
/// orthographic camera projects differently, so such a scene is refused with the reason.
fn check_history_camera(plan: &Plan, scene: &Scene) -> Result<(), RenderError> {
    let kind = scene.camera.kind();
    if kind == crate::scene::CameraKind::Pinhole {
        return Ok(());
    }
    let reprojects = plan.passes.iter().find(|p| {
        p.bindings
            .iter()
            .any(|b| plan.resources[b.resource].name == CAMERA_PREVIOUS)
    });
    match reprojects {
        None => Ok(()),
        Some(pass) => Err(RenderError::Other(format!(
            "{}: the scene's camera is {}, but pass '{}' of graph {} reprojects history through \
             `camera_previous` as a pinhole camera only; render this scene with a graph that \
             does not reproject (e.g. graphs/pathtracer.ron)",
            scene.path.display(),
            kind.name(),
            pass.name,
            plan.graph.display()
        ))),
    }
}

/// Loads `settings.scene` with `settings.max_depth` applied, and its GPU form.
pub(crate) fn load_scene_for(settings: &RenderSettings) -> Result<(Scene, SceneGpu), RenderError> {
    let options = SceneOptions {
        defines: settings.defines.clone(),
        max_depth: settings.max_depth,
        camera: settings.camera.clone(),
    };
    let scene = load_scene_with(&settings.scene, &options)?.scene;
    let gpu_scene = scene.to_gpu();
    Ok((scene, gpu_scene))
}

/// The graph as a session runs it: `settings.set` applied, and the textures the session keeps
/// (`settings.keep`, the texture channel `shown`, what a `partial` file reads) made outputs.
pub(crate) fn prepare_graph(
    mut graph: LoadedGraph,
    settings: &RenderSettings,
    shown: Option<&ChannelSelection>,
    partial: bool,
) -> Result<LoadedGraph, RenderError> {
    for s in &settings.set {
        set_param(&mut graph, s, crate::render::provided::path_tracer())?;
    }
    graph.keep_used_textures = settings.keep == Keep::EveryTexture;
    let mut keep = Vec::new();
    if let Some(ChannelSelection::Texture(name)) = shown {
        keep.push(
            texture_channel(name)
                .map_err(RenderError::Other)?
                .0
                .to_string(),
        );
    }
    if partial {
        keep.extend([RESULT.to_string(), COMPENSATION.to_string()]);
    }
    for name in keep {
        // A name the graph lacks stays unkept: showing it then says what the graph has.
        if graph.decl.resources.contains_key(&name) && !graph.decl.outputs.contains(&name) {
            graph.decl.outputs.push(name);
        }
    }
    Ok(graph)
}

/// The plan of a graph made by [`prepare_graph`] for frames of `size`, checked against what
/// `render` reads back for `shown` (and a `partial` file).
pub(crate) fn compile_for(
    graph: &LoadedGraph,
    size: [u32; 2],
    shown: Option<&ChannelSelection>,
    partial: bool,
) -> Result<Plan, RenderError> {
    let plan = compile(graph, size, path_tracer())?;
    if let Some(channel) = shown {
        check_render_contract(&plan, channel)?;
    }
    if partial {
        partial_contract().check(&plan)?;
    }
    Ok(plan)
}

/// Every file `graph` was built from, sorted: graph files, pass files, shaders and includes.
pub fn graph_files(graph: &LoadedGraph) -> Vec<PathBuf> {
    let mut files = graph.graph_files.clone();
    for pass in graph.passes.values() {
        files.push(pass.file.clone());
        files.extend(pass.shader.files().iter().cloned());
    }
    files.sort();
    files.dedup();
    files
}
