//! Grouped horizontal bars over named categories (plotters' segmented coordinates), with
//! the legend beside them (module doc of [`super`]).
use super::{colour, font, linear_label, pt, text, type_size, Draw, PrintWidth};
use crate::IoError;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// One group of bars: a legend label and one value per category (`None`: no bar).
#[derive(Debug, Clone)]
pub struct BarGroup {
    /// Legend label.
    pub label: String,
    /// Value per category.
    pub values: Vec<Option<f64>>,
}

/// Categories down the vertical axis, each with one bar per group.
#[derive(Debug, Clone)]
pub struct BarFigure {
    /// Title.
    pub title: String,
    /// Label of the value axis, with unit.
    pub axis: String,
    /// One name per category.
    pub categories: Vec<String>,
    /// The bars of each category, one per group.
    pub groups: Vec<BarGroup>,
    /// What a category without a bar of a group means, per group and category (drawn as
    /// a short text at the bar's place, e.g. `0` for a limit of zero or `n/c` for not
    /// computed); empty: nothing drawn.
    pub missing: Vec<Vec<Option<String>>>,
    /// A note printed under the legend (e.g. what the missing-bar marks mean).
    pub note: Option<String>,
    /// The printed width the figure is made for: at full width the legend is a column
    /// beside the bars, in a single column it goes under them.
    pub width: PrintWidth,
}

/// The category labels' column, the legend column (pixels).
fn columns() -> (u32, u32) {
    (pt(105.0), pt(95.0))
}

impl BarFigure {
    /// The legend's width and, in a single column (legend under the bars), its height;
    /// 0 at full width (legend beside the bars).
    fn legend_box(&self) -> (u32, u32) {
        match self.width {
            PrintWidth::Full => (columns().1, 0),
            PrintWidth::Single => {
                let width = self.width.pixels();
                let notes = super::lines::wrap(
                    self.note.as_deref().unwrap_or(""),
                    note_chars(width).max(10),
                )
                .len();
                let s = pt(type_size::LABEL) as f64;
                let height = 2.0 * s
                    + 1.6 * s * self.groups.len() as f64
                    + 1.3 * pt(type_size::TICK) as f64 * (notes as f64 + 1.0);
                (width, height as u32)
            }
        }
    }
}

/// Characters of the note per line in a legend `width` pixels wide.
fn note_chars(width: u32) -> usize {
    (width as f64 / (0.52 * pt(type_size::TICK) as f64)) as usize
}

impl Draw for BarFigure {
    fn print_width(&self) -> PrintWidth {
        self.width
    }

    fn set_print_width(&mut self, width: PrintWidth) {
        self.width = width;
    }

