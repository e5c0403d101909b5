//! Joins a pass's WGSL with its `#include`d files, keeping a map back to the original lines so
//! that naga's errors point at the file and line the user wrote.

use super::error::GraphError;
use std::collections::HashSet;
use std::path::{Component, Path, PathBuf};
use std::sync::{Arc, OnceLock};

/// A shader's WGSL after the include step, with the map from `code` back to the source files.
#[derive(Clone, Debug)]
pub struct ShaderSource {
    /// The pass's main shader file.
    pub path: PathBuf,
    /// The joined WGSL handed to naga.
    pub code: String,
    /// Every file that went into `code`; `files[0]` is `path`.
    files: Vec<PathBuf>,
    /// Runs of consecutive lines from one file, ordered by `start`.
    segments: Vec<Segment>,
    /// `code` parsed and validated once, by reflection; shared by every clone, so that
    /// specialising a pass (passgraph-gpu) starts from it instead of parsing the WGSL again.
    validated: OnceLock<Arc<ValidShader>>,
}

/// A shader's naga module and its validation info under the framework's capability policy
/// ([`crate::reflect::capabilities`]).
pub struct ValidShader {
    pub module: naga::Module,
    pub info: naga::valid::ModuleInfo,
}

impl std::fmt::Debug for ValidShader {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        // The module would print thousands of lines into any failing test's message.
        f.write_str("ValidShader { .. }")
    }
}

/// `code[start..]` (up to the next segment) holds consecutive lines of `files[file]`,
/// beginning with line `line`. Segments always begin at the start of a line of `code`.
#[derive(Clone, Copy, Debug)]
struct Segment {
    start: usize,
    file: usize,
    line: usize,
}

impl ShaderSource {
    /// The module reflection parsed and validated, if reflection has run on this source.
    pub fn validated(&self) -> Option<&ValidShader> {
        self.validated.get().map(|v| v.as_ref())
    }

    /// Keeps the module reflection validated (the first one kept stays).
    pub(crate) fn keep_validated(&self, shader: ValidShader) {
        let _ = self.validated.set(Arc::new(shader));
    }

    /// Reads `path`, replacing each line `#include "rel/path.wgsl"` (leading whitespace allowed)
    /// by that file's content, recursively.
    ///
    /// An include is resolved relative to the including file's directory first, then relative
    /// to `shader_root` (the project's `shaders/` dir), so `#include "lib/rng.wgsl"` works from
    /// anywhere. Each file is included at most once per shader, identified by canonical path:
    /// WGSL forbids redefinitions, so a repeated or circular include is skipped silently.
    ///
    /// Errors: an unreadable main file is [`GraphError::Io`]; a missing include or a malformed
    /// `#include` line is [`GraphError::Include`] at its line in the including file.
    pub fn load(path: &Path, shader_root: &Path) -> Result<ShaderSource, GraphError> {
        let text = crate::text_file::read_utf8(path).map_err(|source| GraphError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let mut builder = Builder {
            shader_root,
            code: String::with_capacity(text.len()),
            files: Vec::new(),
            segments: Vec::new(),
            included: HashSet::new(),
            depth: 0,
        };
        // The main file counts as included, so a library including it back is a skipped cycle.
        if let Ok(canonical) = path.canonicalize() {
            builder.included.insert(canonical);
        }
        builder.append_file(path.to_path_buf(), &text)?;

        // Errors at the very end of the code (e.g. a missing `}`) belong to the main file, even
        // when its last line is an include.
        if builder.segments.last().is_some_and(|s| s.file != 0) {
            let main_lines = text.lines().count();
            builder.segments.push(Segment {
                start: builder.code.len(),
                file: 0,
                line: main_lines + usize::from(text.ends_with('\n')),
            });
        }

        Ok(ShaderSource {
            path: path.to_path_buf(),
            code: builder.code,
            files: builder.files,
            segments: builder.segments,
            validated: OnceLock::new(),
        })
    }

    /// A source without includes (for tests and generated shaders).
    pub fn from_code(path: PathBuf, code: String) -> ShaderSource {
        ShaderSource {
            files: vec![path.clone()],
            segments: vec![Segment {
                start: 0,
                file: 0,
                line: 1,
            }],
            path,
            code,
            validated: OnceLock::new(),
        }
    }

    /// Every file that went into `code`, the main file first: what a file watcher should watch.
    pub fn files(&self) -> &[PathBuf] {
        &self.files
    }

    /// Maps a byte offset in `code` to (original file, 1-based line, 1-based column).
    ///
    /// The column counts characters, as editors do. Offsets past the end map to the end.
    pub fn locate(&self, offset: usize) -> (PathBuf, usize, usize) {
        let mut offset = offset.min(self.code.len());
        while !self.code.is_char_boundary(offset) {
            offset -= 1;
        }
        let index = self.segments.partition_point(|s| s.start <= offset);
        let Some(segment) = index.checked_sub(1).map(|i| self.segments[i]) else {
            return (self.path.clone(), 1, 1);
        };
        let before = &self.code[segment.start..offset];
        let line = segment.line + before.matches('\n').count();
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let col = before[line_start..].chars().count() + 1;
        let file = self.files.get(segment.file).unwrap_or(&self.path).clone();
        (file, line, col)
    }
}

struct Builder<'a> {
    shader_root: &'a Path,
    code: String,
    files: Vec<PathBuf>,
    segments: Vec<Segment>,
    /// Canonical paths of the files already in `code`.
    included: HashSet<PathBuf>,
    /// How many includes deep `append_file` is: each level recurses, so it is bounded.
    depth: usize,
}

