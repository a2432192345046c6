//! `impact stability`: the sweep of every configuration's critical Courant number on the
//! default sweep scenes or on one scene, its table lines, and the output folder
//! (stability.csv, stability.png, the swept scenes, provenance.json). The CLI parses the
//! flags into [`StabilityOptions`]; the Python package builds them from its arguments.
use crate::stability::{sweep, StabilityRow};
use crate::{Overrides, Study};
use anyhow::{bail, Result};
use impact_core::method::LayoutKind;
use impact_core::Scene;
use std::path::PathBuf;

/// What `impact stability` sweeps, with the CLI's flags' meaning.
#[derive(Debug, Clone)]
pub struct StabilityOptions {
    /// `--scene`: a shipped name or a scene file (default: the sweep scenes).
    pub scene: Option<String>,
    /// `--dim`: dimensions to sweep (default 1,2; with a scene, the scene's).
    pub dim: Option<Vec<usize>>,
    /// Scene and method flags the sweep does not vary.
    pub overrides: Overrides,
    /// `--steps-1d`: steps of each perturbed run in 1D.
    pub steps_1d: usize,
    /// `--steps-2d`: steps of each perturbed run in 2D and 3D.
    pub steps_2d: usize,
    /// `--out`: output folder.
    pub out: PathBuf,
    /// `--layout`: where the points sit in a cell.
    pub layout: Option<LayoutKind>,
    /// `--shift`: shift of every point in sub-cell widths.
    pub shift: Option<f64>,
    /// `--positions`: 1D local positions in (0, 1) of the points of a cell.
    pub positions: Option<Vec<f64>>,
}

impl StabilityOptions {
    /// Put the layout flags on a scene (checked with the scene's validation).
    fn layout_onto(&self, scene: &mut Scene) -> Result<()> {
        // no layout flag: the scene's layout (centred for the default sweep scenes)
        if self.layout.is_some() || self.shift.is_some() || self.positions.is_some() {
            scene.domain.layout = Some(self.layout.unwrap_or(LayoutKind::Centred));
            scene.domain.shift = self.shift;
            scene.domain.positions = None;
        }
        if let Some(list) = &self.positions {
            if scene.dim != 1 {
                bail!("--positions: 1D only (one local coordinate per point); run with --dim 1");
            }
            scene.domain.points_per_cell = list.len();
            scene.domain.positions = Some(list.iter().map(|u| vec![*u]).collect());
        } else if self.layout == Some(LayoutKind::Given) {
            bail!("--layout given needs --positions (e.g. --positions 0.2,0.7)");
        }
        scene
            .validate()
            .map_err(|e| anyhow::anyhow!("{e} (from --layout, --shift or --positions)"))
    }
}

/// The table's header line.
pub fn header() -> String {
    format!(
        "{:>3} {:<6} {:>4} {:>8} {:>5} {:>9} {:>10} {:>12} {:>9}",
        "dim", "method", "ppc", "integr.", "flux", "update", "empirical", "von_neumann", "monotone"
    )
}

/// The table's line of one row.
pub fn line(r: &StabilityRow) -> String {
    format!(
        "{:>3} {:<6} {:>4} {:>8} {:>5} {:>9} {:>10.4} {:>12} {:>9}",
        r.dim,
        r.method,
        r.points_per_cell,
        r.integrator,
        r.flux,
        r.update,
        r.empirical,
        r.von_neumann.map_or("-".to_string(), |v| format!("{v:.4}")),
        r.monotone.map_or("-".to_string(), |v| format!("{v:.4}"))
    )
}

/// Run the sweep and write its folder; `say` receives the table (header, then each row as
/// it is measured) and the notes of skipped configurations. Returns the rows.
pub fn run(options: &StabilityOptions, mut say: impl FnMut(&str)) -> Result<Vec<StabilityRow>> {
    let clock = crate::provenance::Clock::start();
    for (flag, steps, most) in [
        ("--steps-1d", options.steps_1d, 1_000_000),
        ("--steps-2d", options.steps_2d, 100_000),
    ] {
        if steps == 0 || steps > most {
            bail!("invalid value for `{flag}`: {steps} (allowed: 1 to {most} steps per perturbed run)");
        }
    }
    let mut scenes = crate::ladder::sweep_scenes(
        options.scene.as_deref(),
        options.dim.as_deref(),
        &options.overrides,
    )?;
    for scene in scenes.iter_mut() {
        if options.positions.is_some() && scene.dim != 1 && options.scene.is_none() {
            continue;
        }
        options.layout_onto(scene)?;
    }
    let folder = impact_io::folder::OutputFolder::open(&options.out)?;
    say(&header());
    let mut rows = Vec::new();
    let mut record = crate::provenance::Provenance::new("stability", &clock);
    record.reference = "none: the sweep measures stability limits, not errors".into();
    for scene in &scenes {
        let study = Study::new(scene.clone(), Overrides::default())?;
        let skipped = match scene.dim {
            1 => crate::stability::refused::<1>(&study.problem::<1>()?, scene),
            2 => crate::stability::refused::<2>(&study.problem::<2>()?, scene),
            _ => crate::stability::refused::<3>(&study.problem::<3>()?, scene),
        };
        for note in &skipped {
            say(&format!("skipped: {note}"));
        }
        record.notes.extend(skipped);
        let print = |r: &StabilityRow| say(&line(r));
        let (steps_1d, steps_2d) = (options.steps_1d, options.steps_2d);
        match scene.dim {
            1 => rows.extend(sweep(&study.problem::<1>()?, scene, steps_1d, print)),
            2 => rows.extend(sweep(&study.problem::<2>()?, scene, steps_2d, print)),
            _ => rows.extend(sweep(&study.problem::<3>()?, scene, steps_2d, print)),
        }
    }
    crate::interrupt::check()?;
    crate::stability::write(folder.path(), &rows)?;
    // the swept scenes: scene.toml (one scene) or scene-<d>d.toml (the default sweep)
    for scene in &scenes {
        let file = match scenes.len() {
            1 => crate::provenance::SCENE_FILE.to_string(),
            _ => format!("scene-{}d.toml", scene.dim),
        };
        crate::provenance::write_scene(&folder.path().join(&file), scene)?;
        record.scene = Some(scene.name.clone());
        record.scene_file = Some(file);
    }
    if scenes.len() > 1 {
        record.scene = None;
        record.scene_file = None;
        record
            .notes
            .push("swept scenes: scene-1d.toml and scene-2d.toml".into());
    }
    record.scene_source = options.scene.clone();
    record.overrides = options.overrides.given();
    record.configurations = scenes
        .iter()
        .flat_map(|scene| {
            match scene.dim {
                1 => crate::stability::configurations::<1>(scene),
                2 => crate::stability::configurations::<2>(scene),
                _ => crate::stability::configurations::<3>(scene),
            }
            .into_iter()
            .map(|c| crate::provenance::MethodOptionsRecord::of(&c, scene.dim))
        })
        .collect();
    record.write(folder.path(), &clock)?;
    crate::interrupt::check()?;
    folder.commit(concat!("impact ", env!("CARGO_PKG_VERSION")))?;
    Ok(rows)
}
