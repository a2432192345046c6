//! Output files: CSV profiles, VTK unstructured grids (`.vtu`), PNG plots and JSON. Every
//! file is written to a temporary name beside its target and renamed when complete, so
//! an output file is never left half-written.
//!
//! Layout: `vtu` (VTK), `plot` (PNG), `h5` (feature `hdf5`), `folder` (a run's output folder:
//! staged, locked, replaced as a whole with its manifest).
pub mod folder;
#[cfg(feature = "hdf5")]
pub mod h5;
pub mod plot;
pub mod vtu;

use std::io::Write;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Output errors.
#[derive(Debug, Error)]
pub enum IoError {
    /// File system error, with the path.
    #[error("cannot write {path}")]
    File {
        /// Target path.
        path: PathBuf,
        /// Cause.
        source: std::io::Error,
    },
    /// Plotting error.
    #[error("cannot draw {path}: {message}")]
    Plot {
        /// Target path.
        path: PathBuf,
        /// Cause.
        message: String,
    },
    /// The output folder cannot be used.
    #[error("cannot write into {path}: {message}")]
    Refused {
        /// Target folder.
        path: PathBuf,
        /// Why.
        message: String,
    },
    /// Serialisation error.
    #[error("cannot serialise {path}: {message}")]
    Serialise {
        /// Target path.
        path: PathBuf,
        /// Cause.
        message: String,
    },
}

fn file_error(path: &Path) -> impl FnOnce(std::io::Error) -> IoError + '_ {
    move |source| IoError::File {
        path: path.to_path_buf(),
        source,
    }
}

/// The temporary name used while `path` is written: hidden, unique to this process and
/// this write (`.<name>.<pid>.<n>.tmp`), so two writers never share one.
pub fn temporary_path(path: &Path) -> PathBuf {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static COUNT: AtomicUsize = AtomicUsize::new(0);
    let mut name = std::ffi::OsString::from(".");
    name.push(path.file_name().unwrap_or_default());
    name.push(format!(
        ".{}.{}.tmp",
        std::process::id(),
        COUNT.fetch_add(1, Ordering::Relaxed)
    ));
    path.with_file_name(name)
}

/// Write `path` atomically: `fill` writes into a buffered temporary file, which is flushed,
/// synced and renamed onto `path`. On error the temporary file is removed.
pub fn write_atomic(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<(), IoError> {
    let tmp = temporary_path(path);
    let result = (|| {
        let file = std::fs::File::create(&tmp)?;
        let mut w = std::io::BufWriter::new(file);
        fill(&mut w)?;
        let file = w.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.map_err(file_error(path))
}

/// Write a CSV file with a header row and equally long columns.
pub fn write_csv(path: &Path, header: &[&str], columns: &[&[f64]]) -> Result<(), IoError> {
    let rows = columns.first().map_or(0, |c| c.len());
    write_atomic(path, |w| {
        writeln!(w, "{}", header.join(","))?;
        for r in 0..rows {
            let mut first = true;
            for c in columns {
                if !first {
                    write!(w, ",")?;
                }
                first = false;
                write!(w, "{:.12e}", c[r])?;
            }
            writeln!(w)?;
        }
        Ok(())
    })
}

/// Write a value as pretty JSON.
pub fn write_json<T: serde::Serialize>(path: &Path, value: &T) -> Result<(), IoError> {
    let bytes = serde_json::to_vec_pretty(value).map_err(|e| IoError::Serialise {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    write_atomic(path, |w| w.write_all(&bytes))
}

/// Create a directory and its parents.
pub fn create_dir(path: &Path) -> Result<(), IoError> {
    std::fs::create_dir_all(path).map_err(file_error(path))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn atomic_write_leaves_no_temporary_and_failed_write_leaves_no_file() {
        let dir = std::env::temp_dir().join(format!("impact-io-test-{}", std::process::id()));
        create_dir(&dir).unwrap();
        let path = dir.join("a.csv");
        write_csv(&path, &["x", "y"], &[&[1.0, 2.0], &[3.0, 4.0]]).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text.lines().count(), 3);
        assert!(!temporary_path(&path).exists());
        let bad = dir.join("b.csv");
        let err = write_atomic(&bad, |_| Err(std::io::Error::other("disk full")));
        assert!(err.is_err());
        assert!(!bad.exists() && !temporary_path(&bad).exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
