//! `impact check`: the CI gate. DGMPM (the study's DGMPM configuration, method overrides
//! included) and MPM (the scene's configuration) run on the same problem; the gate passes
//! only if, at every output time with a front, DGMPM's front is narrower **and** its
//! overshoot smaller than MPM's ([`judge`]), and neither run stopped.
use crate::run::{run_method, RunRecord, Silent};
use crate::study::Study;
use anyhow::{Context, Result};
use impact_core::method::{MethodConfig, MethodKind, MpmShape};

/// The verdict at one output time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
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
#[derive(Debug, Clone, PartialEq)]
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
}

/// The metrics of the second front of a row.
#[derive(Debug, Clone, Copy, PartialEq)]
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
}

/// The pass/fail rule on two runs: `has_front(t)` tells whether the reference has a front
/// at `t`. An undefined width or overshoot counts as infinitely bad. The gate passes when
/// both runs reached every output time, at least one time was compared, and every
/// compared time passes.
pub fn judge(
    dgmpm: &RunRecord,
    mpm: &RunRecord,
    has_front: impl Fn(f64) -> bool,
) -> (Vec<CheckRow>, bool) {
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
        };
        let mut r = row(Verdict::NoFront);
        r.verdict = if d.is_none() || m.is_none() {
            Verdict::RunStopped
        } else if !has_front(t) {
            Verdict::NoFront
        } else {
            compared += 1;
            // both fronts where the reference has two (width narrower; overshoot not
            // larger, so two monotone fronts with no overshoot tie and pass)
            let second_ok = r.second.is_none_or(|s| {
                worse(s.dgmpm_front) < worse(s.mpm_front)
                    && worse(s.dgmpm_overshoot) <= worse(s.mpm_overshoot)
            });
            if worse(r.dgmpm_front) < worse(r.mpm_front)
                && worse(r.dgmpm_overshoot) < worse(r.mpm_overshoot)
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

/// Which MPM the gate compares DGMPM with (`--against`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Against {
    /// The scene's MPM configuration.
    SceneMpm,
    /// The scene's MPM with these shape functions.
    Shape(MpmShape),
    /// The scene's MPM with every shape function, one verdict each.
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

    /// The MPM configurations compared with, from the scene's.
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
            Against::AllMpm => MpmShape::ALL.into_iter().map(with).collect(),
        }
    }
}

/// Run the gate on `study` in dimension `D`: DGMPM once, then each MPM of `against`; one
/// report per MPM.
pub fn check_study<const D: usize>(study: &Study, against: Against) -> Result<Vec<CheckReport>> {
    study.check_work(&[MethodKind::Dgmpm, MethodKind::Mpm])?;
    let problem = study.problem::<D>()?;
    let reference = crate::reference_for(&problem, false)?.with_context(|| {
        format!(
            "scene {} has no reference to measure fronts against",
            study.name()
        )
    })?;
    let dgmpm = study.config(MethodKind::Dgmpm);
    let (dgmpm_record, _) = run_method(&problem, dgmpm, Some(&reference), &mut Silent)?;
    let mut reports = Vec::new();
    for mpm in against.configs(study.scene_config(MethodKind::Mpm)) {
        let (mpm_record, _) = run_method(&problem, mpm, Some(&reference), &mut Silent)?;
        let (rows, pass) = judge(&dgmpm_record, &mpm_record, |t| reference.front(t).is_some());
        reports.push(CheckReport {
            dgmpm,
            mpm,
            dgmpm_record: dgmpm_record.clone(),
            mpm_record,
            rows,
            pass,
        });
    }
    Ok(reports)
}