/// The deepest chain of nested includes: far beyond any real library, far below a stack overflow.
pub const MAX_INCLUDE_DEPTH: usize = 64;

impl Builder<'_> {
    /// Appends `text` (the content of `path`), expanding its includes.
    fn append_file(&mut self, path: PathBuf, text: &str) -> Result<(), GraphError> {
        let file = self.files.len();
        self.files.push(path);
        // Whether the last segment is this file's and continues with the next line.
        let mut in_segment = false;
        for (index, line) in text.split_inclusive('\n').enumerate() {
            let line_number = index + 1;
            match parse_include(line) {
                Directive::None => {
                    if !in_segment {
                        self.segments.push(Segment {
                            start: self.code.len(),
                            file,
                            line: line_number,
                        });
                        in_segment = true;
                    }
                    self.code.push_str(line);
                }
                Directive::Include(include) => {
                    // The directive line itself is dropped; the next line starts a new segment.
                    in_segment = false;
                    self.include(file, line_number, include)?;
                }
                Directive::Malformed { argument, reason } => {
                    return Err(GraphError::Include {
                        file: self.files[file].clone(),
                        line: line_number,
                        include: argument.to_string(),
                        reason: reason.to_string(),
                    });
                }
            }
        }
        Ok(())
    }

    /// Expands `#include "include"` found on line `line` of `files[from]`.
    fn include(&mut self, from: usize, line: usize, include: &str) -> Result<(), GraphError> {
        let including_file = self.files[from].clone();
        let error = |reason: String| GraphError::Include {
            file: including_file.clone(),
            line,
            include: include.to_string(),
            reason,
        };
        let including_dir = including_file.parent().unwrap_or(Path::new(""));
        let candidates = [including_dir.join(include), self.shader_root.join(include)];
        let Some(found) = candidates.iter().find(|c| c.is_file()) else {
            return Err(error(format!(
                "file not found (looked for {} and {})",
                candidates[0].display(),
                candidates[1].display()
            )));
        };
        let canonical = found
            .canonicalize()
            .map_err(|e| error(format!("cannot resolve {}: {e}", found.display())))?;
        if !self.included.insert(canonical) {
            return Ok(());
        }
        if self.depth >= MAX_INCLUDE_DEPTH {
            return Err(error(format!(
                "includes are nested more than {MAX_INCLUDE_DEPTH} deep; a chain this long is a mistake (or a generated file): join the files"
            )));
        }
        let text = crate::text_file::read_utf8(found)
            .map_err(|e| error(format!("cannot read {}: {e}", found.display())))?;
        self.depth += 1;
        let appended = self.append_file(normalize(found), &text);
        self.depth -= 1;
        appended?;
        // The including file's next line must start on a line of its own.
        if !self.code.is_empty() && !self.code.ends_with('\n') {
            self.code.push('\n');
        }
        Ok(())
    }
}

enum Directive<'a> {
    None,
    Include(&'a str),
    Malformed {
        argument: &'a str,
        reason: &'static str,
    },
}

/// Recognises `#include "path"`, optionally followed by a `//` comment.
fn parse_include(line: &str) -> Directive<'_> {
    const USAGE: &str = "expected #include \"relative/path.wgsl\"";
    let Some(rest) = line.trim_start().strip_prefix("#include") else {
        return Directive::None;
    };
    let argument = rest.trim();
    // `#includes` and the like are still meant as directives: WGSL has no `#` syntax.
    if !rest.is_empty() && !rest.starts_with(|c: char| c.is_whitespace() || c == '"') {
        return Directive::Malformed {
            argument,
            reason: USAGE,
        };
    }
    let Some(quoted) = argument.strip_prefix('"') else {
        return Directive::Malformed {
            argument,
            reason: USAGE,
        };
    };
    let Some((path, after)) = quoted.split_once('"') else {
        return Directive::Malformed {
            argument,
            reason: "missing closing quote",
        };
    };
    let after = after.trim();
    if !after.is_empty() && !after.starts_with("//") {
        return Directive::Malformed {
            argument,
            reason: "unexpected text after the path",
        };
    }
    if path.trim().is_empty() {
        return Directive::Malformed {
            argument,
            reason: "empty path",
        };
    }
    Directive::Include(path)
}

