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

/// Starts a thread that, on SIGINT, SIGTERM or SIGHUP, removes every registered path and then
/// ends the process as that signal would have. Call once, early in `main`.
#[cfg(unix)]
pub fn install_signal_cleanup() -> std::io::Result<()> {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP])?;
    std::thread::Builder::new()
        .name("signal-cleanup".into())
        .spawn(move || {
            if let Some(signal) = signals.forever().next() {
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
                let _ = signal_hook::low_level::emulate_default_handler(signal);
                std::process::exit(128 + signal);
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
    if std::fs::metadata(target).is_ok_and(|m| m.is_dir()) {
        return Err(std::io::Error::new(
            std::io::ErrorKind::IsADirectory,
            "it is a directory",
        ));
    }
    Ok(())
}

/// Writes one file whole or not at all.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    write_atomic_set(&[(path, bytes)]).map_err(|(_, e)| e)
}

/// Writes several files as a set: all are written and synced beside their targets before any
/// is renamed into place, so an error before the renames changes none of them. (The renames
/// themselves are separate steps: POSIX has no rename of several files at once.) The error
/// names the file it concerns.
pub fn write_atomic_set(files: &[(&Path, &[u8])]) -> Result<(), (PathBuf, std::io::Error)> {
    let mut pending = Vec::with_capacity(files.len());
    for &(target, bytes) in files {
        let fail = |e: std::io::Error| (target.to_path_buf(), e);
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

    #[test]
    fn a_directory_target_is_an_error_and_untouched() {
        let dir = tempfile::tempdir().unwrap();
        assert!(write_atomic(dir.path(), b"x").is_err());
        assert!(dir.path().is_dir());
    }
}
