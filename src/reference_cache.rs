//! The on-disk cache of converged references ([`crate::reference_for`]).
//!
//! A converged reference is a run of DGMPM, FEM or MPM on a grid 8× finer (4× in 3D;
//! [`crate::reference_setup`]), and each run with one needs two (the second gives the
//! spread); at `--cells 400` on the plate a 4× DGMPM reference took 14 s and 1 GB for a
//! 0.18 s FEM run, so each is computed once per key and stored.
//!
//! - **Folder**: `$IMPACT_CACHE_DIR` if set, else `$XDG_CACHE_HOME/impact/references`, else
//!   `$HOME/.cache/impact/references`, else `.impact-cache/references` in the working
//!   directory.
//! - **Key**: the reference's method and refinement, and the `Debug` text of everything
//!   that determines the run (the fine problem: grid,
//!   material, model, boundaries, loads, initial state, point layout, output times; the
//!   method configuration; the `impact` version, this file's format version, and the size
//!   and modification time of the running executable, so a rebuilt solver never reads a
//!   reference an earlier build computed). The file
//!   name is a 64-bit hash of it; the file stores the whole key and a load compares it, so a
//!   hash collision is a miss, never a wrong reference.
//! - **Format** (little endian): `IMPACT-REFERENCE 1\n`, the key's length (u64) and bytes,
//!   the number of output times and of fine cells (u64 each), then per output time the
//!   cells' σ_xx, the cells' v_x and the work (f64).
//! - **Safety**: written to a temporary name, synced and renamed (a `kill -9` leaves at most a
//!   hidden temporary file, never a partial entry); computing a key holds an exclusive lock
//!   on `<hash>.lock`, so concurrent runs compute it once and the others then read it; an
//!   entry that does not parse, does not match its key or holds a non-finite value is
//!   ignored and recomputed.
//! - **Ranks** (issue 27): rank 0 alone reads, locks and writes the folder; the other ranks
//!   receive a hit from it or join the decomposed run of a miss
//!   ([`Entry::get_or_compute_on`]).
use impact_core::comm::{Comm, SerialComm};
use std::hash::{Hash, Hasher};
use std::io::Read;
use std::path::{Path, PathBuf};

/// Bumped when the stored layout or what the key holds changes.
const FORMAT: &str = "IMPACT-REFERENCE 1\n";

/// The fields of a converged reference that a run computes: σ_xx and v_x per fine cell and
/// the work of the loads, at each output time.
#[derive(Debug, Clone, PartialEq)]
pub struct Stored {
    /// σ_xx per fine cell, per output time.
    pub stress_xx: Vec<Vec<f64>>,
    /// v_x per fine cell, per output time.
    pub velocity_x: Vec<Vec<f64>>,
    /// Work of the loads at each output time.
    pub work: Vec<f64>,
}

/// The cache folder (module doc).
pub fn folder() -> PathBuf {
    let env = |name: &str| {
        std::env::var_os(name)
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
    };
    if let Some(dir) = env("IMPACT_CACHE_DIR") {
        return dir;
    }
    let base = env("XDG_CACHE_HOME")
        .or_else(|| env("HOME").map(|home| home.join(".cache")))
        .map(|cache| cache.join("impact"))
        .unwrap_or_else(|| PathBuf::from(".impact-cache"));
    base.join("references")
}

/// The running executable's size and modification time (nanoseconds since the epoch).
fn build_stamp() -> String {
    std::env::current_exe()
        .and_then(std::fs::metadata)
        .map(|m| {
            let modified = m
                .modified()
                .ok()
                .and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok())
                .map_or(0, |d| d.as_nanos());
            format!("executable {} bytes, modified {modified}", m.len())
        })
        .unwrap_or_else(|_| "executable unknown".into())
}

/// One cache entry: its key text and paths.
pub struct Entry {
    key: String,
    path: PathBuf,
    lock: PathBuf,
}

impl Entry {
    /// The entry of `key` (the `Debug` text of what determines the reference) in `dir`.
    pub fn new(dir: &Path, key: &str) -> Self {
        let key = format!(
            "{FORMAT}impact {} ({})\n{key}",
            env!("CARGO_PKG_VERSION"),
            build_stamp()
        );
        let mut hasher = std::collections::hash_map::DefaultHasher::new();
        key.hash(&mut hasher);
        let name = format!("{:016x}", hasher.finish());
        Self {
            key,
            path: dir.join(format!("{name}.ref")),
            lock: dir.join(format!("{name}.lock")),
        }
    }

