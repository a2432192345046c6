//! Checking a scene before anything is allocated or stepped.
//!
//! [`Scene::validate`] checks each field against a documented range, then the quantities
//! derived from them, so that nothing downstream can overflow, underflow, divide by zero
//! or loop without end:
//! - lengths, Young's modulus and density are positive SI values in [`SI_RANGE`]
//!   (`[1e-30, 1e30]`: wide enough for nondimensional runs, narrow enough that products of
//!   a few of them stay finite and normal);
//! - the cell size `h = L/N`, the P-wave speed `c_p = sqrt(M/ρ)` (`M = E` in 1D,
//!   `λ + 2μ` in 2D plane strain), the transit time `h/c_p` and the output times in seconds
//!   must be finite normal numbers;
//! - loads stay within the model: linear elasticity is a small-strain model, so the strain a
//!   load imposes on the incident wave (`|p|/M`, or `|v|/c_p`) is at most [`MAX_STRAIN`];
//!   Saint-Venant–Kirchhoff compression must stay below the hyperbolicity limit
//!   `E/(3√3)` (uniaxial `F = 1/√3`, where `Π' = 0`), its tension below `Π(F = 2) = 3E`,
//!   and a velocity load below `0.4 c_p` (uniaxial stretch above `0.6 > 1/√3`);
//! - a loaded segment lies on its edge and covers at least one face centre (the edge
//!   checks are in `boundary.rs`);
//! - no output time lies after `t_end`.
//!
//! The work a method configuration implies is estimated by [`Scene::work_estimate`] and
//! refused past a budget by [`check_work`] (the CLI's `--work-budget`).
use super::Scene;
use crate::error::SceneError;
use crate::material::LinearElastic;
use crate::options::{MaterialModel, MethodConfig, MethodKind, RiemannSolver};

/// Largest number of cells × points per cell a scene may ask for: a 512³ block at one
/// point per cell (about 60 GB). Whether a grid fits the machine it runs on is checked when
/// the run starts (the CLI's `memory` module).
pub const MAX_POINTS: f64 = 1.5e8;

/// Allowed range of the Courant number.
pub const COURANT_RANGE: &str = "a number in (0, 2]";

/// Range of a positive SI value (length, modulus, density).
pub const SI_RANGE: (f64, f64) = (1e-30, 1e30);

/// Largest strain a load may impose on linear elasticity (a small-strain model: at 10 %
/// strain its stress is about 10 % off any finite-strain model; use `svk` beyond).
pub const MAX_STRAIN: f64 = 0.1;

/// Default work budget of one method run, in point-updates (cells × points per cell ×
/// steps): about an hour on one core at the slowest method's 3e7 updates/s.
pub const DEFAULT_WORK_BUDGET: f64 = 1e11;

/// Largest number of output times.
pub const MAX_OUTPUTS: usize = 1000;

/// Largest cell count along one axis.
pub const MAX_CELLS_PER_AXIS: usize = 100_000_000;

fn positive(field: &str, value: f64, allowed: &str) -> Result<(), SceneError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(SceneError::new(field, value, allowed))
    }
}

fn si_value(field: &str, value: f64, unit: &str) -> Result<(), SceneError> {
    let (lo, hi) = SI_RANGE;
    if value.is_finite() && (lo..=hi).contains(&value) {
        Ok(())
    } else {
        Err(SceneError::new(
            field,
            value,
            format!("a positive number in {unit} from {lo:e} to {hi:e}"),
        ))
    }
}

/// A derived quantity must be a finite normal positive number.
fn derived(field: &str, what: &str, value: f64) -> Result<(), SceneError> {
    if value.is_finite() && value.is_normal() && value > 0.0 {
        Ok(())
    } else {
        Err(SceneError::new(
            field,
            format!("{what} = {value:e}"),
            "values whose derived quantities are finite normal numbers",
        ))
    }
}

/// Check a Courant number (also used for CLI flags).
pub fn check_courant(field: &str, courant: f64) -> Result<(), SceneError> {
    if courant.is_finite() && courant > 0.0 && courant <= 2.0 {
        Ok(())
    } else {
        Err(SceneError::new(field, courant, COURANT_RANGE))
    }
}

