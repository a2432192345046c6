//! The methods' sections of a scene file (`[dgmpm]`, `[mpm]`, `[fem]`): their Courant
//! numbers and options (each absent option at its default), and the [`MethodConfig`] a
//! scene gives each method ([`Scene::method_config`]).
use super::Scene;
use crate::options::{
    DgmpmOptions, EdgeTreatment, Integrator, MaterialModel, MethodConfig, MethodKind,
    MethodOptions, MpmFrame, MpmOptions, MpmShape, MpmTransfer, PointUpdate, RiemannSolver,
    SchemeOrder, StressUpdate, TransverseFlux, WaveLimiter,
};
use serde::{Deserialize, Serialize};

/// DGMPM's section: Courant number and options (each absent option takes its default,
/// [`DgmpmOptions::default`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DgmpmSpec {
    /// Courant number `c_p Δt / Δx_min` (default 1, the paper's).
    #[serde(default = "courant_one")]
    pub courant: f64,
    /// Time integrator.
    #[serde(default)]
    pub integrator: Option<Integrator>,
    /// Point update after the nodal solve.
    #[serde(default)]
    pub update: Option<PointUpdate>,
    /// Transverse flux (2D only).
    #[serde(default)]
    pub flux: Option<TransverseFlux>,
    /// Riemann solver (Saint-Venant–Kirchhoff).
    #[serde(default)]
    pub riemann: Option<RiemannSolver>,
    /// CTU's edge treatment (2D): `restricted` (default) or `ghost` (Clawpack's).
    #[serde(default)]
    pub edges: Option<EdgeTreatment>,
    /// Spatial order, `1` (the paper's, default) or `2` (limited wave corrections).
    #[serde(default)]
    pub order: Option<SchemeOrder>,
    /// Wave limiter of `order = 2` (default `"mc"`); refused with order 1.
    #[serde(default)]
    pub limiter: Option<WaveLimiter>,
}

/// MPM's section.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MpmSpec {
    /// Courant number (default 0.5, the paper's).
    #[serde(default = "courant_half")]
    pub courant: f64,
    /// Stress update.
    #[serde(default)]
    pub stress_update: Option<StressUpdate>,
    /// Frame of the shape functions.
    #[serde(default)]
    pub frame: Option<MpmFrame>,
    /// Shape functions.
    #[serde(default)]
    pub shape: Option<MpmShape>,
    /// Velocity transfer (default `"flip"`).
    #[serde(default)]
    pub transfer: Option<MpmTransfer>,
    /// The FLIP share `α ∈ [0, 1]` of `transfer = "blend"` (required there, refused with
    /// the other transfers).
    #[serde(default)]
    pub flip_fraction: Option<f64>,
}

/// FEM's section.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FemSpec {
    /// Courant number (default 0.9, the paper's).
    #[serde(default = "courant_fem")]
    pub courant: f64,
}

fn courant_one() -> f64 {
    1.0
}
fn courant_half() -> f64 {
    0.5
}
fn courant_fem() -> f64 {
    0.9
}

impl Default for DgmpmSpec {
    fn default() -> Self {
        Self {
            courant: courant_one(),
            integrator: None,
            update: None,
            flux: None,
            riemann: None,
            edges: None,
            order: None,
            limiter: None,
        }
    }
}

impl Default for MpmSpec {
    fn default() -> Self {
        Self {
            courant: courant_half(),
            stress_update: None,
            frame: None,
            shape: None,
            transfer: None,
            flip_fraction: None,
        }
    }
}

impl Default for FemSpec {
    fn default() -> Self {
        Self {
            courant: courant_fem(),
        }
    }
}

impl Scene {
    /// The configuration of `kind` written in this scene (absent options at their
    /// defaults).
    pub fn method_config(&self, kind: MethodKind) -> MethodConfig {
        let ppc = self.domain.points_per_cell;
        match kind {
            MethodKind::Dgmpm => {
                let s = &self.dgmpm;
                let d = DgmpmOptions::default();
                MethodConfig {
                    courant: s.courant,
                    points_per_cell: ppc,
                    options: MethodOptions::Dgmpm(DgmpmOptions {
                        integrator: s.integrator.unwrap_or(d.integrator),
                        update: s.update.unwrap_or(d.update),
                        flux: s.flux.unwrap_or(d.flux),
                        riemann: s
                            .riemann
                            .unwrap_or(if self.material.model == MaterialModel::J2 {
                                RiemannSolver::Elastic
                            } else {
                                d.riemann
                            }),
                        edges: s.edges.unwrap_or(d.edges),
                        order: s.order.unwrap_or(d.order),
                        limiter: s.limiter,
                    }),
                }
            }
            MethodKind::Mpm => {
                let s = &self.mpm;
                let d = MpmOptions::default();
                MethodConfig {
                    courant: s.courant,
                    points_per_cell: ppc,
                    options: MethodOptions::Mpm(MpmOptions {
                        stress_update: s.stress_update.unwrap_or(d.stress_update),
                        frame: s.frame.unwrap_or(d.frame),
                        shape: s.shape.unwrap_or(d.shape),
                        transfer: s.transfer.unwrap_or(d.transfer),
                        flip_fraction: s.flip_fraction,
                    }),
                }
            }
            MethodKind::Fem => MethodConfig::new(MethodKind::Fem, self.fem.courant, ppc),
        }
    }
}
