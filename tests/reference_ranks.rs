//! The converged reference on several ranks (issue 27): rank 0 alone reads the cache and
//! sends a hit to every rank; a miss is run decomposed over the ranks and rank 0 writes
//! the entry. The ranks are threads of this process ([`ThreadComm`]); the cache folder is
//! read from the environment, so this binary holds one test.
use impact::reference::{reference_on, Ranks};
use impact::{Overrides, Study};
use impact_core::comm::{RankGrid, SerialComm, ThreadComm};
use impact_core::converged::Converged;
use impact_core::method::MethodKind;
use impact_core::reference::Reference;
use impact_core::{Problem, Scene};
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;

/// The converged reference of `problem` computed or read on `ranks` ranks split as `grid`,
/// with the cache in `dir`: each rank's.
fn references(problem: &Problem<2>, dir: &Path, ranks: usize, grid: &RankGrid) -> Vec<Reference> {
    std::env::set_var("IMPACT_CACHE_DIR", dir);
    let on = |comm| {
        let ranks = Ranks {
            comm,
            grid: grid.clone(),
        };
        // each rank on its own pool: the controller's loop runs on a pool worker, and ranks
        // sharing the global pool's workers would wait there for ranks that cannot enter
        rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| reference_on(problem, &MethodKind::ALL, false, &ranks))
            .unwrap()
            .expect("the plate has a converged reference")
    };
    match ranks {
        1 => vec![on(Arc::new(SerialComm))],
        n => ThreadComm::on_ranks(n, on),
    }
}

fn converged(r: &Reference) -> &Converged {
    match r {
        Reference::Converged(c) => c,
        _ => panic!("the plate has no exact solution"),
    }
}

/// The cache entries (`*.ref`) in `dir` by file name.
fn entries(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "ref"))
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read(&p).unwrap())
        })
        .collect()
}

/// On 2 ranks in slabs and on 4 as 2 x 2 boxes, with empty cache folders, every rank holds
/// the one-rank reference (DGMPM judging, FEM's spread: both decomposed bit for bit) and
/// rank 0 writes the one-rank cache entries byte for byte; a second run on 2 ranks reads
/// rank 0's entries on every rank without computing: entries altered on disk (a finite
/// value changed, the key kept) come back altered on every rank.
#[test]
fn a_reference_on_ranks_is_the_one_rank_reference_and_cache_entry() {
    let base = std::env::temp_dir().join(format!("impact-refranks-{}", std::process::id()));
    let study = Study::new(
        Scene::builtin("plate").unwrap(),
        Overrides {
            cells: Some(16),
            ..Default::default()
        },
    )
    .unwrap();
    let problem: Problem<2> = study.problem().unwrap();
    let serial_dir = base.join("one");
    let serial = references(&problem, &serial_dir, 1, &RankGrid::automatic());
    let serial = converged(&serial[0]);
    let serial_entries = entries(&serial_dir);
    assert_eq!(
        serial_entries.len(),
        2,
        "the judge's and the spread's entries"
    );
    for (label, ranks, grid) in [
        ("2 ranks in slabs", 2, RankGrid::automatic()),
        ("4 ranks as boxes 2 x 2", 4, RankGrid(vec![2, 2])),
    ] {
        let dir = base.join(format!("ranks{ranks}"));
        for (rank, r) in references(&problem, &dir, ranks, &grid).iter().enumerate() {
            let c = converged(r);
            assert!(c.stress == serial.stress, "{label}, rank {rank}: σ_xx");
            assert!(c.velocity == serial.velocity, "{label}, rank {rank}: v_x");
            assert_eq!(c.work, serial.work, "{label}, rank {rank}: work");
            let (s, one) = (c.spread.as_ref().unwrap(), serial.spread.as_ref().unwrap());
            assert!(
                s.stress == one.stress && s.velocity == one.velocity,
                "{label}, rank {rank}: the spread"
            );
        }
        assert!(
            entries(&dir) == serial_entries,
            "{label}: the cache entries differ from one rank's"
        );
    }
    // alter the last v_x of each entry written on 2 ranks (the 8 bytes before the last work)
    let dir = base.join("ranks2");
    for (name, mut bytes) in entries(&dir) {
        let at = bytes.len() - 16;
        let v = f64::from_le_bytes(bytes[at..at + 8].try_into().unwrap());
        bytes[at..at + 8].copy_from_slice(&(v + 1.0).to_le_bytes());
        std::fs::write(dir.join(name), bytes).unwrap();
    }
    let last = |v: &[Vec<f64>]| *v.last().unwrap().last().unwrap();
    for (rank, r) in references(&problem, &dir, 2, &RankGrid::automatic())
        .iter()
        .enumerate()
    {
        let c = converged(r);
        assert_eq!(
            last(&c.velocity),
            last(&serial.velocity) + 1.0,
            "rank {rank}: read"
        );
        let (s, one) = (c.spread.as_ref().unwrap(), serial.spread.as_ref().unwrap());
        assert_eq!(
            last(&s.velocity),
            last(&one.velocity) + 1.0,
            "rank {rank}: spread read"
        );
        assert!(c.stress == serial.stress, "rank {rank}: σ_xx read");
    }
    let _ = std::fs::remove_dir_all(&base);
}