/// Check a points-per-cell count for dimension `dim` (also used for CLI flags).
pub fn check_points_per_cell(dim: usize, ppc: usize) -> Result<(), SceneError> {
    let per_axis = points_per_axis(dim, ppc);
    if ppc == 0 || ppc > 64 || per_axis.is_none() {
        let allowed = match dim {
            1 => "a whole number from 1 to 64",
            2 => "a square number (1, 4, 9, 16, ...) up to 64 in 2D",
            _ => "a cube (1, 8, 27, 64) in 3D",
        }
        .to_string();
        return Err(SceneError::new("domain.points_per_cell", ppc, allowed));
    }
    Ok(())
}

/// Points per axis for `ppc` points per cell, if `ppc` is an exact `dim`-th power.
pub fn points_per_axis(dim: usize, ppc: usize) -> Option<usize> {
    let power = u32::try_from(dim).ok()?;
    (1..=64usize).find(|n| n.checked_pow(power) == Some(ppc))
}

/// Check output times (also used for CLI flags): at most `MAX_OUTPUTS`, positive,
/// finite, strictly increasing.
pub fn check_output_times(field: &str, times: &[f64]) -> Result<(), SceneError> {
    if times.is_empty() || times.len() > MAX_OUTPUTS {
        return Err(SceneError::new(
            field,
            format!("{} times", times.len()),
            format!("from 1 to {MAX_OUTPUTS} output times"),
        ));
    }
    let mut last = 0.0;
    for &t in times {
        if !(t.is_finite() && t > last) {
            return Err(SceneError::new(
                field,
                format!("{times:?}"),
                "positive, finite, strictly increasing times",
            ));
        }
        last = t;
    }
    Ok(())
}

/// The work one method run implies: at least `steps` steps (Courant number over the
/// P-wave transit time) over `points` points (cells × points per cell; nodes for FEM).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorkEstimate {
    /// What runs: a method's name, or `the converged reference`.
    pub what: &'static str,
    /// Points (or cells) updated per step.
    pub points: f64,
    /// Number of steps (a lower bound: large-strain wave speeds shorten the step).
    pub steps: f64,
}

impl WorkEstimate {
    /// Point-updates: `points × steps`.
    pub fn point_updates(&self) -> f64 {
        self.points * self.steps
    }
}

/// Refuse a run whose estimated work exceeds `budget` point-updates.
pub fn check_work(estimate: &WorkEstimate, budget: f64) -> Result<(), SceneError> {
    let work = estimate.point_updates();
    if work.is_finite() && work <= budget {
        return Ok(());
    }
    Err(SceneError::new(
        format!("work of {}", estimate.what),
        format!(
            "{:.3e} points × {:.3e} steps = {work:.3e} point-updates",
            estimate.points, estimate.steps
        ),
        format!(
            "at most {budget:.1e} point-updates (lower the end time or the resolution, raise \
             the Courant number, or raise the budget with --work-budget)"
        ),
    ))
}

impl Scene {
    /// Check every value and derived quantity; the first problem found is returned.
    pub fn validate(&self) -> Result<(), SceneError> {
        self.check_name()?;
        self.check_domain()?;
        self.check_material()?;
        self.check_time()?;
        self.check_methods()?;
        self.check_derived()?;
        self.check_layout()?;
        self.check_initial()?;
        self.check_metrics()?;
        self.check_boundaries()
    }

    fn check_name(&self) -> Result<(), SceneError> {
        let ok = |c: char| c.is_ascii_alphanumeric() || c == '-' || c == '_';
        if self.name.is_empty() || self.name.len() > 64 || !self.name.chars().all(ok) {
            return Err(SceneError::new(
                "name",
                format!("{:?}", self.name),
                "a name of 1 to 64 letters, digits, '-' and '_'",
            ));
        }
        Ok(())
    }

    fn check_domain(&self) -> Result<(), SceneError> {
        if !(1..=3).contains(&self.dim) {
            return Err(SceneError::new("dim", self.dim, "1, 2 or 3"));
        }
        let d = &self.domain;
        if d.length.len() != self.dim {
            return Err(SceneError::new(
                "domain.length",
                format!("{:?}", d.length),
                format!("{} lengths (one per axis)", self.dim),
            ));
        }
        for (l, &len) in d.length.iter().enumerate() {
            si_value(&format!("domain.length[{l}]"), len, "m")?;
        }
        if d.cells.len() != self.dim {
            return Err(SceneError::new(
                "domain.cells",
                format!("{:?}", d.cells),
                format!("{} cell counts (one per axis)", self.dim),
            ));
        }
        for (l, &n) in d.cells.iter().enumerate() {
            if n == 0 || n > MAX_CELLS_PER_AXIS {
                return Err(SceneError::new(
                    format!("domain.cells[{l}]"),
                    n,
                    format!("from 1 to {MAX_CELLS_PER_AXIS:.0e} cells"),
                ));
            }
        }
        check_points_per_cell(self.dim, d.points_per_cell)?;
        let total = d.cells.iter().map(|&n| n as f64).product::<f64>() * d.points_per_cell as f64;
        if total > MAX_POINTS {
            return Err(SceneError::new(
                "domain.cells",
                format!("{:?} × {} points per cell", d.cells, d.points_per_cell),
                format!(
                    "at most {MAX_POINTS:.1e} cells × points per cell in total (a 512³ block at one \
                     point per cell; whether a grid fits this machine is checked when it runs)"
                ),
            ));
        }
        Ok(())
    }

