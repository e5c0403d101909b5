//! The viewer's window and frame loop (winit): input from the keyboard, the mouse or a script;
//! one frame rendered, read back and presented per redraw; hot reload polled each frame.

use super::ViewOptions;
use super::camera_control::{CameraInput, FlyCamera};
use super::channel_list::ChannelChoice;
use super::frame_clock::FrameClock;
use super::keys::Key;
use super::present::{Presenter, capturable};
use super::reload::{ReloadOutcome, Reloader};
use super::script::{Script, ScriptFrame};
use crate::gpu::GpuContext;
use crate::gpu::context::{backends as passgraph_backends, describe};
use crate::render::session::Session;
use crate::scene::CameraDesc;
use glam::Vec2;
use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::PhysicalKey;
use winit::window::{Window, WindowId};

/// Camera movement in a scripted run advances by this much per frame, so it does not depend
/// on how fast the machine renders.
const SCRIPT_FRAME_SECONDS: f32 = 1.0 / 30.0;
/// When nothing changes (accumulation done, no input), check for edits this often.
const IDLE_PERIOD: Duration = Duration::from_millis(100);

pub fn run(options: ViewOptions) -> Result<(), String> {
    // A bad script is reported before any window opens...
    let script = options.script.as_deref().map(Script::load).transpose()?;
    // So is a graph that does not compile (this needs no GPU and no display).
    crate::compile_file(&options.settings.graph, options.settings.size)
        .map_err(|e| e.to_string())?;
    const HINT: &str =
        "on a machine without a display, run under Xvfb: xvfb-run passgraph view ...";
    if ["DISPLAY", "WAYLAND_DISPLAY", "WAYLAND_SOCKET"]
        .iter()
        .all(|v| std::env::var_os(v).is_none_or(|s| s.is_empty()))
    {
        return Err(format!(
            "cannot open a window: no display (DISPLAY is not set); {HINT}"
        ));
    }
    let event_loop = EventLoop::new().map_err(|e| {
        // winit's OS errors start with the winit source file and line that raised them.
        let text = e.to_string();
        let reason = match text.strip_prefix("os error at ") {
            Some(rest) => rest.split_once(": ").map_or(rest, |(_, r)| r).to_string(),
            None => text,
        };
        format!("cannot open a window: {reason}; {HINT}")
    })?;
    let mut app = App {
        options,
        script,
        viewer: None,
        result: Ok(()),
    };
    event_loop
        .run_app(&mut app)
        .map_err(|e| format!("the window's event loop failed: {e}"))?;
    if let Some(viewer) = &app.viewer {
        viewer.clock.report();
    }
    app.result
}

struct App {
    options: ViewOptions,
    script: Option<Script>,
    viewer: Option<Viewer>,
    result: Result<(), String>,
}

impl App {
    fn fail(&mut self, event_loop: &ActiveEventLoop, message: String) {
        self.result = Err(message);
        event_loop.exit();
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.viewer.is_some() {
            return;
        }
        match Viewer::new(event_loop, &self.options) {
            Ok(viewer) => self.viewer = Some(viewer),
            Err(message) => self.fail(event_loop, message),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let Some(viewer) = self.viewer.as_mut() else {
            return;
        };
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => viewer.resize([size.width, size.height]),
            WindowEvent::RedrawRequested => {
                let scripted = self.script.as_mut().map(Script::frame);
                match viewer.frame(scripted, self.options.frames) {
                    Ok(true) => {}
                    Ok(false) => event_loop.exit(),
                    Err(message) => self.fail(event_loop, message),
                }
            }
            other => viewer.input.event(&other),
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let Some(viewer) = self.viewer.as_mut() else {
            return;
        };
        // A script counts frames, so it keeps them coming; so does work in progress.
        let busy = self.script.is_some() || viewer.busy();
        if busy || viewer.clock.since_redraw() >= IDLE_PERIOD {
            event_loop.set_control_flow(ControlFlow::Poll);
            viewer.display.window.request_redraw();
        } else {
            event_loop.set_control_flow(ControlFlow::WaitUntil(Instant::now() + IDLE_PERIOD));
        }
    }
}

/// Keyboard and mouse state between two frames.
#[derive(Default)]
struct LiveInput {
    held: HashSet<Key>,
    taps: Vec<Key>,
    dragging: bool,
    cursor: Option<Vec2>,
    drag: Vec2,
    scroll: f32,
}

impl LiveInput {
    fn event(&mut self, event: &WindowEvent) {
        match event {
            WindowEvent::KeyboardInput { event, .. } => {
                let PhysicalKey::Code(code) = event.physical_key else {
                    return;
                };
                let Some(key) = Key::from_code(code) else {
                    return;
                };
                match event.state {
                    ElementState::Pressed if key.is_movement() => {
                        self.held.insert(key);
                    }
                    ElementState::Pressed if !event.repeat => self.taps.push(key),
                    ElementState::Released => {
                        self.held.remove(&key);
                    }
                    _ => {}
                }
            }
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left,
                ..
            } => self.dragging = state.is_pressed(),
            WindowEvent::CursorMoved { position, .. } => {
                let now = Vec2::new(position.x as f32, position.y as f32);
                if let (true, Some(before)) = (self.dragging, self.cursor) {
                    self.drag += now - before;
                }
                self.cursor = Some(now);
            }
            WindowEvent::MouseWheel { delta, .. } => {
                self.scroll += match delta {
                    MouseScrollDelta::LineDelta(_, y) => *y,
                    // Roughly one line per 40 pixels of touchpad scrolling.
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
            }
            WindowEvent::Focused(false) => {
                // Releases are not delivered to an unfocused window: stop moving.
                self.held.clear();
                self.dragging = false;
            }
            _ => {}
        }
    }

