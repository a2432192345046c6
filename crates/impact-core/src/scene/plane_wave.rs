//! `[initial] plane_wave`: a travelling P or S pulse ([`crate::exact::PlaneWave`]), its
//! checks (one part of [`Scene::validate`]) and its typed form.
//!
//! ```toml
//! [initial]
//! plane_wave = { amplitude = 1.0, direction = [1.0, 2.0, 2.0], centre = [0.45, 0.4, 0.4],
//!                half_width = 0.2 }                      # a P pulse; kind = "s" with
//!                                                        # polarisation = [1.0, 0.0, 0.0]
//! ```
use super::validate::MAX_STRAIN;
use super::Scene;
use crate::error::SceneError;
use crate::exact::PlaneWave;
use crate::options::{option_enum, MaterialModel};
use serde::{Deserialize, Serialize};

option_enum! {
    /// Which plane wave.
    PlaneWaveKind {
        /// Longitudinal: polarised along the direction, at `c_p`.
        P = "p",
        /// Transverse: polarised normal to the direction, at `c_s` (2D and 3D).
        S = "s",
    }
}

/// A plane pulse `v = a U g((n·x − c t − n·x₀)/w)`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlaneWaveSpec {
    /// Peak speed `U` (m/s).
    pub amplitude: f64,
    /// Direction of travel `n`, one component per axis (normalised; not zero).
    pub direction: Vec<f64>,
    /// A point on the pulse's centre plane at `t = 0` (m), one coordinate per axis.
    pub centre: Vec<f64>,
    /// Half-width `w` of the pulse along `n` (m).
    pub half_width: f64,
    /// `p` (default) or `s`.
    #[serde(default)]
    pub kind: Option<PlaneWaveKind>,
    /// An S wave's polarisation: its part normal to `n` is used (not parallel to `n`).
    #[serde(default)]
    pub polarisation: Option<Vec<f64>>,
}

const FIELD: &str = "initial.plane_wave";

fn vector3(v: &[f64]) -> [f64; 3] {
    std::array::from_fn(|l| v.get(l).copied().unwrap_or(0.0))
}

/// `v / |v|` (scaled by its largest component first: no overflow), zero for zero.
fn unit(v: &[f64]) -> [f64; 3] {
    let largest = v.iter().fold(0.0f64, |m, c| m.max(c.abs()));
    if largest == 0.0 {
        return [0.0; 3];
    }
    let scaled = vector3(v).map(|c| c / largest);
    let norm = scaled.iter().map(|c| c * c).sum::<f64>().sqrt();
    scaled.map(|c| c / norm)
}

impl Scene {
    /// Check `[initial] plane_wave`: linear elasticity; one component per axis, finite; a
    /// direction that is not zero; an S polarisation with a part normal to it (2D, 3D); a
    /// half-width of at least one cell and at most the body's diagonal; a peak speed within
    /// the small-strain bound.
    pub(super) fn check_plane_wave(&self, wave: &PlaneWaveSpec) -> Result<(), SceneError> {
        if self.material.model != MaterialModel::LinearElastic {
            return Err(SceneError::new(
                format!("{FIELD} (material.model)"),
                self.material.model.name(),
                "\"linear-elastic\": the plane wave is exact for linear elasticity only",
            ));
        }
        let dim = self.dim;
        let finite = |v: &[f64]| v.iter().all(|c| c.is_finite());
        for (key, v) in [("direction", &wave.direction), ("centre", &wave.centre)] {
            if v.len() != dim || !finite(v) {
                return Err(SceneError::new(
                    format!("{FIELD}.{key}"),
                    format!("{v:?}"),
                    format!("{dim} finite components (one per axis)"),
                ));
            }
        }
        let largest = wave.direction.iter().fold(0.0f64, |m, c| m.max(c.abs()));
        if largest == 0.0 {
            return Err(SceneError::new(
                format!("{FIELD}.direction"),
                format!("{:?}", wave.direction),
                "a direction that is not zero (it is normalised)",
            ));
        }
        let kind = wave.kind.unwrap_or(PlaneWaveKind::P);
        match (kind, &wave.polarisation) {
            (PlaneWaveKind::P, Some(p)) => {
                return Err(SceneError::new(
                    format!("{FIELD}.polarisation"),
                    format!("{p:?}"),
                    "no polarisation for a P wave (it is the direction); `kind = \"s\"` for a \
                     transverse wave",
                ))
            }
            (PlaneWaveKind::S, _) if dim == 1 => {
                return Err(SceneError::new(
                    format!("{FIELD}.kind"),
                    "s",
                    "\"p\" in 1D (a bar in uniaxial stress carries no shear wave)",
                ))
            }
            (PlaneWaveKind::S, None) => {
                return Err(SceneError::new(
                    format!("{FIELD}.polarisation"),
                    "missing",
                    format!("{dim} components for an S wave, not parallel to the direction"),
                ))
            }
            (PlaneWaveKind::S, Some(p)) => {
                let n = unit(&wave.direction);
                let along: f64 = p.iter().zip(&n).map(|(a, b)| a * b).sum();
                let normal = p
                    .iter()
                    .zip(&n)
                    .map(|(a, b)| (a - along * b).powi(2))
                    .sum::<f64>()
                    .sqrt();
                let size = p.iter().map(|c| c * c).sum::<f64>().sqrt();
                if p.len() != dim || !finite(p) || normal <= 1e-6 * size {
                    return Err(SceneError::new(
                        format!("{FIELD}.polarisation"),
                        format!("{p:?}"),
                        format!(
                            "{dim} finite components with a part normal to the direction \
                             (not zero, not parallel to it)"
                        ),
                    ));
                }
            }
            (PlaneWaveKind::P, None) => {}
        }
        let (h, _) = self.transit();
        let diagonal = self.domain.length.iter().map(|l| l * l).sum::<f64>().sqrt();
        if !(wave.half_width.is_finite() && wave.half_width >= h && wave.half_width <= diagonal) {
            return Err(SceneError::new(
                format!("{FIELD}.half_width"),
                wave.half_width,
                format!(
                    "a half-width in [{h:.4e}, {diagonal:.4e}] m (from one cell to the body's \
                     diagonal)"
                ),
            ));
        }
        let (material, modulus) = self.p_modulus();
        let speed = if kind == PlaneWaveKind::S {
            material.lame.mu
        } else {
            modulus
        } / self.material.density;
        let limit = MAX_STRAIN * speed.sqrt();
        if !(wave.amplitude.is_finite() && wave.amplitude > 0.0 && wave.amplitude <= limit) {
            return Err(SceneError::new(
                format!("{FIELD}.amplitude"),
                wave.amplitude,
                format!("a peak speed in (0, {limit:.4e}] m/s (a strain of at most {MAX_STRAIN})"),
            ));
        }
        Ok(())
    }

    /// The typed pulse of a checked spec.
    pub(super) fn plane_wave(&self, wave: &PlaneWaveSpec) -> PlaneWave {
        let (material, _) = self.p_modulus();
        let polarisation = wave.polarisation.as_deref().map_or([0.0; 3], unit);
        PlaneWave::new(
            &material,
            self.dim,
            (unit(&wave.direction), polarisation),
            wave.kind == Some(PlaneWaveKind::S),
            (vector3(&wave.centre), wave.half_width),
            wave.amplitude,
        )
    }
}