    fn size(&self) -> (u32, u32) {
        let row = (1.9 * pt(type_size::TICK) as f64) as u32;
        (
            self.width.pixels(),
            pt(40.0) + row * self.categories.len().max(1) as u32 + self.legend_box().1,
        )
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        root.fill(&WHITE).map_err(text)?;
        let (width, height) = self.size();
        let (left, _) = columns();
        let (legend_width, legend_height) = self.legend_box();
        let (plot, legend) = match self.width {
            PrintWidth::Full => root.split_horizontally(width - legend_width),
            PrintWidth::Single => root.split_vertically(height - legend_height),
        };
        let top = self
            .groups
            .iter()
            .flat_map(|g| g.values.iter().flatten())
            .fold(0.0f64, |m, &v| m.max(v));
        let x_max = if top > 0.0 { 1.1 * top } else { 1.0 };
        let n = self.categories.len().max(1);
        let plot = super::titled(&plot, &self.title, type_size::TITLE)?;
        let mut chart = ChartBuilder::on(&plot)
            .margin(pt(4.0))
            .x_label_area_size(pt(3.2 * type_size::TICK))
            .y_label_area_size(left)
            // n categories: the discrete values 0..=n-1, one segment each
            .build_cartesian_2d(0.0..x_max, (0..n - 1).into_segmented())
            .map_err(text)?;
        let categories = &self.categories;
        let y_format = |v: &SegmentValue<usize>| match v {
            SegmentValue::CenterOf(k) => categories.get(*k).cloned().unwrap_or_default(),
            _ => String::new(),
        };
        let x_format = move |v: &f64| linear_label(*v, x_max / 10.0);
        chart
            .configure_mesh()
            .y_labels(n)
            .y_label_formatter(&y_format)
            .x_label_formatter(&x_format)
            .x_desc(self.axis.as_str())
            .label_style(font(type_size::TICK))
            .axis_desc_style(font(type_size::LABEL))
            .light_line_style(RGBColor(240, 240, 240))
            .draw()
            .map_err(text)?;
        let groups = self.groups.len().max(1) as f64;
        for (g, group) in self.groups.iter().enumerate() {
            let c = colour(g + 1);
            let (lo, hi) = (
                0.15 + 0.7 * g as f64 / groups,
                0.15 + 0.7 * (g + 1) as f64 / groups,
            );
            // a bar is a rectangle in the segment's pixel band: draw it on the plotting
            // area's pixels through the chart's coordinate mapping
            for (k, value) in group.values.iter().enumerate() {
                let Some(v) = *value else {
                    // say why there is no bar, at its place
                    let mark = self
                        .missing
                        .get(g)
                        .and_then(|m| m.get(k))
                        .cloned()
                        .flatten();
                    if let Some(mark) = mark {
                        let (x0, y0) = chart.backend_coord(&(0.0, SegmentValue::Exact(k)));
                        let end = if k + 1 < n {
                            SegmentValue::Exact(k + 1)
                        } else {
                            SegmentValue::Last
                        };
                        let (_, y1) = chart.backend_coord(&(0.0, end));
                        let y = y0 + ((y1 - y0) as f64 * 0.5 * (lo + hi)) as i32;
                        let size = pt(type_size::TICK * 0.85) as i32;
                        // side by side along the bar, so the groups' marks never overlap
                        let x = x0 + size / 3 + g as i32 * 2 * size;
                        root.draw(&Text::new(
                            mark,
                            (x, y - size / 2),
                            ("sans-serif", size as u32).into_font().color(&c),
                        ))
                        .map_err(text)?;
                    }
                    continue;
                };
                let (x0, y0) = chart.backend_coord(&(0.0, SegmentValue::Exact(k)));
                let end = if k + 1 < n {
                    SegmentValue::Exact(k + 1)
                } else {
                    SegmentValue::Last
                };
                let (x1, y1) = chart.backend_coord(&(v, end));
                let (ya, yb) = (
                    y0 + ((y1 - y0) as f64 * lo) as i32,
                    y0 + ((y1 - y0) as f64 * hi) as i32,
                );
                root.draw(&Rectangle::new([(x0, ya), (x1, yb)], c.filled()))
                    .map_err(text)?;
            }
        }
        let s = pt(type_size::LABEL) as i32;
        let label_font = font(type_size::LABEL).into_font();
        let mut y = if legend_height > 0 { s } else { 3 * s };
        for (g, group) in self.groups.iter().enumerate() {
            legend
                .draw(&Rectangle::new(
                    [(s / 2, y - s / 3), (2 * s, y + s / 3)],
                    colour(g + 1).filled(),
                ))
                .map_err(text)?;
            legend
                .draw(&Text::new(
                    group.label.clone(),
                    (5 * s / 2, y - s / 2),
                    label_font.clone(),
                ))
                .map_err(text)?;
            y += (1.6 * s as f64) as i32;
        }
        let note_font = font(type_size::TICK).into_font();
        let chars = note_chars(legend_width);
        for line in super::lines::wrap(self.note.as_deref().unwrap_or(""), chars.max(10)) {
            y += (1.3 * pt(type_size::TICK) as f64) as i32;
            legend
                .draw(&Text::new(line, (s / 2, y), note_font.clone()))
                .map_err(text)?;
        }
        Ok(())
    }
}

/// Draw grouped horizontal bars into `path` (PNG or SVG by extension).
pub fn bar_chart(
    path: &Path,
    title: &str,
    axis: &str,
    categories: Vec<String>,
    groups: Vec<BarGroup>,
) -> Result<(), IoError> {
    super::save(
        path,
        &BarFigure {
            title: title.to_string(),
            axis: axis.to_string(),
            categories,
            groups,
            missing: Vec::new(),
            note: None,
            width: PrintWidth::Full,
        },
    )
}
