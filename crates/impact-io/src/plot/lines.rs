//! Line panels in a grid with one legend column beside them (module doc of [`super`]).
use super::{colour, decade_label, decade_range, linear_label, text, Draw, MARKER_LIMIT};
use crate::IoError;
use plotters::coord::ranged1d::{AsRangedCoord, Ranged, ValueFormatter};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// One axis: its label (symbol and unit, e.g. `σ_xx (MPa)`) and scale.
#[derive(Debug, Clone, Default)]
pub struct Axis {
    /// Label with symbol and unit.
    pub label: String,
    /// Logarithmic (whole decades, a tick at each power of ten).
    pub log: bool,
}

impl Axis {
    /// A linear axis.
    pub fn linear(label: impl Into<String>) -> Self {
        Self {
            label: label.into(),
            log: false,
        }
    }

    /// A logarithmic axis.
    pub fn log(label: impl Into<String>) -> Self {
        Self {
            label: label.into(),
            log: true,
        }
    }
}

/// One curve of a panel.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend label (the same label in several panels is one legend entry).
    pub label: String,
    /// `(x, y)` points, in the axes' units.
    pub points: Vec<(f64, f64)>,
    /// Colour index (0: black, the exact or reference curve; 1..: [`super::colour`]); also
    /// picks the marker shape.
    pub colour: usize,
    /// The exact/reference curve: 3 px, no markers.
    pub reference: bool,
}

/// One panel: a title, its axes and curves.
#[derive(Debug, Clone)]
pub struct Panel {
    /// Panel title.
    pub title: String,
    /// Horizontal axis.
    pub x: Axis,
    /// Vertical axis.
    pub y: Axis,
    /// Curves.
    pub series: Vec<Series>,
}

/// Panels in `columns` columns (rows as needed) and a legend column at the right.
#[derive(Debug, Clone)]
pub struct LineFigure {
    /// The panels.
    pub panels: Vec<Panel>,
    /// Panels per row.
    pub columns: usize,
    /// Panel size in pixels.
    pub panel_size: (u32, u32),
}

impl LineFigure {
    /// Width of the legend column in pixels: room for the longest label.
    fn legend_width(&self) -> u32 {
        let longest = self
            .panels
            .iter()
            .flat_map(|p| p.series.iter().map(|s| s.label.chars().count()))
            .max()
            .unwrap_or(0);
        (70 + 8 * longest as u32).max(160)
    }
}

impl Draw for LineFigure {
    /// `panel,series,x,y`: the panel's index (0-based, in drawing order), the series'
    /// label (commas replaced by `;`), and each plotted point.
    fn data(&self) -> Option<String> {
        let mut csv = String::from("panel,series,x,y\n");
        for (k, panel) in self.panels.iter().enumerate() {
            for series in &panel.series {
                let label = series.label.replace(',', ";");
                for (x, y) in &series.points {
                    csv.push_str(&format!("{k},{label},{x},{y}\n"));
                }
            }
        }
        Some(csv)
    }

    fn size(&self) -> (u32, u32) {
        let columns = self.columns.max(1);
        let rows = self.panels.len().div_ceil(columns).max(1);
        (
            self.panel_size.0 * columns as u32 + self.legend_width(),
            self.panel_size.1 * rows as u32,
        )
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        root.fill(&WHITE).map_err(text)?;
        let (width, _) = self.size();
        let (plots, legend) = root.split_horizontally(width - self.legend_width());
        let columns = self.columns.max(1);
        let rows = self.panels.len().div_ceil(columns).max(1);
        let areas = plots.split_evenly((rows, columns));
        for (panel, area) in self.panels.iter().zip(areas.iter()) {
            draw_panel(area, panel)?;
        }
        draw_legend(&legend, &self.panels)
    }
}

