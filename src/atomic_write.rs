//! Writing output files whole or not at all: write beside the target, then rename over it.
//!
//! Several outputs are written as a set: every temporary file is written and synced before the
//! first rename, so a failure (disk full, a bad directory) leaves all targets as they were. A
//! new file gets the usual mode (0666 less the umask, as `open` would give it); an overwritten
//! file keeps its mode. Temporary files, and other scratch paths registered with
//! [`remove_on_signal`], are removed when SIGINT, SIGTERM or SIGHUP ends the process (see
//! [`install_signal_cleanup`]).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};
use std::sync::{Mutex, MutexGuard};

/// Paths to remove if a signal ends the process.
static SCRATCH: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn scratch() -> MutexGuard<'static, Vec<PathBuf>> {
    // A panic while holding the lock leaves a list that is still valid.
    SCRATCH.lock().unwrap_or_else(|e| e.into_inner())
}

/// Registers a temporary file or directory to remove if a signal ends the process.
pub fn remove_on_signal(path: PathBuf) {
    scratch().push(path);
}

/// Unregisters a path (after it was renamed into place or removed).
pub fn forget(path: &Path) {
    scratch().retain(|p| p != path);
}

/// Whether the first signal is left to the program ([`defer_signals`]).
static DEFERRING: AtomicBool = AtomicBool::new(false);
/// The signal a deferring program has not yet acted on; 0: none.
static PENDING: AtomicI32 = AtomicI32::new(0);

/// From now on the first SIGINT, SIGTERM or SIGHUP does not end the process: it is kept for
/// [`pending_signal`], so that a render can write a checkpoint first and then
/// [`die_of`] it. A second signal ends the process at once, as without deferral (temporary
/// files removed, targets untouched), so a stuck program can still be stopped.
pub fn defer_signals() {
    DEFERRING.store(true, Ordering::SeqCst);
}

/// The deferred signal received, if any (see [`defer_signals`]).
pub fn pending_signal() -> Option<i32> {
    match PENDING.load(Ordering::SeqCst) {
        0 => None,
        signal => Some(signal),
    }
}

/// Removes every registered path and ends the process as `signal` would have.
pub fn die_of(signal: i32) -> ! {
    // Keep the lock: no temporary file is created after the list is emptied.
    let paths = scratch();
    for path in paths.iter() {
        if path.is_dir() {
            let _ = std::fs::remove_dir_all(path);
        } else {
            let _ = std::fs::remove_file(path);
        }
    }
    // Die of the signal, so the parent sees how we ended.
    #[cfg(unix)]
    let _ = signal_hook::low_level::emulate_default_handler(signal);
    std::process::exit(128 + signal);
}

/// Starts a thread that, on SIGINT, SIGTERM or SIGHUP, removes every registered path and then
/// ends the process as that signal would have (or, after [`defer_signals`], keeps the first
/// signal for the program). Call once, early in `main`.
#[cfg(unix)]
pub fn install_signal_cleanup() -> std::io::Result<()> {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP])?;
    std::thread::Builder::new()
        .name("signal-cleanup".into())
        .spawn(move || {
            for signal in signals.forever() {
                let first = PENDING
                    .compare_exchange(0, signal, Ordering::SeqCst, Ordering::SeqCst)
                    .is_ok();
                if !(first && DEFERRING.load(Ordering::SeqCst)) {
                    die_of(signal);
                }
            }
        })?;
    Ok(())
}

#[cfg(not(unix))]
pub fn install_signal_cleanup() -> std::io::Result<()> {
    Ok(())
}

/// A temporary file beside its target, registered for removal until it is renamed or dropped.
struct Pending<'a> {
    target: &'a Path,
    file: Option<tempfile::NamedTempFile>,
}

impl Drop for Pending<'_> {
    fn drop(&mut self) {
        if let Some(file) = self.file.take() {
            let path = file.path().to_path_buf();
            drop(file); // removes it
            forget(&path);
        }
    }
}

