//! Runs a compiled `Plan` frame after frame: everything is created once in `new`, and a frame
//! is one command encoder with one compute pass per stage.

use super::context::GpuContext;
use super::error::GpuError;
use super::error_scope::capture_errors;
use super::pass::{Pipeline, PreparedPass, RenderDraw};
use super::provided_data::ProvidedData;
use super::resources::{GpuResources, write_padded};
use super::timing::{FrameTimes, StageTimer};
use passgraph_graph::id::{IdVec, KeptPass, Stage};
use passgraph_graph::plan::Plan;

pub struct Executor {
    // Kept so reads and uploads need no context argument.
    device: wgpu::Device,
    queue: wgpu::Queue,
    resources: GpuResources,
    /// In `Plan::passes` order, so `stages` indexes it directly.
    passes: Vec<PreparedPass>,
    stages: IdVec<Stage, Vec<KeptPass>>,
    stage_labels: Vec<String>,
    timer: Option<StageTimer>,
}

impl Executor {
    /// Allocates the plan's resources, uploads `provided`, and builds every kept pass's
    /// pipeline (with its param and scene overrides as pipeline constants), params uniform and
    /// bind groups. Errors name the pass or resource; wgpu validation errors are caught.
    pub fn new(
        ctx: &GpuContext,
        plan: &Plan,
        provided: &ProvidedData,
    ) -> Result<Executor, GpuError> {
        super::limits::check_limits(plan, &ctx.device().limits(), ctx.device().features())?;
        let resources = GpuResources::new(ctx, plan, provided)?;
        let passes = plan
            .passes
            .iter()
            .map(|pass| PreparedPass::new(ctx, pass, &resources, provided))
            .collect::<Result<Vec<_>, _>>()?;
        let stage_labels = plan
            .stage_names()
            .iter()
            .enumerate()
            .map(|(s, names)| format!("stage {s}: {}", names.join(", ")))
            .collect();
        Ok(Executor {
            device: ctx.device().clone(),
            queue: ctx.queue().clone(),
            resources,
            passes,
            stages: plan.stages.clone(),
            stage_labels,
            timer: StageTimer::new(
                ctx.device(),
                ctx.queue(),
                plan.stages.len(),
                plan.passes.len(),
            ),
        })
    }

    /// The passes whose pipelines were built from their WGSL as written, not specialised to
    /// their override values (crates/gpu/src/specialise.rs), each with why: (pass, reason).
    pub fn unspecialised(&self) -> Vec<(&str, &str)> {
        self.passes
            .iter()
            .filter_map(|p| Some((p.name.as_str(), p.unspecialised.as_deref()?)))
            .collect()
    }

