//! The global values of a method split in slabs ([`crate::comm`]), formed from each rank's
//! own points: the samples gathered in rank order (the global point order, so outputs equal
//! one rank's), the first failure over the ranks at its global place, and the fastest
//! point's place. Shared by the point methods' slab wrappers (DGMPM, MPM).
use crate::comm::{Comm, CommError};
use crate::method::{BadState, Samples};
use crate::{Tensor, Vector};

/// Every rank's samples `mine` (its own points, in order, or a subset of them in order)
/// gathered into `out` on every rank, in the global point order: `global_index[i]` is the
/// global index of `mine`'s sample `i` (a box's own points are not one run of the global
/// order; the gathered samples are sorted by it), or, where `global_index` is empty on
/// every rank, concatenated in rank order (a slab's own points are). The plastic strain and the out-of-plane stress are carried where any rank's `mine`
/// has them (one model: every rank alike, but a rank may hold no sample of a subset).
pub fn gather_samples<const D: usize>(
    comm: &dyn Comm,
    mine: &Samples<D>,
    global_index: &[usize],
    out: &mut Samples<D>,
) {
    // (a rank may hold none of a subset: the optional arrays are carried where any rank has
    // them, every rank alike)
    let flags = [!mine.plastic_strain.is_empty(), !mine.stress_zz.is_empty()];
    let flags = comm.all_gather(&flags.map(|f| f64::from(u8::from(f))));
    let any = |k: usize| flags.iter().skip(k).step_by(2).any(|&f| f != 0.0);
    let (plastic, zz) = (any(0), any(1));
    let width = 4 * D + D * D + usize::from(plastic) + usize::from(zz);
    let mut packed = Vec::with_capacity(mine.len() * width);
    for i in 0..mine.len() {
        packed.extend_from_slice(mine.reference[i].as_slice());
        packed.extend_from_slice(mine.position[i].as_slice());
        packed.extend_from_slice(mine.half_size[i].as_slice());
        packed.extend_from_slice(mine.stress[i].as_slice());
        packed.extend_from_slice(mine.velocity[i].as_slice());
        if plastic {
            packed.push(mine.plastic_strain[i]);
        }
        if zz {
            packed.push(mine.stress_zz[i]);
        }
    }
    let all = comm.all_gather(&packed);
    let chunks: Vec<&[f64]> = all.chunks_exact(width).collect();
    // (indices below 2^53 travel exactly as f64)
    let indices = comm.all_gather(&global_index.iter().map(|&i| i as f64).collect::<Vec<_>>());
    let mut slot: Vec<usize> = (0..chunks.len()).collect();
    if indices.len() == chunks.len() {
        slot.sort_unstable_by(|&a, &b| indices[a].total_cmp(&indices[b]));
    }
    out.clear();
    for s in slot.into_iter().map(|k| chunks[k]) {
        let v = |k: usize| Vector::<D>::from_column_slice(&s[k * D..(k + 1) * D]);
        out.reference.push(v(0));
        out.position.push(v(1));
        out.half_size.push(v(2));
        out.stress
            .push(Tensor::<D>::from_column_slice(&s[3 * D..3 * D + D * D]));
        out.velocity.push(Vector::<D>::from_column_slice(
            &s[3 * D + D * D..4 * D + D * D],
        ));
        let mut k = 4 * D + D * D;
        if plastic {
            out.plastic_strain.push(s[k]);
            k += 1;
        }
        if zz {
            out.stress_zz.push(s[k]);
        }
    }
}

/// The first failure over the ranks (the lowest failing rank's), the same [`BadState`] on
/// every rank: its reason and its global place.
pub fn first_bad<const D: usize>(
    comm: &dyn Comm,
    local: Result<(), BadState<D>>,
) -> Result<(), BadState<D>> {
    let reason = local.as_ref().err().map(|b| b.reason.clone());
    let Some(CommError::Rank { rank, message }) = comm.first_error(reason.as_deref()) else {
        return Ok(());
    };
    let place = local.err().map_or_else(Vector::<D>::zeros, |b| b.place);
    let all = comm.all_gather(place.as_slice());
    Err(BadState {
        place: Vector::<D>::from_fn(|k, _| all[rank * D + k]),
        reason: message,
    })
}

/// The place of the fastest point over the ranks, from each rank's `(speed, place)` of its
/// fastest own point (`None` where it owns none): the last rank of the largest speed, as one
/// rank's `max_by` keeps the last of equals.
pub fn hottest_place<const D: usize>(comm: &dyn Comm, mine: Option<(f64, Vector<D>)>) -> Vector<D> {
    let (speed, place) = mine.unwrap_or((f64::NEG_INFINITY, Vector::<D>::zeros()));
    let mut entry = vec![speed];
    entry.extend_from_slice(place.as_slice());
    let all = comm.all_gather(&entry);
    let best = (0..comm.size())
        .max_by(|&a, &b| all[a * (D + 1)].total_cmp(&all[b * (D + 1)]))
        .unwrap_or(0);
    Vector::<D>::from_column_slice(&all[best * (D + 1) + 1..(best + 1) * (D + 1)])
}
