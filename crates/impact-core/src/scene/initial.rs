//! The initial-state part of [`Scene::validate`] and its typed form
//! ([`Scene::initial_state`]): a standing mode, a plane wave (`plane_wave.rs`) or formulas
//! (one of them), formulas that parse,
//! read only the body's coordinates and stay finite and within the small-strain bounds at
//! every cell centre.
use super::validate::MAX_STRAIN;
use super::{InitialSpec, Scene};
use crate::error::SceneError;
use crate::exact::StandingWave;
use crate::initial::{Formula, InitialState};
use crate::options::MaterialModel;

impl Scene {
    pub(super) fn check_initial(&self) -> Result<(), SceneError> {
        let Some(spec) = &self.initial else {
            return Ok(());
        };
        let formulas = spec.velocity.is_some() || spec.stress.is_some();
        if let Some(wave) = &spec.plane_wave {
            if formulas || spec.standing_wave.is_some() {
                return Err(SceneError::new(
                    "initial.plane_wave",
                    "given with another initial state",
                    "one of `plane_wave`, `standing_wave` or `velocity`/`stress` formulas",
                ));
            }
            return self.check_plane_wave(wave);
        }
        if let Some(wave) = &spec.standing_wave {
            if formulas {
                return Err(SceneError::new(
                    "initial.standing_wave",
                    "given with formulas",
                    "either `standing_wave` or `velocity`/`stress` formulas, not both",
                ));
            }
            if wave.modes.len() != self.dim {
                return Err(SceneError::new(
                    "initial.standing_wave.modes",
                    format!("{:?}", wave.modes),
                    format!("{} mode numbers (one per axis)", self.dim),
                ));
            }
            if wave.modes[0] == 0 || wave.modes.iter().any(|&m| m > 10_000) {
                return Err(SceneError::new(
                    "initial.standing_wave.modes",
                    format!("{:?}", wave.modes),
                    "m ≥ 1 half wavelengths along x, n ≥ 0 along y (and q ≥ 0 along z), each at \
                     most 10000",
                ));
            }
            let speed = self.p_modulus().1 / self.material.density;
            let limit = MAX_STRAIN * speed.sqrt();
            if !(wave.amplitude.is_finite() && wave.amplitude > 0.0 && wave.amplitude <= limit) {
                return Err(SceneError::new(
                    "initial.standing_wave.amplitude",
                    wave.amplitude,
                    format!(
                        "a peak speed in (0, {limit:.4e}] m/s (a strain of at most {MAX_STRAIN})"
                    ),
                ));
            }
            return Ok(());
        }
        if spec.stress.is_some() && self.material.model == MaterialModel::Svk {
            return Err(SceneError::new(
                "initial.stress",
                "given",
                "no initial stress under `svk` (its state is the deformation gradient)",
            ));
        }
        let stress_count = crate::initial::stress_components(self.dim).len();
        for (key, list, count) in [
            ("velocity", &spec.velocity, self.dim),
            ("stress", &spec.stress, stress_count),
        ] {
            let Some(list) = list else { continue };
            if list.len() != count {
                return Err(SceneError::new(
                    format!("initial.{key}"),
                    format!("{} formulas", list.len()),
                    if key == "stress" {
                        format!(
                            "{count} formulas: {} in {}D",
                            crate::initial::stress_component_names(self.dim),
                            self.dim
                        )
                    } else {
                        format!("{count} formulas (one per axis)")
                    },
                ));
            }
            for (k, text) in list.iter().enumerate() {
                let formula = Formula::parse(text, self.dim)
                    .map_err(|why| SceneError::new(format!("initial.{key}[{k}]"), text, why))?;
                self.check_formula_values(&format!("initial.{key}[{k}]"), &formula, key)?;
            }
        }
        Ok(())
    }

    /// The formula is finite and within the small-strain bound at every cell centre.
    fn check_formula_values(
        &self,
        field: &str,
        formula: &Formula,
        key: &str,
    ) -> Result<(), SceneError> {
        let (_, modulus) = self.p_modulus();
        let limit = if key == "velocity" {
            MAX_STRAIN * (modulus / self.material.density).sqrt()
        } else {
            MAX_STRAIN * modulus
        };
        let cells = &self.domain.cells;
        let count: usize = cells.iter().product();
        for c in 0..count {
            let mut rest = c;
            let mut x = [0.0; 3];
            for (l, n) in cells.iter().enumerate() {
                let h = self.domain.length[l] / *n as f64;
                x[l] = (rest % n) as f64 * h + 0.5 * h;
                rest /= n;
            }
            let value = formula.eval(&x[..self.dim]);
            if !(value.is_finite() && value.abs() <= limit) {
                let unit = if key == "velocity" { "m/s" } else { "Pa" };
                return Err(SceneError::new(
                    field,
                    format!("{:?} = {value:e} at {:?} m", formula.text(), &x[..self.dim]),
                    format!(
                        "a finite value of at most {limit:.4e} {unit} in magnitude at every cell \
                         centre (a strain of at most {MAX_STRAIN})"
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The typed initial state of a scene that [`Scene::validate`] accepted.
    pub fn initial_state(&self) -> InitialState {
        let Some(InitialSpec {
            standing_wave,
            plane_wave,
            velocity,
            stress,
        }) = &self.initial
        else {
            return InitialState::Rest;
        };
        if let Some(wave) = plane_wave {
            return InitialState::PlaneWave(self.plane_wave(wave));
        }
        if let Some(wave) = standing_wave {
            let (material, _) = self.p_modulus();
            let lengths: [f64; 3] =
                std::array::from_fn(|l| self.domain.length.get(l).copied().unwrap_or(1.0));
            let modes: [u32; 3] = std::array::from_fn(|l| wave.modes.get(l).copied().unwrap_or(0));
            return InitialState::StandingWave(StandingWave::new(
                &material,
                self.dim,
                lengths,
                modes,
                wave.amplitude,
            ));
        }
        let parse = |list: &Option<Vec<String>>| -> Vec<Formula> {
            list.iter()
                .flatten()
                .map(|text| Formula::parse(text, self.dim).expect("internal: validated formula"))
                .collect()
        };
        InitialState::Formula {
            velocity: parse(velocity),
            stress: parse(stress),
        }
    }
}