    /// The file of this entry.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The stored reference, if there is a valid one for this key.
    pub fn load(&self, times: usize, cells: usize) -> Option<Stored> {
        let mut bytes = Vec::new();
        std::fs::File::open(&self.path)
            .ok()?
            .read_to_end(&mut bytes)
            .ok()?;
        let mut at = 0;
        let mut take = |n: usize| -> Option<&[u8]> {
            let slice = bytes.get(at..at + n)?;
            at += n;
            Some(slice)
        };
        let word = |b: &[u8]| u64::from_le_bytes(b.try_into().unwrap_or([0; 8]));
        let key_len = word(take(8)?) as usize;
        if take(key_len)? != self.key.as_bytes() {
            return None;
        }
        if (word(take(8)?) as usize, word(take(8)?) as usize) != (times, cells) {
            return None;
        }
        let mut floats = |n: usize| -> Option<Vec<f64>> {
            let raw = take(8 * n)?;
            let v: Vec<f64> = raw
                .chunks_exact(8)
                .map(|c| f64::from_le_bytes(c.try_into().unwrap_or([0; 8])))
                .collect();
            v.iter().all(|x| x.is_finite()).then_some(v)
        };
        let mut stored = Stored {
            stress_xx: Vec::with_capacity(times),
            velocity_x: Vec::with_capacity(times),
            work: Vec::with_capacity(times),
        };
        for _ in 0..times {
            stored.stress_xx.push(floats(cells)?);
            stored.velocity_x.push(floats(cells)?);
            stored.work.push(floats(1)?[0]);
        }
        (at == bytes.len()).then_some(stored)
    }

    /// Store `reference` under this key (atomically).
    pub fn store(&self, reference: &Stored) -> Result<(), impact_io::IoError> {
        if let Some(dir) = self.path.parent() {
            impact_io::create_dir(dir)?;
        }
        let cells = reference.stress_xx.first().map_or(0, |v| v.len());
        impact_io::write_atomic(&self.path, |w| {
            w.write_all(&(self.key.len() as u64).to_le_bytes())?;
            w.write_all(self.key.as_bytes())?;
            w.write_all(&(reference.work.len() as u64).to_le_bytes())?;
            w.write_all(&(cells as u64).to_le_bytes())?;
            for k in 0..reference.work.len() {
                for v in reference.stress_xx[k]
                    .iter()
                    .chain(&reference.velocity_x[k])
                {
                    w.write_all(&v.to_le_bytes())?;
                }
                w.write_all(&reference.work[k].to_le_bytes())?;
            }
            Ok(())
        })
    }

    /// Hold the entry's lock while `compute` runs unless a valid entry appears meanwhile
    /// (another process computed it): the stored or computed reference. Without a usable
    /// cache folder it computes without the cache. One rank: [`Self::get_or_compute_on`].
    pub fn get_or_compute(
        &self,
        times: usize,
        cells: usize,
        compute: impl FnOnce() -> anyhow::Result<Stored>,
    ) -> anyhow::Result<(Stored, bool)> {
        self.get_or_compute_on(&SerialComm, times, cells, compute)
    }

    /// [`Self::get_or_compute`] on the ranks of `comm`, every rank calling it: rank 0 alone
    /// reads the cache (and holds the lock while the ranks compute), tells every rank
    /// whether it hit ([`Comm::any`]) and on a hit sends the stored reference to every
    /// rank (`share`); on a miss every rank runs `compute` (a collective: the reference
    /// run decomposed over the ranks, each rank ending with the whole reference) and
    /// rank 0 stores its result. The flag says whether it was read from the cache.
    pub fn get_or_compute_on(
        &self,
        comm: &dyn Comm,
        times: usize,
        cells: usize,
        compute: impl FnOnce() -> anyhow::Result<Stored>,
    ) -> anyhow::Result<(Stored, bool)> {
        let mut found = None;
        let mut lock = None;
        if comm.is_root() {
            found = self.load(times, cells);
            if found.is_none() {
                lock = self.lock_file().map(fd_lock::RwLock::new);
            }
        }
        let guard = lock.as_mut().and_then(|l| l.write().ok());
        if guard.is_some() {
            // another process may have written it while this one waited for the lock
            found = self.load(times, cells);
        }
        if comm.any(found.is_some()) {
            return Ok((share(comm, found, times, cells), true));
        }
        let computed = compute()?;
        if guard.is_some() {
            if let Err(e) = self.store(&computed) {
                eprintln!("note: the converged reference is not cached: {e}");
            }
        }
        Ok((computed, false))
    }

