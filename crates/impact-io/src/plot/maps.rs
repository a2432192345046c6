//! Colour maps of cell values with one shared colour bar (module doc of [`super`]).
use super::{linear_label, text, Draw};
use crate::IoError;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// One colour map: values per cell of a regular `nx × ny` grid covering `extent`.
#[derive(Debug, Clone)]
pub struct MapPanel {
    /// Panel title.
    pub title: String,
    /// Cells along x and y.
    pub cells: [usize; 2],
    /// `[x0, x1, y0, y1]` in m.
    pub extent: [f64; 4],
    /// Values in the colour bar's unit, x fastest (`NaN` = no data, drawn grey).
    pub values: Vec<f64>,
}

/// Maps in `columns` columns sharing the symmetric range `[-range, range]`.
#[derive(Debug, Clone)]
pub struct MapFigure {
    /// The maps.
    pub panels: Vec<MapPanel>,
    /// Maps per row.
    pub columns: usize,
    /// The half-range of the colour bar (values beyond saturate).
    pub range: f64,
    /// Colour bar label with unit, e.g. `σ_xx (MPa)`.
    pub label: String,
    /// How the range was chosen, printed under the bar.
    pub range_note: String,
}

/// The robust half-range of a diverging map: the 99th percentile of `|v|` over the finite
/// values (nearest rank), so that one extreme cell (the corner of an impact segment) does
/// not wash out the waves; at least the smallest positive number.
pub fn robust_range<'a>(values: impl IntoIterator<Item = &'a f64>) -> f64 {
    let mut magnitudes: Vec<f64> = values
        .into_iter()
        .filter(|v| v.is_finite())
        .map(|v| v.abs())
        .collect();
    if magnitudes.is_empty() {
        return f64::MIN_POSITIVE;
    }
    magnitudes.sort_by(f64::total_cmp);
    let rank = ((0.99 * magnitudes.len() as f64).ceil() as usize).clamp(1, magnitudes.len());
    magnitudes[rank - 1].max(f64::MIN_POSITIVE)
}

/// ColorBrewer RdBu (through `colorous`), centred at zero: blue for negative values
/// (compression), white at zero, red for positive (tension).
fn diverging(value: f64, range: f64) -> RGBColor {
    let s = (value / range).clamp(-1.0, 1.0);
    let c = colorous::RED_BLUE.eval_continuous(0.5 * (1.0 - s));
    RGBColor(c.r, c.g, c.b)
}

/// Grey for cells without data.
const NO_DATA: RGBColor = RGBColor(160, 160, 160);
/// Width of the colour-bar column in pixels.
const BAR_WIDTH: u32 = 190;
/// Map size in pixels.
const MAP_SIZE: (u32, u32) = (440, 370);

impl Draw for MapFigure {
    fn size(&self) -> (u32, u32) {
        let columns = self.columns.max(1);
        let rows = self.panels.len().div_ceil(columns).max(1);
        (
            MAP_SIZE.0 * columns as u32 + BAR_WIDTH,
            MAP_SIZE.1 * rows as u32,
        )
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        root.fill(&WHITE).map_err(text)?;
        let (width, height) = self.size();
        let (maps, bar) = root.split_horizontally(width - BAR_WIDTH);
        let columns = self.columns.max(1);
        let rows = self.panels.len().div_ceil(columns).max(1);
        for (panel, area) in self
            .panels
            .iter()
            .zip(maps.split_evenly((rows, columns)).iter())
        {
            self.draw_map(area, panel)?;
        }
        self.draw_bar(&bar, height)
    }
}

impl MapFigure {
    fn draw_map<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        panel: &MapPanel,
    ) -> Result<(), String> {
        let [x0, x1, y0, y1] = panel.extent;
        let mut chart = ChartBuilder::on(area)
            .caption(&panel.title, ("sans-serif", 17))
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(48)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(text)?;
        let (x_step, y_step) = ((x1 - x0) / 5.0, (y1 - y0) / 5.0);
        let x_format = move |v: &f64| linear_label(*v, x_step);
        let y_format = move |v: &f64| linear_label(*v, y_step);
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("x (m)")
            .y_desc("y (m)")
            .x_labels(5)
            .y_labels(5)
            .x_label_formatter(&x_format)
            .y_label_formatter(&y_format)
            .label_style(("sans-serif", 13))
            .axis_desc_style(("sans-serif", 14))
            .draw()
            .map_err(text)?;
        let ([nx, ny], values) = coarsened(panel, MAP_SIZE.0 as usize);
        let (dx, dy) = ((x1 - x0) / nx as f64, (y1 - y0) / ny as f64);
        let range = self.range;
        chart
            .draw_series(
                (0..ny)
                    .flat_map(|j| (0..nx).map(move |i| (i, j)))
                    .map(|(i, j)| {
                        let v = values.get(j * nx + i).copied().unwrap_or(f64::NAN);
                        let colour = if v.is_finite() {
                            diverging(v, range)
                        } else {
                            NO_DATA
                        };
                        let (xa, ya) = (x0 + i as f64 * dx, y0 + j as f64 * dy);
                        Rectangle::new([(xa, ya), (xa + dx, ya + dy)], colour.filled())
                    }),
            )
            .map_err(text)?;
        Ok(())
    }

    /// The colour bar: a vertical gradient from -range to +range with five labelled ticks,
    /// the label, the range note and the no-data swatch.
    fn draw_bar<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        height: u32,
    ) -> Result<(), String> {
        let (top, bottom) = (50i32, (height as i32 - 150).max(120));
        let (left, right) = (20i32, 50i32);
        let steps = (bottom - top).max(1);
        for k in 0..steps {
            let value = self.range * (1.0 - 2.0 * k as f64 / steps as f64);
            area.draw(&Rectangle::new(
                [(left, top + k), (right, top + k + 1)],
                diverging(value, self.range).filled(),
            ))
            .map_err(text)?;
        }
        area.draw(&Rectangle::new([(left, top), (right, bottom)], BLACK))
            .map_err(text)?;
        let font = ("sans-serif", 14).into_font();
        for k in 0..=4 {
            let value = self.range * (1.0 - 0.5 * k as f64);
            let y = top + (bottom - top) * k / 4;
            area.draw(&PathElement::new(vec![(right, y), (right + 6, y)], BLACK))
                .map_err(text)?;
            let label = linear_label(value, self.range / 4.0);
            area.draw(&Text::new(label, (right + 10, y - 7), font.clone()))
                .map_err(text)?;
        }
        area.draw(&Text::new(
            self.label.clone(),
            (left, top - 30),
            ("sans-serif", 16),
        ))
        .map_err(text)?;
        let mut y = bottom + 16;
        for line in wrap(&self.range_note, 26) {
            area.draw(&Text::new(line, (left - 10, y), font.clone()))
                .map_err(text)?;
            y += 17;
        }
        area.draw(&Rectangle::new(
            [(left - 10, y + 4), (left + 10, y + 18)],
            NO_DATA.filled(),
        ))
        .map_err(text)?;
        area.draw(&Text::new("no data", (left + 16, y + 4), font))
            .map_err(text)?;
        Ok(())
    }
}

