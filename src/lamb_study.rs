//! The ladder of `impact bench lamb` ([`crate::lamb`]): every method on the scene's grid
//! scaled by `2^(k−1)`, `k = 0..levels` (half the scene's cells, the scene's, twice), the
//! metrics per receiver, `lamb.csv`, `lamb.txt`, `lamb_traces.png` (the finest level's
//! traces against the exact ones), `provenance.json` and `scene.toml`.
use crate::lamb::{lamb_load, onset, receivers, relative_l2, steepest, traces, Trace};
use anyhow::{bail, Result};
use impact_core::method::MethodKind;
use impact_core::Problem;
use impact_io::plot::{Axis, LineFigure, Panel, Series};
use std::path::Path;

/// One method at one level at one receiver.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Row {
    /// Method name.
    pub method: String,
    /// Cells along x.
    pub cells_x: usize,
    /// Cell size (m).
    pub h: f64,
    /// Distance of the receiving sample (m).
    pub r: f64,
    /// Relative L2 error of the vertical trace.
    pub l2_vertical: f64,
    /// Relative L2 error of the radial trace.
    pub l2_radial: f64,
    /// P pick, numerical minus exact, in cells (`c_p Δt / h`).
    pub p_cells: Option<f64>,
    /// Rayleigh pick, numerical minus exact, in cells (`c_R Δt / h`).
    pub rayleigh_cells: Option<f64>,
    /// Exact arrivals P, S, R (s).
    pub arrivals: [f64; 3],
}

/// Measure one receiver's traces.
pub fn row(
    method: &str,
    cells_x: usize,
    h: f64,
    trace: &Trace,
    load: &crate::lamb::LambLoad,
) -> Row {
    let level = crate::lamb::p_level(&trace.radial_exact);
    let e = &load.exact;
    let pick = |f: &dyn Fn(&[f64]) -> Option<f64>, speed: f64, vertical: bool| {
        let (numerical, exact) = if vertical {
            (&trace.vertical, &trace.vertical_exact)
        } else {
            (&trace.radial, &trace.radial_exact)
        };
        Some((f(numerical)? - f(exact)?) * speed / h)
    };
    let arrivals = e
        .arrivals(trace.r)
        .map(|a| [a.p, a.s, a.rayleigh])
        .unwrap_or([f64::NAN; 3]);
    Row {
        method: method.to_string(),
        cells_x,
        h,
        r: trace.r,
        l2_vertical: relative_l2(&trace.vertical, &trace.vertical_exact),
        l2_radial: relative_l2(&trace.radial, &trace.radial_exact),
        p_cells: pick(&|u| onset(&trace.t, u, level), e.pressure_speed(), false),
        rayleigh_cells: pick(&|w| steepest(&trace.t, w), e.rayleigh_speed(), true),
        arrivals,
    }
}

