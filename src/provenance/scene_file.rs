//! The resolved scene of a run (`scene.toml`: [`resolved_scene`], [`write_scene`]) and
//! what `impact run --from <folder>` reads back from it ([`replay_study`]).
use super::{MethodOptionsRecord, Provenance, RunFlags, GIT_COMMIT, PROVENANCE_FILE, SCENE_FILE};
use crate::study::{Overrides, Study};
use anyhow::{bail, Context, Result};
use impact_core::method::{EdgeKind, LayoutKind, MethodKind};
use impact_core::Scene;
use std::path::Path;

/// The scene of `study` with every default and override written out: cells, load and
/// schedule overrides (already in `study.scene`), `--points-per-cell` in
/// `domain.points_per_cell`, the point layout, and each method's section holding the
/// configuration its run uses (`kinds`; the sections of the other methods keep the
/// scene's own configuration, which the scene validated).
pub fn resolved_scene(study: &Study, kinds: &[MethodKind]) -> Scene {
    let mut scene = study.scene.clone();
    let config = |kind: MethodKind| match kinds.contains(&kind) {
        true => study.config(kind),
        false => study.scene_config(kind),
    };
    let dgmpm = config(MethodKind::Dgmpm);
    if kinds.iter().any(|k| *k != MethodKind::Fem) {
        scene.domain.points_per_cell = study
            .overrides
            .points_per_cell
            .unwrap_or(scene.domain.points_per_cell);
    }
    scene.domain.layout.get_or_insert(LayoutKind::Centred);
    // edges not given are free: written out
    let free = impact_core::scene::EdgeSpec {
        kind: EdgeKind::Free,
        value: None,
        from: None,
        to: None,
        cover: None,
        centre: None,
        radius: None,
        history: None,
        duration: None,
    };
    for axis in 0..scene.dim {
        for side in 0..2 {
            let slot = scene.boundary.side_mut(axis, side);
            if slot.is_none() {
                *slot = Some(free.clone());
            }
        }
    }
    if let Some(o) = dgmpm.dgmpm() {
        let s = &mut scene.dgmpm;
        s.courant = dgmpm.courant;
        s.integrator = Some(o.integrator);
        s.update = Some(o.update);
        s.riemann = Some(o.riemann);
        s.order = Some(o.order);
        s.limiter = o.limiter;
        if scene.dim > 1 {
            s.flux = Some(o.flux);
            s.edges = Some(o.edges);
        }
    }
    let mpm = config(MethodKind::Mpm);
    if let Some(o) = mpm.mpm() {
        let s = &mut scene.mpm;
        s.courant = mpm.courant;
        s.stress_update = Some(o.stress_update);
        s.frame = Some(o.frame);
        s.shape = Some(o.shape);
        s.transfer = Some(o.transfer);
        s.flip_fraction = o.flip_fraction;
    }
    scene.fem.courant = config(MethodKind::Fem).courant;
    crate::reference_setup::state_in(study, kinds, &mut scene);
    scene
}

/// Write `scene` as TOML to `path` (atomically).
pub fn write_scene(path: &Path, scene: &Scene) -> Result<()> {
    let text = toml::to_string(scene).context("serialising the resolved scene")?;
    let header = format!(
        "# The resolved scene (every default and command-line override written out), by impact \
         {} ({GIT_COMMIT}).\n# `impact run <this file>` runs it; `impact run --from <folder>` repeats the \
         run of an `impact run` folder.\n",
        env!("CARGO_PKG_VERSION")
    );
    impact_io::write_atomic(path, |w| {
        w.write_all(header.as_bytes())?;
        w.write_all(text.as_bytes())
    })?;
    Ok(())
}

/// What `impact run --from <folder>` runs: the study of the folder's `scene.toml` (no
/// overrides: it holds them) and the recorded run flags; refused when the record's options
/// differ from the scene's (a folder edited by hand).
pub fn replay_study(folder: &Path) -> Result<(Study, Provenance, RunFlags)> {
    let record = Provenance::read(folder)?;
    let Some(flags) = record.run.clone() else {
        bail!(
            "--from {}: the folder was written by `impact {}`, not `impact run` (allowed: an \
             output folder of `impact run`)",
            folder.display(),
            record.command
        );
    };
    let path = folder.join(SCENE_FILE);
    let scene = Scene::parse_file(&path)?;
    let study = Study::new(scene, Overrides::default())?;
    for entry in &record.runs {
        let now = MethodOptionsRecord::of(&study.config(entry.options.method), study.dim());
        let same_courant =
            (now.courant - entry.options.courant).abs() <= 1e-12 * entry.options.courant.abs();
        if !same_courant || now.points_per_cell != entry.options.points_per_cell {
            bail!(
                "--from {}: {} and {PROVENANCE_FILE} disagree on {} (Courant {} / {}, points \
                 per cell {} / {}): the folder was edited",
                folder.display(),
                SCENE_FILE,
                entry.options.method,
                now.courant,
                entry.options.courant,
                now.points_per_cell,
                entry.options.points_per_cell
            );
        }
        let mut recorded = entry.options.clone();
        recorded.courant = now.courant;
        if now != recorded {
            bail!(
                "--from {}: {SCENE_FILE} and {PROVENANCE_FILE} disagree on the options of {}: \
                 the folder was edited",
                folder.display(),
                entry.options.method
            );
        }
    }
    Ok((study, record, flags))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The resolved scene of every shipped scene, with and without overrides, reads back as
    /// the same scene (every float exact) and builds the same configurations: a study run
    /// from its `scene.toml` is the study that wrote it.
    #[test]
    fn resolved_scenes_round_trip_exactly() {
        let overrides = Overrides {
            cells: Some(37),
            courant: Some(0.3),
            points_per_cell: Some(4),
            ..Overrides::default()
        };
        for name in impact_core::scene::BUILTIN {
            // several points per cell: 2 per axis (4 in 1D and 2D, 8 in 3D)
            let mut several = overrides.clone();
            if Scene::builtin(name).unwrap().dim == 3 {
                several.points_per_cell = Some(8);
            }
            for o in [Overrides::default(), several] {
                let study = Study::load(name, o).unwrap();
                let scene = resolved_scene(&study, &MethodKind::ALL);
                let text = toml::to_string(&scene).unwrap();
                let back = Scene::from_toml(&text, "scene.toml").unwrap();
                assert_eq!(back, scene, "{name}");
                let again = Study::new(back, Overrides::default()).unwrap();
                for kind in MethodKind::ALL {
                    assert_eq!(again.config(kind), study.config(kind), "{name} {kind}");
                }
                assert_eq!(
                    again.scene.schedule_seconds(),
                    study.scene.schedule_seconds()
                );
            }
        }
    }
}
