//! The configuration of a method run ([`MethodConfig`]): what every method shares and each
//! method's own options ([`DgmpmOptions`], [`MpmOptions`], [`FemOptions`]), and the
//! `impact run` flags that select it ([`MethodConfig::to_flags`]).
use super::{
    EdgeTreatment, Integrator, MethodKind, MpmFrame, MpmShape, MpmTransfer, PointUpdate,
    RiemannSolver, SchemeOrder, StressUpdate, TransverseFlux, WaveLimiter,
};

/// DGMPM's options.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DgmpmOptions {
    /// Time integrator.
    pub integrator: Integrator,
    /// Point update after the nodal solve.
    pub update: PointUpdate,
    /// Transverse flux (2D).
    pub flux: TransverseFlux,
    /// Riemann solver (Saint-Venant–Kirchhoff).
    pub riemann: RiemannSolver,
    /// Edge treatment of CTU (2D).
    pub edges: EdgeTreatment,
    /// Spatial order: the paper's first-order flux or the limited second-order corrections.
    pub order: SchemeOrder,
    /// The wave limiter of `order = 2` (`None`: not chosen, [`DgmpmOptions::DEFAULT_LIMITER`]
    /// there); refused with `order = 1` (`Problem::check_config`).
    pub limiter: Option<WaveLimiter>,
}

impl DgmpmOptions {
    /// The limiter of `order = 2` when none is chosen: MC, Clawpack's template default.
    pub const DEFAULT_LIMITER: WaveLimiter = WaveLimiter::Mc;

    /// The limiter the second-order corrections use (`None`: first order, no corrections).
    pub fn wave_limiter(&self) -> Option<WaveLimiter> {
        match self.order {
            SchemeOrder::First => None,
            SchemeOrder::Second => Some(self.limiter.unwrap_or(Self::DEFAULT_LIMITER)),
        }
    }
}

impl Default for DgmpmOptions {
    /// The paper's: forward Euler, nodal point update, CTU in 2D, approximate SVK solver.
    fn default() -> Self {
        Self {
            integrator: Integrator::Euler,
            update: PointUpdate::Nodal,
            flux: TransverseFlux::Ctu,
            riemann: RiemannSolver::Approximate,
            edges: EdgeTreatment::Restricted,
            order: SchemeOrder::First,
            limiter: None,
        }
    }
}

/// MPM's options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MpmOptions {
    /// Stress update order.
    pub stress_update: StressUpdate,
    /// Frame of the shape functions.
    pub frame: MpmFrame,
    /// Shape functions.
    pub shape: MpmShape,
    /// Velocity transfer.
    pub transfer: MpmTransfer,
    /// The FLIP share `α ∈ [0, 1]` of `transfer = "blend"` (required there, refused with
    /// the other transfers: `Problem::check_config`).
    pub flip_fraction: Option<f64>,
}

impl Default for MpmOptions {
    /// USL in the total Lagrangian frame with linear hats and the FLIP transfer (the paper's
    /// comparisons, §5).
    fn default() -> Self {
        Self {
            stress_update: StressUpdate::Usl,
            frame: MpmFrame::TotalLagrangian,
            shape: MpmShape::Linear,
            transfer: MpmTransfer::Flip,
            flip_fraction: None,
        }
    }
}

impl MpmOptions {
    /// The transfer as labels and file names show it: empty for FLIP (the default, so
    /// existing labels stay), `pic`, `apic`, or `blend0.95` with the FLIP share.
    pub fn transfer_tag(&self) -> String {
        match (self.transfer, self.flip_fraction) {
            (MpmTransfer::Flip, _) => String::new(),
            (MpmTransfer::Blend, Some(alpha)) => format!("blend{alpha}"),
            (transfer, _) => transfer.name().to_string(),
        }
    }
}

/// FEM's options (none yet: linear elements, lumped mass, central differences).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FemOptions {}

/// The options of one method.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MethodOptions {
    /// DGMPM.
    Dgmpm(DgmpmOptions),
    /// MPM.
    Mpm(MpmOptions),
    /// FEM.
    Fem(FemOptions),
}

