//! Checks of a method configuration against a problem, before anything is allocated:
//! [`Problem::check_config`]. The method constructors (`Dgmpm::new`, `Mpm::new`,
//! `Fem::new`) call it first, and the CLI calls it for every configuration of a command
//! before the reference or any run starts, so an incompatible combination is refused in
//! milliseconds, not after minutes spent on a converged reference (issue 23, item 9).
//!
//! Each refusal is a [`SceneError`]: the option's scene field and flag, the value given and
//! what is allowed with this problem.
use crate::method::Model;
use crate::options::{
    DgmpmOptions, MethodConfig, MethodOptions, MpmFrame, MpmOptions, MpmShape, MpmTransfer,
    RiemannSolver, SchemeOrder, TransverseFlux,
};
use crate::{CoreError, Problem, SceneError};

/// `dgmpm.<name> (--<flag>)`: the field of a refusal, named as in scene files and flags.
fn field(section: &str, name: &str, flag: &str) -> String {
    format!("{section}.{name} (--{flag})")
}

/// MPM's transfer and its FLIP share: `flip_fraction` in `[0, 1]`, given with
/// `transfer = "blend"` only (required there: no hidden default share); APIC not with CPDI
/// (its domain-averaged weights have no affine transfer implemented: `impact_mpm`'s
/// `transfer` module).
fn check_transfer(o: &MpmOptions) -> Result<(), CoreError> {
    let fraction = field("mpm", "flip_fraction", "flip-fraction");
    match (o.transfer, o.flip_fraction) {
        (MpmTransfer::Blend, None) => Err(SceneError::new(
            fraction,
            "missing",
            "a FLIP share in [0, 1] with transfer = \"blend\" (1 is FLIP, 0 is PIC)",
        )
        .into()),
        (MpmTransfer::Blend, Some(alpha)) if !(0.0..=1.0).contains(&alpha) => Err(SceneError::new(
            fraction,
            alpha,
            "a FLIP share in [0, 1] (1 is FLIP, 0 is PIC)",
        )
        .into()),
        (transfer, Some(alpha)) if transfer != MpmTransfer::Blend => Err(SceneError::new(
            fraction,
            alpha,
            format!(
                "no flip_fraction with transfer = \"{transfer}\": it is the FLIP share of \
                 transfer = \"blend\" (--transfer blend)"
            ),
        )
        .into()),
        (MpmTransfer::Apic, _) if o.shape == MpmShape::Cpdi => Err(SceneError::new(
            field("mpm", "transfer", "transfer"),
            o.transfer,
            "\"flip\", \"pic\" or \"blend\" with shape = \"cpdi\" (APIC's affine transfer \
             is implemented for hats, GIMP and B-splines, not for CPDI's domain-averaged \
             weights)",
        )
        .into()),
        _ => Ok(()),
    }
}

impl<const D: usize> Problem<D> {
    /// Whether `config` can run on this problem: Courant number, points per cell (and the
    /// scene's point layout), and the method's options against the material model and the
    /// dimension. Allocates nothing.
    pub fn check_config(&self, config: &MethodConfig) -> Result<(), CoreError> {
        let method = config.kind().name();
        crate::scene::check_courant(&format!("{method}.courant (--courant)"), config.courant)?;
        match config.options {
            MethodOptions::Fem(_) => self.check_fem(),
            MethodOptions::Mpm(o) => {
                self.check_points(config)?;
                if matches!(self.model, Model::Svk(_)) && o.frame != MpmFrame::TotalLagrangian {
                    return Err(SceneError::new(
                        field("mpm", "frame", "frame"),
                        o.frame,
                        "\"total-lagrangian\" with Saint-Venant-Kirchhoff (MPM solves it in \
                         the reference configuration)",
                    )
                    .into());
                }
                check_transfer(&o)
            }
            MethodOptions::Dgmpm(o) => {
                self.check_points(config)?;
                self.check_dgmpm(config.points_per_cell, o.flux, o.riemann)?;
                self.check_order(&o)
            }
        }
    }

    /// Points per cell: a count the dimension allows, which the scene's layout seeds.
    fn check_points(&self, config: &MethodConfig) -> Result<(), CoreError> {
        let ppc = config.points_per_cell;
        crate::scene::check_points_per_cell(D, ppc).map_err(|mut e| {
            e.field = "domain.points_per_cell (--points-per-cell)".into();
            e
        })?;
        if !self.layout.fits(ppc) {
            return Err(SceneError::new(
                "domain.points_per_cell (--points-per-cell)",
                ppc,
                format!(
                    "the count the scene's point layout seeds ({})",
                    self.layout.label()
                ),
            )
            .into());
        }
        Ok(())
    }

    /// FEM's state is a displacement: no initial stress by formula.
    fn check_fem(&self) -> Result<(), CoreError> {
        if self.initial.has_stress() {
            return Err(SceneError::new(
                "--method",
                "fem",
                "dgmpm or mpm with an initial stress by formula (initial.stress): FEM's state \
                 is its displacement, and a stress field is not in general the stress of one",
            )
            .into());
        }
        Ok(())
    }