/// Creates the temporary file for `target`, with the mode the target has (if it exists) or
/// would get from `open` (0666 less the umask).
fn create_temp(target: &Path) -> std::io::Result<Pending<'_>> {
    let dir = match target.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let existing = match std::fs::metadata(target) {
        Ok(m) if m.is_dir() => {
            return Err(std::io::Error::new(
                std::io::ErrorKind::IsADirectory,
                "it is a directory",
            ));
        }
        Ok(m) => Some(m.permissions()),
        Err(_) => None,
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".passgraph-").suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    // Hold the list while creating, so a signal cannot come between creation and registration.
    let mut list = scratch();
    let file = builder.tempfile_in(dir)?;
    list.push(file.path().to_path_buf());
    drop(list);
    let pending = Pending {
        target,
        file: Some(file),
    };
    if let (Some(permissions), Some(file)) = (existing, &pending.file) {
        file.as_file().set_permissions(permissions)?;
    }
    Ok(pending)
}

/// Whether a file could be written at `target`: its directory exists, and it is not itself
/// a directory. For checking command-line outputs before long work.
pub fn check_target(target: &Path) -> std::io::Result<()> {
    let dir = match target.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let meta = std::fs::metadata(dir)
        .map_err(|e| std::io::Error::new(e.kind(), format!("directory {}: {e}", dir.display())))?;
    if !meta.is_dir() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::NotADirectory,
            format!("{} is not a directory", dir.display()),
        ));
    }
    match std::fs::metadata(target) {
        Ok(m) if m.is_dir() => {
            return Err(std::io::Error::new(
                std::io::ErrorKind::IsADirectory,
                "it is a directory",
            ));
        }
        Ok(m) if !m.is_file() => return Err(not_a_regular_file()),
        _ => {}
    }
    // A file can be created there (the directory is writable, the disk not read-only): found
    // now rather than after the work whose result it would hold.
    tempfile::Builder::new()
        .prefix(".passgraph-")
        .suffix(".tmp")
        .tempfile_in(dir)
        .map_err(|e| std::io::Error::new(e.kind(), format!("directory {}: {e}", dir.display())))?;
    Ok(())
}

fn not_a_regular_file() -> std::io::Error {
    std::io::Error::new(
        std::io::ErrorKind::InvalidInput,
        "it is not a regular file (a FIFO, socket or device): outputs are written whole by renaming over them; name a regular file",
    )
}

/// Where an output is written: a symbolic link's target (followed to the end), so that the
/// file the link names is replaced and the link stays; else the path itself.
fn resolve_link(target: &Path) -> std::io::Result<PathBuf> {
    match std::fs::symlink_metadata(target) {
        Ok(m) if m.file_type().is_symlink() => std::fs::canonicalize(target).or_else(|_| {
            // A dangling link: write where it points.
            let link = std::fs::read_link(target)?;
            Ok(match target.parent() {
                Some(dir) => dir.join(link),
                None => link,
            })
        }),
        _ => Ok(target.to_path_buf()),
    }
}

/// Whether `a` and `b` name one existing file (the same device and inode, so `./x`, `x`, a
/// symbolic link to it and a hard link all count).
#[cfg(unix)]
pub fn same_file(a: &Path, b: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

#[cfg(not(unix))]
pub fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}

/// Refuses an output that is one of the command's inputs (`what` says which, e.g.
/// "--reference"): writing it would destroy what the command read.
pub fn refuse_outputs_that_are_inputs(
    outputs: &[&Path],
    inputs: &[(&str, &Path)],
) -> Result<(), String> {
    for output in outputs {
        if let Some((what, input)) = inputs.iter().find(|(_, input)| same_file(output, input)) {
            return Err(format!(
                "{}: is also {what} {}, which this command reads; writing it would destroy that input: name another output",
                output.display(),
                input.display()
            ));
        }
    }
    Ok(())
}

/// Writes one file whole or not at all.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    write_atomic_set(&[(path, bytes)]).map_err(|(_, e)| e)
}

/// [`write_atomic`] of a text file, its error a message naming the file.
pub fn write_text(path: &Path, text: &str) -> Result<(), String> {
    write_atomic(path, text.as_bytes())
        .map_err(|e| format!("{}: cannot write: {e}", path.display()))
}

