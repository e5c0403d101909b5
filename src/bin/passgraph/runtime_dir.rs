//! Private temporary folders of a run (Mesa's runtime folder, the built-in defaults), removed
//! at exit, and those of killed runs removed at the next start.

use std::path::{Path, PathBuf};

/// Mesa's Vulkan drivers print "XDG_RUNTIME_DIR is invalid or not set" when probing window
/// systems, which reads like an error of ours on a headless machine. Give them a private,
/// valid directory when the session has none; the guard removes it when dropped (also when a
/// panic unwinds), and a signal's cleanup removes it too.
pub(crate) fn quiet_mesa_without_a_session() -> Option<RuntimeDir> {
    if std::env::var_os("XDG_RUNTIME_DIR").is_some() {
        return None;
    }
    let dir = std::env::temp_dir().join(format!("{RUNTIME_DIR_PREFIX}{}", std::process::id()));
    #[cfg(unix)]
    let made = {
        use std::os::unix::fs::DirBuilderExt;
        std::fs::DirBuilder::new().mode(0o700).create(&dir).is_ok()
    };
    #[cfg(not(unix))]
    let made = false;
    if !made {
        return None;
    }
    passgraph::atomic_write::remove_on_signal(dir.clone());
    // SAFETY: called in main before any other thread exists.
    unsafe { std::env::set_var("XDG_RUNTIME_DIR", &dir) };
    Some(RuntimeDir(dir))
}

pub(crate) const RUNTIME_DIR_PREFIX: &str = "passgraph-runtime-";

/// The built-in defaults of a binary outside its build tree (see [`builtin_defaults`]).
pub(crate) const BUILTIN_DIR_PREFIX: &str = "passgraph-builtin-";

/// SIGKILL (or SIGQUIT, or a crash) ends a process without its guard: the runtime and built-in
/// directories of this user's passgraph processes that no longer run are removed at the next
/// start.
pub(crate) fn remove_runtime_dirs_of_dead_processes() {
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::fs::MetadataExt;
        let Ok(entries) = std::fs::read_dir(std::env::temp_dir()) else {
            return;
        };
        // SAFETY: getuid has no preconditions and cannot fail.
        let uid = unsafe { libc::getuid() };
        for entry in entries.flatten() {
            let name = entry.file_name();
            let Some(pid) = name
                .to_str()
                .and_then(|n| {
                    n.strip_prefix(RUNTIME_DIR_PREFIX)
                        .or_else(|| n.strip_prefix(BUILTIN_DIR_PREFIX))
                })
                .and_then(|p| p.parse::<u32>().ok())
            else {
                continue;
            };
            let ours = entry.metadata().is_ok_and(|m| m.is_dir() && m.uid() == uid);
            let alive = Path::new(&format!("/proc/{pid}")).exists();
            if ours && !alive {
                let _ = std::fs::remove_dir_all(entry.path());
            }
        }
    }
}

pub(crate) struct RuntimeDir(pub(crate) PathBuf);

impl Drop for RuntimeDir {
    fn drop(&mut self) {
        // Best effort: nothing should have been written there.
        let _ = std::fs::remove_dir_all(&self.0);
        passgraph::atomic_write::forget(&self.0);
    }
}
