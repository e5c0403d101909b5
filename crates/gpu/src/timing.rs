//! GPU time per stage and per pass: a timestamp at the start and end of each stage's compute
//! pass, and around each dispatch where the device can write timestamps inside passes; resolved
//! on the GPU every frame and read back only when asked.

use super::error_scope::capture_errors;
use super::readback::read_mapped;

pub struct StageTimer {
    /// Query `2 * s` is stage `s`'s start, `2 * s + 1` its end; after the stages, query
    /// `2 * (stages + p)` is pass `p`'s start and the next its end.
    queries: wgpu::QuerySet,
    /// Resolved ticks of the latest frame; resolving every frame costs a tiny GPU copy.
    resolved: wgpu::Buffer,
    /// Filled from `resolved` only on request, so frames never wait for a map.
    readback: wgpu::Buffer,
    stages: u32,
    /// Passes timed one by one (0 when the device cannot write timestamps inside passes).
    passes: u32,
    /// Nanoseconds per tick.
    period_ns: f64,
    /// Whether a frame has written the queries yet; reading them before is meaningless.
    written: bool,
}

impl StageTimer {
    /// `None` when the device has no timestamp queries or the stages exceed one query set.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        stages: usize,
        passes: usize,
    ) -> Option<StageTimer> {
        if !device.features().contains(wgpu::Features::TIMESTAMP_QUERY) || stages == 0 {
            return None;
        }
        let inside = device
            .features()
            .contains(wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES);
        let passes = if inside { passes } else { 0 };
        let count = u32::try_from((stages + passes) * 2)
            .ok()
            .filter(|&c| c <= wgpu::QUERY_SET_MAX_QUERIES)?;
        let size = u64::from(count) * u64::from(wgpu::QUERY_SIZE);
        // Timing is optional: if the device refuses any of this, run without it.
        capture_errors(device, || StageTimer {
            queries: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("stage timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count,
            }),
            resolved: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("stage timestamps resolved"),
                size,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            readback: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("stage timestamps readback"),
                size,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            stages: stages as u32,
            passes: passes as u32,
            period_ns: f64::from(queue.get_timestamp_period()),
            written: false,
        })
        .ok()
    }

    /// The timestamp writes for one compute pass of stage `stage`: a stage is one compute pass
    /// unless it holds raster passes, which split it; its first such pass writes the stage's
    /// start and its last the stage's end.
    pub fn pass_writes(
        &self,
        stage: usize,
        first: bool,
        last: bool,
    ) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        let (begin, end) = self.stage_indices(stage, first, last)?;
        Some(wgpu::ComputePassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: begin,
            end_of_pass_write_index: end,
        })
    }

    /// Like `pass_writes`, for a raster pass's render pass.
    pub fn render_writes(
        &self,
        stage: usize,
        first: bool,
        last: bool,
    ) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        let (begin, end) = self.stage_indices(stage, first, last)?;
        Some(wgpu::RenderPassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: begin,
            end_of_pass_write_index: end,
        })
    }

    fn stage_indices(
        &self,
        stage: usize,
        first: bool,
        last: bool,
    ) -> Option<(Option<u32>, Option<u32>)> {
        let start = stage as u32 * 2;
        (first || last).then_some((first.then_some(start), last.then_some(start + 1)))
    }

    /// Writes pass `pass`'s start (`end == false`) or end timestamp inside a compute pass.
    pub fn write_pass(&self, compute: &mut wgpu::ComputePass<'_>, pass: usize, end: bool) {
        if let Some(index) = self.pass_index(pass, end) {
            compute.write_timestamp(&self.queries, index);
        }
    }

    /// Writes pass `pass`'s start or end timestamp inside a render pass.
    pub fn write_render_pass(&self, render: &mut wgpu::RenderPass<'_>, pass: usize, end: bool) {
        if let Some(index) = self.pass_index(pass, end) {
            render.write_timestamp(&self.queries, index);
        }
    }

    fn pass_index(&self, pass: usize, end: bool) -> Option<u32> {
        ((pass as u32) < self.passes).then(|| 2 * (self.stages + pass as u32) + u32::from(end))
    }

    /// Records the resolve at the end of a frame's commands.
    pub fn resolve(&mut self, encoder: &mut wgpu::CommandEncoder) {
        let count = (self.stages + self.passes) * 2;
        encoder.resolve_query_set(&self.queries, 0..count, &self.resolved, 0);
        self.written = true;
    }

    /// Milliseconds per stage, then per pass (if timed), of the latest submitted frame,
    /// blocking until it is done.
    pub fn read_ms(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Option<FrameTimes> {
        if !self.written {
            return None;
        }
        capture_errors(device, || {
            let mut encoder = device.create_command_encoder(&Default::default());
            encoder.copy_buffer_to_buffer(&self.resolved, 0, &self.readback, 0, None);
            queue.submit([encoder.finish()]);
        })
        .ok()?;
        let bytes = read_mapped(device, &self.readback, self.readback.size()).ok()?;
        let ticks: Vec<u64> = bytes
            .chunks_exact(8)
            .map(|b| u64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]))
            .collect();
        let ms: Vec<f64> = ticks
            .chunks_exact(2)
            // Clocks may not be monotonic across a pass on every driver; never go negative.
            .map(|t| t[1].saturating_sub(t[0]) as f64 * self.period_ns / 1e6)
            .collect();
        let (stages, passes) = ms.split_at(self.stages as usize);
        Some(FrameTimes {
            stages: stages.to_vec(),
            passes: (self.passes > 0).then(|| passes.to_vec()),
        })
    }
}

/// GPU milliseconds of one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameTimes {
    /// One per stage.
    pub stages: Vec<f64>,
    /// One per kept pass in plan order, when the device can time inside compute passes.
    pub passes: Option<Vec<f64>>,
}
