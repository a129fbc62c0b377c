//! grime's temporary files (`.NAME.grime-PID-N.tmp`, see
//! [`super::write_atomic`]): the ones this process is writing, so a signal
//! handler can remove them, and orphans left by a killed run.

use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::{Duration, SystemTime};

/// Temporary files being written now.
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// An orphan must be at least this old: a file written a moment ago may
/// belong to a run on another machine sharing the folder.
pub const ORPHAN_AGE: Duration = Duration::from_secs(60);

pub(super) fn register(path: &Path) {
    if let Ok(mut live) = LIVE.lock() {
        live.push(path.to_path_buf());
    }
}

pub(super) fn unregister(path: &Path) {
    if let Ok(mut live) = LIVE.lock() {
        live.retain(|p| p != path);
    }
}

/// Removes every temporary file this process is writing (for a signal
/// handler about to exit). Returns how many were removed.
pub fn remove_live() -> usize {
    let live = match LIVE.try_lock() {
        Ok(mut l) => std::mem::take(&mut *l),
        Err(_) => return 0,
    };
    live.iter()
        .filter(|p| std::fs::remove_file(p).is_ok())
        .count()
}

/// The process id in a grime temporary file's name
/// (`.NAME.grime-PID-N.tmp`), or `None` for any other name.
pub fn temp_file_pid(name: &str) -> Option<u32> {
    let stem = name.strip_prefix('.')?.strip_suffix(".tmp")?;
    let (rest, counter) = stem.rsplit_once('-')?;
    counter.parse::<u64>().ok()?;
    let at = rest.rfind(".grime-")?;
    rest[at + ".grime-".len()..].parse().ok()
}

/// True when process `pid` runs on this machine (Linux: `/proc/PID`;
/// elsewhere every process counts as gone once [`ORPHAN_AGE`] has passed).
fn alive(pid: u32) -> bool {
    pid == std::process::id()
        || (cfg!(target_os = "linux") && Path::new(&format!("/proc/{pid}")).exists())
}

/// Removes grime's orphaned temporary files in `dir` (and its sub-folders
/// when `recursive`): those whose process no longer runs and that are older
/// than [`ORPHAN_AGE`]. Other files are never touched. Returns the removed
/// paths; folders that cannot be read are skipped.
pub fn remove_orphans(dir: &Path, recursive: bool) -> Vec<PathBuf> {
    let mut removed = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    let now = SystemTime::now();
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for entry in entries.flatten() {
            let Ok(kind) = entry.file_type() else {
                continue;
            };
            if kind.is_dir() {
                if recursive {
                    stack.push(entry.path());
                }
                continue;
            }
            let name = entry.file_name();
            let Some(pid) = name.to_str().and_then(temp_file_pid) else {
                continue;
            };
            let old = entry
                .metadata()
                .and_then(|m| m.modified())
                .is_ok_and(|t| now.duration_since(t).is_ok_and(|age| age >= ORPHAN_AGE));
            if kind.is_file() && old && !alive(pid) && std::fs::remove_file(entry.path()).is_ok() {
                removed.push(entry.path());
            }
        }
    }
    removed.sort();
    removed
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_give_their_pid() {
        assert_eq!(temp_file_pid(".a.png.grime-1234-0.tmp"), Some(1234));
        assert_eq!(temp_file_pid(".x.grime-y.png.grime-7-12.tmp"), Some(7));
        assert_eq!(temp_file_pid("a.png.grime-1234-0.tmp"), None);
        assert_eq!(temp_file_pid(".a.png.tmp"), None);
        assert_eq!(temp_file_pid(".a.grime-x-0.tmp"), None);
    }

    #[test]
    fn only_old_orphans_of_dead_processes_go() {
        let dir = tempfile::tempdir().unwrap();
        let old = SystemTime::now() - Duration::from_secs(3600);
        let make = |name: &str, mtime: SystemTime| {
            let p = dir.path().join(name);
            std::fs::write(&p, b"x").unwrap();
            std::fs::File::options()
                .write(true)
                .open(&p)
                .unwrap()
                .set_modified(mtime)
                .unwrap();
            p
        };
        // pid 0x7FFFFFF0 is above Linux's pid_max: never running.
        let orphan = make(".a.png.grime-2147483632-0.tmp", old);
        let fresh = make(".b.png.grime-2147483632-1.tmp", SystemTime::now());
        let mine = make(&format!(".c.png.grime-{}-0.tmp", std::process::id()), old);
        let user = make("notes.tmp", old);
        let photo = make("a.png", old);
        assert_eq!(remove_orphans(dir.path(), false), vec![orphan.clone()]);
        assert!(!orphan.exists());
        for kept in [fresh, mine, user, photo] {
            assert!(kept.exists(), "{}", kept.display());
        }
    }
}
