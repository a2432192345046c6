//! The figures no paper has: work-precision, the stability map, DGMPM against every MPM
//! shape function, and the elastoplastic fronts.
use super::paper::{three_methods, Shipped};
use super::{Entry, Target};
use anyhow::{Context, Result};
use impact_core::method::{MethodConfig, MethodKind, MpmShape, RiemannSolver, TransverseFlux};
use impact_core::{Problem, Scene};

/// Work-precision ladders of the four scenes, one image each. Reduced levels by default
/// (bar and svk-bar 6, to 4,800 cells; plate-wave 4, to 128×96; plate 3, to 64×48); `--full`: those
/// of `impact bench work-precision` (9, 9, 7, 6). Runs `impact run` child processes like
/// the bench (timings from separate processes), so it needs the `impact` executable.
pub fn work_precision(target: &Target) -> Result<Entry> {
    let exe = std::env::current_exe().context("locating the impact executable")?;
    let scratch = std::env::temp_dir().join(format!("impact-figures-{}", std::process::id()));
    impact_io::create_dir(&scratch)?;
    let mut images = Vec::new();
    let mut lines = Vec::new();
    let mut levels_used = Vec::new();
    for (scene, reduced, full) in [
        ("bar", 6, 9),
        ("svk-bar", 6, 9),
        ("plate-wave", 4, 7),
        ("plate", 3, 6),
    ] {
        let levels = if target.full { full } else { reduced };
        levels_used.push(format!("{scene} {levels}"));
        let out = scratch.join(format!("work-precision-{scene}"));
        let study = crate::Study::load(scene, crate::Overrides::default())?;
        let (points, sentence) =
            crate::work_precision::run(&exe, (&study, scene), levels, &out, |_| {}, |_| {})?;
        let stem = format!("work_precision_{}", scene.replace('-', "_"));
        images.push(target.save(&stem, crate::work_precision::figure(scene, &points))?);
        lines.push(sentence);
    }
    let _ = std::fs::remove_dir_all(&scratch);
    lines.insert(0, format!("levels: {}", levels_used.join(", ")));
    Ok(Entry {
        name: "work-precision".into(),
        title: "Work-precision: relative L1 error against stepping time".into(),
        images,
        command: format!(
            "{}   # the ladders: impact bench work-precision --scene bar|svk-bar|plate-wave|plate",
            target.command
        ),
        numbers: lines,
        seconds: 0.0,
    })
}

/// The stability map: every configuration's critical Courant numbers. Perturbed runs of
/// 2,000 steps in 1D and 300 in 2D by default; `--full`: 20,000 and 3,000 (those of
/// `impact stability`).
pub fn stability(target: &Target) -> Result<Entry> {
    use crate::stability::{sweep, sweep_scene};
    let (steps_1d, steps_2d) = if target.full {
        (20_000, 3_000)
    } else {
        (2_000, 300)
    };
    let (bar, plate) = (sweep_scene(1), sweep_scene(2));
    let mut rows = sweep(&Problem::<1>::from_scene(&bar)?, &bar, steps_1d, |_| {});
    rows.extend(sweep(
        &Problem::<2>::from_scene(&plate)?,
        &plate,
        steps_2d,
        |_| {},
    ));
    let image = target.save("stability", crate::stability::figure(&rows))?;
    let mut lines = vec![format!(
        "perturbed runs of {steps_1d} steps (1D) and {steps_2d} (2D); the full sweep: impact stability"
    )];
    for r in &rows {
        lines.push(format!(
            "{}: empirical {:.3}, von Neumann {}, monotone {}",
            r.label(),
            r.empirical,
            r.von_neumann.map_or("-".into(), |v| format!("{v:.3}")),
            r.monotone.map_or("-".into(), |v| format!("{v:.3}"))
        ));
    }
    Ok(Entry {
        name: "stability".into(),
        title: "Stability map: critical Courant numbers".into(),
        images: vec![image],
        command: target.command.clone(),
        numbers: lines,
        seconds: 0.0,
    })
}

/// DGMPM against MPM with every shape function on the bar (the scene's MPM otherwise).
pub fn mpm_variants(target: &Target) -> Result<Entry> {
    let bar = Shipped::<1>::run("bar", target.progress, |scene| {
        let mut configs = vec![("dgmpm".to_string(), scene.method_config(MethodKind::Dgmpm))];
        for shape in MpmShape::ALL {
            let mut config = scene.method_config(MethodKind::Mpm);
            if let Some(o) = config.mpm_mut() {
                o.shape = shape;
            }
            configs.push((format!("mpm {}", shape.name()), config));
        }
        configs
    })?;
    let mut numbers = bar.numbers();
    let mut merged = bar;
    let notes = merge_coincident(&mut merged.collected);
    let mut figure = merged.profile_figure();
    if !notes.is_empty() {
        figure.note = Some(notes.join(" "));
    }
    numbers.extend(notes);
    let image = target.save("mpm_variants_bar", figure)?;
    Ok(Entry {
        name: "mpm-variants".into(),
        title: "DGMPM against MPM with every shape function (bar)".into(),
        images: vec![image],
        command: format!(
            "{}   # the gate: impact check bar --against all-mpm",
            target.command
        ),
        numbers,
        seconds: 0.0,
    })
}