    /// DGMPM's order and limiter: a limiter only with `order = 2` (the first-order scheme
    /// has no corrections to limit: a limiter given there is refused, not ignored), and
    /// `order = 2` in 1D, 2D and 3D (CTU or donor-cell; the elastoplastic solver where it
    /// runs: donor-cell); with Saint-Venant–Kirchhoff only in 1D with the
    /// approximate solver.
    fn check_order(&self, o: &DgmpmOptions) -> Result<(), CoreError> {
        match (o.order, o.limiter) {
            (SchemeOrder::First, Some(limiter)) => Err(SceneError::new(
                field("dgmpm", "limiter", "limiter"),
                limiter,
                "no limiter with order = 1 (the first-order scheme has no corrections to \
                 limit): set order = 2 (--order 2) or leave the limiter out",
            )
            .into()),
            (SchemeOrder::Second, _)
                if matches!(self.model, Model::Svk(_)) && o.riemann == RiemannSolver::Exact =>
            {
                Err(SceneError::new(
                    field("dgmpm", "order", "order"),
                    o.order,
                    "1 with Saint-Venant-Kirchhoff and riemann = \"exact\" (the second-order \
                     wave corrections take the approximate solver's waves)",
                )
                .into())
            }
            _ => Ok(()),
        }
    }