    /// This frame's input, the live one merged with the script's; clears the one-shot parts.
    fn take(&mut self, scripted: Option<ScriptFrame>) -> ScriptFrame {
        let mut frame = scripted.unwrap_or_default();
        frame.taps.splice(0..0, self.taps.drain(..));
        frame.held.extend(self.held.iter().copied());
        frame.drag += std::mem::take(&mut self.drag);
        frame.scroll += std::mem::take(&mut self.scroll);
        frame
    }
}

/// The window and the surface it presents through.
struct Display {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
}

impl Display {
    fn size(&self) -> [u32; 2] {
        [self.config.width, self.config.height]
    }

    fn resize(&mut self, ctx: &GpuContext, size: [u32; 2]) {
        self.config.width = size[0];
        self.config.height = size[1];
        self.surface.configure(ctx.device(), &self.config);
    }

    /// Draws the presenter's image into the window.
    fn present(&mut self, ctx: &GpuContext, presenter: &Presenter) -> Result<(), String> {
        let frame = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(f)
            | wgpu::CurrentSurfaceTexture::Suboptimal(f) => f,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                // Reconfigure and show it next frame.
                self.surface.configure(ctx.device(), &self.config);
                return Ok(());
            }
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => {
                return Ok(());
            }
            wgpu::CurrentSurfaceTexture::Validation => {
                return Err("the window's surface failed validation".into());
            }
        };
        let view = frame
            .texture
            .create_view(&wgpu::TextureViewDescriptor::default());
        let mut encoder = ctx
            .device()
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("present"),
            });
        presenter.draw(&mut encoder, &view);
        ctx.queue().submit([encoder.finish()]);
        self.window.pre_present_notify();
        ctx.queue().present(frame);
        Ok(())
    }
}

/// The viewer's state by role: the display, the device and the session it renders (with the
/// reloader that rebuilds it), the camera and its input, the channel shown, the clock.
struct Viewer {
    display: Display,
    ctx: GpuContext,
    reloader: Reloader,
    session: Session,
    presenter: Presenter,
    fly: FlyCamera,
    camera: CameraDesc,
    channels: ChannelChoice,
    input: LiveInput,
    /// A script drives the camera: it moves by a fixed step per frame.
    scripted: bool,
    /// The shown image is older than the accumulation (or the channel changed).
    stale: bool,
    clock: FrameClock,
}

