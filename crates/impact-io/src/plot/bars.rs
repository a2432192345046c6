//! Grouped horizontal bars over named categories (plotters' segmented coordinates), with
//! the legend beside them (module doc of [`super`]).
use super::{colour, linear_label, text, Draw};
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
}

const LEFT: u32 = 330;
const LEGEND: u32 = 200;

impl Draw for BarFigure {
    fn size(&self) -> (u32, u32) {
        (1100, 120 + 34 * self.categories.len().max(1) as u32)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        root.fill(&WHITE).map_err(text)?;
        let (width, _) = self.size();
        let (plot, legend) = root.split_horizontally(width - LEGEND);
        let top = self
            .groups
            .iter()
            .flat_map(|g| g.values.iter().flatten())
            .fold(0.0f64, |m, &v| m.max(v));
        let x_max = if top > 0.0 { 1.1 * top } else { 1.0 };
        let n = self.categories.len().max(1);
        let mut chart = ChartBuilder::on(&plot)
            .caption(&self.title, ("sans-serif", 19))
            .margin(12)
            .x_label_area_size(46)
            .y_label_area_size(LEFT)
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
            .label_style(("sans-serif", 14))
            .axis_desc_style(("sans-serif", 16))
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
                let Some(v) = *value else { continue };
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
        let font = ("sans-serif", 15).into_font();
        for (g, group) in self.groups.iter().enumerate() {
            let y = 60 + 26 * g as i32;
            legend
                .draw(&Rectangle::new(
                    [(10, y - 7), (40, y + 7)],
                    colour(g + 1).filled(),
                ))
                .map_err(text)?;
            legend
                .draw(&Text::new(group.label.clone(), (48, y - 8), font.clone()))
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
        },
    )
}
