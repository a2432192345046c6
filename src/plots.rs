//! The run's figures, built from the profiles and maps kept by [`crate::output::FileWriter`]
//! and drawn by `impact_io::plot`: profiles of σₓₓ (or Πₓₓ) against the reference
//! ([`profile_figure`], `stress.png`; the paper's Fig. 3 and Fig. 5's bottom row), the
//! large-strain bar ([`svk_figure`], `svk.png`; the paper's Fig. 6) and colour maps of
//! every method and the reference at each output time ([`map_figure`],
//! `stress_map.png`; the paper's Fig. 5). Stresses are plotted in MPa, positions in m,
//! displacements in mm, times in ms.
use crate::output::{CellMaps, Profiles};
use impact_core::line::MeasureLine;
use impact_core::reference::Reference;
use impact_core::{Grid, StressMeasure, Vector};
use impact_io::plot::{
    robust_range, Axis, LineFigure, MapFigure, MapPanel, Panel, PrintWidth, Series,
};

/// What one method's run kept for the figures.
#[derive(Debug, Clone, Default)]
pub struct Collected {
    /// Method name (`dgmpm`, `mpm`, `fem`, or a variant's label).
    pub name: String,
    /// The legend's label: the method as the papers name it, its variant, Courant number
    /// and points per cell ([`legend_label`]), e.g. `DGMPM (C 1.0, 1 ppc)`.
    pub legend: String,
    /// Bottom-row profiles `(t, [(X, σ_xx)])` at each output time.
    pub profiles: Profiles,
    /// Current x of the same samples at each output time.
    pub positions: Vec<(f64, Vec<f64>)>,
    /// σ_xx per grid cell at each output time.
    pub maps: CellMaps,
}

/// Pa to MPa.
pub const MPA: f64 = 1e-6;

/// A run's name as the figures print it: the method upper-case (DGMPM, MPM, FEM), a
/// variant's words after it (`mpm gimp` → `MPM gimp`).
pub fn display_name(name: &str) -> String {
    let (method, rest) = name.split_once(' ').unwrap_or((name, ""));
    let method = match method {
        "dgmpm" | "mpm" | "fem" => method.to_uppercase(),
        other => other.to_string(),
    };
    if rest.is_empty() {
        method
    } else {
        format!("{method} {rest}")
    }
}

/// The Courant number with its decimals (`1.0`, `0.5`, `0.95`).
pub fn courant_text(courant: f64) -> String {
    let tenths = courant * 10.0;
    if (tenths - tenths.round()).abs() < 1e-9 {
        format!("{courant:.1}")
    } else {
        format!("{courant}")
    }
}

/// The legend label of run `name` with `config`: `DGMPM (C 1.0, 1 ppc)`.
pub fn legend_label(name: &str, config: &impact_core::method::MethodConfig) -> String {
    format!(
        "{} (C {}, {} ppc)",
        display_name(name),
        courant_text(config.courant),
        config.points_per_cell
    )
}

/// The palette index of each run: DGMPM blue, MPM vermillion, FEM green wherever they
/// appear; other labels (variants) the free colours after them, in order.
pub fn method_colours(runs: &[Collected]) -> Vec<usize> {
    let fixed = |name: &str| match name {
        "dgmpm" => Some(1),
        "mpm" => Some(2),
        "fem" => Some(3),
        _ => None,
    };
    let taken: Vec<usize> = runs.iter().filter_map(|r| fixed(&r.name)).collect();
    let mut free = (1..).filter(move |c| !taken.contains(c));
    runs.iter()
        .map(|r| fixed(&r.name).unwrap_or_else(|| free.next().unwrap_or(1)))
        .collect()
}