impl Viewer {
    fn new(event_loop: &ActiveEventLoop, options: &ViewOptions) -> Result<Viewer, String> {
        let settings = &options.settings;
        let [w, h] = settings
            .size
            .map(|s| s.saturating_mul(options.window_scale.max(1)));
        let window = event_loop
            .create_window(
                Window::default_attributes()
                    .with_title("passgraph view")
                    .with_inner_size(winit::dpi::PhysicalSize::new(w, h)),
            )
            .map_err(|e| format!("cannot create a window: {e}"))?;
        let window = Arc::new(window);
        let mut descriptor = wgpu::InstanceDescriptor::new_with_display_handle(Box::new(
            event_loop.owned_display_handle(),
        ))
        .with_env();
        descriptor.backends = passgraph_backends().map_err(|e| e.to_string())?;
        let instance = wgpu::Instance::new(descriptor);
        let surface = instance
            .create_surface(window.clone())
            .map_err(|e| format!("cannot draw into the window: {e}"))?;
        let ctx = GpuContext::with_instance(&instance, Some(&surface), settings.adapter.as_deref())
            .map_err(|e| e.to_string())?;
        let caps = surface.get_capabilities(ctx.adapter());
        // An 8-bit format the screenshot can read back; sRGB first so the hardware encodes.
        let format = caps
            .formats
            .iter()
            .copied()
            .filter(|f| capturable(*f))
            .max_by_key(|f| f.is_srgb())
            .ok_or_else(|| {
                format!(
                    "the window offers no 8-bit RGBA or BGRA format (it offers {:?})",
                    caps.formats
                )
            })?;
        let size = window.inner_size();
        let mut config = surface
            .get_default_config(ctx.adapter(), size.width.max(1), size.height.max(1))
            .ok_or("the adapter cannot present to this window")?;
        config.format = format;
        config.present_mode = wgpu::PresentMode::AutoVsync;
        surface.configure(ctx.device(), &config);

        let (reloader, session) = Reloader::new(ctx.clone(), settings.clone())?;
        let info = ctx.adapter_info();
        eprintln!(
            "adapter: {}; surface {:?}; watching {} files for changes",
            describe(info),
            format,
            reloader.watched_files().count()
        );
        eprintln!(
            "keys: WASD/QE fly, drag to look, scroll for speed, 1-9 or C channel, R reset, P save, Esc quit"
        );
        let camera = session.scene_description().camera;
        let presenter = Presenter::new(ctx.device(), format, settings.size);
        let channels = ChannelChoice::new(session.plan());
        Ok(Viewer {
            display: Display {
                window,
                surface,
                config,
            },
            ctx,
            reloader,
            fly: FlyCamera::new(&camera),
            camera,
            channels,
            session,
            presenter,
            input: LiveInput::default(),
            scripted: options.script.is_some(),
            stale: true,
            clock: FrameClock::start(),
        })
    }

    fn busy(&self) -> bool {
        self.stale
            || self.session.accumulated() < self.session_max_frames()
            || !self.input.held.is_empty()
            || !self.input.taps.is_empty()
            || self.input.drag != Vec2::ZERO
            || self.input.scroll != 0.0
    }

    fn session_max_frames(&self) -> u32 {
        self.reloader.settings().max_frames
    }

    fn resize(&mut self, size: [u32; 2]) {
        if size[0] == 0 || size[1] == 0 {
            return;
        }
        self.display.resize(&self.ctx, size);
        self.stale = true;
    }

    /// One frame: input, reload, render, present, screenshots. Ok(false) ends the run.
    fn frame(
        &mut self,
        scripted: Option<ScriptFrame>,
        max_frames: Option<u32>,
    ) -> Result<bool, String> {
        let since_last = self.clock.redraw();
        let input = self.input.take(scripted);
        let seconds = if self.scripted {
            SCRIPT_FRAME_SECONDS
        } else {
            // Clamped, so a stall (a reload, a slow frame) does not fling the camera away.
            since_last.min(0.1)
        };
        let mut quit = input.quit;
        for key in &input.taps {
            match key {
                Key::Escape => quit = true,
                Key::R => {
                    self.session.reset();
                    self.stale = true;
                }
                Key::P => self.save()?,
                Key::C => self.select((self.channels.current() + 1) % self.channels.len()),
                Key::Digit(n) => {
                    let i = usize::from(*n) - 1;
                    if i < self.channels.len() {
                        self.select(i);
                    } else {
                        eprintln!("no channel {n}: this graph has {}", self.channels.len());
                    }
                }
                _ => {}
            }
        }
        let axis = |plus: Key, minus: Key| {
            f32::from(u8::from(input.held.contains(&plus)))
                - f32::from(u8::from(input.held.contains(&minus)))
        };
        let camera_input = CameraInput {
            forward: axis(Key::W, Key::S),
            right: axis(Key::D, Key::A),
            up: axis(Key::E, Key::Q),
            drag: input.drag,
            scroll: input.scroll,
        };
        if let Some(camera) = self.fly.update(&camera_input, seconds) {
            self.camera = camera;
            self.session.set_camera(camera).map_err(|e| e.to_string())?;
            self.stale = true;
        }

        let t = Instant::now();
        self.poll_reload();
        self.clock.costs.reload_poll += t.elapsed();

        let t = Instant::now();
        if self.session.render_frame().map_err(|e| e.to_string())? {
            self.session.wait().map_err(|e| e.to_string())?;
            self.clock.costs.render += t.elapsed();
            self.clock.costs.rendered += 1;
            self.stale = true;
        }
        if self.stale {
            let t = Instant::now();
            let (label, selection) = self.channels.shown();
            let image = self
                .session
                .image(selection)
                .map_err(|e| format!("cannot show channel '{label}': {e}"))?;
            self.clock.costs.readback += t.elapsed();
            let t = Instant::now();
            self.presenter.upload(self.ctx.queue(), &image);
            self.display.present(&self.ctx, &self.presenter)?;
            self.clock.costs.present += t.elapsed();
            self.stale = false;
        }
        for path in &input.screenshots {
            self.screenshot(path)?;
        }
        if self.clock.count_frame() {
            self.update_title();
        }
        let done = max_frames.is_some_and(|n| self.clock.frames() >= n);
        Ok(!(quit || done))
    }

