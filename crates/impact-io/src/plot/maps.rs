//! Colour maps of cell values with one shared colour bar (module doc of [`super`]).
use super::lines::wrap;
use super::{font, linear_label, pt, text, type_size, Draw, PrintWidth};
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
    /// The printed width the figure is made for.
    pub width: PrintWidth,
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
/// Width of the colour-bar column in pixels (about 24 mm at print size).
fn bar_width() -> u32 {
    pt(68.0)
}

impl MapFigure {
    /// One map's width and height in pixels.
    fn map_size(&self) -> (u32, u32) {
        let columns = self.columns.max(1) as u32;
        let w = (self.width.pixels() - bar_width()) / columns;
        (w, (w as f64 * 0.84) as u32)
    }
}

impl Draw for MapFigure {
    fn print_width(&self) -> PrintWidth {
        self.width
    }

    fn set_print_width(&mut self, width: PrintWidth) {
        self.width = width;
    }

    fn size(&self) -> (u32, u32) {
        let columns = self.columns.max(1);
        let rows = self.panels.len().div_ceil(columns).max(1);
        (self.width.pixels(), self.map_size().1 * rows as u32)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        root.fill(&WHITE).map_err(text)?;
        let (width, height) = self.size();
        let (maps, bar) = root.split_horizontally(width - bar_width());
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
        let area = &super::titled(area, &panel.title, type_size::LABEL)?;
        let mut chart = ChartBuilder::on(area)
            .margin(pt(3.0))
            .margin_right(pt(7.0))
            .x_label_area_size(pt(3.0 * type_size::TICK))
            .y_label_area_size(pt(3.6 * type_size::TICK))
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
            .label_style(font(type_size::TICK))
            .axis_desc_style(font(type_size::TICK))
            .draw()
            .map_err(text)?;
        let ([nx, ny], values) = coarsened(panel, self.map_size().0 as usize);
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
        let s = pt(type_size::TICK) as i32;
        let chars = ((bar_width() as f64) / (0.52 * s as f64)) as usize;
        let note = wrap(&self.range_note, chars.max(10));
        let below = (1.3 * s as f64) as i32 * (note.len() as i32 + 1) + 2 * s;
        let (top, bottom) = (3 * s, (height as i32 - below).max(7 * s));
        let (left, right) = (s, 3 * s);
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
        let tick_font = font(type_size::TICK).into_font();
        for k in 0..=4 {
            let value = self.range * (1.0 - 0.5 * k as f64);
            let y = top + (bottom - top) * k / 4;
            area.draw(&PathElement::new(
                vec![(right, y), (right + s / 2, y)],
                BLACK,
            ))
            .map_err(text)?;
            let label = linear_label(value, self.range / 4.0);
            area.draw(&Text::new(label, (right + s, y - s / 2), tick_font.clone()))
                .map_err(text)?;
        }
        area.draw(&Text::new(
            self.label.clone(),
            (left, top - 2 * s),
            font(type_size::LABEL),
        ))
        .map_err(text)?;
        let mut y = bottom + s;
        for line in note {
            area.draw(&Text::new(line, (left / 2, y), tick_font.clone()))
                .map_err(text)?;
            y += (1.3 * s as f64) as i32;
        }
        area.draw(&Rectangle::new(
            [(left / 2, y + s / 4), (left / 2 + s, y + s)],
            NO_DATA.filled(),
        ))
        .map_err(text)?;
        area.draw(&Text::new("no data", (left / 2 + 3 * s / 2, y), tick_font))
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
            width: PrintWidth::Full,
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
