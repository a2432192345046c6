//! Per-rank pieces of the samples frames (issue 27). On one rank a frame's samples are one
//! `<method>_<frame>.vtu`, listed by `<method>.pvd` (unchanged). On `N > 1` ranks every
//! rank writes its owned samples ([`Method::owned_samples_into`](impact_core::Method::owned_samples_into)) as
//! `<method>_<frame>_r<rank>.vtu` into rank 0's staging folder, rank 0 writes
//! `<method>_<frame>.pvtu` listing the `N` pieces in rank order (so a reader's
//! concatenation is the global sample order, the serial file's), and `<method>.pvd` lists
//! the `.pvtu` files. The pieces carry the serial file's arrays; the reference solution's
//! arrays are in every piece or in none (the test that every value is finite is reduced
//! over the ranks, so the pieces agree with each other and with the serial file).
//!
//! The grid's cells are pieces too ([`super::grid_pieces`], FEM's mesh included);
//! the `.h5` series (feature `hdf5`) is one file per rank, `<method>_r<rank>.h5` with its
//! `.xdmf`, of the rank's owned samples (and its grid piece's cells), in the shared staging
//! folder. What is gathered: the measuring line's samples for the CSV profiles and the
//! metrics of `summary.json` ([`impact_core::comm_line`]), and the figures' map plane.
//!
//! **One staging folder, published once.** Rank 0 opens the output folder's staging folder
//! ([`impact_io::folder::OutputFolder`]) and sends its path to every rank
//! ([`shared_staging`]); the other ranks write their pieces there (the staging folder must
//! be on a file system every rank sees: on a cluster, the shared one) and everything else
//! into a private scratch folder as before ([`crate::ranks`]). Every step that writes is
//! followed by [`agree`]: every rank learns whether any rank failed, and all stop with the
//! lowest failing rank's message (`rank r: ...`) instead of waiting for it. Rank 0 commits
//! (publishes) the folder only after the last [`agree`], when every rank has reported its
//! pieces written; a rank killed before that leaves the staging folder unpublished.
use super::FileWriter;
use impact_io::vtu::write_pvtu;
use std::path::{Path, PathBuf};

/// Where this rank writes its pieces.
#[derive(Debug, Clone)]
pub struct Pieces {
    /// Rank 0's staging folder (shared by every rank).
    pub dir: PathBuf,
    /// This rank.
    pub rank: usize,
    /// Number of ranks.
    pub ranks: usize,
}

impl Pieces {
    /// The pieces of this run when it runs on several ranks, into the shared `dir`.
    pub fn of_ranks(dir: PathBuf) -> Option<Self> {
        let comm = crate::ranks::comm();
        (comm.size() > 1).then(|| Self {
            dir,
            rank: comm.rank(),
            ranks: comm.size(),
        })
    }

    /// Rank `rank`'s piece of `method`'s `frame`.
    pub fn file(method: &str, frame: &str, rank: usize) -> String {
        format!("{method}_{frame}_r{rank}.vtu")
    }
}

/// A piece ready to write: the reference solution at this rank's samples, where every
/// rank's is finite.
pub(super) struct Piece {
    reference: Option<(Vec<f64>, Vec<f64>)>,
}

impl<const D: usize> FileWriter<'_, D> {
    /// This rank's owned samples and their reference solution, agreed over the ranks of
    /// `comm` (the method's; collective: every rank calls it at every frame); `None` on one
    /// rank or without files.
    pub(super) fn owned_piece(
        &mut self,
        comm: &dyn impact_core::comm::Comm,
        frame: &str,
        t: f64,
    ) -> Option<Piece> {
        self.pieces.as_ref().filter(|_| self.files)?;
        // (`owned` holds this rank's owned samples: `FileWriter::gather`)
        std::mem::swap(&mut self.samples, &mut self.owned);
        let reference = self.reference_values(frame, t);
        std::mem::swap(&mut self.samples, &mut self.owned);
        let finite = reference
            .as_ref()
            .is_none_or(|(s, v)| s.iter().chain(v).all(|x| x.is_finite()));
        let everywhere = !comm.any(!finite);
        Some(Piece {
            reference: reference.filter(|_| everywhere),
        })
    }

    /// The samples of `frame`: one `.vtu` on one rank; this rank's piece and (on every
    /// rank, into its own folder) the `.pvtu` on several (module doc).
    pub(super) fn write_frame(
        &mut self,
        frame: &str,
        t: f64,
        piece: Option<Piece>,
    ) -> anyhow::Result<()> {
        let (Some(pieces), Some(piece)) = (self.pieces.clone(), piece) else {
            return self.write_samples(frame, t);
        };
        let name = Pieces::file(&self.method, frame, pieces.rank);
        std::mem::swap(&mut self.samples, &mut self.owned);
        let written =
            self.write_sample_vtu(&pieces.dir.join(&name), frame, t, piece.reference, true);
        std::mem::swap(&mut self.samples, &mut self.owned);
        let arrays = written?;
        let names: Vec<String> = (0..pieces.ranks)
            .map(|r| Pieces::file(&self.method, frame, r))
            .collect();
        let listed: Vec<(&str, usize)> = arrays.iter().map(|(n, c)| (n.as_str(), *c)).collect();
        let file = format!("{}_{frame}.pvtu", self.method);
        write_pvtu(&self.dir.join(&file), &listed, &names, self.encoding)?;
        self.pvd.push((t, file));
        Ok(())
    }
}

/// `local` made every rank's (collective): on one rank `local` itself; on several, `Ok`
/// where no rank failed, else the lowest failing rank's message on every rank (`rank r:
/// ...`), so that a failure seen by one rank only (its folder, its piece) stops them all
/// instead of leaving the others waiting at the next exchange.
pub fn agree<T>(local: anyhow::Result<T>) -> anyhow::Result<T> {
    let comm = crate::ranks::comm();
    if comm.size() == 1 {
        return local;
    }
    let message = local.as_ref().err().map(|e| format!("{e:#}"));
    match comm.first_error(message.as_deref()) {
        None => local,
        Some(e) => Err(e.into()),
    }
}

/// Rank 0's staging folder `own` (every rank passes its own folder; collective): the
/// folder every rank writes its pieces into.
pub fn shared_staging(own: &Path) -> anyhow::Result<PathBuf> {
    let comm = crate::ranks::comm();
    if comm.size() == 1 {
        return Ok(own.to_path_buf());
    }
    let mine = own.to_str().map(str::as_bytes);
    let (mut bytes, mut counts) = (Vec::new(), Vec::new());
    comm.all_gather_bytes(mine.unwrap_or_default(), &mut bytes, &mut counts);
    agree(match mine {
        Some(_) => Ok(()),
        None => Err(anyhow::anyhow!(
            "the output folder {} is not UTF-8: it cannot be sent to the other ranks; \
             give --out a UTF-8 path",
            own.display()
        )),
    })?;
    Ok(PathBuf::from(
        String::from_utf8_lossy(&bytes[..counts[0]]).into_owned(),
    ))
}
