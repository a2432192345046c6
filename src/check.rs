//! `impact check`: the CI gate. DGMPM and MPM run on the same problem, each in the scene's
//! configuration with the method flags of `run` applied as there (`--courant` and
//! `--points-per-cell` to both, `--integrator`/`--flux`/... to DGMPM, `--stress-update`/
//! `--shape`/... to MPM) and the gate's own per-method flags last ([`CheckOptions`]). The
//! gate passes only if, at every output time with a front, DGMPM's front is narrower and
//! its overshoot smaller than MPM's (or both fronts monotone), within the [`Thresholds`]
//! ([`judge`]), and neither run stopped. [`crate::check_report`] writes the outcome as JSON and JUnit XML.
use crate::run::{run_method, RunRecord, Silent};
use crate::study::Study;
use anyhow::{bail, Context, Result};
use impact_core::method::{MethodConfig, MethodKind, MpmShape, MpmTransfer};
use serde::Serialize;

/// The verdict at one output time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Verdict {
    /// DGMPM's front is narrower and its overshoot smaller.
    Pass,
    /// It is not.
    Fail,
    /// A run stopped before this output time.
    RunStopped,
    /// The reference has no front at this time: not compared.
    NoFront,
}

impl Verdict {
    /// Text of the verdict column.
    pub fn label(self) -> &'static str {
        match self {
            Verdict::Pass => "pass",
            Verdict::Fail => "FAIL",
            Verdict::RunStopped => "FAIL (run stopped)",
            Verdict::NoFront => "skip (no front)",
        }
    }
}

/// One output time of the gate.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CheckRow {
    /// Output time (s).
    pub t: f64,
    /// DGMPM's front width (cells).
    pub dgmpm_front: Option<f64>,
    /// MPM's front width (cells).
    pub mpm_front: Option<f64>,
    /// DGMPM's overshoot (% of the jump).
    pub dgmpm_overshoot: Option<f64>,
    /// MPM's overshoot (% of the jump).
    pub mpm_overshoot: Option<f64>,
    /// The second front (an elastoplastic reference's plastic wave): DGMPM's and MPM's
    /// width (cells) and overshoot (%), when the reference has one.
    pub second: Option<SecondFront>,
    /// The verdict.
    pub verdict: Verdict,
    /// Why the front was not compared (with [`Verdict::NoFront`]).
    pub reason: Option<impact_core::exact::NoFront>,
}

/// The metrics of the second front of a row.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SecondFront {
    /// DGMPM's width (cells).
    pub dgmpm_front: Option<f64>,
    /// MPM's width (cells).
    pub mpm_front: Option<f64>,
    /// DGMPM's overshoot (%).
    pub dgmpm_overshoot: Option<f64>,
    /// MPM's overshoot (%).
    pub mpm_overshoot: Option<f64>,
}

/// The gate's outcome.
#[derive(Debug, Clone)]
pub struct CheckReport {
    /// DGMPM's configuration.
    pub dgmpm: MethodConfig,
    /// MPM's configuration.
    pub mpm: MethodConfig,
    /// DGMPM's run.
    pub dgmpm_record: RunRecord,
    /// MPM's run.
    pub mpm_record: RunRecord,
    /// One row per output time.
    pub rows: Vec<CheckRow>,
    /// Whether the gate passes.
    pub pass: bool,
    /// The reference the fronts and errors are measured against, in words (for a
    /// converged one: method, grid and the second reference of the spread).
    pub reference: String,
}

/// An overshoot (% of the jump) at or below which a front counts as monotone (round-off).
pub const MONOTONE_PCT: f64 = 1e-6;

/// How much better DGMPM must be (`--min-width-ratio`, `--max-overshoot`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Thresholds {
    /// MPM's front width over DGMPM's must exceed this (default 1: strictly narrower).
    pub min_width_ratio: f64,
    /// An overshoot of DGMPM at most this many % passes whatever MPM's is (default none:
    /// DGMPM's must be below MPM's).
    pub max_overshoot: Option<f64>,
}

impl Default for Thresholds {
    fn default() -> Self {
        Self {
            min_width_ratio: 1.0,
            max_overshoot: None,
        }
    }
}

impl Thresholds {
    /// Whether DGMPM's front (`dgmpm` cells) is narrow enough against MPM's.
    fn width_ok(&self, dgmpm: f64, mpm: f64) -> bool {
        dgmpm * self.min_width_ratio < mpm
    }

