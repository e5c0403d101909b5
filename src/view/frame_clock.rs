//! The viewer's clock: frames shown, the time since the last redraw (how far the camera moves),
//! the title's frames per second, and what frames cost on the CPU side for the report at exit.

use std::time::{Duration, Instant};

/// How often the title's figures are refreshed.
const TITLE_PERIOD: Duration = Duration::from_millis(500);

/// Running sums of what a frame costs on the CPU side.
#[derive(Default)]
pub struct Costs {
    pub frames: u32,
    pub rendered: u32,
    pub render: Duration,
    pub readback: Duration,
    pub present: Duration,
    pub reload_poll: Duration,
}

pub struct FrameClock {
    frames: u32,
    started: Instant,
    last_redraw: Instant,
    title_at: Instant,
    title_frames: u32,
    pub costs: Costs,
}

impl FrameClock {
    pub fn start() -> FrameClock {
        let now = Instant::now();
        FrameClock {
            frames: 0,
            started: now,
            last_redraw: now,
            title_at: now,
            title_frames: 0,
            costs: Costs::default(),
        }
    }

    /// Seconds since the previous call (the previous redraw).
    pub fn redraw(&mut self) -> f32 {
        let since = self.last_redraw.elapsed().as_secs_f32();
        self.last_redraw = Instant::now();
        since
    }

    /// Counts a frame shown; true when the title is due for new figures.
    pub fn count_frame(&mut self) -> bool {
        self.frames += 1;
        self.costs.frames += 1;
        self.title_frames += 1;
        self.title_at.elapsed() >= TITLE_PERIOD
    }

    /// Time since the last redraw, without starting a new one.
    pub fn since_redraw(&self) -> Duration {
        self.last_redraw.elapsed()
    }

    pub fn frames(&self) -> u32 {
        self.frames
    }

    /// Frames per second since the title was last updated; starts the next period.
    pub fn title_fps(&mut self) -> f64 {
        let fps = f64::from(self.title_frames) / self.title_at.elapsed().as_secs_f64();
        self.title_at = Instant::now();
        self.title_frames = 0;
        fps
    }

    /// What the run cost, per frame, on stderr.
    pub fn report(&self) {
        let c = &self.costs;
        let per = |d: Duration, n: u32| d.as_secs_f64() * 1e3 / f64::from(n.max(1));
        eprintln!(
            "view: {} frames in {:.2} s ({:.1} frames/s); per frame: render {:.1} ms, readback {:.2} ms, upload+present {:.2} ms, reload poll {:.3} ms",
            c.frames,
            self.started.elapsed().as_secs_f64(),
            f64::from(c.frames) / self.started.elapsed().as_secs_f64(),
            per(c.render, c.rendered),
            per(c.readback, c.rendered),
            per(c.present, c.rendered),
            per(c.reload_poll, c.frames),
        );
    }
}