/// The bounds of every finite point (positive ones on a log axis).
fn bounds(panel: &Panel) -> ((f64, f64), (f64, f64)) {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for s in &panel.series {
        for &(x, y) in &s.points {
            let usable = x.is_finite()
                && y.is_finite()
                && (!panel.x.log || x > 0.0)
                && (!panel.y.log || y > 0.0);
            if usable {
                (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
            }
        }
    }
    if x0 > x1 {
        return ((1.0, 10.0), (1.0, 10.0));
    }
    ((x0, x1), (y0, y1))
}

/// A linear range with 6 % padding (a flat series gets a unit-wide range).
fn padded(low: f64, high: f64) -> (f64, f64) {
    let pad = if high > low {
        0.06 * (high - low)
    } else {
        0.5 * low.abs().max(1.0)
    };
    (low - pad, high + pad)
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panel: &Panel,
) -> Result<(), String> {
    let ((x0, x1), (y0, y1)) = bounds(panel);
    let linear = |(a, b): (f64, f64)| padded(a, b);
    match (panel.x.log, panel.y.log) {
        (false, false) => {
            let ((a, b), (c, d)) = (linear((x0, x1)), linear((y0, y1)));
            chart(area, panel, a..b, c..d, (b - a) / 8.0, (d - c) / 8.0)
        }
        (true, true) => {
            let ((a, b), (c, d)) = (decade_range(x0, x1), decade_range(y0, y1));
            chart(
                area,
                panel,
                (a..b).log_scale(),
                (c..d).log_scale(),
                0.0,
                0.0,
            )
        }
        (true, false) => {
            let ((a, b), (c, d)) = (decade_range(x0, x1), linear((y0, y1)));
            chart(area, panel, (a..b).log_scale(), c..d, 0.0, (d - c) / 8.0)
        }
        (false, true) => {
            let ((a, b), (c, d)) = (linear((x0, x1)), decade_range(y0, y1));
            chart(area, panel, a..b, (c..d).log_scale(), (b - a) / 8.0, 0.0)
        }
    }
}

/// The tick label of `value` on an axis: `10ⁿ` on a log axis, fixed-point otherwise.
fn tick(value: f64, log: bool, step: f64) -> String {
    if log {
        decade_label(value)
    } else {
        linear_label(value, step)
    }
}

fn chart<DB, X, Y>(
    area: &DrawingArea<DB, Shift>,
    panel: &Panel,
    x: X,
    y: Y,
    x_step: f64,
    y_step: f64,
) -> Result<(), String>
where
    DB: DrawingBackend,
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 19))
        .margin(12)
        .x_label_area_size(48)
        .y_label_area_size(72)
        .build_cartesian_2d(x, y)
        .map_err(text)?;
    let (x_log, y_log) = (panel.x.log, panel.y.log);
    let x_format = move |v: &f64| tick(*v, x_log, x_step);
    let y_format = move |v: &f64| tick(*v, y_log, y_step);
    chart
        .configure_mesh()
        .x_desc(panel.x.label.as_str())
        .y_desc(panel.y.label.as_str())
        .x_labels(8)
        .y_labels(8)
        .x_label_formatter(&x_format)
        .y_label_formatter(&y_format)
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 16))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()
        .map_err(text)?;
    for s in &panel.series {
        let c = colour(s.colour);
        let points: Vec<(f64, f64)> = s
            .points
            .iter()
            .copied()
            .filter(|&(x, y)| {
                x.is_finite() && y.is_finite() && (!x_log || x > 0.0) && (!y_log || y > 0.0)
            })
            .collect();
        let width = if s.reference { 3 } else { 2 };
        chart
            .draw_series(LineSeries::new(
                points.iter().copied(),
                c.stroke_width(width),
            ))
            .map_err(text)?;
        if !s.reference && points.len() <= MARKER_LIMIT {
            draw_markers(&mut chart, &points, s.colour)?;
        }
    }
    Ok(())
}

/// Markers of series `index`: circle, triangle, square, cross, cycling with the colours
/// (seven colours × four shapes keep 28 series apart).
fn draw_markers<DB, X, Y>(
    chart: &mut ChartContext<DB, Cartesian2d<X, Y>>,
    points: &[(f64, f64)],
    index: usize,
) -> Result<(), String>
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let c = colour(index);
    let style = c.filled();
    let drawn = match marker_shape(index) {
        0 => chart.draw_series(points.iter().map(|&p| Circle::new(p, 4, style))),
        1 => chart.draw_series(points.iter().map(|&p| TriangleMarker::new(p, 5, style))),
        2 => chart.draw_series(
            points
                .iter()
                .map(|&p| EmptyElement::at(p) + Rectangle::new([(-4, -4), (4, 4)], style)),
        ),
        _ => chart.draw_series(points.iter().map(|&p| Cross::new(p, 5, c.stroke_width(2)))),
    };
    drawn.map(|_| ()).map_err(text)
}

/// The marker shape of series `index`: 0 circle, 1 triangle, 2 square, 3 cross.
fn marker_shape(index: usize) -> usize {
    (index.max(1) - 1) / 7 % 4
}

/// One entry per distinct label, in order of first appearance.
fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panels: &[Panel],
) -> Result<(), String> {
    let mut entries: Vec<(&str, usize, bool, bool)> = Vec::new();
    for p in panels {
        for s in &p.series {
            if !entries.iter().any(|e| e.0 == s.label) {
                let marker = !s.reference && s.points.len() <= MARKER_LIMIT;
                entries.push((&s.label, s.colour, s.reference, marker));
            }
        }
    }
    let font = ("sans-serif", 15).into_font();
    for (k, (label, index, reference, marker)) in entries.into_iter().enumerate() {
        let y = 50 + 26 * k as i32;
        let c = colour(index);
        let width = if reference { 3 } else { 2 };
        area.draw(&PathElement::new(
            vec![(10, y), (50, y)],
            c.stroke_width(width),
        ))
        .map_err(text)?;
        if marker {
            let style = c.filled();
            let point = (30, y);
            match marker_shape(index) {
                0 => area.draw(&Circle::new(point, 4, style)),
                1 => area.draw(&TriangleMarker::new(point, 5, style)),
                2 => area.draw(&Rectangle::new([(26, y - 4), (34, y + 4)], style)),
                _ => area.draw(&Cross::new(point, 5, c.stroke_width(2))),
            }
            .map_err(text)?;
        }
        area.draw(&Text::new(label.to_string(), (58, y - 8), font.clone()))
            .map_err(text)?;
    }
    Ok(())
}

/// Draw `panels` (one column) into `path` (PNG or SVG by extension).
pub fn line_panels(path: &Path, panels: Vec<Panel>) -> Result<(), IoError> {
    super::save(
        path,
        &LineFigure {
            panels,
            columns: 1,
            panel_size: (900, 340),
        },
    )
}