/// The reference's normal stress along the measuring line (MPa) at `t`, averaged over
/// 1000 pieces of the line and, in 2D and 3D, across the row of cells the line runs in
/// ([`MeasureLine::holds`]: for the plate's bottom row `[0, Δy]`); labelled `exact` or
/// `reference`.
pub fn reference_series<const D: usize>(
    r: &Reference,
    t: f64,
    line: &MeasureLine,
    grid: &Grid<D>,
) -> Series {
    let n = 1000;
    let (start, end) = line.span();
    let dx = (end - start) / n as f64;
    // the row of cells across the line
    let (mut low, mut high) = (Vector::<D>::zeros(), Vector::<D>::zeros());
    let at = line.point::<D>(start);
    for k in Grid::<D>::tangent_axes(line.axis) {
        low[k] = grid.origin[k] + grid.layer_of(k, at[k]) as f64 * grid.spacing[k];
        high[k] = low[k] + grid.spacing[k];
    }
    let points = (0..n)
        .map(|i| {
            let x = start + (i as f64 + 0.5) * dx;
            let (mut lo, mut hi) = (low, high);
            lo[line.axis] = x - 0.5 * dx;
            hi[line.axis] = x + 0.5 * dx;
            (x, r.averages(&lo, &hi, t).0 * MPA)
        })
        .filter(|p| p.1.is_finite())
        .collect();
    Series {
        label: reference_label(r).into(),
        points,
        colour: 0,
        reference: true,
        marker: None,
    }
}

/// `exact` for closed-form references, `reference` for a converged run.
pub fn reference_label(r: &Reference) -> &'static str {
    match r {
        Reference::Converged(_) => "reference",
        _ => "exact",
    }
}

/// Every run's profile (MPa) at output time `t`.
fn method_series(runs: &[Collected], t: f64) -> Vec<Series> {
    let colours = method_colours(runs);
    runs.iter()
        .enumerate()
        .filter_map(|(m, run)| {
            run.profiles
                .iter()
                .find(|p| (p.0 - t).abs() <= 1e-12 * t.max(1e-30))
                .map(|(_, pts)| Series {
                    label: run.legend.clone(),
                    points: pts.iter().map(|&(x, s)| (x, s * MPA)).collect(),
                    colour: colours[m],
                    reference: false,
                    marker: None,
                })
        })
        .collect()
}

/// The output times of the longest run; at most three (first, middle, last).
pub fn picked_times(runs: &[Collected]) -> Vec<f64> {
    let times: Vec<f64> = runs
        .iter()
        .map(|r| r.profiles.iter().map(|p| p.0).collect::<Vec<_>>())
        .max_by_key(|t| t.len())
        .unwrap_or_default();
    match times.len() {
        0..=3 => times,
        n => vec![times[0], times[n / 2], times[n - 1]],
    }
}

/// Profiles of the normal stress along the measuring line at each of `times` (one panel
/// each, stacked), every run and the reference (averaged across the line's row of cells).
pub fn profile_figure<const D: usize>(
    scene: &str,
    measure: StressMeasure,
    runs: &[Collected],
    reference: Option<&Reference>,
    (line, grid): (&MeasureLine, &Grid<D>),
    times: &[f64],
) -> LineFigure {
    let axis = ["x", "y", "z"][line.axis];
    let symbol = measure.xx_symbol().replace("ₓₓ", &format!("_{axis}{axis}"));
    let symbol = if line.axis == 0 {
        measure.xx_symbol().to_string()
    } else {
        symbol
    };
    let where_ = if D > 1 {
        let point = line.point::<D>(line.start);
        let across: Vec<String> = Grid::<D>::tangent_axes(line.axis)
            .map(|k| format!("{} = {}", ["x", "y", "z"][k], point[k]))
            .collect();
        format!(" along {axis} at {}", across.join(", "))
    } else {
        String::new()
    };
    let panels = times
        .iter()
        .map(|&t| {
            let mut series: Vec<Series> = reference
                .map(|r| reference_series(r, t, line, grid))
                .into_iter()
                .collect();
            series.extend(method_series(runs, t));
            Panel {
                title: format!("{scene}: {symbol}{where_}, t = {:.4} ms", t * 1e3),
                x: Axis::linear(format!("{axis} (m)")),
                y: Axis::linear(format!("{symbol} (MPa)")),
                series,
            }
        })
        .collect();
    LineFigure::new(panels, 1, PrintWidth::Full, 0.3)
}

