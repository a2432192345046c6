//! Output folders that always hold exactly one complete run.
//!
//! A run writes into a private staging folder `.<name>.staging-<pid>-<n>` beside its
//! target folder `<name>`, while holding an advisory lock on `.<name>.lock` (the standard
//! library's `File::try_lock`: `flock` on Linux), so a second run into the same target is
//! refused at start. [`OutputFolder::commit`] writes `manifest.json` (every file and its
//! size) and replaces the target as a whole: rename the target to `.<name>.old-<pid>`,
//! rename the staging folder to the target, remove the old folder. Dropped without a
//! commit (an error, an interruption), the staging folder is removed and the target is
//! untouched.
//!
//! A run killed outright (`kill -9`) leaves its staging folder behind; the next run into
//! the same target removes it under the lock, and if the kill fell between the two renames
//! of a commit (no target, an `.old-` folder) it first puts the old complete folder back.
//!
//! An existing target is replaced only when it is empty or an impact output folder (it
//! holds `manifest.json`, or the `summary.json`, `stability.json` or `work_precision.json`
//! of an earlier version): anything else is refused, so `--out ~` cannot delete a home
//! folder.
use crate::IoError;
use serde::Serialize;
use std::fs::File;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The manifest's file name.
pub const MANIFEST: &str = "manifest.json";

/// A run's output folder being written.
#[derive(Debug)]
pub struct OutputFolder {
    target: PathBuf,
    staging: PathBuf,
    /// Held (locked) until the folder is committed or dropped.
    _lock: File,
    committed: bool,
}

/// One file of the manifest.
#[derive(Debug, Serialize)]
struct Entry {
    name: String,
    bytes: u64,
}

#[derive(Debug, Serialize)]
struct Manifest<'a> {
    written_by: &'a str,
    unix_time_s: u64,
    files: Vec<Entry>,
}

fn io_error(path: &Path) -> impl FnOnce(std::io::Error) -> IoError + '_ {
    move |source| IoError::File {
        path: path.to_path_buf(),
        source,
    }
}

fn refused(path: &Path, message: impl Into<String>) -> IoError {
    IoError::Refused {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

/// The folder holding `target` and the target's file name.
fn split(target: &Path) -> Result<(PathBuf, String), IoError> {
    let name = target
        .file_name()
        .and_then(|n| n.to_str())
        .filter(|n| !n.is_empty() && *n != "." && *n != "..")
        .ok_or_else(|| {
            refused(
                target,
                "an output folder needs a path ending in a plain name",
            )
        })?;
    let parent = match target.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    Ok((parent, name.to_string()))
}

/// The lock file of `target`: `.<name>.lock` beside it.
fn lock_path(target: &Path) -> Result<PathBuf, IoError> {
    let (parent, name) = split(target)?;
    Ok(parent.join(format!(".{name}.lock")))
}

/// Remove a finished output folder and its lock file (a caller's scratch run). Not for a
/// folder another run may be writing.
pub fn remove(target: &Path) -> Result<(), IoError> {
    if target.exists() {
        std::fs::remove_dir_all(target).map_err(io_error(target))?;
    }
    let lock = lock_path(target)?;
    if lock.exists() {
        std::fs::remove_file(&lock).map_err(io_error(&lock))?;
    }
    Ok(())
}

fn is_replaceable(target: &Path) -> Result<bool, IoError> {
    if !target.exists() {
        return Ok(true);
    }
    if !target.is_dir() {
        return Ok(false);
    }
    let mut entries = std::fs::read_dir(target).map_err(io_error(target))?;
    if entries.next().is_none() {
        return Ok(true);
    }
    // earlier versions wrote no manifest: their summary files mark them as impact's
    Ok([
        MANIFEST,
        "summary.json",
        "stability.json",
        "work_precision.json",
    ]
    .iter()
    .any(|marker| target.join(marker).is_file()))
}

impl OutputFolder {
    /// Lock `target`, clean what killed runs left beside it and open a staging folder.
    pub fn open(target: &Path) -> Result<Self, IoError> {
        let (parent, name) = split(target)?;
        std::fs::create_dir_all(&parent).map_err(io_error(&parent))?;
        let lock_path = lock_path(target)?;
        let lock = File::options()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&lock_path)
            .map_err(io_error(&lock_path))?;
        match lock.try_lock() {
            Ok(()) => {}
            Err(std::fs::TryLockError::WouldBlock) => {
                return Err(refused(
                    target,
                    format!(
                        "another impact run is writing this folder (it holds {}); wait for it \
                         to finish or choose another --out",
                        lock_path.display()
                    ),
                ))
            }
            Err(std::fs::TryLockError::Error(e)) => return Err(io_error(&lock_path)(e)),
        }
        recover(&parent, &name, target)?;
        if !is_replaceable(target)? {
            return Err(refused(
                target,
                "it exists and is not an impact output folder (no manifest.json or \
                 summary.json): choose a new or empty folder",
            ));
        }
        static COUNT: AtomicUsize = AtomicUsize::new(0);
        let staging = parent.join(format!(
            ".{name}.staging-{}-{}",
            std::process::id(),
            COUNT.fetch_add(1, Ordering::Relaxed)
        ));
        std::fs::create_dir(&staging).map_err(io_error(&staging))?;
        Ok(Self {
            target: target.to_path_buf(),
            staging,
            _lock: lock,
            committed: false,
        })
    }

    /// Where the run writes its files.
    pub fn path(&self) -> &Path {
        &self.staging
    }

    /// The folder the run will replace.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Write the manifest and replace the target with the staging folder.
    pub fn commit(mut self, written_by: &str) -> Result<(), IoError> {
        let mut files = Vec::new();
        let entries = std::fs::read_dir(&self.staging).map_err(io_error(&self.staging))?;
        for entry in entries {
            let entry = entry.map_err(io_error(&self.staging))?;
            let meta = entry.metadata().map_err(io_error(&entry.path()))?;
            files.push(Entry {
                name: entry.file_name().to_string_lossy().into_owned(),
                bytes: meta.len(),
            });
        }
        files.sort_by(|a, b| a.name.cmp(&b.name));
        let unix_time_s = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_secs());
        crate::write_json(
            &self.staging.join(MANIFEST),
            &Manifest {
                written_by,
                unix_time_s,
                files,
            },
        )?;
        let (parent, name) = split(&self.target)?;
        let old = parent.join(format!(".{name}.old-{}", std::process::id()));
        if self.target.exists() {
            std::fs::rename(&self.target, &old).map_err(io_error(&self.target))?;
        }
        std::fs::rename(&self.staging, &self.target).map_err(io_error(&self.target))?;
        self.committed = true;
        if old.exists() {
            std::fs::remove_dir_all(&old).map_err(io_error(&old))?;
        }
        Ok(())
    }
}