    /// Whether DGMPM's overshoot (%) passes against MPM's (`strict`: below it, or both
    /// fronts monotone; else not above it). Two monotone fronts (both overshoots at most
    /// [`MONOTONE_PCT`]) tie and pass: against PIC's monotone 25.7-cell front on the bar,
    /// DGMPM's exact 0.8-cell one failed for want of a smaller overshoot than 0 %.
    fn overshoot_ok(&self, dgmpm: f64, mpm: f64, strict: bool) -> bool {
        let within = self.max_overshoot.is_some_and(|cap| dgmpm <= cap);
        let monotone = dgmpm <= MONOTONE_PCT && mpm <= MONOTONE_PCT;
        within
            || if strict {
                dgmpm < mpm || monotone
            } else {
                dgmpm <= mpm
            }
    }
}

/// The pass/fail rule on two runs measured against the same reference: a time whose
/// metrics say the reference has no front there ([`FrontStatus::NoFront`], with its
/// reason) is not compared; an undefined width or overshoot counts as infinitely bad. The
/// gate passes when both runs reached every output time, at least one time was compared,
/// and every compared time passes.
///
/// [`FrontStatus::NoFront`]: impact_core::metrics::FrontStatus::NoFront
pub fn judge(dgmpm: &RunRecord, mpm: &RunRecord, thresholds: &Thresholds) -> (Vec<CheckRow>, bool) {
    use impact_core::metrics::FrontStatus;
    let mut ok = dgmpm.error.is_none() && mpm.error.is_none();
    let worse = |v: Option<f64>| v.unwrap_or(f64::INFINITY);
    let n = dgmpm.times.len().max(mpm.times.len());
    let mut compared = 0;
    let mut rows = Vec::with_capacity(n);
    for k in 0..n {
        let (d, m) = (dgmpm.times.get(k), mpm.times.get(k));
        let t = d.or(m).map_or(0.0, |x| x.t);
        let row = |verdict| CheckRow {
            t,
            dgmpm_front: d.and_then(|x| x.front_width_cells),
            mpm_front: m.and_then(|x| x.front_width_cells),
            dgmpm_overshoot: d.and_then(|x| x.overshoot_pct),
            mpm_overshoot: m.and_then(|x| x.overshoot_pct),
            second: {
                let has = |x: Option<&impact_core::reference::TimeMetrics>| {
                    x.is_some_and(|x| {
                        x.plastic_front_width_cells.is_some() || x.plastic_overshoot_pct.is_some()
                    })
                };
                (has(d) || has(m)).then(|| SecondFront {
                    dgmpm_front: d.and_then(|x| x.plastic_front_width_cells),
                    mpm_front: m.and_then(|x| x.plastic_front_width_cells),
                    dgmpm_overshoot: d.and_then(|x| x.plastic_overshoot_pct),
                    mpm_overshoot: m.and_then(|x| x.plastic_overshoot_pct),
                })
            },
            verdict,
            reason: None,
        };
        let mut r = row(Verdict::NoFront);
        let no_front = |x: &impact_core::reference::TimeMetrics| x.front == FrontStatus::NoFront;
        r.verdict = if d.is_none() || m.is_none() {
            Verdict::RunStopped
        } else if d.is_some_and(no_front) || m.is_some_and(no_front) {
            r.reason = d
                .and_then(|x| x.front_reason)
                .or(m.and_then(|x| x.front_reason));
            Verdict::NoFront
        } else {
            compared += 1;
            // both fronts where the reference has two (width narrower; overshoot not
            // larger, so two monotone fronts with no overshoot tie and pass)
            let second_ok = r.second.is_none_or(|s| {
                thresholds.width_ok(worse(s.dgmpm_front), worse(s.mpm_front))
                    && thresholds.overshoot_ok(
                        worse(s.dgmpm_overshoot),
                        worse(s.mpm_overshoot),
                        false,
                    )
            });
            if thresholds.width_ok(worse(r.dgmpm_front), worse(r.mpm_front))
                && thresholds.overshoot_ok(worse(r.dgmpm_overshoot), worse(r.mpm_overshoot), true)
                && second_ok
            {
                Verdict::Pass
            } else {
                Verdict::Fail
            }
        };
        ok &= matches!(r.verdict, Verdict::Pass | Verdict::NoFront);
        rows.push(r);
    }
    (rows, ok && compared > 0)
}

