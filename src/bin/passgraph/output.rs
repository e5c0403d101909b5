//! What a command writes: standard output that a closed pipe ends quietly, files as a set,
//! and how a command fails.

/// Writes encoded files as a set (all or none, see `write_atomic_set`); errors name the file.
pub(crate) fn write_files(encoded: &[(&std::path::Path, Vec<u8>)]) -> Result<(), String> {
    let files: Vec<(&std::path::Path, &[u8])> =
        encoded.iter().map(|(p, b)| (*p, b.as_slice())).collect();
    passgraph::atomic_write::write_atomic_set(&files)
        .map_err(|(path, e)| format!("{}: cannot write: {e}", path.display()))
}

/// Why a command failed: invalid input (exit 1) or a command-line usage error (exit 2, like
/// clap's own).
pub(crate) enum Failure {
    Invalid(String),
    Usage(String),
}

impl From<String> for Failure {
    fn from(message: String) -> Failure {
        Failure::Invalid(message)
    }
}

/// Writes to standard output. A closed pipe (`passgraph plan G | head -1`) ends the output
/// quietly, as Unix tools do; any other write error (a full disk) is an error saying so.
pub(crate) fn say(text: &str) -> Result<(), String> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) => Err(format!("cannot write to standard output: {e}")),
    }
}

/// [`say`] with a line break.
pub(crate) fn say_line(text: &str) -> Result<(), String> {
    say(&format!("{text}\n"))
}
