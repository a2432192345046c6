//! The reference a run is measured against: the exact solution, or a converged solution
//! (which method, on which grid, and the second reference of the spread:
//! [`crate::reference_setup`]).
use crate::reference_setup::{describe_config, ReferenceMethod};
use impact_core::method::{MethodConfig, MethodKind};
use impact_core::{Method, Problem};

pub use crate::reference_setup::REFERENCE_REFINEMENT;

/// Largest fine grid of a converged reference (cells): beyond it errors are not computed
/// (the reference is an automatic extra run, kept to what any machine holds in minutes).
pub const MAX_REFERENCE_CELLS: f64 = 1e7;

/// The reference of `problem` when the command compares the methods `compared`: its exact
/// solution when it has one; otherwise a converged solution ([`crate::reference_setup`]:
/// by default a method not compared, on a grid [`REFERENCE_REFINEMENT`] times finer, at
/// the same output times) with a second one of another method on the same grid (the
/// spread, each error's uncertainty), each computed once and then read from the cache
/// ([`crate::reference_cache`]), its description stating why there is no exact one. `say`
/// prints what is computed or read (on stderr) and shows a progress bar.
pub fn reference_for<const D: usize>(
    problem: &Problem<D>,
    compared: &[MethodKind],
    say: bool,
) -> anyhow::Result<Option<impact_core::reference::Reference>> {
    let ranks = Ranks {
        comm: crate::ranks::comm(),
        grid: crate::ranks::rank_grid(),
    };
    reference_on(problem, compared, say, &ranks)
}

/// The ranks a converged reference is shared by: their communicator and the rank grid its
/// run is split as (`impact run`'s, [`crate::ranks::build_ranked_on`]).
#[derive(Debug, Clone)]
pub struct Ranks {
    /// The ranks (every one calls [`reference_on`]).
    pub comm: std::sync::Arc<dyn impact_core::comm::Comm>,
    /// How a reference run is split over them.
    pub grid: impact_core::comm::RankGrid,
}