/// The panel's values averaged over blocks of `k × k` cells, `k` the smallest factor that
/// leaves at most `most` blocks along x (a map finer than the panel's pixels draws no more
/// detail, only more rectangles); cells without data are left out of a block's average,
/// and a block with none stays without data.
fn coarsened(panel: &MapPanel, most: usize) -> ([usize; 2], Vec<f64>) {
    let [nx, ny] = panel.cells;
    let k = nx.div_ceil(most.max(1)).max(1);
    if k == 1 {
        return (panel.cells, panel.values.clone());
    }
    let (cx, cy) = (nx.div_ceil(k), ny.div_ceil(k));
    let mut sum = vec![0.0; cx * cy];
    let mut count = vec![0usize; cx * cy];
    for j in 0..ny {
        for i in 0..nx {
            let v = panel.values.get(j * nx + i).copied().unwrap_or(f64::NAN);
            if v.is_finite() {
                let b = (j / k) * cx + i / k;
                sum[b] += v;
                count[b] += 1;
            }
        }
    }
    let values = sum
        .iter()
        .zip(&count)
        .map(|(&s, &n)| if n > 0 { s / n as f64 } else { f64::NAN })
        .collect();
    ([cx, cy], values)
}

/// Split `text` into lines of at most about `width` characters at spaces.
fn wrap(text: &str, width: usize) -> Vec<String> {
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

/// Draw maps side by side (one row) into `path` with a robust shared range.
pub fn colour_maps(path: &Path, panels: Vec<MapPanel>, label: &str) -> Result<(), IoError> {
    let range = robust_range(panels.iter().flat_map(|p| p.values.iter()));
    let columns = panels.len().max(1);
    super::save(
        path,
        &MapFigure {
            panels,
            columns,
            range,
            label: label.to_string(),
            range_note: format!(
                "range ±{} = 99th percentile of |value|; beyond it saturates",
                linear_label(range, range / 100.0)
            ),
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_extreme_cell_does_not_set_the_range() {
        // a plate of waves up to 300 with one cell at 690 (the end of an impact segment)
        let mut values: Vec<f64> = (0..1000).map(|i| -300.0 * (i as f64 / 999.0)).collect();
        values[17] = -690.0;
        values.push(f64::NAN);
        let range = robust_range(&values);
        assert!(range < 300.0 && range > 290.0, "{range}");
        // no data is not zero
        assert_eq!(robust_range(&[f64::NAN]), f64::MIN_POSITIVE);
        // the map is centred: zero is the middle colour, signs are opposite hues
        let (zero, minus, plus) = (
            diverging(0.0, range),
            diverging(-range, range),
            diverging(range, range),
        );
        // near-white and neutral
        let channels = [zero.0, zero.1, zero.2];
        let (lightest, darkest) = (
            channels.iter().max().unwrap(),
            channels.iter().min().unwrap(),
        );
        assert!(*darkest > 230 && lightest - darkest < 10, "{zero:?}");
        assert!(minus.2 > minus.0 && plus.0 > plus.2, "{minus:?} {plus:?}");
        assert_ne!(NO_DATA, zero);
    }

    #[test]
    fn fine_maps_are_block_averaged_keeping_no_data_apart() {
        let (nx, ny) = (1000, 750);
        let mut values: Vec<f64> = (0..nx * ny).map(|c| (c % nx) as f64).collect();
        values[..3].iter_mut().for_each(|v| *v = f64::NAN);
        let panel = MapPanel {
            title: String::new(),
            cells: [nx, ny],
            extent: [0.0, 4.0, 0.0, 3.0],
            values,
        };
        let ([cx, cy], coarse) = coarsened(&panel, 440);
        assert_eq!((cx, cy), (334, 250));
        // block (0, 0): columns 0..3 of rows 0..3, its first row without data
        assert_eq!(coarse[0], 1.0);
        assert_eq!(coarse[1], 4.0);
        assert!(coarse.iter().all(|v| v.is_finite()));
        let blank = MapPanel {
            values: vec![f64::NAN; nx * ny],
            ..panel
        };
        assert!(coarsened(&blank, 440).1.iter().all(|v| v.is_nan()));
    }
}