impl Drop for OutputFolder {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.staging);
        }
    }
}

/// Under the lock: put back an old folder a kill left between the two renames of a
/// commit, and remove staging and old folders of runs that were killed.
fn recover(parent: &Path, name: &str, target: &Path) -> Result<(), IoError> {
    let staging_prefix = format!(".{name}.staging-");
    let old_prefix = format!(".{name}.old-");
    let entries = std::fs::read_dir(parent).map_err(io_error(parent))?;
    let mut stale = Vec::new();
    for entry in entries.flatten() {
        let file_name = entry.file_name().to_string_lossy().into_owned();
        if file_name.starts_with(&old_prefix) && !target.exists() {
            std::fs::rename(entry.path(), target).map_err(io_error(target))?;
        } else if file_name.starts_with(&staging_prefix) || file_name.starts_with(&old_prefix) {
            stale.push(entry.path());
        }
    }
    for path in stale {
        std::fs::remove_dir_all(&path).map_err(io_error(&path))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh folder for test `name`, removed when dropped (kept if the test panics).
    struct Scratch(PathBuf);

    impl Drop for Scratch {
        fn drop(&mut self) {
            if !std::thread::panicking() {
                let _ = std::fs::remove_dir_all(&self.0);
            }
        }
    }

    impl std::ops::Deref for Scratch {
        type Target = Path;
        fn deref(&self) -> &Path {
            &self.0
        }
    }

    fn scratch(name: &str) -> Scratch {
        let dir = std::env::temp_dir().join(format!("impact-folder-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        Scratch(dir)
    }

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn commit_replaces_the_whole_folder_and_drop_leaves_it_untouched() {
        let root = scratch("commit");
        let target = root.join("out");
        let first = OutputFolder::open(&target).unwrap();
        crate::write_csv(&first.path().join("a.csv"), &["x"], &[&[1.0]]).unwrap();
        crate::write_csv(&first.path().join("b.csv"), &["x"], &[&[1.0]]).unwrap();
        first.commit("test").unwrap();
        assert_eq!(names(&target), ["a.csv", "b.csv", "manifest.json"]);
        // a second run with fewer files: nothing of the first remains
        let second = OutputFolder::open(&target).unwrap();
        crate::write_csv(&second.path().join("c.csv"), &["x"], &[&[2.0]]).unwrap();
        second.commit("test").unwrap();
        assert_eq!(names(&target), ["c.csv", "manifest.json"]);
        // an abandoned run: the target keeps the complete second run
        let third = OutputFolder::open(&target).unwrap();
        crate::write_csv(&third.path().join("d.csv"), &["x"], &[&[3.0]]).unwrap();
        drop(third);
        assert_eq!(names(&target), ["c.csv", "manifest.json"]);
        assert_eq!(names(&root), [".out.lock", "out"]);
    }

    #[test]
    fn a_locked_folder_is_refused_and_a_foreign_folder_is_never_replaced() {
        let root = scratch("lock");
        let target = root.join("out");
        let held = OutputFolder::open(&target).unwrap();
        let err = OutputFolder::open(&target).unwrap_err().to_string();
        assert!(err.contains("another impact run"), "{err}");
        drop(held);
        let foreign = root.join("home");
        std::fs::create_dir_all(&foreign).unwrap();
        std::fs::write(foreign.join("thesis.tex"), "precious").unwrap();
        let err = OutputFolder::open(&foreign).unwrap_err().to_string();
        assert!(err.contains("not an impact output folder"), "{err}");
        assert!(foreign.join("thesis.tex").exists());
    }

    #[test]
    fn stale_staging_is_removed_and_an_interrupted_swap_is_undone() {
        let root = scratch("stale");
        let target = root.join("out");
        std::fs::create_dir_all(root.join(".out.staging-999999-0")).unwrap();
        std::fs::write(root.join(".out.staging-999999-0/x.csv"), "partial").unwrap();
        // a commit killed between its renames: only the old folder exists
        std::fs::create_dir_all(root.join(".out.old-999998")).unwrap();
        std::fs::write(root.join(".out.old-999998/summary.json"), "{}").unwrap();
        let folder = OutputFolder::open(&target).unwrap();
        assert!(target.join("summary.json").exists());
        drop(folder);
        assert_eq!(names(&root), [".out.lock", "out"]);
    }
}
