//! Running graph test files: read and check each file (a mistake in it is an error naming the
//! file and line, before anything renders), then per case compile the graph, check the plan,
//! render the seeds the expectations need and check the images. One line per case.

use super::decl::{CaseDecl, Expectation, TestFile};
use super::expect::{Measured, SeedMeasure, Verdict, check};
use crate::bench::metrics::downsample_2x;
use crate::compile;
use crate::gpu::GpuContext;
use crate::graph::compose::flatten_inline;
use crate::graph::load::{LoadedGraph, load_flattened, load_graph};
use crate::graph::ron_file::{parse_ron, read_text};
use crate::graph::set_param::set_param;
use crate::render::channels::ChannelSelection;
use crate::render::image::RgbImage;
use crate::render::session::{RenderSettings, Session};
use std::collections::{BTreeMap, BTreeSet};
use std::io::Write;
use std::path::{Path, PathBuf};

/// What a run of test files came to.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Summary {
    pub passed: usize,
    pub failed: usize,
    /// Test files that could not be read or are malformed (none of their cases ran).
    pub bad_files: usize,
}

impl Summary {
    pub fn success(&self) -> bool {
        self.failed == 0 && self.bad_files == 0 && self.passed > 0
    }
}

/// A case, checked and with its paths resolved.
struct Case {
    name: String,
    /// Where the case starts in its file, for the report.
    line: usize,
    graph: GraphSource,
    scene: Option<PathBuf>,
    size: [u32; 2],
    frames: u32,
    /// The case renders seeds first_seed, first_seed + 1, ... (`seeds` of them, wrapping),
    /// generated as it goes: a count is not a list to allocate.
    first_seed: u32,
    seeds: u32,
    set: Vec<String>,
    expect: Vec<Expectation>,
    /// Reference images by path as written, at the case's size (or as read, for `Mean`).
    references: BTreeMap<String, RgbImage>,
}

enum GraphSource {
    File(PathBuf),
    /// Changes written in the test file (`text` finds their lines).
    Inline {
        decl: Box<crate::graph::decl::GraphDecl>,
        text: String,
    },
}

/// Runs every case of every file, writing one line per case and a summary to `out`.
/// With `measure`, every expectation's measurement is printed under its case, passed or not
/// (how a new case's bounds are derived).
pub fn run_files(
    files: &[PathBuf],
    adapter: Option<&str>,
    measure: bool,
    out: &mut dyn Write,
) -> Summary {
    let mut summary = Summary::default();
    let mut gpu: Option<Result<GpuContext, String>> = None;
    for file in files {
        let cases = match read_cases(file) {
            Ok(cases) => cases,
            Err(message) => {
                let _ = writeln!(out, "error {message}");
                summary.bad_files += 1;
                continue;
            }
        };
        for case in &cases {
            let verdicts = run_case(file, case, adapter, &mut gpu);
            let failures: Vec<String> = verdicts
                .iter()
                .filter(|(_, v)| !v.passed)
                .map(|(label, v)| format!("{label}: {}", v.report))
                .collect();
            let place = format!("{}:{}", file.display(), case.line);
            if failures.is_empty() {
                summary.passed += 1;
                let n = case.expect.len();
                let plural = if n == 1 { "" } else { "s" };
                let _ = writeln!(out, "ok    {place} {} ({n} expectation{plural})", case.name);
            } else {
                summary.failed += 1;
                let _ = writeln!(out, "FAIL  {place} {}: {}", case.name, failures.join("; "));
            }
            if measure {
                for (label, v) in &verdicts {
                    let _ = writeln!(out, "      {label}: {}", v.report);
                }
            }
        }
    }
    let _ = writeln!(
        out,
        "{} cases: {} passed, {} failed{}",
        summary.passed + summary.failed,
        summary.passed,
        summary.failed,
        match summary.bad_files {
            0 => String::new(),
            n => format!("; {n} test file(s) with errors"),
        }
    );
    summary
}

