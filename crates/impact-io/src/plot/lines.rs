//! Line panels in a grid with one legend column beside them (module doc of [`super`]).
use super::{
    colour, decade_label, decade_range, font, linear_label, pt, text, type_size, Draw, PrintWidth,
    MARKER_LIMIT,
};
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
    /// The exact/reference curve: a thin line drawn over the others, no markers.
    pub reference: bool,
    /// Marker shape and line pattern, for series that share a colour: `k % 4` the marker
    /// (0 circle, 1 triangle, 2 square, 3 cross), `k / 4 % 3` the line (solid, dashed,
    /// dotted), so twelve variants of one colour stay apart; `None`: the marker from the
    /// colour index, a solid line.
    pub marker: Option<usize>,
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

/// Panels in `columns` columns (rows as needed), the legend in rows below them, and an
/// optional note under the legend; laid out for a printed width ([`PrintWidth`]).
#[derive(Debug, Clone)]
pub struct LineFigure {
    /// The panels.
    pub panels: Vec<Panel>,
    /// Panels per row.
    pub columns: usize,
    /// The printed width the figure is made for.
    pub width: PrintWidth,
    /// Each panel's height over its width.
    pub aspect: f64,
    /// A note printed under the legend (e.g. which series coincide), if any.
    pub note: Option<String>,
}

/// One legend entry: label, colour index, the reference's thin line, its marker shape
/// (`None`: no marker), its line pattern (0 solid, 1 dashed, 2 dotted).
type Entry<'a> = (&'a str, usize, bool, Option<usize>, usize);

impl LineFigure {
    /// A figure of `panels` in `columns` columns for `width`, panels `aspect` high.
    pub fn new(panels: Vec<Panel>, columns: usize, width: PrintWidth, aspect: f64) -> Self {
        Self {
            panels,
            columns,
            width,
            aspect,
            note: None,
        }
    }

    /// One entry per distinct label, in order of first appearance.
    fn entries(&self) -> Vec<Entry<'_>> {
        let mut entries: Vec<Entry<'_>> = Vec::new();
        for p in &self.panels {
            for s in &p.series {
                if !entries.iter().any(|e| e.0 == s.label) {
                    let marker = (!s.reference && s.points.len() <= MARKER_LIMIT)
                        .then(|| s.marker.unwrap_or_else(|| marker_shape(s.colour)));
                    let pattern = s.marker.map_or(0, |k| k / 4 % 3);
                    entries.push((&s.label, s.colour, s.reference, marker, pattern));
                }
            }
        }
        entries
    }

    /// Legend geometry: (entry width, entries per row, row height, rows).
    fn legend_layout(&self) -> (u32, u32, u32, u32) {
        let entries = self.entries();
        let longest = entries
            .iter()
            .map(|e| e.0.chars().count())
            .max()
            .unwrap_or(0) as f64;
        let size = pt(type_size::LABEL) as f64;
        let entry = (3.2 * size + 0.56 * size * longest + size) as u32;
        let per_row = (self.width.pixels() / entry.max(1)).max(1);
        let rows = (entries.len() as u32).div_ceil(per_row);
        (entry, per_row, (1.6 * size) as u32, rows)
    }

    /// The note's lines, wrapped to the figure's width.
    fn note_lines(&self) -> Vec<String> {
        let chars = (self.width.pixels() as f64 / (0.52 * pt(type_size::TICK) as f64)) as usize;
        self.note
            .as_deref()
            .map(|n| wrap(n, chars.max(20)))
            .unwrap_or_default()
    }

    fn panel_height(&self) -> u32 {
        let columns = self.columns.max(1) as u32;
        ((self.width.pixels() / columns) as f64 * self.aspect) as u32
    }
}