    /// Records and submits one frame without waiting for it. wgpu orders the stages' accesses
    /// (the plan's barriers) by itself, from each dispatch's bindings.
    pub fn run_frame(&mut self, ctx: &GpuContext) -> Result<(), GpuError> {
        let device = ctx.device();
        capture_errors(device, || {
            let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            });
            for (s, stage) in self.stages.iter().enumerate() {
                // One compute pass per run of compute passes, one render pass per raster pass.
                let mut i = 0;
                while i < stage.len() {
                    let first = i == 0;
                    let KeptPass(p) = stage[i];
                    if let Pipeline::Render(draw) = &self.passes[p].pipeline {
                        let last = i + 1 == stage.len();
                        self.record_draw(&mut encoder, s, p, draw, first, last);
                        i += 1;
                        continue;
                    }
                    let run = stage[i..]
                        .iter()
                        .take_while(|&&KeptPass(q)| {
                            matches!(self.passes[q].pipeline, Pipeline::Compute(_))
                        })
                        .count();
                    let last = i + run == stage.len();
                    let mut compute = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                        label: Some(&self.stage_labels[s]),
                        timestamp_writes: self
                            .timer
                            .as_ref()
                            .and_then(|t| t.pass_writes(s, first, last)),
                    });
                    for &KeptPass(p) in &stage[i..i + run] {
                        let pass = &self.passes[p];
                        let Pipeline::Compute(pipeline) = &pass.pipeline else {
                            continue;
                        };
                        compute.set_pipeline(pipeline);
                        for (group, bind_group) in &pass.bind_groups {
                            compute.set_bind_group(*group, bind_group, &[]);
                        }
                        let [x, y, z] = pass.workgroups;
                        if let Some(timer) = &self.timer {
                            timer.write_pass(&mut compute, p, false);
                        }
                        match &pass.indirect {
                            Some((buffer, offset)) => {
                                compute.dispatch_workgroups_indirect(buffer, *offset)
                            }
                            None => compute.dispatch_workgroups(x, y, z),
                        }
                        if let Some(timer) = &self.timer {
                            timer.write_pass(&mut compute, p, true);
                        }
                    }
                    i += run;
                }
            }
            if let Some(timer) = &mut self.timer {
                timer.resolve(&mut encoder);
            }
            ctx.queue().submit([encoder.finish()]);
        })
        .map_err(|message| GpuError::Frame { message })
    }

    /// Records a raster pass: one render pass over its attachments, the viewport being the
    /// output (the attachments' size), drawing 3 vertices per triangle.
    fn record_draw(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        stage: usize,
        p: usize,
        draw: &RenderDraw,
        first: bool,
        last: bool,
    ) {
        let pass = &self.passes[p];
        let color: Vec<Option<wgpu::RenderPassColorAttachment>> = draw
            .color
            .iter()
            .map(|view| {
                Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: if draw.clear {
                            wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT)
                        } else {
                            wgpu::LoadOp::Load
                        },
                        store: wgpu::StoreOp::Store,
                    },
                })
            })
            .collect();
        let depth = draw
            .depth
            .as_ref()
            .map(|view| wgpu::RenderPassDepthStencilAttachment {
                view,
                depth_ops: Some(wgpu::Operations {
                    load: if draw.clear {
                        wgpu::LoadOp::Clear(1.0)
                    } else {
                        wgpu::LoadOp::Load
                    },
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            });
        let mut render = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(&pass.name),
            color_attachments: &color,
            depth_stencil_attachment: depth,
            timestamp_writes: self
                .timer
                .as_ref()
                .and_then(|t| t.render_writes(stage, first, last)),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        render.set_pipeline(&draw.pipeline);
        for (group, bind_group) in &pass.bind_groups {
            render.set_bind_group(*group, bind_group, &[]);
        }
        if let Some(timer) = &self.timer {
            timer.write_render_pass(&mut render, p, false);
        }
        render.draw(0..draw.vertices, 0..1);
        if let Some(timer) = &self.timer {
            timer.write_render_pass(&mut render, p, true);
        }
    }

    /// Blocks until every submitted frame has finished on the GPU (for timing).
    pub fn wait(&self) -> Result<(), GpuError> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| GpuError::Frame {
                message: e.to_string(),
            })
    }

    /// Replaces the bytes of a provided uniform (e.g. `frame`, every frame). A uniform no kept
    /// pass binds is accepted and ignored, so callers need not know which ones the graph uses.
    pub fn update_uniform(&mut self, name: &str, bytes: &[u8]) -> Result<(), GpuError> {
        let Some(buffer) = self.resources.provided_uniform(name)? else {
            return Ok(());
        };
        if bytes.len() as u64 > buffer.size() {
            return Err(GpuError::WrongSize {
                name: name.to_string(),
                expected: buffer.size(),
                got: bytes.len() as u64,
            });
        }
        write_buffer(&self.device, &self.queue, buffer, bytes).map_err(|message| {
            GpuError::Transfer {
                name: name.to_string(),
                message,
            }
        })
    }

    /// Replaces a graph resource's whole content (textures: layer-major, then row-major,
    /// tightly packed), e.g. to initialise persistent history.
    pub fn write_resource(&mut self, name: &str, bytes: &[u8]) -> Result<(), GpuError> {
        self.resources.write(&self.device, &self.queue, name, bytes)
    }

    /// A graph resource's content after every submitted frame, blocking: textures layer-major,
    /// then row-major, tightly packed; buffers as their declared bytes.
    pub fn read_resource(&self, name: &str) -> Result<Vec<u8>, GpuError> {
        self.resources.read(&self.device, &self.queue, name)
    }

    /// Replaces a pass's `params` uniform (live edits); `bytes` must keep the block's length.
    pub fn set_params(&mut self, pass_name: &str, bytes: &[u8]) -> Result<(), GpuError> {
        let pass = self
            .passes
            .iter()
            .find(|p| p.name == pass_name)
            .ok_or_else(|| GpuError::UnknownPass {
                pass: pass_name.to_string(),
                known: self.passes.iter().map(|p| p.name.clone()).collect(),
            })?;
        let (buffer, len) = pass.params.as_ref().ok_or_else(|| GpuError::NoParams {
            pass: pass_name.to_string(),
        })?;
        if bytes.len() as u64 != *len {
            return Err(GpuError::WrongParamsSize {
                pass: pass_name.to_string(),
                expected: *len,
                got: bytes.len() as u64,
            });
        }
        write_buffer(&self.device, &self.queue, buffer, bytes).map_err(|message| {
            GpuError::Transfer {
                name: format!("{pass_name} params"),
                message,
            }
        })
    }

    /// GPU milliseconds each stage took in the latest frame, one per stage; `None` without
    /// timestamp support or before the first frame. Waits for that frame, so call it now and
    /// then rather than every frame.
    pub fn last_stage_times_ms(&self) -> Option<Vec<f64>> {
        Some(self.last_frame_times()?.stages)
    }

    /// GPU milliseconds per stage and, where the device times inside passes, per pass (plan
    /// order) of the latest frame. Blocks like `last_stage_times_ms`.
    pub fn last_frame_times(&self) -> Option<FrameTimes> {
        self.timer.as_ref()?.read_ms(&self.device, &self.queue)
    }
}

fn write_buffer(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    buffer: &wgpu::Buffer,
    bytes: &[u8],
) -> Result<(), String> {
    capture_errors(device, || write_padded(queue, buffer, bytes))
}