/// MPM's shape functions, and its transfer where not FLIP (`bspline2 apic`): how
/// reports, tables and `check --against all-mpm` name the MPM compared with.
pub fn mpm_label(config: &MethodConfig) -> String {
    match config.mpm() {
        None => "-".into(),
        Some(o) => match o.transfer_tag() {
            tag if tag.is_empty() => o.shape.name().into(),
            tag => format!("{} {tag}", o.shape.name()),
        },
    }
}

/// Which MPM the gate compares DGMPM with (`--against`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Against {
    /// The scene's MPM configuration.
    SceneMpm,
    /// The scene's MPM with these shape functions.
    Shape(MpmShape),
    /// The scene's MPM with every shape function, and every shape with FLIP, PIC and APIC,
    /// one verdict each.
    AllMpm,
}

impl Against {
    /// Parse `--against`: `all-mpm` or a shape function's name.
    pub fn parse(text: &str) -> Result<Self> {
        if text == "all-mpm" {
            return Ok(Against::AllMpm);
        }
        MpmShape::parse(text).map(Against::Shape).with_context(|| {
            format!(
                "invalid value for `--against`: {text:?} (allowed: \"all-mpm\" or an MPM shape \
                 function: {})",
                MpmShape::allowed()
            )
        })
    }

    /// The MPM configurations compared with, from the scene's. `all-mpm`: every shape with
    /// the scene's transfer, then with FLIP, PIC and APIC (each configuration once; APIC
    /// not with CPDI, which it does not take: `Problem::check_config`).
    fn configs(self, scene_mpm: MethodConfig) -> Vec<MethodConfig> {
        let with = |shape: MpmShape| {
            let mut c = scene_mpm;
            if let Some(o) = c.mpm_mut() {
                o.shape = shape;
            }
            c
        };
        match self {
            Against::SceneMpm => vec![scene_mpm],
            Against::Shape(shape) => vec![with(shape)],
            Against::AllMpm => {
                let mut out: Vec<MethodConfig> = MpmShape::ALL.into_iter().map(with).collect();
                for transfer in [MpmTransfer::Flip, MpmTransfer::Pic, MpmTransfer::Apic] {
                    for shape in MpmShape::ALL {
                        let mut c = with(shape);
                        if let Some(o) = c.mpm_mut() {
                            (o.transfer, o.flip_fraction) = (transfer, None);
                        }
                        let refused = transfer == MpmTransfer::Apic && shape == MpmShape::Cpdi;
                        if !refused && !out.contains(&c) {
                            out.push(c);
                        }
                    }
                }
                out
            }
        }
    }
}

/// The gate's own settings besides the study: which MPM, per-method overrides applied
/// after the study's flags, thresholds, progress bars.
#[derive(Debug, Clone, Copy, Default)]
pub struct CheckOptions {
    /// Which MPM (`--against`).
    pub against: Option<Against>,
    /// DGMPM's Courant number (`--dgmpm-courant`).
    pub dgmpm_courant: Option<f64>,
    /// MPM's Courant number (`--mpm-courant`).
    pub mpm_courant: Option<f64>,
    /// DGMPM's points per cell (`--dgmpm-points-per-cell`).
    pub dgmpm_points_per_cell: Option<usize>,
    /// MPM's points per cell (`--mpm-points-per-cell`).
    pub mpm_points_per_cell: Option<usize>,
    /// Pass/fail thresholds.
    pub thresholds: Thresholds,
    /// Progress bars on stderr.
    pub progress: bool,
}

impl CheckOptions {
    /// Refuse flags that contradict each other or are out of range, naming them.
    pub fn validate(&self, study: &Study) -> Result<()> {
        use impact_core::scene::{check_courant, check_points_per_cell};
        let o = &study.overrides;
        for (flag, own, shared) in [
            ("--dgmpm-courant", self.dgmpm_courant, o.courant),
            ("--mpm-courant", self.mpm_courant, o.courant),
        ] {
            if let Some(c) = own {
                check_courant(flag, c)?;
                if shared.is_some() {
                    bail!("{flag} and --courant both given: --courant sets both methods, {flag} one; give one");
                }
            }
        }
        for (flag, own) in [
            ("--dgmpm-points-per-cell", self.dgmpm_points_per_cell),
            ("--mpm-points-per-cell", self.mpm_points_per_cell),
        ] {
            if let Some(ppc) = own {
                check_points_per_cell(study.dim(), ppc).map_err(|mut e| {
                    e.field = flag.into();
                    e
                })?;
                if o.points_per_cell.is_some() {
                    bail!("{flag} and --points-per-cell both given: give one");
                }
            }
        }
        if let (Some(Against::Shape(_) | Against::AllMpm), Some(shape)) = (self.against, o.shape) {
            bail!(
                "--shape {} and --against both choose MPM's shape functions: give one",
                shape.name()
            );
        }
        let ratio = self.thresholds.min_width_ratio;
        if !(ratio.is_finite() && ratio > 0.0) {
            bail!("invalid value for `--min-width-ratio`: {ratio} (allowed: a positive number; 1 = strictly narrower)");
        }
        if let Some(cap) = self.thresholds.max_overshoot {
            if !(cap.is_finite() && cap >= 0.0) {
                bail!("invalid value for `--max-overshoot`: {cap} (allowed: a percentage >= 0)");
            }
        }
        Ok(())
    }