/// Split `text` into lines of at most about `width` characters at spaces.
pub(super) fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split_whitespace() {
        match lines.last_mut() {
            Some(line) if line.chars().count() + 1 + word.chars().count() <= width => {
                line.push(' ');
                line.push_str(word);
            }
            _ => lines.push(word.to_string()),
        }
    }
    lines
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

    fn print_width(&self) -> PrintWidth {
        self.width
    }

    fn set_print_width(&mut self, width: PrintWidth) {
        self.width = width;
    }

    fn size(&self) -> (u32, u32) {
        let columns = self.columns.max(1);
        let rows = self.panels.len().div_ceil(columns).max(1) as u32;
        let (_, _, row_height, legend_rows) = self.legend_layout();
        let note = self.note_lines().len() as u32 * (1.5 * pt(type_size::TICK) as f64) as u32;
        (
            self.width.pixels(),
            self.panel_height() * rows + legend_rows * row_height + note + pt(6.0),
        )
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        root.fill(&WHITE).map_err(text)?;
        let columns = self.columns.max(1);
        let rows = self.panels.len().div_ceil(columns).max(1);
        let (plots, legend) = root.split_vertically(self.panel_height() * rows as u32);
        let areas = plots.split_evenly((rows, columns));
        for (panel, area) in self.panels.iter().zip(areas.iter()) {
            draw_panel(area, panel)?;
        }
        self.draw_legend(&legend)
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
    let area = &super::titled(area, &panel.title, type_size::TITLE)?;
    let mut chart = ChartBuilder::on(area)
        .margin(pt(4.0))
        .margin_right(pt(8.0))
        .x_label_area_size(pt(3.2 * type_size::TICK))
        .y_label_area_size(pt(5.0 * type_size::TICK))
        .build_cartesian_2d(x, y)
        .map_err(text)?;
    let (x_log, y_log) = (panel.x.log, panel.y.log);
    let x_format = move |v: &f64| tick(*v, x_log, x_step);
    let y_format = move |v: &f64| tick(*v, y_log, y_step);
    chart
        .configure_mesh()
        .x_desc(panel.x.label.as_str())
        .y_desc(panel.y.label.as_str())
        .x_labels(6)
        .y_labels(6)
        .x_label_formatter(&x_format)
        .y_label_formatter(&y_format)
        .label_style(font(type_size::TICK))
        .axis_desc_style(font(type_size::LABEL))
        .axis_style(BLACK.stroke_width(pt(0.5).max(1)))
        .light_line_style(RGBColor(240, 240, 240))
        .bold_line_style(RGBColor(220, 220, 220).stroke_width(pt(0.3).max(1)))
        .draw()
        .map_err(text)?;
    // the methods first, the exact/reference curve last: a thin line over them, so a
    // method lying on it hides neither
    let (methods, exact): (Vec<&Series>, Vec<&Series>) =
        panel.series.iter().partition(|s| !s.reference);
    for s in methods.into_iter().chain(exact) {
        let c = colour(s.colour);
        let points: Vec<(f64, f64)> = s
            .points
            .iter()
            .copied()
            .filter(|&(x, y)| {
                x.is_finite() && y.is_finite() && (!x_log || x > 0.0) && (!y_log || y > 0.0)
            })
            .collect();
        let style = c.stroke_width(line_width(s.reference));
        match s.marker.map_or(0, |k| k / 4 % 3) {
            0 => chart
                .draw_series(LineSeries::new(points.iter().copied(), style))
                .map(|_| ()),
            pattern => {
                let (dash, gap) = if pattern == 1 {
                    (pt(4.0), pt(2.0))
                } else {
                    (pt(1.0), pt(1.5))
                };
                chart
                    .draw_series(DashedLineSeries::new(
                        points.iter().copied(),
                        dash,
                        gap,
                        style,
                    ))
                    .map(|_| ())
            }
        }
        .map_err(text)?;
        if !s.reference && points.len() <= MARKER_LIMIT {
            let shape = s.marker.unwrap_or_else(|| marker_shape(s.colour));
            draw_markers(&mut chart, &points, s.colour, shape)?;
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
    shape: usize,
) -> Result<(), String>
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let c = colour(index);
    let style = c.filled();
    let r = pt(1.6) as i32;
    let drawn = match shape % 4 {
        0 => chart.draw_series(points.iter().map(|&p| Circle::new(p, r, style))),
        1 => chart.draw_series(points.iter().map(|&p| TriangleMarker::new(p, r + 2, style))),
        2 => chart.draw_series(
            points
                .iter()
                .map(|&p| EmptyElement::at(p) + Rectangle::new([(-r, -r), (r, r)], style)),
        ),
        _ => chart.draw_series(
            points
                .iter()
                .map(|&p| Cross::new(p, r + 1, c.stroke_width(pt(0.6)))),
        ),
    };
    drawn.map(|_| ()).map_err(text)
}

/// The marker shape of series `index`: 0 circle, 1 triangle, 2 square, 3 cross.
fn marker_shape(index: usize) -> usize {
    (index.max(1) - 1) / 7 % 4
}

/// A method's line width (1 pt) or the exact/reference curve's (0.5 pt, drawn over them).
fn line_width(reference: bool) -> u32 {
    if reference {
        pt(0.5).max(1)
    } else {
        pt(1.0)
    }
}

impl LineFigure {
    /// The legend in rows under the panels, then the note.
    fn draw_legend<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let (entry, per_row, row_height, rows) = self.legend_layout();
        let size = pt(type_size::LABEL) as i32;
        let label_font = font(type_size::LABEL).into_font();
        for (k, (label, index, reference, marker, pattern)) in
            self.entries().into_iter().enumerate()
        {
            let (row, column) = (k as u32 / per_row, k as u32 % per_row);
            let x = (column * entry) as i32 + size / 2;
            let y = (row * row_height) as i32 + row_height as i32 / 2 + size / 3;
            let c = colour(index);
            let style = c.stroke_width(line_width(reference));
            match pattern {
                0 => area.draw(&PathElement::new(vec![(x, y), (x + 2 * size, y)], style)),
                p => {
                    let (dash, gap) = if p == 1 {
                        (pt(4.0), pt(2.0))
                    } else {
                        (pt(1.0), pt(1.5))
                    };
                    area.draw(&plotters::element::DashedPathElement::new(
                        vec![(x, y), (x + 2 * size, y)],
                        dash,
                        gap,
                        style,
                    ))
                }
            }
            .map_err(text)?;
            if let Some(shape) = marker {
                let style = c.filled();
                let (point, r) = ((x + size, y), pt(1.6) as i32);
                match shape % 4 {
                    0 => area.draw(&Circle::new(point, r, style)),
                    1 => area.draw(&TriangleMarker::new(point, r + 2, style)),
                    2 => area.draw(&Rectangle::new(
                        [(point.0 - r, y - r), (point.0 + r, y + r)],
                        style,
                    )),
                    _ => area.draw(&Cross::new(point, r + 1, c.stroke_width(pt(0.6)))),
                }
                .map_err(text)?;
            }
            area.draw(&Text::new(
                label.to_string(),
                (x + 2 * size + size / 2, y - size / 2),
                label_font.clone(),
            ))
            .map_err(text)?;
        }
        let note_font = font(type_size::TICK).into_font();
        let step = (1.5 * pt(type_size::TICK) as f64) as i32;
        let mut y = (rows * row_height) as i32 + pt(2.0) as i32;
        for line in self.note_lines() {
            area.draw(&Text::new(line, (size / 2, y), note_font.clone()))
                .map_err(text)?;
            y += step;
        }
        Ok(())
    }
}

/// Draw `panels` (one column) into `path` (PNG or SVG by extension).
pub fn line_panels(path: &Path, panels: Vec<Panel>) -> Result<(), IoError> {
    super::save(path, &LineFigure::new(panels, 1, PrintWidth::Full, 0.36))
}