/// Reads and checks a test file and loads and compiles each case's graph, rendering nothing:
/// the number of cases, or the first error (what the input fuzzer exercises).
pub fn check_file(file: &Path) -> Result<usize, String> {
    let cases = read_cases(file)?;
    for case in &cases {
        let graph = load_case_graph(file, case)?;
        compile(&graph, case.size).map_err(|e| e.to_string())?;
    }
    Ok(cases.len())
}

/// The line (1-based) of the first `needle` at or after byte `from`, else of `from`.
fn line_at(text: &str, from: usize, needle: &str) -> usize {
    let at = text[from..].find(needle).map_or(from, |i| from + i);
    text[..at].matches('\n').count() + 1
}

/// Reads a test file and checks everything that can be checked without the graph: one case
/// per name, a graph, a scene where frames are needed, channels, references, bounds.
fn read_cases(file: &Path) -> Result<Vec<Case>, String> {
    let text = read_text(file).map_err(|e| e.to_string())?;
    let decl: TestFile = parse_ron(file, &text).map_err(|e| e.to_string())?;
    if decl.cases.is_empty() {
        return Err(format!(
            "{}: no cases; list them in `cases`",
            file.display()
        ));
    }
    let dir = file.parent().unwrap_or(Path::new("."));
    let mut names = BTreeSet::new();
    let mut cases = Vec::new();
    for c in decl.cases {
        let start = text
            .find(&format!("name: \"{}\"", c.name))
            .or_else(|| text.find(&format!("\"{}\"", c.name)))
            .unwrap_or(0);
        let line = text[..start].matches('\n').count() + 1;
        let at = |needle: &str| format!("{}:{}", file.display(), line_at(&text, start, needle));
        let case_at = format!("{}:{line}: case '{}'", file.display(), c.name);
        if !names.insert(c.name.clone()) {
            return Err(format!(
                "{case_at}: two cases have this name; names must be unique"
            ));
        }
        cases.push(read_case(c, dir, &text, &at, &case_at, line)?);
    }
    Ok(cases)
}