    fn apply(courant: Option<f64>, ppc: Option<usize>, mut config: MethodConfig) -> MethodConfig {
        config.courant = courant.unwrap_or(config.courant);
        config.points_per_cell = ppc.unwrap_or(config.points_per_cell);
        config
    }
}

/// Run the gate on `study` in dimension `D`: DGMPM once, then each MPM of `against`; one
/// report per MPM.
pub fn check_study<const D: usize>(
    study: &Study,
    options: &CheckOptions,
) -> Result<Vec<CheckReport>> {
    options.validate(study)?;
    study.check_work(&[MethodKind::Dgmpm, MethodKind::Mpm])?;
    // every configuration compared, before the reference (issue 23, item 9)
    let configs = [
        CheckOptions::apply(
            options.dgmpm_courant,
            options.dgmpm_points_per_cell,
            study.config(MethodKind::Dgmpm),
        ),
        CheckOptions::apply(
            options.mpm_courant,
            options.mpm_points_per_cell,
            study.config(MethodKind::Mpm),
        ),
    ];
    study.check_configs(&configs)?;
    study.check_configs(
        &options
            .against
            .unwrap_or(Against::SceneMpm)
            .configs(configs[1]),
    )?;
    let problem = study.problem::<D>()?;
    let [dgmpm, mpm] = configs;
    let mpms = options.against.unwrap_or(Against::SceneMpm).configs(mpm);
    crate::run::check_all_stable(
        study,
        &problem,
        std::iter::once(dgmpm).chain(mpms.iter().copied()),
    )?;
    let reference = crate::reference_for(
        &problem,
        &[MethodKind::Dgmpm, MethodKind::Mpm],
        options.progress,
    )?
    .with_context(|| {
        format!(
            "scene {} has no reference to measure fronts against",
            study.name()
        )
    })?;
    let run = |config: MethodConfig| -> Result<RunRecord> {
        let name = config.kind().name();
        let (record, _) = match options.progress {
            true => {
                let bar = crate::run::progress_bar(name);
                let mut observer = crate::run::Progress::new(bar, problem.t_end);
                run_method(&problem, config, Some(&reference), &mut observer)?
            }
            false => run_method(&problem, config, Some(&reference), &mut Silent)?,
        };
        Ok(record)
    };
    let dgmpm_record = run(dgmpm)?;
    let mut reports = Vec::new();
    for mpm in mpms {
        let mpm_record = run(mpm)?;
        let (rows, pass) = judge(&dgmpm_record, &mpm_record, &options.thresholds);
        reports.push(CheckReport {
            dgmpm,
            mpm,
            dgmpm_record: dgmpm_record.clone(),
            mpm_record,
            rows,
            pass,
            reference: reference.describe(),
        });
    }
    Ok(reports)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The overshoot rule: strictly below MPM's on the first front, not above on the
    /// second; two monotone fronts tie and pass on either; the cap passes whatever MPM's.
    #[test]
    fn overshoot_rule() {
        let t = Thresholds::default();
        assert!(t.overshoot_ok(2.0, 3.0, true));
        assert!(!t.overshoot_ok(3.0, 3.0, true));
        assert!(t.overshoot_ok(3.0, 3.0, false));
        assert!(t.overshoot_ok(0.0, 0.0, true));
        assert!(!t.overshoot_ok(0.1, 0.0, true));
        assert!(!t.overshoot_ok(0.1, 0.0, false));
        let capped = Thresholds {
            max_overshoot: Some(1.0),
            ..Thresholds::default()
        };
        assert!(capped.overshoot_ok(0.5, 0.0, true));
    }
}