    /// The entry's lock file, created (with the folder) if need be; `None` without a
    /// usable cache folder.
    fn lock_file(&self) -> Option<std::fs::File> {
        let dir = self.path.parent().unwrap_or(Path::new("."));
        impact_io::create_dir(dir).ok()?;
        std::fs::File::options()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&self.lock)
            .ok()
    }
}

/// Rank 0's `stored` reference (`Some` there) on every rank of `comm`: one gather per
/// output time of `[σ_xx (cells), v_x (cells), work]` to which only rank 0 contributes (a
/// broadcast; per time so that no message exceeds one time's fields).
fn share(comm: &dyn Comm, stored: Option<Stored>, times: usize, cells: usize) -> Stored {
    if comm.size() == 1 {
        return stored.expect("internal: rank 0 holds the stored reference");
    }
    let mut shared = stored.unwrap_or_else(|| Stored {
        stress_xx: Vec::with_capacity(times),
        velocity_x: Vec::with_capacity(times),
        work: Vec::with_capacity(times),
    });
    let root = comm.is_root();
    let (mut local, mut out, mut counts) = (Vec::new(), Vec::new(), Vec::new());
    for k in 0..times {
        local.clear();
        if root {
            local.extend_from_slice(&shared.stress_xx[k]);
            local.extend_from_slice(&shared.velocity_x[k]);
            local.push(shared.work[k]);
        }
        comm.all_gather_into(&local, &mut out, &mut counts);
        if !root {
            // rank 0's part comes first; the others sent nothing
            shared.stress_xx.push(out[..cells].to_vec());
            shared.velocity_x.push(out[cells..2 * cells].to_vec());
            shared.work.push(out[2 * cells]);
        }
    }
    shared
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Stored {
        Stored {
            stress_xx: vec![vec![1.0, -2.5e8, 0.0], vec![3.0, 4.0, 5.0]],
            velocity_x: vec![vec![0.1, 0.2, 0.3], vec![-1.0, 2.0, 1e-300]],
            work: vec![12.5, 25.0],
        }
    }

    #[test]
    fn a_stored_reference_loads_back_exactly_and_only_under_its_key() {
        let dir = std::env::temp_dir().join(format!("impact-cache-test-{}", std::process::id()));
        let entry = Entry::new(&dir, "plate 132x100 ...");
        assert!(entry.load(2, 3).is_none());
        entry.store(&sample()).unwrap();
        assert_eq!(entry.load(2, 3), Some(sample()));
        // another key, other sizes, a truncated or altered file: misses
        assert!(Entry::new(&dir, "plate 132x101 ...").load(2, 3).is_none());
        assert!(entry.load(3, 3).is_none());
        let bytes = std::fs::read(entry.path()).unwrap();
        std::fs::write(entry.path(), &bytes[..bytes.len() - 4]).unwrap();
        assert!(entry.load(2, 3).is_none());
        let mut nan = bytes.clone();
        let at = nan.len() - 8;
        nan[at..].copy_from_slice(&f64::NAN.to_le_bytes());
        std::fs::write(entry.path(), &nan).unwrap();
        assert!(entry.load(2, 3).is_none());
        // get_or_compute recomputes a bad entry, then serves the stored one
        let mut calls = 0;
        let (got, hit) = entry
            .get_or_compute(2, 3, || {
                calls += 1;
                Ok(sample())
            })
            .unwrap();
        assert!(!hit && got == sample());
        let (_, hit) = entry
            .get_or_compute(2, 3, || unreachable!("served from the cache"))
            .unwrap();
        assert!(hit && calls == 1);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