fn read_case(
    c: CaseDecl,
    dir: &Path,
    text: &str,
    at: &dyn Fn(&str) -> String,
    case_at: &str,
    line: usize,
) -> Result<Case, String> {
    let graph = match (c.graph, c.changes) {
        (Some(path), None) => {
            let resolved = dir.join(&path);
            if !resolved.is_file() {
                return Err(format!(
                    "{}: case '{}': graph \"{path}\": no such file ({})",
                    at(&format!("\"{path}\"")),
                    c.name,
                    resolved.display()
                ));
            }
            GraphSource::File(resolved)
        }
        (None, Some(decl)) => GraphSource::Inline {
            decl: Box::new(decl),
            text: text.to_string(),
        },
        _ => {
            return Err(format!(
                "{case_at}: give either `graph: \"FILE.ron\"` or `changes: Graph(...)`, not both or neither"
            ));
        }
    };
    if c.expect.is_empty() {
        return Err(format!("{case_at}: no expectations; list them in `expect`"));
    }
    let (w, h) = c.size;
    if w == 0 || h == 0 {
        return Err(format!(
            "{}: case '{}': size ({w}, {h}) has a zero side",
            at("size:"),
            c.name
        ));
    }
    let renders = c.expect.iter().any(Expectation::renders);
    if renders && c.frames == 0 {
        return Err(format!(
            "{}: case '{}': frames must be at least 1",
            at("frames:"),
            c.name
        ));
    }
    if c.seeds == 0 {
        return Err(format!(
            "{}: case '{}': seeds must be at least 1",
            at("seeds:"),
            c.name
        ));
    }
    let samples = u64::from(c.frames) * u64::from(c.seeds) * u64::from(w) * u64::from(h);
    if renders && samples > c.max_samples {
        return Err(format!(
            "{}: case '{}': {} frames x {} seeds x {w}x{h} pixels is {samples} pixel-samples, more than max_samples ({}): lower frames, or raise max_samples if the case needs them",
            at("frames:"),
            c.name,
            c.frames,
            c.seeds,
            c.max_samples
        ));
    }
    let scene = match c.scene {
        Some(path) => {
            let resolved = dir.join(&path);
            if !resolved.is_file() {
                return Err(format!(
                    "{}: case '{}': scene \"{path}\": no such file ({})",
                    at(&format!("\"{path}\"")),
                    c.name,
                    resolved.display()
                ));
            }
            Some(resolved)
        }
        None if renders => {
            return Err(format!(
                "{case_at}: its expectations read images or counters, so it needs a `scene`"
            ));
        }
        None => None,
    };
    let mut references = BTreeMap::new();
    for e in &c.expect {
        let bad = |field: &str, message: String| -> Result<Case, String> {
            Err(format!(
                "{}: case '{}': {}: {message}",
                at(field),
                c.name,
                e.label()
            ))
        };
        if let Some(channel) = e.channel() {
            if let Err(message) = channel.parse::<ChannelSelection>() {
                return bad(&format!("\"{channel}\""), message);
            }
        }
        let (reference, resample) = match e {
            Expectation::Mean {
                value,
                reference,
                uncertainty,
                within,
                ..
            } => {
                if value.is_some() == reference.is_some() {
                    return bad(
                        "Mean",
                        "give either `value: (r, g, b)` or `reference: \"REF.exr\"`".into(),
                    );
                }
                if c.seeds < 2 {
                    return bad(
                        "Mean",
                        format!(
                            "the standard error comes from the spread between seeds: set `seeds` to at least 2 (it is {})",
                            c.seeds
                        ),
                    );
                }
                if !(within.is_finite() && *within > 0.0) {
                    return bad(
                        "within:",
                        format!(
                            "within must be a positive number of standard errors, not {within}"
                        ),
                    );
                }
                if !(uncertainty.is_finite() && *uncertainty >= 0.0) {
                    return bad(
                        "uncertainty:",
                        format!("uncertainty must be finite and not negative, not {uncertainty}"),
                    );
                }
                (reference.as_ref(), false)
            }
            Expectation::Rmse {
                reference, below, ..
            }
            | Expectation::RelMse {
                reference, below, ..
            } => {
                if !(below.is_finite() && *below > 0.0) {
                    return bad(
                        "below:",
                        format!("below must be a positive number, not {below}"),
                    );
                }
                (Some(reference), true)
            }
            _ => (None, false),
        };
        let Some(reference) = reference else { continue };
        let key = if resample {
            reference.clone()
        } else {
            format!("mean:{reference}")
        };
        if references.contains_key(&key) {
            continue;
        }
        let image = match RgbImage::read_exr(&dir.join(reference)) {
            Ok(image) => image,
            Err(message) => return bad(&format!("\"{reference}\""), message),
        };
        let image = if resample {
            match to_size(image, [w, h]) {
                Ok(image) => image,
                Err(message) => return bad(&format!("\"{reference}\""), message),
            }
        } else {
            image
        };
        references.insert(key, image);
    }
    Ok(Case {
        name: c.name,
        line,
        graph,
        scene,
        size: [w, h],
        frames: c.frames,
        first_seed: c.seed,
        seeds: c.seeds,
        set: c.set,
        expect: c.expect,
        references,
    })
}

/// A reference at the case's size: as it is, or box-filtered down by 2, 4, 8, ... (a
/// box-filtered 2W x 2H image averaged 2x2 is the W x H one).
fn to_size(mut image: RgbImage, [w, h]: [u32; 2]) -> Result<RgbImage, String> {
    let (rw, rh) = (image.width, image.height);
    while image.width > w && image.width.is_multiple_of(2) && image.height.is_multiple_of(2) {
        image = downsample_2x(&image);
    }
    if [image.width, image.height] != [w, h] {
        return Err(format!(
            "the reference is {rw}x{rh}, which is not the case's size {w}x{h} times a power of 2"
        ));
    }
    Ok(image)
}