/// The large-strain bar (the paper's Fig. 6): the displacement `u = x − X` of DGMPM's
/// points along the bar at each output time (top: the motion the positions alone would
/// hide, 4 cm on 6 m) and Πₓₓ of every run against the exact solution at every output
/// time, one panel each, as the paper's Fig. 6 shows several times.
pub fn svk_figure<const D: usize>(
    scene: &str,
    runs: &[Collected],
    reference: Option<&Reference>,
    (line, grid): (&MeasureLine, &Grid<D>),
) -> LineFigure {
    let mut top = Vec::new();
    if let Some(dgmpm) = runs.iter().find(|r| r.name == "dgmpm") {
        for (k, ((t, xs), (_, profile))) in dgmpm.positions.iter().zip(&dgmpm.profiles).enumerate()
        {
            top.push(Series {
                label: format!("DGMPM u at t = {:.3} ms", t * 1e3),
                points: xs
                    .iter()
                    .zip(profile)
                    .map(|(x, (reference_x, _))| (*reference_x, (x - reference_x) * 1e3))
                    .collect(),
                colour: 4 + k,
                reference: false,
                marker: None,
            });
        }
    }
    // Πₓₓ at every output time, one panel each, like the paper's Fig. 6
    let times: Vec<f64> = runs
        .iter()
        .map(|r| r.profiles.iter().map(|p| p.0).collect::<Vec<f64>>())
        .max_by_key(|t| t.len())
        .unwrap_or_default();
    let mut panels = vec![Panel {
        title: format!("{scene}: displacement of DGMPM's points"),
        x: Axis::linear("X (m), reference position"),
        y: Axis::linear("u = x − X (mm)"),
        series: top,
    }];
    for &t in &times {
        let mut series: Vec<Series> = reference
            .map(|r| reference_series(r, t, line, grid))
            .into_iter()
            .collect();
        series.extend(method_series(runs, t));
        panels.push(Panel {
            title: format!("{scene}: Πₓₓ at t = {:.3} ms", t * 1e3),
            x: Axis::linear("X (m)"),
            y: Axis::linear("Πₓₓ (MPa)"),
            series,
        });
    }
    LineFigure::new(panels, 1, PrintWidth::Full, 0.26)
}

/// The reference's average of σₓₓ over a map cell `[lo, hi]` at `t`, with its label.
pub type ReferenceMap<'a> = (&'static str, &'a dyn Fn(&Vector<2>, &Vector<2>, f64) -> f64);

/// σₓₓ maps (MPa): one row per time of `times`, one column per run and, last, the
/// reference averaged over each cell; one colour bar with a robust range. `grid` is the
/// map's plane ([`crate::plane::MapPlane`]), `where_` its words for the titles.
pub fn map_figure(
    grid: &Grid<2>,
    where_: &str,
    runs: &[Collected],
    reference: Option<ReferenceMap>,
    times: &[f64],
) -> Option<MapFigure> {
    let upper = grid.upper();
    let extent = [grid.origin[0], upper[0], grid.origin[1], upper[1]];
    let place = if where_.is_empty() {
        String::new()
    } else {
        format!(", {where_}")
    };
    let mut panels = Vec::new();
    for &t in times {
        for run in runs {
            if let Some((_, values)) = run.maps.iter().find(|m| (m.0 - t).abs() <= 1e-12 * t) {
                panels.push(MapPanel {
                    title: format!("{}, t = {:.3} ms{place}", display_name(&run.name), t * 1e3),
                    cells: grid.cells,
                    extent,
                    values: values.iter().map(|v| v * MPA).collect(),
                });
            }
        }
        if let Some((label, average)) = reference {
            let values = (0..grid.cell_count())
                .map(|c| {
                    let (i, j) = (c % grid.cells[0], c / grid.cells[0]);
                    let lo = grid.origin
                        + Vector::<2>::new(i as f64 * grid.spacing[0], j as f64 * grid.spacing[1]);
                    average(&lo, &(lo + grid.spacing), t) * MPA
                })
                .collect();
            panels.push(MapPanel {
                title: format!("{label}, t = {:.3} ms{place}", t * 1e3),
                cells: grid.cells,
                extent,
                values,
            });
        }
    }
    if panels.is_empty() {
        return None;
    }
    let columns = runs.len() + usize::from(reference.is_some());
    let range = robust_range(panels.iter().flat_map(|p| p.values.iter()));
    Some(MapFigure {
        panels,
        columns: columns.max(1),
        range,
        label: "σₓₓ (MPa)".into(),
        range_note: format!(
            "colour range ±{range:.0} MPa: the 99th percentile of |σₓₓ| over all maps; beyond it \
             saturates"
        ),
        width: PrintWidth::Full,
    })
}
