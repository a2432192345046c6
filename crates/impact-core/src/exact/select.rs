//! Which exact solution a problem has ([`Reference::exact`]), or why it has none.
use super::{BarEnd, BarExact, ElastoplasticWave, SvkBarExact};
use crate::initial::InitialState;
use crate::load::LoadHistory;
use crate::problem::{Boundary, Load, Model, Problem};
use crate::reference::Reference;

impl Reference {
    /// The exact reference of `problem`, or why it has none (a sentence for "reference:
    /// none because ...").
    ///
    /// - linear elasticity, 1D, or 2D and 3D with symmetry sides across x (a plane wave in
    ///   uniaxial strain) and loads over whole edges: [`BarExact`] with any condition at
    ///   each end and any load history; in 1D from any initial state (d'Alembert);
    /// - the standing P mode with symmetry edges all round: [`StandingWave`](super::StandingWave);
    /// - a travelling plane pulse, with any boundaries: [`PlaneWave`](super::PlaneWave), exact
    ///   in the clean interior ([`crate::interior`]);
    /// - J2: a step pressure at the left end of a free rod (1D) or a step velocity on the
    ///   whole left edge of a free plane wave (2D): [`ElastoplasticWave`];
    /// - Saint-Venant–Kirchhoff: a step pressure at the left end of a free bar (1D):
    ///   [`SvkBarExact`].
    pub fn exact<const D: usize>(problem: &Problem<D>) -> Result<Self, String> {
        let m = problem.material;
        let all_symmetry = problem
            .boundaries
            .iter()
            .all(|pair| *pair == [Boundary::Symmetry; 2]);
        let plane = (1..D).all(|k| problem.boundaries[k] == [Boundary::Symmetry; 2]);
        let length = problem.grid.upper()[0] - problem.grid.origin[0];
        match (&problem.initial, problem.model) {
            (InitialState::Rest, _) => {}
            (InitialState::StandingWave(w), Model::LinearElastic) if all_symmetry => {
                return Ok(Reference::Standing(*w))
            }
            // exact wherever the boundaries have not acted: the metrics keep to the clean
            // interior (`crate::interior`; the scene's default for a plane wave)
            (InitialState::PlaneWave(w), Model::LinearElastic) => return Ok(Reference::Plane(*w)),
            (_, Model::LinearElastic) if D == 1 => {}
            (_, Model::LinearElastic) => {
                return Err(
                    "the scene starts from an initial state that is not the standing \
                            mode with symmetry edges all round nor a plane wave, and in 2D and 3D \
                            only those have an exact solution"
                        .into(),
                )
            }
            _ => {
                return Err(format!(
                    "the scene starts from an initial state, and under {} only a body at \
                     rest has an exact solution",
                    model_name(&problem.model)
                ))
            }
        }
        if let Model::J2(j2) = problem.model {
            let step = |load: &Load| load.patch.is_none() && load.history.is_step();
            return match problem.boundaries[0] {
                [Boundary::Pressure(load), Boundary::Free] if D == 1 && step(&load) => Ok(
                    Reference::Elastoplastic(ElastoplasticWave::rod(&j2, length, load.value)),
                ),
                [Boundary::Velocity { load, .. }, Boundary::Free]
                    if D == 2 && plane && step(&load) =>
                {
                    Ok(Reference::Elastoplastic(ElastoplasticWave::plane(
                        &j2, length, load.value,
                    )))
                }
                _ => Err(
                    "under J2 plasticity the exact solution is the elastic precursor and \
                          plastic wave of a step pressure at the left end of a rod with a free \
                          right end (1D) or of a step velocity on the whole left edge of a \
                          plane wave (2D, symmetry top and bottom, free right edge)"
                        .into(),
                ),
            };
        }
        if let Model::Svk(svk) = problem.model {
            let reason = "under Saint-Venant–Kirchhoff the exact solution is the fan or shock \
                          of a step pressure at the left end of a 1D bar with a free right end";
            return match (D, problem.boundaries[0]) {
                (
                    1,
                    [Boundary::Pressure(Load {
                        value,
                        patch: None,
                        history: LoadHistory::Step,
                    }), Boundary::Free],
                ) => SvkBarExact::new(svk, length, value)
                    .map(Reference::SvkBar)
                    .ok_or_else(|| {
                        format!(
                            "the SVK bar's pressure {value:e} Pa is beyond the range its \
                             exact fan or shock covers"
                        )
                    }),
                _ => Err(reason.into()),
            };
        }
        if !plane {
            return Err(
                "in 2D and 3D the exact solution is the plane wave along x: it needs symmetry \
                        sides across x (top and bottom in 2D; y and z in 3D; this scene has \
                        other conditions there; a converged reference stands in)"
                    .into(),
            );
        }
        let face = &problem.grid;
        let ends = [0, 1].map(|side| bar_end::<D>(&problem.boundaries[0][side], side, face));
        let ends = [ends[0].clone()?, ends[1].clone()?];
        let bar = BarExact::with_ends(length, m.density, m.p_modulus::<D>(), ends)
            .with_initial(&problem.initial);
        Ok(Reference::Bar(bar))
    }
}

/// The condition of the bar's end `side` (0 left, 1 right) from the boundary of a 1D bar
/// or of a plane wave across the faces of `grid` (a load must cover the whole face).
fn bar_end<const D: usize>(
    boundary: &Boundary,
    side: usize,
    grid: &crate::Grid<D>,
) -> Result<BarEnd, String> {
    let whole = |load: &Load| {
        let Some(patch) = load.patch else {
            return Ok(());
        };
        let (lo, hi) = (grid.origin, grid.upper());
        let covered = match patch.shape {
            crate::PatchShape::Box { lo: from, hi: to } => crate::Grid::<D>::tangent_axes(0)
                .enumerate()
                .all(|(slot, k)| from[slot] <= lo[k] && to[slot] >= hi[k]),
            crate::PatchShape::Disc { .. } => false,
        };
        if covered {
            return Ok(());
        }
        Err(format!(
            "the load on the {} side covers part of it, and the exact plane-wave solution \
             needs a load over the whole face (a converged reference stands in)",
            ["left", "right"][side],
        ))
    };
    Ok(match boundary {
        Boundary::Free => BarEnd::FREE,
        Boundary::Symmetry => BarEnd::FIXED,
        Boundary::Pressure(load) => {
            whole(load)?;
            BarEnd::Traction {
                pressure: load.value,
                history: load.history,
            }
        }
        Boundary::Velocity { load, .. } => {
            whole(load)?;
            BarEnd::Velocity {
                velocity: load.value,
                history: load.history,
            }
        }
    })
}

/// The model's name in reasons.
fn model_name(model: &Model) -> &'static str {
    match model {
        Model::LinearElastic => "linear elasticity",
        Model::Svk(_) => "Saint-Venant–Kirchhoff",
        Model::J2(_) => "J2 plasticity",
    }
}