/// Runs one case: a verdict per expectation, or one failed verdict for the whole case (its
/// graph does not load or compile, or it cannot render).
fn run_case(
    file: &Path,
    case: &Case,
    adapter: Option<&str>,
    gpu: &mut Option<Result<GpuContext, String>>,
) -> Vec<(String, Verdict)> {
    let fail = |what: &str, message: String| {
        vec![(
            what.to_string(),
            Verdict {
                passed: false,
                report: message,
            },
        )]
    };
    let graph = match load_case_graph(file, case) {
        Ok(graph) => graph,
        Err(message) => return fail("graph", message),
    };
    let plan = match compile(&graph, case.size) {
        Ok(plan) => plan,
        Err(e) => return fail("graph", format!("does not compile: {e}")),
    };
    let seeds = if case.expect.iter().any(Expectation::renders) {
        let ctx =
            match gpu.get_or_insert_with(|| GpuContext::new(adapter).map_err(|e| e.to_string())) {
                Ok(ctx) => ctx.clone(),
                Err(e) => return fail("render", format!("no GPU: {e}")),
            };
        match render_seeds(case, &graph, &ctx) {
            Ok(seeds) => seeds,
            Err(message) => return fail("render", message),
        }
    } else {
        Vec::new()
    };
    let references = mean_keys(&case.references);
    let measured = Measured {
        plan: &plan,
        seeds: &seeds,
        references: &references,
    };
    case.expect
        .iter()
        .map(|e| (e.label(), check(e, &measured)))
        .collect()
}

/// References by path as written: `Mean`'s under their plain path too (any size).
fn mean_keys(references: &BTreeMap<String, RgbImage>) -> BTreeMap<String, RgbImage> {
    let mut out = references.clone();
    for (key, image) in references {
        if let Some(path) = key.strip_prefix("mean:") {
            out.entry(path.to_string()).or_insert_with(|| image.clone());
        }
    }
    out
}

fn load_case_graph(file: &Path, case: &Case) -> Result<LoadedGraph, String> {
    let mut graph = match &case.graph {
        GraphSource::File(path) => load_graph(path),
        GraphSource::Inline { decl, text } => {
            flatten_inline(file, text, decl).and_then(|flat| load_flattened(file, flat))
        }
    }
    .map_err(|e| format!("does not load: {e}"))?;
    for s in &case.set {
        set_param(&mut graph, s, crate::render::provided::path_tracer())
            .map_err(|e| format!("set \"{s}\": {e}"))?;
    }
    Ok(graph)
}

/// Renders `frames` frames for every seed and reads what the expectations need.
fn render_seeds(
    case: &Case,
    graph: &LoadedGraph,
    ctx: &GpuContext,
) -> Result<Vec<SeedMeasure>, String> {
    let channels: BTreeSet<&str> = case
        .expect
        .iter()
        .filter_map(Expectation::channel)
        .collect();
    let wants_dropped = case.expect.contains(&Expectation::NoDroppedSamples);
    let scene = case.scene.clone().expect("checked when the file was read");
    let mut seeds = Vec::new();
    for seed in (0..case.seeds).map(|i| case.first_seed.wrapping_add(i)) {
        let settings = RenderSettings {
            size: case.size,
            seed,
            max_frames: u32::MAX,
            ..RenderSettings::new(graph.file.clone(), scene.clone())
        };
        let mut session = Session::builder(&settings)
            .on(ctx.clone())
            .graph(graph.clone())
            .build()
            .map_err(|e| format!("cannot render: {e}"))?;
        for _ in 0..case.frames {
            session
                .render_frame()
                .map_err(|e| format!("frame failed: {e}"))?;
        }
        let mut images = BTreeMap::new();
        for &channel in &channels {
            let selection: ChannelSelection = channel.parse().expect("checked when read");
            let image = session
                .image(&selection)
                .map_err(|e| format!("channel '{channel}': {e}"))?;
            images.insert(channel.to_string(), image);
        }
        let dropped = wants_dropped.then(|| session.dropped().map_err(|e| e.to_string()));
        seeds.push(SeedMeasure {
            seed,
            images,
            dropped,
        });
    }
    Ok(seeds)
}