    /// DGMPM's transverse flux and Riemann solver against the model and the dimension.
    fn check_dgmpm(
        &self,
        ppc: usize,
        flux: TransverseFlux,
        riemann: RiemannSolver,
    ) -> Result<(), CoreError> {
        let flux_field = field("dgmpm", "flux", "flux");
        let riemann_field = field("dgmpm", "riemann", "riemann");
        let refuse = |field: &str, value: &dyn std::fmt::Display, allowed: &str| {
            Err(CoreError::from(SceneError::new(field, value, allowed)))
        };
        match self.model {
            Model::Svk(_) => {
                if D > 1 && flux == TransverseFlux::Ctu {
                    return refuse(
                        &flux_field,
                        &flux,
                        "\"dcu\" with Saint-Venant-Kirchhoff (the CTU transverse solver is \
                         implemented for linear elasticity and J2)",
                    );
                }
                if D > 1 && riemann == RiemannSolver::Exact {
                    return refuse(
                        &riemann_field,
                        &riemann,
                        "\"approximate\" in 2D (the exact Saint-Venant-Kirchhoff Riemann \
                         solver is 1D)",
                    );
                }
                if !matches!(riemann, RiemannSolver::Approximate | RiemannSolver::Exact) {
                    return refuse(
                        &riemann_field,
                        &riemann,
                        "\"approximate\" or \"exact\" with Saint-Venant-Kirchhoff (\"elastic\" \
                         and \"elastoplastic\" are for j2)",
                    );
                }
            }
            Model::J2(_) => {
                if !matches!(
                    riemann,
                    RiemannSolver::Elastic | RiemannSolver::Elastoplastic
                ) {
                    return refuse(
                        &riemann_field,
                        &riemann,
                        "\"elastic\" (the linear solver, then the return map) or \
                         \"elastoplastic\" (the exact rod solver) with j2",
                    );
                }
                if riemann == RiemannSolver::Elastoplastic {
                    if ppc != 1 {
                        return refuse(
                            "domain.points_per_cell (--points-per-cell)",
                            &ppc,
                            "1 with --riemann elastoplastic (the solver reads each cell's \
                             plastic state from its one point), or --riemann elastic",
                        );
                    }
                    if D >= 2 && flux == TransverseFlux::Ctu {
                        return refuse(
                            &flux_field,
                            &flux,
                            "\"dcu\" with --riemann elastoplastic (CTU's transverse \
                             corrections are elastic): use --flux dcu",
                        );
                    }
                }
            }
            Model::LinearElastic => {
                if matches!(
                    riemann,
                    RiemannSolver::Elastic | RiemannSolver::Elastoplastic
                ) {
                    return refuse(
                        &riemann_field,
                        &riemann,
                        "the default with linear elasticity (its exact linear solver; \
                         \"elastic\" and \"elastoplastic\" are for j2, \"approximate\" and \
                         \"exact\" for Saint-Venant-Kirchhoff)",
                    );
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use crate::options::{
        MethodKind, MpmFrame, MpmShape, MpmTransfer, RiemannSolver, TransverseFlux,
    };
    use crate::{Problem, Scene};

    /// The refusal of `config` on `scene`, as text.
    fn refusal<const D: usize>(
        scene: &str,
        change: impl Fn(&mut crate::options::MethodConfig),
        kind: MethodKind,
    ) -> Option<String> {
        let scene = Scene::builtin(scene).unwrap();
        let problem = Problem::<D>::from_scene(&scene).unwrap();
        let mut config = scene.method_config(kind);
        change(&mut config);
        problem.check_config(&config).err().map(|e| e.to_string())
    }

    /// Every shipped scene's own configurations pass; each incompatible option is refused
    /// with its field, its value and what is allowed.
    #[test]
    fn incompatible_options_name_the_field_the_value_and_what_is_allowed() {
        for name in crate::scene::BUILTIN {
            let scene = Scene::builtin(name).unwrap();
            for kind in MethodKind::ALL {
                let config = scene.method_config(kind);
                let result = match scene.dim {
                    1 => Problem::<1>::from_scene(&scene)
                        .unwrap()
                        .check_config(&config),
                    2 => Problem::<2>::from_scene(&scene)
                        .unwrap()
                        .check_config(&config),
                    _ => Problem::<3>::from_scene(&scene)
                        .unwrap()
                        .check_config(&config),
                };
                assert!(result.is_ok(), "{name} {kind}: {result:?}");
            }
        }
        let cases = [
            (
                refusal::<2>(
                    "svk-plate",
                    |c| c.dgmpm_mut().unwrap().flux = TransverseFlux::Ctu,
                    MethodKind::Dgmpm,
                ),
                ["dgmpm.flux (--flux)", "ctu", "\"dcu\""],
            ),
            (
                refusal::<2>(
                    "svk-plate",
                    |c| c.dgmpm_mut().unwrap().riemann = RiemannSolver::Exact,
                    MethodKind::Dgmpm,
                ),
                [
                    "dgmpm.riemann (--riemann)",
                    "exact",
                    "\"approximate\" in 2D",
                ],
            ),
            (
                refusal::<1>(
                    "svk-bar",
                    |c| c.mpm_mut().unwrap().frame = MpmFrame::UpdatedLagrangian,
                    MethodKind::Mpm,
                ),
                [
                    "mpm.frame (--frame)",
                    "updated-lagrangian",
                    "\"total-lagrangian\"",
                ],
            ),
            (
                refusal::<1>(
                    "ep-bar",
                    |c| c.dgmpm_mut().unwrap().riemann = RiemannSolver::Approximate,
                    MethodKind::Dgmpm,
                ),
                ["dgmpm.riemann (--riemann)", "approximate", "\"elastic\""],
            ),
            (
                refusal::<1>(
                    "bar",
                    |c| c.dgmpm_mut().unwrap().riemann = RiemannSolver::Elastic,
                    MethodKind::Dgmpm,
                ),
                ["dgmpm.riemann (--riemann)", "elastic", "linear elasticity"],
            ),
            (
                refusal::<1>(
                    "ep-bar",
                    |c| {
                        c.dgmpm_mut().unwrap().riemann = RiemannSolver::Elastoplastic;
                        c.points_per_cell = 2;
                    },
                    MethodKind::Dgmpm,
                ),
                [
                    "domain.points_per_cell (--points-per-cell)",
                    "2",
                    "1 with --riemann elastoplastic",
                ],
            ),
            (
                refusal::<2>(
                    "ep-plate-wave",
                    |c| c.dgmpm_mut().unwrap().riemann = RiemannSolver::Elastoplastic,
                    MethodKind::Dgmpm,
                ),
                ["dgmpm.flux (--flux)", "ctu", "--flux dcu"],
            ),
            (
                refusal::<2>("plate", |c| c.points_per_cell = 2, MethodKind::Mpm),
                ["domain.points_per_cell (--points-per-cell)", "2", "1, 4, 9"],
            ),
            (
                refusal::<1>(
                    "bar",
                    |c| c.mpm_mut().unwrap().transfer = MpmTransfer::Blend,
                    MethodKind::Mpm,
                ),
                ["mpm.flip_fraction (--flip-fraction)", "missing", "[0, 1]"],
            ),
            (
                refusal::<2>(
                    "plate",
                    |c| {
                        let o = c.mpm_mut().unwrap();
                        (o.transfer, o.flip_fraction) = (MpmTransfer::Blend, Some(1.5));
                    },
                    MethodKind::Mpm,
                ),
                ["mpm.flip_fraction (--flip-fraction)", "1.5", "[0, 1]"],
            ),
            (
                refusal::<1>(
                    "bar",
                    |c| c.mpm_mut().unwrap().flip_fraction = Some(0.5),
                    MethodKind::Mpm,
                ),
                [
                    "mpm.flip_fraction (--flip-fraction)",
                    "0.5",
                    "transfer = \"flip\"",
                ],
            ),
            (
                refusal::<1>(
                    "bar",
                    |c| {
                        let o = c.mpm_mut().unwrap();
                        (o.transfer, o.shape) = (MpmTransfer::Apic, MpmShape::Cpdi);
                    },
                    MethodKind::Mpm,
                ),
                ["mpm.transfer (--transfer)", "apic", "shape = \"cpdi\""],
            ),
            (
                refusal::<1>("bar", |c| c.courant = 2.5, MethodKind::Fem),
                ["fem.courant (--courant)", "2.5", "(0, 2]"],
            ),
        ];
        for (message, fragments) in cases {
            let message = message.expect("refused");
            for f in fragments {
                assert!(message.contains(f), "{message:?} should contain {f:?}");
            }
        }
    }
}
