//! How a [`Session`] is made: its settings, and what else a caller knows — the channel it will
//! show (checked against the graph before any GPU work), whether it writes a partial file, the
//! device it runs on, a graph already loaded. The graph is compiled once.

use super::channels::ChannelSelection;
use super::session::{
    RenderError, RenderSettings, Session, compile_for, load_scene_for, prepare_graph,
};
use super::tiling::Tile;
use crate::gpu::GpuContext;
use crate::graph::load::{LoadedGraph, load_graph};

impl Session {
    /// A session of any graph that compiles; reading the image, the dropped samples or the
    /// rays needs what [`render_contract`] lists (see [`SessionBuilder::showing`]).
    pub fn new(settings: &RenderSettings) -> Result<Session, RenderError> {
        Session::builder(settings).build()
    }

    /// A session with more said about it: what it shows, whether it writes a partial file,
    /// the device it runs on, a graph already loaded.
    pub fn builder(settings: &RenderSettings) -> SessionBuilder<'_> {
        SessionBuilder::new(settings)
    }
}

pub struct SessionBuilder<'a> {
    settings: &'a RenderSettings,
    shown: Option<&'a ChannelSelection>,
    partial: bool,
    context: Option<GpuContext>,
    graph: Option<LoadedGraph>,
}

impl<'a> SessionBuilder<'a> {
    pub fn new(settings: &'a RenderSettings) -> SessionBuilder<'a> {
        SessionBuilder {
            settings,
            shown: None,
            partial: false,
            context: None,
            graph: None,
        }
    }

    /// Checks the graph against what `render` reads back for `channel` before any GPU work, so
    /// a graph that cannot be shown fails naming the graph and resource, not after the frames;
    /// a texture channel is kept.
    pub fn showing(mut self, channel: &'a ChannelSelection) -> SessionBuilder<'a> {
        self.shown = Some(channel);
        self
    }

    /// For `render --partial`: the graph must also have what
    /// [`partial_contract`](super::session::partial_contract) lists, which the session keeps
    /// (made outputs, so they can be read back after the frames).
    pub fn partial(mut self) -> SessionBuilder<'a> {
        self.partial = true;
        self
    }

    /// Runs on an existing device (`settings.adapter` is not consulted): a viewer renders on
    /// the device its window presents with, and rebuilds sessions on it.
    pub fn on(mut self, ctx: GpuContext) -> SessionBuilder<'a> {
        self.context = Some(ctx);
        self
    }

    /// A graph already loaded (e.g. flattened from changes written inline in a graph test);
    /// `settings.graph` is not read.
    pub fn graph(mut self, graph: LoadedGraph) -> SessionBuilder<'a> {
        self.graph = Some(graph);
        self
    }

    /// Loads (unless given) and compiles the graph, loads the scene, then opens the device
    /// (unless given): errors of the files come before any GPU work.
    pub fn build(self) -> Result<Session, RenderError> {
        let settings = self.settings;
        let graph = match self.graph {
            Some(graph) => graph,
            None => load_graph(&settings.graph)?,
        };
        let graph = prepare_graph(graph, settings, self.shown, self.partial)?;
        let plan = compile_for(&graph, settings.size, self.shown, self.partial)?;
        let scene = load_scene_for(settings)?;
        let ctx = match self.context {
            Some(ctx) => ctx,
            None => GpuContext::new(settings.adapter.as_deref())?,
        };
        Session::from_plan(
            ctx,
            &graph,
            plan,
            settings,
            Tile::whole(settings.size),
            scene,
        )
    }
}