/// [`reference_for`] on the ranks `ranks`, every rank calling it: rank 0 alone reads the
/// cache and sends a hit to every rank; a miss is run decomposed over the ranks, every
/// rank gathering its samples, and rank 0 writes the entry
/// ([`crate::reference_cache::Entry::get_or_compute_on`]). Every rank returns the same
/// reference; an entry computed on several ranks holds the one-rank run's σ_xx and v_x
/// bit for bit where the method's decomposed samples are (DGMPM, FEM, MPM in the total
/// frame), and its work, a sum in rank order, to round-off.
pub fn reference_on<const D: usize>(
    problem: &Problem<D>,
    compared: &[MethodKind],
    say: bool,
    ranks: &Ranks,
) -> anyhow::Result<Option<impact_core::reference::Reference>> {
    use impact_core::converged::Spread;
    use impact_core::reference::{Converged, Reference};
    let line = impact_core::line::MeasureLine::of(problem);
    let why = match Reference::exact(problem) {
        Ok(r) => {
            if line.axis != 0 {
                anyhow::bail!(
                    "invalid value for `metrics.line`: {} (allowed: a line along x: the \
                     scene's exact solution is a plane wave along x, measured along x)",
                    line.describe::<D>()
                );
            }
            return Ok(Some(r));
        }
        Err(why) => why,
    };
    let setup = crate::reference_setup::resolve(problem, compared)?;
    let r = setup.refinement;
    let fine_cells = problem.grid.cell_count() as f64 * (r as f64).powi(D as i32);
    if fine_cells > MAX_REFERENCE_CELLS {
        if say {
            use std::io::Write as _;
            let _ = writeln!(
                std::io::stderr(),
                "no converged reference: a grid {r}x finer ({fine_cells:.2e} cells) exceeds the \
                 {:.0e}-cell limit; errors are not computed (no exact solution: {why})",
                MAX_REFERENCE_CELLS
            );
        }
        return Ok(None);
    }
    let fine = fine_problem(problem, r);
    let description = format!(
        "converged reference: {} on {} ({r}x finer); no exact solution: {why}",
        describe_config(&setup.judge.config, D),
        setup.grid(),
    );
    let run = |method, description: &str| {
        computed_or_cached(problem, &fine, (method, r), (description, say), ranks)
    };
    let stored = run(&setup.judge, &description)?;
    let spread_description = format!(
        "second reference (spread): {} on the same grid",
        describe_config(&setup.spread.config, D)
    );
    let second = run(&setup.spread, &spread_description)?;
    let crate::reference_cache::Stored {
        stress_xx,
        velocity_x,
        work,
    } = stored;
    let description = format!(
        "{description}; the spread beside each error is its distance from the {spread_description}"
    );
    let (load_scale, step_load) = problem.load_scale();
    // beyond the scene's dimension: one cell of unit size
    let cells: [usize; 3] = std::array::from_fn(|l| if l < D { fine.grid.cells[l] } else { 1 });
    let spacing: [f64; 3] = std::array::from_fn(|l| if l < D { fine.grid.spacing[l] } else { 1.0 });
    // the band across the line where the jump is read, along each other axis: from the
    // low side of the coarse row the line runs in, one coarse cell length along the line
    // wide (so a square on a square grid; the band the plate's front was always measured
    // in), within the body
    let mut band = [[0.0, 1.0]; 2];
    for (slot, other) in (0..3).filter(|&k| k != line.axis).enumerate() {
        if other >= D {
            band[slot] = [0.0, spacing[other]];
            continue;
        }
        let h = problem.grid.spacing[other];
        // the row `MeasureLine::holds` picks: `lo ≤ offset < hi`, to its tolerance
        let row = problem.grid.layer_of(other, line.offset[slot]);
        let top = problem.grid.upper()[other];
        let low = (row as f64 * h)
            .min(top - problem.grid.spacing[line.axis])
            .max(0.0);
        band[slot] = [low, (low + problem.grid.spacing[line.axis]).min(top)];
    }
    Ok(Some(Reference::Converged(Box::new(Converged {
        description,
        cells,
        spacing,
        times: problem.output_times.clone(),
        stress: stress_xx,
        velocity: velocity_x,
        speed: problem.material.p_wave_speed::<D>(),
        line,
        coarse_dx: problem.grid.spacing[line.axis],
        band,
        load_scale,
        step_load,
        from_load: loaded_at(problem, &line, line.start),
        opposite_load: loaded_at(problem, &line, line.end),
        rest: matches!(problem.initial, impact_core::initial::InitialState::Rest),
        work,
        spread: Some(Spread {
            description: spread_description,
            stress: second.stress_xx,
            velocity: second.velocity_x,
        }),
    }))))
}

/// `problem` on a grid `r` times finer along each axis, its stated reference options
/// cleared (they choose the reference; they do not change its run).
fn fine_problem<const D: usize>(problem: &Problem<D>, r: usize) -> Problem<D> {
    let mut fine = problem.clone();
    for l in 0..D {
        fine.grid.cells[l] *= r;
        fine.grid.spacing[l] /= r as f64;
    }
    fine.reference = Default::default();
    fine
}

/// The cache entry of the reference run of `method` on `fine` (`r` times finer) in `dir`:
/// its key holds the reference's method, options and refinement and the fine problem, so
/// references of different methods, options or grids never share an entry.
pub fn cache_entry<const D: usize>(
    dir: &std::path::Path,
    fine: &Problem<D>,
    (method, r): (&ReferenceMethod, usize),
) -> crate::reference_cache::Entry {
    let config = &method.config;
    crate::reference_cache::Entry::new(
        dir,
        &format!(
            "reference {} refinement {r}\n{fine:?}\n{config:?}",
            method.method.name()
        ),
    )
}