/// Removes `.` and `dir/..` from a path for display, so errors name
/// `shaders/lib/rng.wgsl` rather than `shaders/passes/../lib/rng.wgsl`.
fn normalize(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for component in path.components() {
        match component {
            Component::CurDir => {}
            Component::ParentDir
                if matches!(out.components().next_back(), Some(Component::Normal(_))) =>
            {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fs;

    /// Writes `files` (relative path, content) under a temp dir and returns it.
    fn project(files: &[(&str, &str)]) -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        for (path, content) in files {
            let path = dir.path().join(path);
            fs::create_dir_all(path.parent().unwrap()).unwrap();
            fs::write(path, content).unwrap();
        }
        dir
    }

    fn same_file(a: &Path, b: &Path) -> bool {
        a.canonicalize().unwrap() == b.canonicalize().unwrap()
    }

    /// Where `needle` (first occurrence) lands in the original files.
    fn locate_text(source: &ShaderSource, needle: &str) -> (PathBuf, usize, usize) {
        source.locate(source.code.find(needle).expect("needle in code"))
    }

    #[test]
    fn include_is_replaced_by_file_content() {
        let dir = project(&[
            ("shaders/lib/a.wgsl", "const A = 1;\n"),
            (
                "shaders/main.wgsl",
                "#include \"lib/a.wgsl\"\nconst B = A;\n",
            ),
        ]);
        let root = dir.path().join("shaders");
        let source = ShaderSource::load(&root.join("main.wgsl"), &root).unwrap();
        assert_eq!(source.code, "const A = 1;\nconst B = A;\n");
        assert_eq!(source.files().len(), 2);
    }

    #[test]
    fn lines_in_included_file_map_to_that_file_and_its_own_line() {
        let dir = project(&[
            (
                "shaders/lib/rng.wgsl",
                "// rng\n\nfn rng() -> u32 {\n  return 4u;\n}\n",
            ),
            (
                "shaders/passes/p.wgsl",
                "// pass\n#include \"lib/rng.wgsl\"\nconst X = 1;\n",
            ),
        ]);
        let root = dir.path().join("shaders");
        let source = ShaderSource::load(&root.join("passes/p.wgsl"), &root).unwrap();
        let (file, line, col) = locate_text(&source, "return");
        assert!(same_file(&file, &root.join("lib/rng.wgsl")));
        assert_eq!((line, col), (4, 3));
    }

    #[test]
    fn lines_after_include_keep_main_file_line_numbers() {
        let dir = project(&[
            (
                "shaders/lib/rng.wgsl",
                "const R1 = 1;\nconst R2 = 2;\nconst R3 = 3;\n",
            ),
            (
                "shaders/p.wgsl",
                "// a\n#include \"lib/rng.wgsl\"\n\nconst X = 1;\n",
            ),
        ]);
        let root = dir.path().join("shaders");
        let main = root.join("p.wgsl");
        let source = ShaderSource::load(&main, &root).unwrap();
        let (file, line, col) = locate_text(&source, "X");
        assert_eq!(file, main);
        assert_eq!((line, col), (4, 7));
        assert_eq!(locate_text(&source, "// a"), (main.clone(), 1, 1));
    }

    #[test]
    fn include_resolves_relative_to_including_file_before_shader_root() {
        let dir = project(&[
            ("shaders/common.wgsl", "const ROOT = 1;\n"),
            ("shaders/passes/common.wgsl", "const LOCAL = 1;\n"),
            ("shaders/passes/p.wgsl", "#include \"common.wgsl\"\n"),
        ]);
        let root = dir.path().join("shaders");
        let source = ShaderSource::load(&root.join("passes/p.wgsl"), &root).unwrap();
        assert_eq!(source.code, "const LOCAL = 1;\n");
    }

    #[test]
    fn nested_include_falls_back_to_shader_root() {
        let dir = project(&[
            ("shaders/lib/math.wgsl", "const PI = 3.14;\n"),
            (
                "shaders/lib/rng.wgsl",
                "#include \"lib/math.wgsl\"\nconst R = PI;\n",
            ),
            ("shaders/passes/p.wgsl", "#include \"../lib/rng.wgsl\"\n"),
        ]);
        let root = dir.path().join("shaders");
        let source = ShaderSource::load(&root.join("passes/p.wgsl"), &root).unwrap();
        assert_eq!(source.code, "const PI = 3.14;\nconst R = PI;\n");
        // `passes/../lib` is shown without the detour.
        let (file, line, _) = locate_text(&source, "const R");
        assert_eq!(file, root.join("lib/rng.wgsl"));
        assert_eq!(line, 2);
    }

    #[test]
    fn repeated_include_is_expanded_once() {
        let dir = project(&[
            ("shaders/lib/a.wgsl", "const A = 1;\n"),
            ("shaders/lib/b.wgsl", "#include \"a.wgsl\"\nconst B = A;\n"),
            (
                "shaders/p.wgsl",
                "#include \"lib/a.wgsl\"\n#include \"lib/b.wgsl\"\n#include \"lib/../lib/a.wgsl\"\nconst C = B;\n",
            ),
        ]);
        let root = dir.path().join("shaders");
        let main = root.join("p.wgsl");
        let source = ShaderSource::load(&main, &root).unwrap();
        assert_eq!(source.code, "const A = 1;\nconst B = A;\nconst C = B;\n");
        assert_eq!(locate_text(&source, "const C"), (main, 4, 1));
    }

    #[test]
    fn circular_include_terminates() {
        let dir = project(&[
            ("shaders/a.wgsl", "#include \"b.wgsl\"\nconst A = 1;\n"),
            ("shaders/b.wgsl", "#include \"a.wgsl\"\nconst B = 1;\n"),
        ]);
        let root = dir.path().join("shaders");
        let source = ShaderSource::load(&root.join("a.wgsl"), &root).unwrap();
        assert_eq!(source.code, "const B = 1;\nconst A = 1;\n");
    }

    #[test]
    fn missing_include_reports_including_file_and_line() {
        let dir = project(&[
            ("shaders/lib/a.wgsl", "// a\n\n  #include \"nope.wgsl\"\n"),
            ("shaders/p.wgsl", "#include \"lib/a.wgsl\"\n"),
        ]);
        let root = dir.path().join("shaders");
        let err = ShaderSource::load(&root.join("p.wgsl"), &root).unwrap_err();
        match err {
            GraphError::Include {
                file,
                line,
                include,
                reason,
            } => {
                assert!(same_file(&file, &root.join("lib/a.wgsl")));
                assert_eq!(line, 3);
                assert_eq!(include, "nope.wgsl");
                assert!(reason.contains("not found"), "{reason}");
            }
            other => panic!("expected Include error, got {other:?}"),
        }
    }

    #[test]
    fn malformed_include_lines_are_errors_not_silently_passed_to_naga() {
        for line in [
            "#include lib/a.wgsl",
            "#include \"lib/a.wgsl",
            "#include \"\"",
            "#include \"lib/a.wgsl\" junk",
            "#includes \"lib/a.wgsl\"",
        ] {
            let dir = project(&[("p.wgsl", &format!("const X = 1;\n{line}\n"))]);
            let main = dir.path().join("p.wgsl");
            match ShaderSource::load(&main, dir.path()) {
                Err(GraphError::Include { file, line: 2, .. }) => assert_eq!(file, main),
                other => panic!("{line}: expected Include error on line 2, got {other:?}"),
            }
        }
    }

    #[test]
    fn include_may_carry_trailing_comment_and_crlf() {
        let dir = project(&[
            ("a.wgsl", "const A = 1;"),
            ("p.wgsl", "#include \"a.wgsl\" // the A\r\nconst B = A;\r\n"),
        ]);
        let main = dir.path().join("p.wgsl");
        let source = ShaderSource::load(&main, dir.path()).unwrap();
        // A missing final newline in the include must not glue lines together.
        assert_eq!(source.code, "const A = 1;\nconst B = A;\r\n");
        assert_eq!(locate_text(&source, "const B"), (main, 2, 1));
    }

    #[test]
    fn unreadable_main_file_is_io_error() {
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("missing.wgsl");
        match ShaderSource::load(&missing, dir.path()) {
            Err(GraphError::Io { path, .. }) => assert_eq!(path, missing),
            other => panic!("expected Io error, got {other:?}"),
        }
    }

    #[test]
    fn end_of_code_after_trailing_include_maps_to_main_file() {
        let dir = project(&[
            ("a.wgsl", "const A = 1;\n"),
            ("p.wgsl", "fn f() {\n#include \"a.wgsl\"\n"),
        ]);
        let main = dir.path().join("p.wgsl");
        let source = ShaderSource::load(&main, dir.path()).unwrap();
        assert_eq!(source.locate(source.code.len()), (main, 3, 1));
    }

    #[test]
    fn from_code_locates_lines_and_character_columns() {
        let source = ShaderSource::from_code("gen.wgsl".into(), "// é\n  x\n".into());
        assert_eq!(source.locate(0), ("gen.wgsl".into(), 1, 1));
        assert_eq!(source.locate(8), ("gen.wgsl".into(), 2, 3));
        // Mid-character and out-of-range offsets do not panic.
        assert_eq!(source.locate(4).1, 1);
        assert_eq!(source.locate(1000).1, 3);
    }
}