    fn check_material(&self) -> Result<(), SceneError> {
        let m = &self.material;
        si_value("material.young", m.young, "Pa")?;
        si_value("material.density", m.density, "kg/m³")?;
        if !(m.poisson > -1.0 && m.poisson < 0.5) {
            return Err(SceneError::new(
                "material.poisson",
                m.poisson,
                "a number in (-1, 0.5)",
            ));
        }
        self.check_plasticity()
    }

    /// `yield_stress` in (0, E) and `hardening` in [0, E] exactly for `j2`, with `H > 0` in
    /// 1D: the rod's plastic wave moves at `c_t = sqrt(E H/((E + H) ρ))`, which is zero for a
    /// perfectly plastic rod (a load above yield then strains the loaded end without bound).
    /// In plane strain the plastic wave keeps `c_p = sqrt(K/ρ)` at `H = 0`, so perfect
    /// plasticity is allowed there. `H ≤ E` keeps the tangent below the elastic one.
    fn check_plasticity(&self) -> Result<(), SceneError> {
        let m = &self.material;
        if m.model != MaterialModel::J2 {
            for (field, value) in [
                ("material.yield_stress", m.yield_stress),
                ("material.hardening", m.hardening),
            ] {
                if let Some(v) = value {
                    return Err(SceneError::new(
                        field,
                        v,
                        format!(
                            "no plasticity parameter for model = \"{}\" (use \"j2\")",
                            m.model
                        ),
                    ));
                }
            }
            return Ok(());
        }
        let yield_stress = m.yield_stress.ok_or_else(|| {
            SceneError::new(
                "material.yield_stress",
                "missing",
                "σ_y in (0, E) Pa for j2",
            )
        })?;
        if !(yield_stress.is_finite() && yield_stress > 0.0 && yield_stress < m.young) {
            return Err(SceneError::new(
                "material.yield_stress",
                yield_stress,
                format!("σ_y in (0, E = {:e}) Pa", m.young),
            ));
        }
        let allowed = if self.dim == 1 {
            format!(
                "H in (0, E = {:e}] Pa in 1D (with H = 0 the rod's plastic wave does not move)",
                m.young
            )
        } else {
            format!("H in [0, E = {:e}] Pa", m.young)
        };
        let hardening = m
            .hardening
            .ok_or_else(|| SceneError::new("material.hardening", "missing", allowed.clone()))?;
        let lowest_ok = if self.dim == 1 {
            hardening > 0.0
        } else {
            hardening >= 0.0
        };
        if !(hardening.is_finite() && lowest_ok && hardening <= m.young) {
            return Err(SceneError::new("material.hardening", hardening, allowed));
        }
        Ok(())
    }

    fn check_time(&self) -> Result<(), SceneError> {
        let t = &self.time;
        let (field, times) = match (&t.output_times, &t.output_transits) {
            (Some(_), Some(_)) => {
                return Err(SceneError::new(
                    "time",
                    "both output_times and output_transits",
                    "one of `output_times` and `output_transits`",
                ))
            }
            (Some(v), None) => ("time.output_times", v),
            (None, Some(v)) => ("time.output_transits", v),
            (None, None) => {
                return Err(SceneError::new(
                    "time",
                    "no output times",
                    "`output_times` (s) or `output_transits` (multiples of Δx/c)",
                ))
            }
        };
        check_output_times(field, times)?;
        if let Some(t_end) = t.t_end {
            positive("time.t_end", t_end, "a positive finite time in s")?;
        }
        Ok(())
    }