impl MethodOptions {
    /// The defaults of `kind`.
    pub fn defaults(kind: MethodKind) -> Self {
        match kind {
            MethodKind::Dgmpm => Self::Dgmpm(DgmpmOptions::default()),
            MethodKind::Mpm => Self::Mpm(MpmOptions::default()),
            MethodKind::Fem => Self::Fem(FemOptions::default()),
        }
    }
}

/// Options of one method run: what every method shares and the method's own part.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MethodConfig {
    /// Courant number `c_p Δt / Δx_min`.
    pub courant: f64,
    /// Material points per cell (DGMPM, MPM; FEM ignores it).
    pub points_per_cell: usize,
    /// The method and its own options.
    pub options: MethodOptions,
}

impl MethodConfig {
    /// `kind` with its default options.
    pub fn new(kind: MethodKind, courant: f64, points_per_cell: usize) -> Self {
        Self {
            courant,
            points_per_cell,
            options: MethodOptions::defaults(kind),
        }
    }

    /// Which method.
    pub fn kind(&self) -> MethodKind {
        match self.options {
            MethodOptions::Dgmpm(_) => MethodKind::Dgmpm,
            MethodOptions::Mpm(_) => MethodKind::Mpm,
            MethodOptions::Fem(_) => MethodKind::Fem,
        }
    }

    /// DGMPM's options (`None` for another method).
    pub fn dgmpm(&self) -> Option<&DgmpmOptions> {
        match &self.options {
            MethodOptions::Dgmpm(o) => Some(o),
            _ => None,
        }
    }

    /// DGMPM's options, to change (`None` for another method).
    pub fn dgmpm_mut(&mut self) -> Option<&mut DgmpmOptions> {
        match &mut self.options {
            MethodOptions::Dgmpm(o) => Some(o),
            _ => None,
        }
    }

    /// MPM's options (`None` for another method).
    pub fn mpm(&self) -> Option<&MpmOptions> {
        match &self.options {
            MethodOptions::Mpm(o) => Some(o),
            _ => None,
        }
    }

    /// MPM's options, to change (`None` for another method).
    pub fn mpm_mut(&mut self) -> Option<&mut MpmOptions> {
        match &mut self.options {
            MethodOptions::Mpm(o) => Some(o),
            _ => None,
        }
    }

    /// Short label of the integrator column: DGMPM's integrator, the stress update for
    /// MPM, `central` for FEM.
    pub fn integrator_label(&self) -> &'static str {
        match &self.options {
            MethodOptions::Dgmpm(o) => o.integrator.name(),
            MethodOptions::Mpm(o) => o.stress_update.name(),
            MethodOptions::Fem(_) => "central",
        }
    }

    /// The `impact run` flags that select this configuration (`--method`, `--courant`,
    /// `--points-per-cell` and the method's own options; `--flux` only in 2D).
    pub fn to_flags(&self, dim: usize) -> Vec<String> {
        let mut flags = vec![
            "--method".to_string(),
            self.kind().name().to_string(),
            "--courant".to_string(),
            self.courant.to_string(),
            "--points-per-cell".to_string(),
            self.points_per_cell.to_string(),
        ];
        let mut push = |flag: &str, value: &str| {
            flags.push(flag.to_string());
            flags.push(value.to_string());
        };
        match &self.options {
            MethodOptions::Dgmpm(o) => {
                push("--integrator", o.integrator.name());
                push("--update", o.update.name());
                push("--riemann", o.riemann.name());
                push("--order", o.order.name());
                if let Some(limiter) = o.limiter {
                    push("--limiter", limiter.name());
                }
                if dim > 1 {
                    push("--flux", o.flux.name());
                    push("--edges", o.edges.name());
                }
            }
            MethodOptions::Mpm(o) => {
                push("--stress-update", o.stress_update.name());
                push("--frame", o.frame.name());
                push("--shape", o.shape.name());
                push("--transfer", o.transfer.name());
                if let Some(alpha) = o.flip_fraction {
                    push("--flip-fraction", &alpha.to_string());
                }
            }
            MethodOptions::Fem(_) => {}
        }
        flags
    }
}