/// Writes several files as a set: all are written and synced beside their targets before any
/// is renamed into place, so an error before the renames changes none of them. (The renames
/// themselves are separate steps: POSIX has no rename of several files at once.) The error
/// names the file it concerns.
pub fn write_atomic_set(files: &[(&Path, &[u8])]) -> Result<(), (PathBuf, std::io::Error)> {
    let resolved = files
        .iter()
        .map(|&(target, _)| resolve_link(target).map_err(|e| (target.to_path_buf(), e)))
        .collect::<Result<Vec<PathBuf>, _>>()?;
    let mut pending = Vec::with_capacity(files.len());
    for (&(shown, bytes), target) in files.iter().zip(&resolved) {
        let fail = |e: std::io::Error| (shown.to_path_buf(), e);
        if std::fs::metadata(target).is_ok_and(|m| !m.is_file() && !m.is_dir()) {
            return Err(fail(not_a_regular_file()));
        }
        let mut p = create_temp(target).map_err(fail)?;
        if let Some(file) = p.file.as_mut() {
            file.write_all(bytes).map_err(fail)?;
            file.as_file().sync_all().map_err(fail)?;
        }
        pending.push(p);
    }
    for p in &mut pending {
        if let Some(file) = p.file.take() {
            let temp = file.path().to_path_buf();
            let persisted = file.persist(p.target);
            forget(&temp);
            if let Err(e) = persisted {
                drop(e.file); // removes the temporary file
                return Err((p.target.to_path_buf(), e.error));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(unix)]
    #[test]
    fn an_overwritten_file_keeps_its_mode_and_a_new_one_is_not_private() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let old = dir.path().join("old.txt");
        std::fs::write(&old, "old").unwrap();
        std::fs::set_permissions(&old, std::fs::Permissions::from_mode(0o640)).unwrap();
        write_atomic(&old, b"new").unwrap();
        let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode(&old), 0o640);
        assert_eq!(std::fs::read(&old).unwrap(), b"new");

        let new = dir.path().join("new.txt");
        write_atomic(&new, b"x").unwrap();
        // 0666 less the umask, as `open` gives (not tempfile's private 0600).
        let status = std::fs::read_to_string("/proc/self/status").unwrap();
        let umask = status
            .lines()
            .find_map(|l| l.strip_prefix("Umask:"))
            .map(|v| u32::from_str_radix(v.trim(), 8).unwrap())
            .expect("Linux reports the umask in /proc/self/status");
        assert_eq!(mode(&new), 0o666 & !umask);
    }

    #[test]
    fn a_set_with_one_bad_target_changes_no_file_and_leaves_no_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let good = dir.path().join("a.png");
        std::fs::write(&good, "old").unwrap();
        let bad = dir.path().join("missing-dir/b.exr");
        let err = write_atomic_set(&[(&good, b"new"), (&bad, b"new")]).unwrap_err();
        assert_eq!(err.0, bad);
        assert_eq!(std::fs::read(&good).unwrap(), b"old");
        let names: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("a.png")]);
        assert!(!scratch().iter().any(|p| p.starts_with(dir.path())));
    }

    #[test]
    fn a_pending_temporary_file_is_registered_for_signal_cleanup_until_dropped() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("x.png");
        let pending = create_temp(&target).unwrap();
        let temp = pending.file.as_ref().unwrap().path().to_path_buf();
        assert!(scratch().contains(&temp));
        drop(pending);
        assert!(!temp.exists());
        assert!(!scratch().contains(&temp));
    }

    #[cfg(unix)]
    #[test]
    fn writing_through_a_symbolic_link_replaces_the_file_it_names_and_keeps_the_link() {
        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().join("real.png");
        let link = dir.path().join("link.png");
        std::fs::write(&real, "old").unwrap();
        std::os::unix::fs::symlink("real.png", &link).unwrap();
        write_atomic(&link, b"new").unwrap();
        assert!(
            std::fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(std::fs::read(&real).unwrap(), b"new");
    }

    #[cfg(unix)]
    #[test]
    fn a_fifo_or_an_unwritable_directory_is_refused_before_any_work() {
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("out.png");
        let status = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap();
        assert!(status.success());
        let e = check_target(&fifo).unwrap_err().to_string();
        assert!(e.contains("not a regular file"), "{e}");
        let e = write_atomic(&fifo, b"x").unwrap_err().to_string();
        assert!(e.contains("not a regular file"), "{e}");
        // /proc takes no new files, not even from root.
        let e = check_target(Path::new("/proc/out.png"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("directory /proc"), "{e}");
    }

    #[test]
    fn a_directory_target_is_an_error_and_untouched() {
        let dir = tempfile::tempdir().unwrap();
        assert!(write_atomic(dir.path(), b"x").is_err());
        assert!(dir.path().is_dir());
    }
}