    fn check_methods(&self) -> Result<(), SceneError> {
        check_courant("dgmpm.courant", self.dgmpm.courant)?;
        check_courant("mpm.courant", self.mpm.courant)?;
        check_courant("fem.courant", self.fem.courant)?;
        if let (Some(f), 1) = (self.dgmpm.flux, self.dim) {
            return Err(SceneError::new(
                "dgmpm.flux",
                format!("{:?}", f.name()),
                "no transverse flux in 1D (DGMPM in 2D and 3D only)",
            ));
        }
        if let Some(r) = self.dgmpm.riemann {
            let (allowed, names): (&[RiemannSolver], &str) = match self.material.model {
                MaterialModel::J2 => (
                    &[RiemannSolver::Elastic, RiemannSolver::Elastoplastic],
                    "\"elastic\" or \"elastoplastic\" for j2",
                ),
                _ => (
                    &[RiemannSolver::Approximate, RiemannSolver::Exact],
                    "\"approximate\" or \"exact\" (Saint-Venant-Kirchhoff; linear elasticity has one solver)",
                ),
            };
            if !allowed.contains(&r) {
                return Err(SceneError::new(
                    "dgmpm.riemann",
                    format!("{:?}", r.name()),
                    names,
                ));
            }
        }
        if let (Some(e), 1) = (self.dgmpm.edges, self.dim) {
            return Err(SceneError::new(
                "dgmpm.edges",
                format!("{:?}", e.name()),
                "no CTU edge treatment in 1D (2D and 3D only)",
            ));
        }
        Ok(())
    }

    /// The linear-elastic material and its P-wave modulus `M` in this scene's dimension.
    pub(super) fn p_modulus(&self) -> (LinearElastic, f64) {
        let m = &self.material;
        let material = LinearElastic::new(m.young, m.poisson, m.density);
        let modulus = if self.dim == 1 {
            m.young
        } else {
            material.p_modulus::<2>()
        };
        (material, modulus)
    }

    /// Smallest cell size and the time a P wave takes to cross it (the unit of
    /// `output_transits`).
    pub fn transit(&self) -> (f64, f64) {
        let d = &self.domain;
        let spacing = d
            .length
            .iter()
            .zip(&d.cells)
            .map(|(&len, &n)| len / n as f64)
            .fold(f64::INFINITY, f64::min);
        let (_, modulus) = self.p_modulus();
        let speed = (modulus / self.material.density).sqrt();
        (spacing, spacing / speed)
    }

    /// The output times in seconds and the end time.
    pub fn schedule_seconds(&self) -> (Vec<f64>, f64) {
        let (_, transit) = self.transit();
        let times: Vec<f64> = match (&self.time.output_times, &self.time.output_transits) {
            (Some(t), _) => t.clone(),
            (None, Some(n)) => n.iter().map(|n| n * transit).collect(),
            (None, None) => Vec::new(),
        };
        let last = times.last().copied().unwrap_or(0.0);
        (times, self.time.t_end.unwrap_or(last))
    }

    fn check_derived(&self) -> Result<(), SceneError> {
        let d = &self.domain;
        for (l, (&len, &n)) in d.length.iter().zip(&d.cells).enumerate() {
            derived(&format!("domain.cells[{l}]"), "cell size", len / n as f64)?;
        }
        let (_, modulus) = self.p_modulus();
        derived("material", "P-wave modulus", modulus)?;
        derived(
            "material",
            "P-wave speed",
            (modulus / self.material.density).sqrt(),
        )?;
        let (_, transit) = self.transit();
        derived("domain", "cell transit time h/c_p", transit)?;
        let (times, t_end) = self.schedule_seconds();
        let field = if self.time.output_times.is_some() {
            "time.output_times"
        } else {
            "time.output_transits"
        };
        for &t in &times {
            derived(field, "output time (s)", t)?;
        }
        derived("time.t_end", "end time (s)", t_end)?;
        if let Some(&late) = times.iter().find(|&&t| t > t_end * (1.0 + 1e-12)) {
            return Err(SceneError::new(
                field,
                format!("an output at {late:e} s, after time.t_end = {t_end:e} s"),
                "output times at or before the end time",
            ));
        }
        Ok(())
    }

    /// The work `config` implies on this scene (validated).
    pub fn work_estimate(&self, config: &MethodConfig) -> WorkEstimate {
        let cells: f64 = self.domain.cells.iter().map(|&n| n as f64).product();
        let points = match config.kind() {
            MethodKind::Fem => cells,
            _ => cells * config.points_per_cell as f64,
        };
        let (_, transit) = self.transit();
        let (_, t_end) = self.schedule_seconds();
        WorkEstimate {
            what: config.kind().name(),
            points,
            steps: (t_end / (config.courant * transit)).ceil(),
        }
    }
}