/// Run the ladder on `study` and write its files into `out`; returns the table.
pub fn run(
    (study, source): (&crate::Study, &str),
    levels: usize,
    methods: &[MethodKind],
    out: &Path,
) -> Result<String> {
    let clock = crate::provenance::Clock::start();
    if !(1..=4).contains(&levels) {
        bail!(
            "--levels {levels}: allowed: 1 to 4 (grids of half, 1, 2, 4 times the scene's cells)"
        );
    }
    if study.dim() != 3 {
        bail!(
            "invalid value for `dim`: {} (allowed: 3: Lamb's problem is a half-space)",
            study.dim()
        );
    }
    let scene = crate::provenance::resolved_scene(study, methods);
    let mut rows = Vec::new();
    let mut finest: Vec<(String, Vec<Trace>)> = Vec::new();
    for k in 0..levels {
        let mut s = scene.clone();
        if s.time.output_transits.is_some() {
            s.time.output_times = Some(s.schedule_seconds().0);
            s.time.output_transits = None;
        }
        for n in &mut s.domain.cells {
            *n = if k == 0 {
                (*n).div_ceil(2)
            } else {
                *n << (k - 1)
            };
        }
        let problem = Problem::<3>::from_scene(&s)?;
        let load = lamb_load(&problem)?;
        let points = receivers(&s, &load, &problem)?;
        let h = problem.grid.min_spacing();
        for &kind in methods {
            let config = s.method_config(kind);
            crate::guard::check_stable(&problem, config, false)?;
            let recorded = traces(&problem, config, &load, &points)?;
            for trace in &recorded {
                let r = row(kind.name(), s.domain.cells[0], h, trace, &load);
                crate::root_eprintln!(
                    "{:<6} {:>4} cells, r = {:.3} m: L2 w {:.3e}, u_r {:.3e}; P {:+.2} cells, R {:+.2} cells",
                    r.method,
                    r.cells_x,
                    r.r,
                    r.l2_vertical,
                    r.l2_radial,
                    r.p_cells.unwrap_or(f64::NAN),
                    r.rayleigh_cells.unwrap_or(f64::NAN)
                );
                rows.push(r);
            }
            if k + 1 == levels {
                finest.push((kind.name().to_string(), recorded));
            }
        }
    }
    let table = table(&rows);
    let folder = impact_io::folder::OutputFolder::open(out)?;
    let mut csv = String::from(
        "method,cells_x,h,r,l2_vertical,l2_radial,p_cells,rayleigh_cells,t_p,t_s,t_rayleigh\n",
    );
    for r in &rows {
        let opt = |v: Option<f64>| v.map_or("nan".to_string(), |v| format!("{v:.6e}"));
        csv += &format!(
            "{},{},{:.6e},{:.6e},{:.6e},{:.6e},{},{},{:.6e},{:.6e},{:.6e}\n",
            r.method,
            r.cells_x,
            r.h,
            r.r,
            r.l2_vertical,
            r.l2_radial,
            opt(r.p_cells),
            opt(r.rayleigh_cells),
            r.arrivals[0],
            r.arrivals[1],
            r.arrivals[2]
        );
    }
    std::fs::write(folder.path().join("lamb.csv"), csv)?;
    std::fs::write(folder.path().join("lamb.txt"), &table)?;
    impact_io::plot::save(&folder.path().join("lamb_traces.png"), &figure(&finest))?;
    let mut record = crate::provenance::Provenance::new("bench lamb", &clock);
    record.reference = "exact: Pekeris (1955) step response convolved with the load history, \
                        averaged over the patch (impact_core::exact::lamb)"
        .into();
    record.scene = Some(scene.name.clone());
    record.scene_file = Some(crate::provenance::SCENE_FILE.into());
    record.scene_source = Some(source.to_string());
    crate::provenance::write_scene(&folder.path().join(crate::provenance::SCENE_FILE), &scene)?;
    record.write(folder.path(), &clock)?;
    folder.commit("impact bench lamb")?;
    Ok(table)
}

/// Per method and receiver: the errors at each level and their observed orders.
pub fn table(rows: &[Row]) -> String {
    let mut text = format!(
        "{:<6} {:>6} {:>7} {:>10} {:>10} {:>8} {:>8}\n",
        "method", "cells", "r_m", "L2 w", "L2 u_r", "P_cells", "R_cells"
    );
    for r in rows {
        text += &format!(
            "{:<6} {:>6} {:>7.3} {:>10.3e} {:>10.3e} {:>8.2} {:>8.2}\n",
            r.method,
            r.cells_x,
            r.r,
            r.l2_vertical,
            r.l2_radial,
            r.p_cells.unwrap_or(f64::NAN),
            r.rayleigh_cells.unwrap_or(f64::NAN)
        );
    }
    text
}

/// Two panels per receiver, vertical and radial: the traces of every method and the exact
/// one (µm).
pub fn figure(finest: &[(String, Vec<Trace>)]) -> LineFigure {
    let receivers = finest.first().map_or(0, |(_, t)| t.len());
    let micro = 1e6;
    let mut panels = Vec::new();
    for k in 0..receivers {
        for vertical in [true, false] {
            let pick = |tr: &Trace, exact: bool| -> Vec<(f64, f64)> {
                let values = match (vertical, exact) {
                    (true, true) => &tr.vertical_exact,
                    (true, false) => &tr.vertical,
                    (false, true) => &tr.radial_exact,
                    (false, false) => &tr.radial,
                };
                tr.t.iter()
                    .zip(values)
                    .map(|(t, w)| (t * 1e3, w * micro))
                    .collect()
            };
            let mut series = Vec::new();
            if let Some((_, traces)) = finest.first() {
                series.push(Series {
                    label: "exact".into(),
                    points: pick(&traces[k], true),
                    colour: 0,
                    reference: true,
                    marker: None,
                });
            }
            for (m, (name, traces)) in finest.iter().enumerate() {
                series.push(Series {
                    label: crate::plots::display_name(name),
                    points: pick(&traces[k], false),
                    colour: m + 1,
                    reference: false,
                    marker: None,
                });
            }
            let r = finest.first().map_or(0.0, |(_, t)| t[k].r);
            let (what, axis) = if vertical {
                ("vertical", "w (µm, into the body)")
            } else {
                ("radial", "u_r (µm, away from the load)")
            };
            panels.push(Panel {
                title: format!("Lamb: {what} surface displacement at r = {r:.3} m"),
                x: Axis::linear("t (ms)"),
                y: Axis::linear(axis),
                series,
            });
        }
    }
    LineFigure::new(panels, 2, impact_io::plot::PrintWidth::Full, 0.5)
}