    fn select(&mut self, channel: usize) {
        self.channels.select(channel);
        self.stale = true;
        eprintln!("channel {}: {}", channel + 1, self.channels.shown().0);
    }

    fn poll_reload(&mut self) {
        match self.reloader.poll(self.camera) {
            ReloadOutcome::Unchanged => {}
            ReloadOutcome::Reloaded { session, changed } => {
                eprintln!("reloaded the graph ({} changed)", list(&changed));
                self.session = *session;
                self.channels.refresh(self.session.plan());
                self.stale = true;
            }
            ReloadOutcome::Failed { message, changed } => {
                eprintln!(
                    "reload failed ({} changed); still running the last good graph:\n{message}",
                    list(&changed)
                );
            }
        }
    }

    /// Writes what the window shows now, at the window's size.
    fn screenshot(&self, path: &Path) -> Result<(), String> {
        let shot =
            self.presenter
                .capture(self.ctx.device(), self.ctx.queue(), self.display.size())?;
        let mut png = Vec::new();
        shot.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
            .map_err(|e| format!("{}: cannot encode PNG: {e}", path.display()))?;
        crate::atomic_write::write_atomic(path, &png)
            .map_err(|e| format!("{}: cannot write: {e}", path.display()))?;
        println!("screenshot: {}", path.display());
        Ok(())
    }

    /// P: the current image as PNG (sRGB) and EXR (linear), under the first unused name.
    fn save(&self) -> Result<(), String> {
        let (label, selection) = self.channels.shown();
        let image = self
            .session
            .image(selection)
            .map_err(|e| format!("cannot save channel '{label}': {e}"))?;
        let stem = (1..)
            .map(|n| format!("passgraph-view-{n:03}"))
            .find(|s| {
                !PathBuf::from(format!("{s}.png")).exists()
                    && !PathBuf::from(format!("{s}.exr")).exists()
            })
            .unwrap_or_else(|| "passgraph-view".into());
        // Both files as a set: written beside their targets, then renamed.
        let paths = ["png", "exr"].map(|ext| PathBuf::from(format!("{stem}.{ext}")));
        let encoded = paths
            .iter()
            .map(|p| image.encode_for(p))
            .collect::<Result<Vec<_>, _>>()?;
        let files: Vec<(&Path, &[u8])> = paths
            .iter()
            .zip(&encoded)
            .map(|(p, b)| (p.as_path(), b.as_slice()))
            .collect();
        crate::atomic_write::write_atomic_set(&files)
            .map_err(|(path, e)| format!("{}: cannot write: {e}", path.display()))?;
        for path in &paths {
            println!(
                "saved {} ({label}, {} frames)",
                path.display(),
                self.session.accumulated()
            );
        }
        Ok(())
    }

    fn update_title(&mut self) {
        let fps = self.clock.title_fps();
        let plan = self.session.plan();
        let times = match self.session.last_frame_times() {
            Some(t) => match t.passes {
                Some(passes) => plan
                    .passes
                    .iter()
                    .zip(passes)
                    .map(|(p, ms)| format!("{} {ms:.1}", p.name))
                    .collect::<Vec<_>>()
                    .join(", "),
                None => t
                    .stages
                    .iter()
                    .enumerate()
                    .map(|(s, ms)| format!("stage {s} {ms:.1}"))
                    .collect::<Vec<_>>()
                    .join(", "),
            },
            None => "no GPU timestamps".into(),
        };
        self.display.window.set_title(&format!(
            "passgraph view | {} | {fps:.1} frames/s | {} frames | GPU ms: {times}",
            self.channels.shown().0,
            self.session.accumulated(),
        ));
    }
}

fn list(files: &[PathBuf]) -> String {
    files
        .iter()
        .map(|f| f.display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
}
