//! The run's figures: `stress.png` (profiles against the reference), `svk.png` (the paper's
//! Fig. 6) and `stress_map.png` (2D colour maps).
use crate::output::{CellMap, Profiles};
use impact_core::reference::Reference;
use impact_core::{Grid, StressMeasure, Vector};
use impact_io::plot::{colour_maps, line_panels, MapPanel, Panel, Series};
use std::path::Path;

/// The reference's σ_xx along x at `t` (averaged over cells of `length/1000` and, in 2D,
/// over the bottom band `[0, band]`), labelled `exact` or `reference`.
fn reference_series(r: &Reference, t: f64, length: f64, band: f64) -> Series {
    let n = 1000;
    let dx = length / n as f64;
    let points = (0..n)
        .map(|i| {
            let x = (i as f64 + 0.5) * dx;
            let lo = Vector::<2>::new(x - 0.5 * dx, 0.0);
            let hi = Vector::<2>::new(x + 0.5 * dx, band);
            (x, r.averages(&lo, &hi, t).0)
        })
        .filter(|p| p.1.is_finite())
        .collect();
    let label = match r {
        Reference::Bar(_)
        | Reference::SvkBar(_)
        | Reference::Standing(_)
        | Reference::Elastoplastic(_) => "exact",
        Reference::Converged(_) => "reference",
    };
    Series {
        label: label.into(),
        points,
        colour: 0,
        reference: true,
    }
}

/// Every method's profile at output time `t`.
fn method_series(writers: &[(String, Profiles)], t: f64) -> Vec<Series> {
    writers
        .iter()
        .enumerate()
        .filter_map(|(m, (name, profiles))| {
            profiles
                .iter()
                .find(|p| (p.0 - t).abs() <= 1e-12 * t.max(1e-30))
                .map(|(_, pts)| Series {
                    label: name.clone(),
                    points: pts.clone(),
                    colour: m + 1,
                    reference: false,
                })
        })
        .collect()
}

/// `stress.png`: one panel per output time (at most three), the reference and every
/// method's σ_xx along x (the bottom row in 2D: the reference averaged over `band`).
pub fn stress_plot(
    path: &Path,
    scene: &str,
    measure: StressMeasure,
    writers: &[(String, Profiles)],
    reference: Option<&Reference>,
    length: f64,
    band: f64,
) -> anyhow::Result<()> {
    let times: Vec<f64> = writers
        .iter()
        .map(|w| w.1.iter().map(|p| p.0).collect::<Vec<_>>())
        .max_by_key(|t| t.len())
        .unwrap_or_default();
    let picks: Vec<usize> = match times.len() {
        0..=3 => (0..times.len()).collect(),
        n => vec![0, n / 2, n - 1],
    };
    let mut panels = Vec::new();
    for &k in &picks {
        let t = times[k];
        let mut series: Vec<Series> = reference
            .map(|r| reference_series(r, t, length, band))
            .into_iter()
            .collect();
        series.extend(method_series(writers, t));
        panels.push(Panel {
            title: format!("{scene}: t = {:.4} ms", t * 1e3),
            series,
            y_label: None,
        });
    }
    let y_label = if band > 0.0 {
        format!("{} along the bottom (Pa)", measure.xx_label())
    } else {
        format!("{} (Pa)", measure.xx_label())
    };
    line_panels(path, &panels, "x (m)", &y_label)?;
    Ok(())
}

/// `svk.png` (large strain, 1D; the paper's Fig. 6): the current positions of DGMPM's
/// points at each output time (top) and the first Piola–Kirchhoff stress of every method
/// against the exact solution at the last output time (bottom).
pub fn svk_plot(
    path: &Path,
    scene: &str,
    positions: &[(f64, Vec<f64>)],
    writers: &[(String, Profiles)],
    reference: Option<&Reference>,
    length: f64,
) -> anyhow::Result<()> {
    let mut top = Vec::new();
    for (k, (t, xs)) in positions.iter().enumerate() {
        top.push(Series {
            label: format!("t = {:.4} ms", t * 1e3),
            points: xs.iter().map(|&x| (x, t * 1e3)).collect(),
            colour: k + 1,
            reference: false,
        });
    }
    let last = positions.last().map_or(0.0, |p| p.0);
    let mut bottom: Vec<Series> = reference
        .map(|r| reference_series(r, last, length, 0.0))
        .into_iter()
        .collect();
    bottom.extend(method_series(writers, last));
    let panels = [
        Panel {
            title: format!("{scene}: DGMPM point positions (time in ms on the vertical axis)"),
            series: top,
            y_label: Some("t (ms)".into()),
        },
        Panel {
            title: format!(
                "{scene}: first Piola-Kirchhoff stress at t = {:.4} ms",
                last * 1e3
            ),
            series: bottom,
            y_label: Some("P_xx (Pa)".into()),
        },
    ];
    line_panels(path, &panels, "x (m)", "P_xx (Pa)")?;
    Ok(())
}

/// `stress_map.png`: σ_xx per grid cell of each method at its last output time.
pub fn stress_map(path: &Path, grid: &Grid<2>, maps: &[(String, CellMap)]) -> anyhow::Result<()> {
    let upper = grid.upper();
    let mut range: f64 = 0.0;
    let mut panels = Vec::new();
    for (name, map) in maps {
        let Some((t, values)) = map else { continue };
        range = values
            .iter()
            .filter(|v| v.is_finite())
            .fold(range, |m, v| m.max(v.abs()));
        panels.push(MapPanel {
            title: format!("{name}: t = {:.4} ms", t * 1e3),
            cells: grid.cells,
            extent: [grid.origin[0], upper[0], grid.origin[1], upper[1]],
            values: values.clone(),
        });
    }
    if panels.is_empty() {
        return Ok(());
    }
    colour_maps(path, &panels, range.max(1e-300), "Cauchy stress σ_xx (Pa)")?;
    Ok(())
}