/// Runs whose profiles coincide at every output time (to 1e-12 of the largest stress) are
/// drawn once: the first keeps its colour, its legend names them all
/// (`MPM linear = gimp = cpdi (C 0.5, 1 ppc)`), and the others are removed. Returns one
/// sentence per merged group, with the largest difference found.
fn merge_coincident(runs: &mut Vec<crate::plots::Collected>) -> Vec<String> {
    let scale = runs
        .iter()
        .flat_map(|r| {
            r.profiles
                .iter()
                .flat_map(|(_, p)| p.iter().map(|q| q.1.abs()))
        })
        .fold(0.0f64, f64::max);
    let distance = |a: &crate::plots::Collected, b: &crate::plots::Collected| -> Option<f64> {
        if a.profiles.len() != b.profiles.len() {
            return None;
        }
        let mut largest = 0.0f64;
        for ((ta, pa), (tb, pb)) in a.profiles.iter().zip(&b.profiles) {
            if ta != tb || pa.len() != pb.len() {
                return None;
            }
            for (p, q) in pa.iter().zip(pb) {
                largest = largest.max((p.1 - q.1).abs()).max((p.0 - q.0).abs());
            }
        }
        (largest <= 1e-12 * scale).then_some(largest)
    };
    let mut notes = Vec::new();
    let mut k = 0;
    while k < runs.len() {
        let mut same = Vec::new();
        let mut largest = 0.0f64;
        for j in k + 1..runs.len() {
            if let Some(d) = distance(&runs[k], &runs[j]) {
                same.push(j);
                largest = largest.max(d);
            }
        }
        if !same.is_empty() {
            let variant = |name: &str| name.split_once(' ').map_or(name, |s| s.1).to_string();
            let mut names = vec![variant(&runs[k].name)];
            names.extend(same.iter().map(|&j| variant(&runs[j].name)));
            let method = crate::plots::display_name(runs[k].name.split(' ').next().unwrap_or(""));
            let suffix = runs[k]
                .legend
                .find(" (C ")
                .map_or(String::new(), |i| runs[k].legend[i..].to_string());
            runs[k].legend = format!("{method} {}{suffix}", names.join(" = "));
            let (last, rest) = names.split_last().expect("two or more names");
            notes.push(format!(
                "{method} {} and {last} coincide at every output time (largest difference \
                 {:.1e} MPa): drawn once.",
                rest.join(", "),
                largest * 1e-6
            ));
            for &j in same.iter().rev() {
                runs.remove(j);
            }
        }
        k += 1;
    }
    notes
}

/// The plastic wave's width and overshoot of each run, one line each.
fn plastic_numbers<const D: usize>(runs: &Shipped<D>) -> Vec<String> {
    let fmt = |v: Option<f64>| v.map_or("-".into(), |x| format!("{x:.2}"));
    let list = |values: Vec<String>| values.join(" / ");
    runs.collected
        .iter()
        .zip(&runs.records)
        .map(|(c, r)| {
            format!(
                "{}: plastic wave width {} cells, overshoot {} %",
                c.name,
                list(
                    r.times
                        .iter()
                        .map(|t| fmt(t.plastic_front_width_cells))
                        .collect()
                ),
                list(
                    r.times
                        .iter()
                        .map(|t| fmt(t.plastic_overshoot_pct))
                        .collect()
                )
            )
        })
        .collect()
}

/// DGMPM with the elastic and the elastoplastic Riemann solvers (in 2D the latter with
/// DCU at Courant 0.6, since CTU is refused with it), MPM and FEM on `scene`.
fn elastoplastic_configs(scene: &Scene) -> Vec<(String, MethodConfig)> {
    let mut solver = scene.method_config(MethodKind::Dgmpm);
    let mut label = "dgmpm elastoplastic solver".to_string();
    if let Some(o) = solver.dgmpm_mut() {
        o.riemann = RiemannSolver::Elastoplastic;
        if scene.dim == 2 {
            o.flux = TransverseFlux::DonorCell;
            solver.courant = 0.6;
            label.push_str(", dcu");
        }
    }
    let mut configs = three_methods(scene);
    configs.insert(1, (label, solver));
    configs
}

/// One elastoplastic scene's profile image, its numbers appended to `lines`.
fn elastoplastic_scene<const D: usize>(
    target: &Target,
    name: &'static str,
    lines: &mut Vec<String>,
) -> Result<super::Image> {
    let runs = Shipped::<D>::run(name, target.progress, elastoplastic_configs)?;
    let stem = format!("elastoplastic_{}", name.replace('-', "_"));
    lines.push(format!("{name}:"));
    lines.extend(runs.numbers());
    lines.extend(plastic_numbers(&runs));
    target.save(&stem, runs.profile_figure())
}

/// The elastoplastic fronts of ep-bar and ep-plate-wave ([`elastoplastic_configs`] and
/// the exact two-wave solution).
pub fn elastoplastic(target: &Target) -> Result<Entry> {
    let mut lines = Vec::new();
    let images = vec![
        elastoplastic_scene::<1>(target, "ep-bar", &mut lines)?,
        elastoplastic_scene::<2>(target, "ep-plate-wave", &mut lines)?,
    ];
    Ok(Entry {
        name: "elastoplastic".into(),
        title: "Elastoplastic fronts: precursor and plastic wave (ep-bar, ep-plate-wave)".into(),
        images,
        command: format!(
            "{}   # the gate: impact check ep-bar; impact check ep-plate-wave",
            target.command
        ),
        numbers: lines,
        seconds: 0.0,
    })
}