/// The reference run of `method` on `fine`, read from the cache or computed and stored.
fn computed_or_cached<const D: usize>(
    problem: &Problem<D>,
    fine: &Problem<D>,
    (method, r): (&ReferenceMethod, usize),
    (description, say): (&str, bool),
    ranks: &Ranks,
) -> anyhow::Result<crate::reference_cache::Stored> {
    let axis = impact_core::line::MeasureLine::of(problem).axis;
    fine.check_config(&method.config).map_err(|e| {
        anyhow::anyhow!(
            "the {description} cannot run this scene: {e}; choose another with `--reference` \
             or `--reference-spread` (`[metrics] reference`, `reference_spread`: {})",
            MethodKind::allowed()
        )
    })?;
    let entry = cache_entry(&crate::reference_cache::folder(), fine, (method, r));
    let fine_cells = fine.grid.cell_count();
    let times = problem.output_times.len();
    let comm = ranks.comm.as_ref();
    let (stored, cached) = entry.get_or_compute_on(comm, times, fine_cells, || {
        if say {
            crate::root_eprintln!("computing the {description}");
        }
        let progress = say.then(|| crate::run::progress_bar("reference"));
        let (stress_xx, velocity_x, work) = converged_run(
            problem,
            fine,
            (method.config, ranks),
            axis,
            progress.as_ref(),
        )?;
        if let Some(p) = progress {
            p.finish_and_clear();
        }
        Ok(crate::reference_cache::Stored {
            stress_xx,
            velocity_x,
            work,
        })
    })?;
    if say && cached {
        crate::root_eprintln!(
            "the {description}: read from the cache {}",
            entry.path().display()
        );
    }
    Ok(stored)
}

/// Whether the edge of the body at coordinate `at` of the line's axis carries a load of
/// non-zero magnitude (on any segment).
fn loaded_at<const D: usize>(
    problem: &Problem<D>,
    line: &impact_core::line::MeasureLine,
    at: f64,
) -> bool {
    use impact_core::Boundary;
    let (lo, hi) = (
        problem.grid.origin[line.axis],
        problem.grid.upper()[line.axis],
    );
    let tol = 1e-9 * (hi - lo).abs();
    let side = if (at - lo).abs() <= tol {
        0
    } else if (at - hi).abs() <= tol {
        1
    } else {
        return false; // a line starting inside the body
    };
    match problem.boundaries[line.axis][side] {
        Boundary::Pressure(load) | Boundary::Velocity { load, .. } => load.value != 0.0,
        Boundary::Free | Boundary::Symmetry => false,
    }
}

/// Step the fine `problem` (split over `ranks`) to the coarse problem's output times, keeping σ_aa, v_a along
/// `axis` (one point per cell, stored cell by cell) and the external work at each.
#[allow(clippy::type_complexity)]
fn converged_run<const D: usize>(
    problem: &Problem<D>,
    fine: &Problem<D>,
    (config, ranks): (MethodConfig, &Ranks),
    axis: usize,
    progress: Option<&indicatif::ProgressBar>,
) -> anyhow::Result<(Vec<Vec<f64>>, Vec<Vec<f64>>, Vec<f64>)> {
    // split like `impact run`'s runs; `sample_into` gathers the whole body to every rank
    let mut method = crate::ranks::build_ranked_on(fine, config, ranks.comm.clone(), &ranks.grid)?;
    let mut samples = impact_core::method::Samples::<D>::default();
    let cells = fine.grid.cell_count();
    let (mut stress_xx, mut velocity_x, mut work) = (Vec::new(), Vec::new(), Vec::new());
    impact_core::controller::run::<D, dyn Method<D>, anyhow::Error>(
        method.as_mut(),
        &problem.output_times,
        crate::interrupt::guard(),
        |m, _, _, _| {
            m.sample_into(&mut samples);
            if samples.len() != cells {
                anyhow::bail!(
                    "internal: the reference run gave {} samples for {cells} cells",
                    samples.len()
                );
            }
            // one point per cell, stored cell by cell: sample i is cell i
            stress_xx.push(samples.stress.iter().map(|s| s[(axis, axis)]).collect());
            velocity_x.push(samples.velocity.iter().map(|v| v[axis]).collect());
            work.push(m.external_work());
            Ok(())
        },
        |t| {
            if let Some(p) = progress {
                p.set_position(crate::run::progress_position(t, problem.t_end));
            }
        },
    )
    .map_err(|e| match e {
        impact_core::controller::RunError::Interrupted { .. } => {
            crate::interrupt::Interrupted(format!("the converged reference: {e}")).into()
        }
        impact_core::controller::RunError::Output(e) => e,
        e => anyhow::anyhow!("the reference run failed: {e}"),
    })?;
    Ok((stress_xx, velocity_x, work))
}
